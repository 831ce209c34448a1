//! `tracer render SCENE -o OUT`: one image (PNG, PFM or OpenEXR), optionally with
//! statistics as JSON; or part of one (`--pixel-bounds`, `--crop`, `--tile` for
//! [`crate::merge`]), or frames of a camera path (`--script`, `--frame`).
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
use crate::tiles::{self, Digest, TileHeader, TileSpec};
use crate::viewer::{camera::FlyCamera, knobs::Knobs, script};
use serde_json::json;
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use tracer::effects::EffectsMode;
use tracer::geometry::AccelOptions;
use tracer::image::{Image, PngEncoding};
use tracer::render::{render_with_progress, PixelBounds, Settings};
use tracer::scene::desc::{CameraDesc, SceneDesc};
use tracer::stats::{CycleClock, Cycles, Mark};
use tracer::world::Scene;

/// Options of `tracer render`.
#[derive(clap::Args, Debug)]
pub struct RenderArgs {
    /// Scene file: NFF (.nff, .nff.gz) or Wavefront OBJ (.obj).
    pub scene: PathBuf,
    /// Output image: .png (8-bit), .pfm or .exr (linear float). `%04d` (or `%d`) in the
    /// file name is replaced by the frame number (--frame) or the tile index (--tile).
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
    /// Render only the pixels X0..X1 by Y0..Y1 (half-open, from the top left, as pbrt's
    /// --pixelbounds); each is bit for bit the pixel of the full render. A .png or .pfm
    /// holds just those pixels; an .exr also says where they lie.
    #[arg(long, value_name = "X0,X1,Y0,Y1", value_parser = parse_bounds,
          conflicts_with_all = ["crop", "tile"])]
    pub pixel_bounds: Option<PixelBounds>,
    /// Render only the fractions X0..X1 by Y0..Y1 of the image (0 to 1, as pbrt's
    /// --cropwindow): pixels ceil(X0 w) to ceil(X1 w), likewise for rows.
    #[arg(long, value_name = "X0,X1,Y0,Y1", value_parser = parse_crop, conflicts_with = "tile")]
    pub crop: Option<[f64; 4]>,
    /// Render tile I (from 0) of an N-tile split into an OpenEXR tile for `tracer merge`.
    /// `auto` takes I and N from SLURM_ARRAY_TASK_ID and SLURM_ARRAY_TASK_COUNT; `auto/N`
    /// takes I from SLURM_ARRAY_TASK_ID or JOB_COMPLETION_INDEX (use it to rerun tasks).
    #[arg(long, value_name = "I/N|auto|auto/N", value_parser = TileSpec::parse,
          conflicts_with = "frame")]
    pub tile: Option<TileSpec>,
    /// A camera path in the viewer's --script format, rendered with --frame.
    #[arg(long, value_name = "PATH", requires = "frame")]
    pub script: Option<PathBuf>,
    /// Frame K of --script (the view after its first K+1 lines, K from 0), a range A-B,
    /// or `auto` (K from SLURM_ARRAY_TASK_ID or JOB_COMPLETION_INDEX). The scene is read
    /// and its tree built once for all frames of a range.
    #[arg(long, value_name = "K|A-B|auto", value_parser = FrameSpec::parse, requires = "script")]
    pub frame: Option<FrameSpec>,
}

/// Which frames of a camera path to render.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameSpec {
    /// Frames `first..=last`.
    Range(u32, u32),
    /// The frame the environment names.
    Auto,
}

impl FrameSpec {
    /// Parses `K`, `A-B` or `auto`.
    ///
    /// # Errors
    /// A message naming the expected forms.
    pub fn parse(text: &str) -> Result<Self, String> {
        let num = |t: &str| {
            t.trim()
                .parse::<u32>()
                .map_err(|_| format!("`{text}`: expected K, A-B (frames from 0) or auto"))
        };
        match text.split_once('-') {
            _ if text == "auto" => Ok(Self::Auto),
            None => num(text).map(|k| Self::Range(k, k)),
            Some((a, b)) => {
                let (a, b) = (num(a)?, num(b)?);
                if a > b {
                    return Err(format!("frame range {a}-{b} is empty"));
                }
                Ok(Self::Range(a, b))
            }
        }
    }

    /// The frame numbers, the index of `auto` read from `env`.
    fn frames(self, env: impl Fn(&str) -> Option<String>) -> Result<(u32, u32), String> {
        match self {
            Self::Range(a, b) => Ok((a, b)),
            Self::Auto => {
                let (var, v) = ["SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"]
                    .into_iter()
                    .find_map(|v| env(v).map(|x| (v, x)))
                    .ok_or(
                        "--frame auto: neither SLURM_ARRAY_TASK_ID nor JOB_COMPLETION_INDEX is set",
                    )?;
                let k = v
                    .trim()
                    .parse::<u32>()
                    .map_err(|_| format!("--frame auto: {var}=`{v}` is not a number"))?;
                Ok((k, k))
            }
        }
    }
}

