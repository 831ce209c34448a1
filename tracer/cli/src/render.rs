//! `tracer render SCENE -o OUT`: one image (PNG, PFM or OpenEXR), optionally with
//! statistics as JSON.
//!
//! Every check that does not need a ray comes first: the output paths ([`Staged`]), the
//! options, the scene, the camera and the memory the render needs ([`Needs`]); then the
//! scene is built and traced, and the outputs are written together or not at all.

use crate::args::{
    image_size, load_scene_with_camera, parse_threshold, whole, CameraArgs, PacketArgs, Precision,
    ScheduleArgs,
};
use crate::memory::{self, Needs};
use crate::output::{extension, ImageFormat, Staged};
use crate::progress::{Feedback, Mode};
use serde_json::json;
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::PathBuf;
use tracer::effects::EffectsMode;
use tracer::geometry::AccelOptions;
use tracer::image::{Image, PngEncoding};
use tracer::render::{render_with_progress, Settings};
use tracer::scene::desc::SceneDesc;
use tracer::stats::{CycleClock, Cycles, Mark};
use tracer::world::Scene;

/// Options of `tracer render`.
#[derive(clap::Args, Debug)]
pub struct RenderArgs {
    /// Scene file: NFF (.nff, .nff.gz) or Wavefront OBJ (.obj).
    pub scene: PathBuf,
    /// Output image: .png (8-bit), .pfm or .exr (linear float).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Image width (default: the scene's); given alone, the height follows the scene's
    /// aspect ratio (rounded).
    #[arg(long, value_parser = whole(1, MAX_SIDE), allow_negative_numbers = true)]
    pub width: Option<u32>,
    /// Image height (default: the scene's); given alone, the width follows the scene's
    /// aspect ratio (rounded). The vertical angle of view is kept.
    #[arg(long, value_parser = whole(1, MAX_SIDE), allow_negative_numbers = true)]
    pub height: Option<u32>,
    /// Antialiasing: an AA x AA grid of rays per pixel.
    #[arg(long, default_value_t = 1, value_parser = whole(1, 64), allow_negative_numbers = true)]
    pub aa: u32,
    /// Maximum ray depth (1 = eye rays only).
    #[arg(long, default_value_t = 5, value_parser = whole(1, 64), allow_negative_numbers = true)]
    pub depth: u32,
    /// Adaptive termination: skip secondary rays whose accumulated weight is below T (0 = off).
    #[arg(long, default_value_t = 0.0, value_parser = parse_threshold, allow_negative_numbers = true)]
    pub threshold: f64,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = whole(1, 1024), allow_negative_numbers = true)]
    pub threads: Option<u32>,
    /// Arithmetic precision of the whole tracer.
    #[arg(long, value_enum, default_value_t = Precision::F32)]
    pub precision: Precision,
    /// SPD testing rules: corner rays averaged into pixels, depth 5, no adaptive cutoff
    /// (so --aa, --depth and --threshold are refused with it).
    #[arg(long, conflicts_with_all = ["aa", "depth", "threshold"])]
    pub spd: bool,
    /// Write statistics (times, ray counts, primitives, BVH, camera, settings) as JSON.
    #[arg(long, value_name = "STATS.json")]
    pub stats: Option<PathBuf>,
    /// Which renderer: specialised for the scene's effects (auto) or general (all).
    #[arg(long, value_enum, default_value_t = EffectsMode::Auto)]
    pub effects: EffectsMode,
    /// Trace without the BVH (brute force), for comparison.
    #[arg(long)]
    pub no_bvh: bool,
    /// Traverse the binary BVH instead of the four-wide one, for comparison (not with
    /// --no-bvh, which traverses none).
    #[arg(long, conflicts_with = "no_bvh")]
    pub binary_bvh: bool,
    /// Parallel scheduler and tile size.
    #[command(flatten)]
    pub schedule: ScheduleArgs,
    /// Eye-ray packets and their instruction set.
    #[command(flatten)]
    pub packets: PacketArgs,
    /// The camera: frames an OBJ scene, overrides an NFF scene's.
    #[command(flatten)]
    pub camera: CameraArgs,
    /// PNG only: write sRGB-encoded values tagged `sRGB` instead of the linear values
    /// tagged `gAMA` 1.0.
    #[arg(long)]
    pub srgb: bool,
    /// Print nothing but errors and warnings (no progress bar, no summary).
    #[arg(short, long, conflicts_with = "progress")]
    pub quiet: bool,
    /// Print progress as plain lines when standard error is not a terminal (for logs).
    #[arg(long)]
    pub progress: bool,
}

/// The largest image side.
pub const MAX_SIDE: u32 = 65536;

