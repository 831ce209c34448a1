//! The `tracer` command line: `tracer render SCENE -o OUT [options]`, `tracer view SCENE`,
//! `tracer bench SCENE...`, `tracer accuracy SCENE... [-o REPORT_DIR]`.
//!
//! Exit status 0 on success, 2 on bad input or a failed write, with one line
//! `FILE:LINE: message` (or `FILE: message`) on stderr and no output file left behind.

use clap::{Parser, Subcommand, ValueEnum};
use serde_json::json;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use tracer::effects::EffectsMode;
use tracer::geometry::AccelOptions;
use tracer::render::{render_with_stats, Schedule, Scheduler, Settings};
use tracer::scene::{self, desc::SceneDesc};
use tracer::stats::{CycleClock, Cycles, Mark};
use tracer::world::Scene;
use vecexpr::Real;

#[derive(Parser, Debug)]
#[command(
    name = "tracer",
    version,
    about = "A Whitted ray tracer built on vecexpr"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render a scene (.nff, .nff.gz or .obj) to an image (.png or .pfm).
    Render(RenderArgs),
    /// Measure build time, ray throughput by kind and frame time of scenes.
    Bench(BenchArgs),
    /// Open a window that renders SCENE continuously, with a camera to fly and live knobs.
    View(tracer::viewer::ViewArgs),
    /// Measure image error against render time for every cheaper setting of each knob.
    Accuracy(tracer::accuracy::AccuracyArgs),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum SchedulerArg {
    Rayon,
    Static,
    Tiles,
}

/// Scheduler options shared by `render` and `bench`.
#[derive(clap::Args, Debug)]
struct ScheduleArgs {
    /// Parallel scheduler: rayon work stealing, static row blocks, or a dynamic tile queue.
    #[arg(long, value_enum, default_value_t = SchedulerArg::Rayon)]
    scheduler: SchedulerArg,
    /// Tile edge in pixels for --scheduler tiles.
    #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u32).range(1..=4096))]
    tile: u32,
}

impl ScheduleArgs {
    fn schedule(&self) -> Schedule {
        Schedule {
            scheduler: match self.scheduler {
                SchedulerArg::Rayon => Scheduler::Rayon,
                SchedulerArg::Static => Scheduler::Static,
                SchedulerArg::Tiles => Scheduler::Tiles,
            },
            tile: self.tile,
        }
    }
}

/// Eye-ray packet options shared by `render` and `bench`.
#[derive(clap::Args, Debug)]
struct PacketArgs {
    /// Trace eye rays in SIMD packets (the image is the same either way); auto: on with
    /// AVX2 or AVX-512, or with the --isa named.
    #[arg(long, value_parser = ["auto", "on", "off"], default_value = "auto")]
    packets: String,
    /// Instruction set of the packet kernels: the CPU's widest (auto) or a named one.
    #[arg(long, value_parser = ["auto", "sse2", "avx2", "avx512"], default_value = "auto")]
    isa: String,
}

impl PacketArgs {
    fn packets(&self) -> Result<tracer::packet::Packets, String> {
        tracer::packet::Packets::from_args(&self.packets, &self.isa)
    }
}