/// Parses `X0,X1,Y0,Y1` pixel bounds (clap value parser).
fn parse_bounds(s: &str) -> Result<PixelBounds, String> {
    let v: Vec<u32> = s
        .split(',')
        .map(|p| p.trim().parse::<u32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("`{s}`: expected X0,X1,Y0,Y1 in pixels"))?;
    let [x0, x1, y0, y1] = v[..] else {
        return Err(format!("`{s}`: expected four numbers X0,X1,Y0,Y1"));
    };
    let b = PixelBounds { x0, x1, y0, y1 };
    if b.is_empty() {
        return Err(format!("`{s}`: no pixel (X0 < X1 and Y0 < Y1 needed)"));
    }
    Ok(b)
}

/// Parses an `X0,X1,Y0,Y1` crop window of fractions (clap value parser).
fn parse_crop(s: &str) -> Result<[f64; 4], String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|p| p.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("`{s}`: expected X0,X1,Y0,Y1 between 0 and 1"))?;
    let [x0, x1, y0, y1] = v[..] else {
        return Err(format!("`{s}`: expected four numbers X0,X1,Y0,Y1"));
    };
    if !v.iter().all(|f| (0.0..=1.0).contains(f)) || x0 >= x1 || y0 >= y1 {
        return Err(format!(
            "`{s}`: fractions between 0 and 1 with X0 < X1 and Y0 < Y1 needed"
        ));
    }
    Ok([x0, x1, y0, y1])
}

/// The pixels of a crop window of a `w` x `h` image: from `ceil(x0 w)` to `ceil(x1 w)`
/// (as pbrt-v4), the same for rows.
fn crop_bounds([x0, x1, y0, y1]: [f64; 4], (w, h): (u32, u32)) -> PixelBounds {
    let at = |f: f64, n: u32| ((f * f64::from(n)).ceil() as u32).min(n);
    PixelBounds {
        x0: at(x0, w),
        x1: at(x1, w),
        y0: at(y0, h),
        y1: at(y1, h),
    }
}

/// The largest image side.
pub const MAX_SIDE: u32 = 65536;

/// Runs `tracer render`: [`prepare`], then [`Prepared::render`].
///
/// # Errors
/// One line `FILE:LINE: message` or `FILE: message` for bad input or a failed write; no
/// output file is left behind.
pub fn run(args: &RenderArgs) -> Result<(), String> {
    prepare(args)?.render()
}

/// A render checked and ready to trace: its options, scene and camera read and checked,
/// its memory estimated against the machine's, its outputs opened as temporary files.
pub struct Prepared<'a> {
    job: Job<'a>,
    staged: Staged,
}

impl Prepared<'_> {
    /// The image size the render will have.
    pub fn size(&self) -> (u32, u32) {
        let s = &self.job.settings;
        (s.width.unwrap_or(0), s.height.unwrap_or(0))
    }

    /// Builds the scene, traces it and writes the outputs.
    ///
    /// # Errors
    /// As [`run`].
    pub fn render(self) -> Result<(), String> {
        match self.job.args.precision {
            Precision::F32 => render_in::<f32>(&self.job, self.staged),
            Precision::F64 => render_in::<f64>(&self.job, self.staged),
        }
    }
}

/// Every check of `tracer render` that needs no ray, in the order [`run`] makes them:
/// the output paths and options first, then the scene, the camera, the image size and
/// region, and the memory. Nothing is written but the outputs' temporary files, which
/// dropping the result removes.
///
/// # Errors
/// As [`run`].
pub fn prepare(args: &RenderArgs) -> Result<Prepared<'_>, String> {
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
    if args.tile.is_some() && format != ImageFormat::Exr {
        return Err(format!(
            "{}: a tile is written as OpenEXR (.exr), which records where it lies",
            args.output.display()
        ));
    }
    let env = |v: &str| std::env::var(v).ok();
    let tile = args.tile.map(|t| t.resolve(env)).transpose()?;
    let frames = frames(args, env)?;
    // The outputs of the first image (frame) are checked and opened now; those of the
    // next frames of a range, in the same directories, as each frame begins.
    let first = frames.as_ref().map(|f| f.1).or(tile.map(|(i, _)| i));
    let staged = stage(args, first)?;
    args.packets.check_applies(args.precision)?;
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
    if let Some(b) = args.pixel_bounds {
        if !b.fits(w, h) {
            return Err(format!("--pixel-bounds {b}: outside the {w} x {h} image"));
        }
    }
    if let Some(c) = args.crop {
        if crop_bounds(c, (w, h)).is_empty() {
            return Err(format!(
                "--crop: no pixel of the {w} x {h} image lies inside"
            ));
        }
    }
    if let Some((_, n)) = tile {
        if n > h {
            return Err(format!(
                "--tile: {n} tiles but the image has {h} rows; a tile is at least one row"
            ));
        }
    }
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
    Ok(Prepared {
        job: Job {
            args,
            desc,
            settings,
            accel,
            format,
            feedback,
            start,
            parse,
            tile,
            frames,
        },
        staged,
    })
}

