//! `tracer render SCENE -o OUT`: one image (PNG or PFM), optionally with statistics as
//! JSON.

use crate::args::{load_scene, parse_threshold, CameraArgs, PacketArgs, Precision, ScheduleArgs};
use crate::progress::Bar;
use serde_json::json;
use std::path::{Path, PathBuf};
use tracer::effects::EffectsMode;
use tracer::geometry::AccelOptions;
use tracer::render::{render_with_progress, Settings};
use tracer::scene::desc::SceneDesc;
use tracer::stats::{CycleClock, Cycles, Mark};
use tracer::world::Scene;

/// Options of `tracer render`.
#[derive(clap::Args, Debug)]
pub struct RenderArgs {
    /// Scene file: NFF (.nff, .nff.gz) or Wavefront OBJ (.obj).
    pub scene: PathBuf,
    /// Output image: .png (8-bit) or .pfm (linear float).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Image width (default: the scene's resolution).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub width: Option<u32>,
    /// Image height (default: the scene's resolution); the vertical angle of view is kept.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub height: Option<u32>,
    /// Antialiasing: an AA x AA grid of rays per pixel.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub aa: u32,
    /// Maximum ray depth (1 = eye rays only).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub depth: u32,
    /// Adaptive termination: skip secondary rays whose accumulated weight is below T (0 = off).
    #[arg(long, default_value_t = 0.0, value_parser = parse_threshold)]
    pub threshold: f64,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// Arithmetic precision of the whole tracer.
    #[arg(long, value_enum, default_value_t = Precision::F32)]
    pub precision: Precision,
    /// SPD testing rules: corner rays averaged into pixels, depth 5, no adaptive cutoff.
    #[arg(long)]
    pub spd: bool,
    /// Write statistics (times, ray counts, primitives, BVH, settings) as JSON.
    #[arg(long, value_name = "STATS.json")]
    pub stats: Option<PathBuf>,
    /// Which renderer: specialised for the scene's effects (auto) or general (all).
    #[arg(long, value_enum, default_value_t = EffectsMode::Auto)]
    pub effects: EffectsMode,
    /// Trace without the BVH (brute force), for comparison.
    #[arg(long)]
    pub no_bvh: bool,
    /// Traverse the binary BVH instead of the four-wide one, for comparison.
    #[arg(long)]
    pub binary_bvh: bool,
    /// Parallel scheduler and tile size.
    #[command(flatten)]
    pub schedule: ScheduleArgs,
    /// Eye-ray packets and their instruction set.
    #[command(flatten)]
    pub packets: PacketArgs,
    /// The camera of an OBJ scene.
    #[command(flatten)]
    pub camera: CameraArgs,
}

/// Runs `tracer render`.
///
/// # Errors
/// One line `FILE:LINE: message` or `FILE: message` for bad input or a failed write; no
/// output file is left behind.
pub fn run(args: &RenderArgs) -> Result<(), String> {
    let start = Mark::now();
    let out_ext = args
        .output
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !matches!(out_ext.as_deref(), Some("png" | "pfm")) {
        return Err(format!(
            "{}: output must end in .png or .pfm",
            args.output.display()
        ));
    }
    let packets = args.packets.packets()?;
    let desc = load_scene(&args.scene, &args.camera.obj_options(), args.precision)?;
    let parse = (start.ms(), start.cycles());
    let settings = Settings {
        width: args.width,
        height: args.height,
        aa: args.aa,
        depth: args.depth,
        threshold: args.threshold,
        threads: args.threads.map(|t| t as usize),
        spd: args.spd,
        effects: args.effects,
        schedule: args.schedule.schedule(),
        packets,
        ..Settings::default()
    };
    let accel = AccelOptions {
        use_bvh: !args.no_bvh,
        wide: !args.binary_bvh,
        ..AccelOptions::default()
    };
    match args.precision {
        Precision::F32 => render_in::<f32>(args, &desc, &settings, &accel, start, parse),
        Precision::F64 => render_in::<f64>(args, &desc, &settings, &accel, start, parse),
    }
}

fn render_in<T: tracer::Float>(
    args: &RenderArgs,
    desc: &SceneDesc,
    settings: &Settings,
    accel: &AccelOptions,
    start: Mark,
    (parse_ms, parse_cycles): (f64, u64),
) -> Result<(), String> {
    let build_start = Mark::now();
    let scene = Scene::<T>::from_desc(desc, accel);
    let (build_ms, build_cycles) = (build_start.ms(), build_start.cycles());
    let (image, stats) = render_with_progress(&scene, settings, &Bar::stderr());
    image
        .save(&args.output)
        .map_err(|e| format!("{}: cannot write image: {e}", args.output.display()))?;
    let (total_ms, total_cycles) = (start.ms(), start.cycles());
    if let Some(path) = &args.stats {
        let g = scene.geometry.stats();
        let (w, h) = settings.size(scene.camera.resolution);
        let report = json!({
            "scene": args.scene.display().to_string(),
            "times_ms": { "parse": parse_ms, "build": build_ms, "trace": stats.trace_ms, "trace_cpu": stats.trace_cpu_ms, "total": total_ms },
            "times_cycles": Cycles { parse: parse_cycles, build: build_cycles, trace: stats.trace_cycles, total: total_cycles },
            "cycle_clock": CycleClock::get(),
            "rays": stats.rays,
            "effects": stats.effects,
            "primitives": {
                "sphere": g.spheres, "triangle": g.triangles, "polygon": g.polygons,
                "patch": g.patches, "cone": g.cones, "degenerate": g.skipped,
                "total": desc.shapes.len(),
            },
            "bvh": { "nodes": g.bvh_nodes, "depth": g.bvh_depth, "bytes": g.bvh_bytes, "build_ms": g.build_ms },
            "image": { "width": w, "height": h },
            "settings": {
                "width": w, "height": h, "aa": if settings.spd { 1 } else { settings.aa },
                "depth": settings.limits::<T>().max_depth,
                "threshold": if settings.spd { 0.0 } else { settings.threshold },
                "threads": settings.threads.unwrap_or_else(rayon::current_num_threads),
                "precision": if std::mem::size_of::<T>() == 4 { "f32" } else { "f64" },
                "spd": settings.spd, "bvh": accel.use_bvh, "effects": settings.effects.name(),
                "packets": settings.packets.name(),
                "output": args.output.display().to_string(),
            },
        });
        write_json(path, &report)?;
    }
    if settings.spd {
        let r = stats.rays;
        eprintln!(
            "rays: eye {} reflection {} refraction {} shadow {} total {}",
            r.eye,
            r.reflection,
            r.refraction,
            r.shadow,
            r.total()
        );
    }
    Ok(())
}

fn write_json(path: &Path, value: &serde_json::Value) -> Result<(), String> {
    let text = serde_json::to_string_pretty(value).map_err(|e| e.to_string())?;
    tracer::image::write_atomic(path, |w| {
        use std::io::Write;
        w.write_all(text.as_bytes())?;
        w.write_all(b"\n")
    })
    .map_err(|e| format!("{}: cannot write stats: {e}", path.display()))
}
