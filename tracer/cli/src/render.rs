//! `tracer render SCENE -o OUT`: one image (PNG, PFM or OpenEXR), optionally with
//! statistics as JSON; or part of one (`--pixel-bounds`, `--crop`, `--tile` for
//! [`crate::merge`]), or frames of a camera path (`--script`, `--frame`).

use crate::args::{load_scene, parse_threshold, CameraArgs, PacketArgs, Precision, ScheduleArgs};
use crate::progress::Bar;
use crate::tiles::{self, Digest, TileHeader, TileSpec};
use crate::viewer::{camera::FlyCamera, knobs::Knobs, script};
use serde_json::json;
use std::path::{Path, PathBuf};
use tracer::effects::EffectsMode;
use tracer::geometry::AccelOptions;
use tracer::render::{render_with_progress, PixelBounds, Settings};
use tracer::scene::desc::CameraDesc;
use tracer::scene::desc::SceneDesc;
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

/// Runs `tracer render`.
///
/// # Errors
/// One line `FILE:LINE: message` or `FILE: message` for bad input or a failed write; no
/// output file is left behind.
pub fn run(args: &RenderArgs) -> Result<(), String> {
    let start = Mark::now();
    let out_ext = ext(&args.output);
    if !matches!(out_ext.as_deref(), Some("png" | "pfm" | "exr")) {
        return Err(format!(
            "{}: output must end in .png, .pfm or .exr",
            args.output.display()
        ));
    }
    if args.tile.is_some() && out_ext.as_deref() != Some("exr") {
        return Err(format!(
            "{}: a tile is written as OpenEXR (.exr), which records where it lies",
            args.output.display()
        ));
    }
    let env = |v: &str| std::env::var(v).ok();
    let tile = args.tile.map(|t| t.resolve(env)).transpose()?;
    let frames = match (&args.script, args.frame) {
        (Some(path), Some(spec)) => {
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
            Some((steps, a, b))
        }
        _ => None,
    };
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
    let (w, h) = settings.size(desc.camera.resolution);
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
    let accel = AccelOptions {
        use_bvh: !args.no_bvh,
        wide: !args.binary_bvh,
        ..AccelOptions::default()
    };
    let job = Job {
        args,
        desc: &desc,
        settings,
        accel,
        start,
        parse,
        tile,
        frames,
    };
    match args.precision {
        Precision::F32 => job.run::<f32>(),
        Precision::F64 => job.run::<f64>(),
    }
}

fn ext(path: &Path) -> Option<String> {
    path.extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
}

/// One `tracer render` after its checks: the scene read, the settings and what to
/// render (a tile, frames).
struct Job<'a> {
    args: &'a RenderArgs,
    desc: &'a SceneDesc,
    settings: Settings,
    accel: AccelOptions,
    start: Mark,
    parse: (f64, u64),
    tile: Option<(u32, u32)>,
    frames: Option<(Vec<script::Step>, u32, u32)>,
}