/// Everything a render needs, in either precision.
struct Job<'a> {
    args: &'a RenderArgs,
    desc: SceneDesc,
    settings: Settings,
    accel: AccelOptions,
    format: ImageFormat,
    feedback: Feedback,
    start: Mark,
    parse: (f64, u64),
    /// Tile index and count (`--tile`).
    tile: Option<(u32, u32)>,
    /// The camera path and the first and last frame (`--script`, `--frame`).
    frames: Option<(Vec<script::Step>, u32, u32)>,
}

/// The camera path and frames `--script` and `--frame` ask for, checked.
fn frames(
    args: &RenderArgs,
    env: impl Fn(&str) -> Option<String>,
) -> Result<Option<(Vec<script::Step>, u32, u32)>, String> {
    let (Some(path), Some(spec)) = (&args.script, args.frame) else {
        return Ok(None);
    };
    let (a, b) = spec.frames(env)?;
    let steps = script::load(path)?;
    if let Some(k) = steps
        .iter()
        .position(|s| matches!(s, script::Step::Set(..)))
    {
        return Err(format!(
            "{}: line {} sets a viewer knob; give render its options instead",
            path.display(),
            k + 1
        ));
    }
    if b as usize >= steps.len() {
        return Err(format!(
            "{}: frame {b} asked for, but the path has frames 0 to {}",
            path.display(),
            steps.len() - 1
        ));
    }
    if a != b && !tiles::has_number(&args.output) {
        return Err(format!(
            "{}: frames {a}-{b} need %04d (or %d) in the output name",
            args.output.display()
        ));
    }
    if a != b && args.stats.as_deref().is_some_and(|p| !tiles::has_number(p)) {
        return Err("--stats with a frame range needs %04d (or %d) in its name".into());
    }
    Ok(Some((steps, a, b)))
}

/// The output and statistics paths of image `number` (a frame or tile; `%d` in the
/// names replaced by it), checked and opened ([`Staged`]).
fn stage(args: &RenderArgs, number: Option<u32>) -> Result<Staged, String> {
    let name = |p: &Path| number.map_or(p.to_path_buf(), |k| tiles::numbered(p, k));
    let mut paths = vec![name(&args.output)];
    paths.extend(args.stats.as_deref().map(name));
    let refs: Vec<&Path> = paths.iter().map(PathBuf::as_path).collect();
    Staged::new(&refs)
}

fn render_in<T: tracer::Float>(job: &Job<'_>, staged: Staged) -> Result<(), String> {
    let desc = &job.desc;
    job.feedback
        .phase("building", &format!("{} primitives", desc.shapes.len()));
    let build_start = Mark::now();
    let mut scene = Scene::<T>::from_desc(desc, &job.accel);
    let build = (build_start.ms(), build_start.cycles());
    let Some((steps, a, b)) = &job.frames else {
        return one(job, &scene, None, build, staged);
    };
    // Frame k: the scene's camera moved by the path's first k + 1 steps.
    let mut cam = FlyCamera::new(&desc.camera);
    let mut knobs = Knobs::default();
    let mut staged = Some(staged);
    for (k, step) in steps.iter().enumerate().take(*b as usize + 1) {
        step.apply(&mut cam, &mut knobs);
        if k >= *a as usize {
            scene.camera = CameraDesc {
                resolution: desc.camera.resolution,
                ..cam.desc()
            };
            let stage_k = match staged.take() {
                Some(s) => s,
                None => stage(job.args, Some(k as u32))?,
            };
            one(job, &scene, Some(k as u32), build, stage_k)?;
        }
    }
    Ok(())
}