#[derive(clap::Args, Debug)]
struct BenchArgs {
    /// Scene files (.nff, .nff.gz, .obj).
    #[arg(required = true)]
    scenes: Vec<PathBuf>,
    /// Image width.
    #[arg(long, default_value_t = 512, value_parser = clap::value_parser!(u32).range(1..=65536))]
    width: u32,
    /// Image height.
    #[arg(long, default_value_t = 512, value_parser = clap::value_parser!(u32).range(1..=65536))]
    height: u32,
    /// Maximum ray depth of the frame.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=64))]
    depth: u32,
    /// Runs per measurement (medians are printed).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=1000))]
    runs: u32,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: Option<u32>,
    /// Arithmetic precision.
    #[arg(long, value_enum, default_value_t = Precision::F32)]
    precision: Precision,
    /// Trace without the BVH (brute force).
    #[arg(long)]
    no_bvh: bool,
    /// Traverse the binary BVH instead of the four-wide one.
    #[arg(long)]
    binary_bvh: bool,
    /// Output of povray-times, for the ratio column.
    #[arg(long, value_name = "FILE")]
    peer: Option<PathBuf>,
    #[command(flatten)]
    schedule: ScheduleArgs,
    #[command(flatten)]
    packets: PacketArgs,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Precision {
    F32,
    F64,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Effects {
    /// The renderer specialised for the effects the scene needs.
    Auto,
    /// The general renderer (same image, for comparison).
    All,
}

#[derive(clap::Args, Debug)]
struct RenderArgs {
    /// Scene file: NFF (.nff, .nff.gz) or Wavefront OBJ (.obj).
    scene: PathBuf,
    /// Output image: .png (8-bit) or .pfm (linear float).
    #[arg(short, long)]
    output: PathBuf,
    /// Image width (default: the scene's resolution).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=65536))]
    width: Option<u32>,
    /// Image height (default: the scene's resolution); the vertical angle of view is kept.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=65536))]
    height: Option<u32>,
    /// Antialiasing: an AA x AA grid of rays per pixel.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=64))]
    aa: u32,
    /// Maximum ray depth (1 = eye rays only).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=64))]
    depth: u32,
    /// Adaptive termination: skip secondary rays whose accumulated weight is below T (0 = off).
    #[arg(long, default_value_t = 0.0, value_parser = parse_threshold)]
    threshold: f64,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: Option<u32>,
    /// Arithmetic precision of the whole tracer.
    #[arg(long, value_enum, default_value_t = Precision::F32)]
    precision: Precision,
    /// SPD testing rules: corner rays averaged into pixels, depth 5, no adaptive cutoff.
    #[arg(long)]
    spd: bool,
    /// Write statistics (times, ray counts, primitives, BVH, settings) as JSON.
    #[arg(long, value_name = "STATS.json")]
    stats: Option<PathBuf>,
    /// Which renderer: specialised for the scene's effects (auto) or general (all).
    #[arg(long, value_enum, default_value_t = Effects::Auto)]
    effects: Effects,
    /// Trace without the BVH (brute force), for comparison.
    #[arg(long)]
    no_bvh: bool,
    /// Traverse the binary BVH instead of the four-wide one, for comparison.
    #[arg(long)]
    binary_bvh: bool,
    #[command(flatten)]
    schedule: ScheduleArgs,
    #[command(flatten)]
    packets: PacketArgs,
    /// OBJ camera position (x,y,z); NFF scenes carry their own camera.
    #[arg(long, value_parser = tracer::scene::parse_vec3, allow_hyphen_values = true)]
    from: Option<[f64; 3]>,
    /// OBJ camera target (x,y,z).
    #[arg(long, value_parser = tracer::scene::parse_vec3, allow_hyphen_values = true)]
    at: Option<[f64; 3]>,
    /// OBJ camera up vector (x,y,z).
    #[arg(long, value_parser = tracer::scene::parse_vec3, allow_hyphen_values = true)]
    up: Option<[f64; 3]>,
    /// OBJ camera vertical angle of view in degrees.
    #[arg(long)]
    angle: Option<f64>,
}

fn parse_threshold(s: &str) -> Result<f64, String> {
    let v: f64 = s.parse().map_err(|_| format!("`{s}` is not a number"))?;
    if !(0.0..=1.0).contains(&v) {
        return Err(format!("threshold must be in [0, 1], got {v}"));
    }
    Ok(v)
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Render(args) => match run_render(&args) {
            Ok(()) => ExitCode::SUCCESS,
            Err(msg) => {
                eprintln!("{msg}");
                ExitCode::from(2)
            }
        },
        Command::Bench(args) => match run_bench(&args) {
            Ok(()) => ExitCode::SUCCESS,
            Err(msg) => {
                eprintln!("{msg}");
                ExitCode::from(2)
            }
        },
        Command::View(args) => match tracer::viewer::run(&args) {
            Ok(()) => ExitCode::SUCCESS,
            Err(msg) => {
                eprintln!("{msg}");
                ExitCode::from(2)
            }
        },
        Command::Accuracy(args) => match tracer::accuracy::run(&args) {
            Ok(()) => ExitCode::SUCCESS,
            Err(msg) => {
                eprintln!("{msg}");
                ExitCode::from(2)
            }
        },
    }
}

fn run_bench(args: &BenchArgs) -> Result<(), String> {
    use tracer::bench::{bench_scene, parse_peer_times, table, BenchOptions};
    let peer = match &args.peer {
        Some(p) => parse_peer_times(
            &std::fs::read_to_string(p).map_err(|e| format!("{}: {e}", p.display()))?,
        ),
        None => Vec::new(),
    };
    let opts = BenchOptions {
        width: args.width,
        height: args.height,
        depth: args.depth,
        runs: args.runs as usize,
        threads: args.threads.map(|t| t as usize),
        schedule: args.schedule.schedule(),
        accel: AccelOptions {
            use_bvh: !args.no_bvh,
            wide: !args.binary_bvh,
            ..AccelOptions::default()
        },
        packets: args.packets.packets()?,
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.threads.unwrap_or(0))
        .build()
        .map_err(|e| format!("cannot create the thread pool: {e}"))?;
    let mut rows = Vec::new();
    for path in &args.scenes {
        let desc = scene::load(path).map_err(|e| e.to_string())?;
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let name = name.split('.').next().unwrap_or_default().to_string();
        let row = pool.install(|| match args.precision {
            Precision::F32 => bench_scene::<f32>(&name, &desc, &opts),
            Precision::F64 => bench_scene::<f64>(&name, &desc, &opts),
        });
        rows.push(row);
    }
    print!("{}", table(&rows, &peer));
    let packets = tracer::bench::packet_table(&rows);
    if !packets.is_empty() {
        print!("\n{packets}");
    }
    Ok(())
}

fn load(args: &RenderArgs) -> Result<SceneDesc, String> {
    let opts = scene::ObjOptions {
        from: args.from,
        at: args.at,
        up: args.up,
        angle: args.angle,
        ..scene::ObjOptions::default()
    };
    let precision = match args.precision {
        Precision::F32 => scene::Precision::F32,
        Precision::F64 => scene::Precision::F64,
    };
    scene::load_for(&args.scene, &opts, precision).map_err(|e| e.to_string())
}

fn run_render(args: &RenderArgs) -> Result<(), String> {
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
    let desc = load(args)?;
    let parse = (start.ms(), start.cycles());
    let settings = Settings {
        width: args.width,
        height: args.height,
        aa: args.aa,
        depth: args.depth,
        threshold: args.threshold,
        threads: args.threads.map(|t| t as usize),
        spd: args.spd,
        progress: true,
        effects: match args.effects {
            Effects::Auto => EffectsMode::Auto,
            Effects::All => EffectsMode::All,
        },
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

fn render_in<T: Real>(
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
    let (image, stats) = render_with_stats(&scene, settings);
    image
        .save(&args.output)
        .map_err(|e| format!("{}: cannot write image: {e}", args.output.display()))?;
    let (total_ms, total_cycles) = (start.ms(), start.cycles());
    if let Some(path) = &args.stats {
        let g = scene.geometry.stats();
        let (w, h) = settings.size(&scene);
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