/// Runs `tracer render`.
///
/// # Errors
/// One line `FILE:LINE: message` or `FILE: message` for bad input or a failed write; no
/// output file is left behind.
pub fn run(args: &RenderArgs) -> Result<(), String> {
    let start = Mark::now();
    let format = ImageFormat::of(&args.output).ok_or_else(|| {
        format!(
            "{}: output must end in .png, .pfm or .exr",
            args.output.display()
        )
    })?;
    if args.srgb && format != ImageFormat::Png {
        return Err(format!(
            "{}: --srgb applies to PNG output only (PFM and EXR hold the linear values)",
            args.output.display()
        ));
    }
    if let Some(stats) = &args.stats {
        if extension(stats).as_deref() != Some("json") {
            return Err(format!("{}: statistics must end in .json", stats.display()));
        }
    }
    let mut paths = vec![args.output.as_path()];
    paths.extend(args.stats.as_deref());
    let staged = Staged::new(&paths)?;
    args.packets
        .check_applies(args.precision, if args.spd { 1 } else { args.aa })?;
    let packets = args.packets.packets()?;
    let schedule = args.schedule.schedule()?;
    let feedback = Feedback::new(Mode::for_stderr(args.quiet, args.progress));
    feedback.phase("parsing", &args.scene.display().to_string());
    let (desc, warning) = load_scene_with_camera(&args.scene, &args.camera, args.precision)?;
    if let Some(w) = warning {
        feedback.warn(&w);
    }
    let parse = (start.ms(), start.cycles());
    let (w, h) = image_size(args.width, args.height, desc.camera.resolution, MAX_SIDE)
        .map_err(|e| format!("{}: {e}", args.scene.display()))?;
    let settings = Settings {
        width: Some(w),
        height: Some(h),
        aa: args.aa,
        depth: args.depth,
        threshold: args.threshold,
        threads: args.threads.map(|t| t as usize),
        spd: args.spd,
        effects: args.effects,
        schedule,
        packets,
        ..Settings::default()
    };
    let scalar = match args.precision {
        Precision::F32 => 4,
        Precision::F64 => 8,
    };
    let needs = Needs::estimate(&memory::Shape {
        size: (w, h),
        scalar,
        aa: if args.spd { 1 } else { args.aa },
        spd: args.spd,
        packets: settings.packets.isa().is_some() && args.precision == Precision::F32,
        format,
        primitives: desc.shapes.len() as u64,
    });
    needs.check(
        memory::available(),
        &format!(
            "{}: a {w}x{h} render in {}",
            args.scene.display(),
            args.precision
        ),
    )?;
    let accel = AccelOptions {
        use_bvh: !args.no_bvh,
        wide: !args.binary_bvh,
        ..AccelOptions::default()
    };
    let job = Job {
        args,
        desc: &desc,
        settings: &settings,
        accel: &accel,
        format,
        feedback: &feedback,
        start,
        parse,
    };
    match args.precision {
        Precision::F32 => render_in::<f32>(&job, staged),
        Precision::F64 => render_in::<f64>(&job, staged),
    }
}

/// Everything a render needs, in either precision.
struct Job<'a> {
    args: &'a RenderArgs,
    desc: &'a SceneDesc,
    settings: &'a Settings,
    accel: &'a AccelOptions,
    format: ImageFormat,
    feedback: &'a Feedback,
    start: Mark,
    parse: (f64, u64),
}

fn render_in<T: tracer::Float>(job: &Job<'_>, mut staged: Staged) -> Result<(), String> {
    let (args, desc, settings, accel) = (job.args, job.desc, job.settings, job.accel);
    let (parse_ms, parse_cycles) = job.parse;
    job.feedback
        .phase("building", &format!("{} primitives", desc.shapes.len()));
    let build_start = Mark::now();
    let scene = Scene::<T>::from_desc(desc, accel);
    let (build_ms, build_cycles) = (build_start.ms(), build_start.cycles());
    let (w, h) = settings.size(scene.camera.resolution);
    job.feedback.phase("tracing", &format!("{w}x{h}"));
    let (image, stats) = render_with_progress(&scene, settings, job.feedback);
    job.feedback
        .phase("writing", &args.output.display().to_string());
    staged.write(0, "image", |out| {
        write_image(&image, job.format, args.srgb, out)
    })?;
    let (total_ms, total_cycles) = (job.start.ms(), job.start.cycles());
    if args.stats.is_some() {
        let g = scene.geometry.stats();
        let c = &desc.camera;
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
            "camera": {
                "from": c.from, "at": c.at, "up": c.up, "angle": c.angle_deg,
                "from_command_line": args.camera.given(),
            },
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
        let text = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?;
        staged.write(1, "stats", |out| {
            out.write_all(text.as_bytes())?;
            out.write_all(b"\n")
        })?;
    }
    staged.commit()?;
    let r = stats.rays;
    job.feedback.summary(&format!(
        "{}: {w}x{h}, {:.2} s, {:.2} Mrays/s",
        args.output.display(),
        job.start.ms() / 1e3,
        r.total() as f64 / (stats.trace_ms.max(1e-9) * 1e3)
    ));
    if settings.spd {
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

/// Encodes `image` in `format` into `out` (sRGB-encoded if `srgb`, for PNG).
fn write_image(
    image: &Image,
    format: ImageFormat,
    srgb: bool,
    out: &mut BufWriter<File>,
) -> io::Result<()> {
    match format {
        ImageFormat::Png if srgb => image.write_png_as(out, PngEncoding::Srgb),
        ImageFormat::Png => image.write_png_as(out, PngEncoding::Linear),
        ImageFormat::Pfm => image.write_pfm(out),
        ImageFormat::Exr => write_exr(image, out),
    }
}

/// Encodes `image` as OpenEXR: one layer of linear 32-bit float R, G and B channels,
/// top row first, losslessly compressed.
pub fn write_exr(image: &Image, out: &mut BufWriter<File>) -> io::Result<()> {
    use exr::prelude::{SpecificChannels, Vec2, WritableImage};
    let (w, h) = (image.width as usize, image.height as usize);
    let channels = SpecificChannels::rgb(|pos: Vec2<usize>| {
        let p = image.pixels[pos.y() * w + pos.x()];
        (p[0], p[1], p[2])
    });
    exr::image::Image::from_channels((w, h), channels)
        .write()
        .to_buffered(out)
        .map_err(io::Error::other)
}