impl Job<'_> {
    fn run<T: tracer::Float>(&self) -> Result<(), String> {
        let build_start = Mark::now();
        let mut scene = Scene::<T>::from_desc(self.desc, &self.accel);
        let build = (build_start.ms(), build_start.cycles());
        let Some((steps, a, b)) = &self.frames else {
            return self.one(&scene, None, build);
        };
        // The camera of frame k: the path's first k + 1 steps from the scene's camera.
        let mut cam = FlyCamera::new(&self.desc.camera);
        let mut knobs = Knobs::default();
        for (k, step) in steps.iter().enumerate().take(*b as usize + 1) {
            step.apply(&mut cam, &mut knobs);
            if k >= *a as usize {
                scene.camera = CameraDesc {
                    resolution: self.desc.camera.resolution,
                    ..cam.desc()
                };
                self.one(&scene, Some(k as u32), build)?;
            }
        }
        Ok(())
    }

    /// Renders one image of `scene` (frame `frame` of a path) and writes it.
    fn one<T: tracer::Float>(
        &self,
        scene: &Scene<T>,
        frame: Option<u32>,
        (build_ms, build_cycles): (f64, u64),
    ) -> Result<(), String> {
        let args = self.args;
        let (w, h) = self.settings.size(scene.camera.resolution);
        let region = match (args.pixel_bounds, args.crop, self.tile) {
            (Some(b), _, _) => Some(b),
            (_, Some(c), _) => Some(crop_bounds(c, (w, h))),
            (_, _, Some((i, n))) => Some(tiles::split(scene, &self.settings, n)?[i as usize]),
            _ => None,
        };
        let settings = Settings {
            region,
            ..self.settings.clone()
        };
        let number = frame.or(self.tile.map(|(i, _)| i));
        let output = number.map_or(args.output.clone(), |k| tiles::numbered(&args.output, k));
        let stats_path = args
            .stats
            .as_ref()
            .map(|p| number.map_or(p.clone(), |k| tiles::numbered(p, k)));
        let (image, stats) = render_with_progress(scene, &settings, &Bar::stderr());
        let (parse_ms, parse_cycles) = self.parse;
        if ext(&output).as_deref() == Some("exr") {
            let header = TileHeader {
                full: (w, h),
                bounds: region.unwrap_or(PixelBounds::full(w, h)),
                digest: self.digest(scene, &settings)?,
                settings: describe::<T>(&settings, scene),
                tile: self.tile,
                rays: stats.rays,
                times_ms: [parse_ms, build_ms, stats.trace_ms],
            };
            tiles::write_exr(&output, &image, &header)?;
        } else {
            image
                .save(&output)
                .map_err(|e| format!("{}: cannot write image: {e}", output.display()))?;
        }
        let (total_ms, total_cycles) = (self.start.ms(), self.start.cycles());
        if let Some(path) = &stats_path {
            let g = scene.geometry.stats();
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
                    "total": self.desc.shapes.len(),
                },
                "bvh": { "nodes": g.bvh_nodes, "depth": g.bvh_depth, "bytes": g.bvh_bytes, "build_ms": g.build_ms },
                "image": { "width": w, "height": h },
                "region": region,
                "tile": self.tile.map(|(i, n)| format!("{i}/{n}")),
                "frame": frame,
                "settings": {
                    "width": w, "height": h, "aa": if settings.spd { 1 } else { settings.aa },
                    "depth": settings.limits::<T>().max_depth,
                    "threshold": if settings.spd { 0.0 } else { settings.threshold },
                    "threads": settings.threads.unwrap_or_else(rayon::current_num_threads),
                    "precision": if std::mem::size_of::<T>() == 4 { "f32" } else { "f64" },
                    "spd": settings.spd, "bvh": self.accel.use_bvh, "effects": settings.effects.name(),
                    "packets": settings.packets.name(),
                    "output": output.display().to_string(),
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

    /// The digest of the scene file and every setting that changes pixels: tiles with
    /// equal digests belong to one image.
    fn digest<T: tracer::Float>(
        &self,
        scene: &Scene<T>,
        settings: &Settings,
    ) -> Result<String, String> {
        let file = std::fs::read(&self.args.scene)
            .map_err(|e| format!("{}: cannot read file: {e}", self.args.scene.display()))?;
        let mut d = Digest::default();
        d.add(&file)
            .add(describe::<T>(settings, scene).as_bytes())
            .add(format!("{:?}", scene.camera).as_bytes());
        Ok(d.hex())
    }
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

fn write_json(path: &Path, value: &serde_json::Value) -> Result<(), String> {
    let text = serde_json::to_string_pretty(value).map_err(|e| e.to_string())?;
    tracer::image::write_atomic(path, |w| {
        use std::io::Write;
        w.write_all(text.as_bytes())?;
        w.write_all(b"\n")
    })
    .map_err(|e| format!("{}: cannot write stats: {e}", path.display()))
}