/// Renders one image of `scene` (frame `frame` of a path) and writes its outputs.
fn one<T: tracer::Float>(
    job: &Job<'_>,
    scene: &Scene<T>,
    frame: Option<u32>,
    (build_ms, build_cycles): (f64, u64),
    mut staged: Staged,
) -> Result<(), String> {
    let (args, desc, accel) = (job.args, &job.desc, &job.accel);
    let (parse_ms, parse_cycles) = job.parse;
    let (w, h) = job.settings.size(scene.camera.resolution);
    // The split's probe render is work every tile task does before tracing its tile.
    let split_start = Mark::now();
    let region = match (args.pixel_bounds, args.crop, job.tile) {
        (Some(b), _, _) => Some(b),
        (_, Some(c), _) => Some(crop_bounds(c, (w, h))),
        (_, _, Some((i, n))) => Some(tiles::split(scene, &job.settings, n)?[i as usize]),
        _ => None,
    };
    let split_ms = split_start.ms();
    // CPU time before the trace: reading, the build and the split, free of the waits
    // that a loaded machine adds to their wall times.
    let setup_cpu_ms = tracer::stats::process_cpu_ms().unwrap_or(0.0);
    let settings = &Settings {
        region,
        ..job.settings.clone()
    };
    let number = frame.or(job.tile.map(|(i, _)| i));
    let output = number.map_or(args.output.clone(), |k| tiles::numbered(&args.output, k));
    let part = region.map_or(String::new(), |b| format!(" pixels {b}"));
    job.feedback.phase("tracing", &format!("{w}x{h}{part}"));
    let (image, stats) = render_with_progress(scene, settings, &job.feedback);
    job.feedback.phase("writing", &output.display().to_string());
    let header = TileHeader {
        full: (w, h),
        bounds: region.unwrap_or(PixelBounds::full(w, h)),
        digest: digest(&args.scene, settings, scene)?,
        settings: describe(settings, scene),
        tile: job.tile,
        rays: stats.rays,
        times_ms: [parse_ms, build_ms, stats.trace_ms],
    };
    staged.write(0, "image", |out| {
        write_image(&image, job.format, args.srgb, &header, out)
    })?;
    let (total_ms, total_cycles) = (job.start.ms(), job.start.cycles());
    if args.stats.is_some() {
        let g = scene.geometry.stats();
        let c = &scene.camera;
        let report = json!({
            "scene": args.scene.display().to_string(),
            "times_ms": { "parse": parse_ms, "build": build_ms, "split": split_ms, "trace": stats.trace_ms, "setup_cpu": setup_cpu_ms, "trace_cpu": stats.trace_cpu_ms, "total": total_ms },
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
            "region": region,
            "tile": job.tile.map(|(i, n)| format!("{i}/{n}")),
            "frame": frame,
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
                "output": output.display().to_string(),
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
        "{}: {}x{}, {:.2} s, {:.2} Mrays/s",
        output.display(),
        image.width,
        image.height,
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

/// The digest of the scene file and every setting that changes pixels, the camera
/// included: images (tiles) with equal digests belong to one render.
fn digest<T: tracer::Float>(
    scene_file: &Path,
    settings: &Settings,
    scene: &Scene<T>,
) -> Result<String, String> {
    let file = std::fs::read(scene_file)
        .map_err(|e| format!("{}: cannot read file: {e}", scene_file.display()))?;
    let mut d = Digest::default();
    d.add(&file)
        .add(describe(settings, scene).as_bytes())
        .add(format!("{:?}", scene.camera).as_bytes());
    Ok(d.hex())
}

/// The settings that change pixels, in words.
fn describe<T: tracer::Float>(settings: &Settings, scene: &Scene<T>) -> String {
    let (w, h) = settings.size(scene.camera.resolution);
    let limits = settings.limits::<T>();
    format!(
        "{w}x{h} aa {} depth {} threshold {} spd {} precision {}",
        if settings.spd { 1 } else { settings.aa },
        limits.max_depth,
        if settings.spd {
            0.0
        } else {
            settings.threshold
        },
        settings.spd,
        if std::mem::size_of::<T>() == 4 {
            "f32"
        } else {
            "f64"
        },
    )
}

/// Encodes `image` in `format` into `out` (sRGB-encoded if `srgb`, for PNG; OpenEXR
/// with its place in the full image and `header`'s attributes, [`tiles::write_exr`]).
pub fn write_image(
    image: &Image,
    format: ImageFormat,
    srgb: bool,
    header: &TileHeader,
    out: &mut BufWriter<File>,
) -> io::Result<()> {
    match format {
        ImageFormat::Png if srgb => image.write_png_as(out, PngEncoding::Srgb),
        ImageFormat::Png => image.write_png_as(out, PngEncoding::Linear),
        ImageFormat::Pfm => image.write_pfm(out),
        ImageFormat::Exr => tiles::write_exr(out, image, header),
    }
}
