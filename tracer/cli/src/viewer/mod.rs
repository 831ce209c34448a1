//! The real-time viewer, `tracer view SCENE`: a window that renders continuously with the
//! tracer's own renderer, a camera to fly, and live knobs to see what accuracy costs.
//!
//! # Pieces
//! - [`engine`]: progressive rendering without a window. While the camera is still it
//!   adds one supersample per pixel per frame ([`tracer::render::accumulate_pass`]) until
//!   the `aa` x `aa` grid is complete, when the image equals `tracer render --aa A` bit
//!   for bit; any change of camera or knob restarts at one sample per pixel.
//! - [`camera`]: the moving camera, along the tracer's $C_d$, $C_l$, $C_u$.
//! - [`knobs`]: the table of live knobs (antialiasing, depth, threshold, precision,
//!   threads, effect set). Pending, to be added as one table entry when the renderer has
//!   it: the instruction set (ISA).
//! - [`script`]: camera paths for scripted runs and the headless test.
//! - `window` (private): the window, input and presentation.
//!
//! # Windowing
//! winit 0.30 for the window and events, softbuffer 0.4 to show a CPU framebuffer, both
//! built for X11 only. Both are pure Rust and load the X11 client libraries with `dlopen`
//! at run time, so they build on a machine with no system packages beyond the toolchain.
//! The lighter minifb (7 crates to build against 49, about 12 s of CPU against 80 s for a
//! clean release build) was the other candidate, but it can only poll for input: its loop
//! wakes up at a fixed rate even when nothing happens. winit blocks until an event
//! arrives, and the rendering thread wakes it through an event loop proxy when a frame is
//! ready, so an idle viewer (still camera, converged image) uses no
//! CPU at all. X11 only keeps the build small; Wayland desktops run it through Xwayland.
//!
//! # Controls
//! W/S move along $C_d$, A/D strafe along $C_l$, E/Q rise and fall along $C_u$ (Shift:
//! four times faster); arrow keys or dragging with the left mouse button look around;
//! the mouse wheel or `+`/`-` zoom the angle of view; R resets to the scene's camera.
//! Tab and Shift+Tab select a knob, `[` and `]` step it. P writes a screenshot (PNG),
//! H prints this help, Escape closes the window. The title shows the last frame's time,
//! frames per second, Mrays/s, samples per pixel so far and every knob.

pub mod camera;
pub mod engine;
pub mod knobs;
pub mod script;
mod window;

use crate::args::{image_size, load_scene_with_camera, parse_threshold, whole, CameraArgs};
use crate::Precision;
use camera::FlyCamera;
use engine::{Engine, PassStats};
use knobs::Knobs;
use std::path::{Path, PathBuf};
use tracer::effects::EffectsMode;
use tracer::geometry::AccelOptions;
use tracer::stats::median;

/// Options of `tracer view`.
#[derive(clap::Args, Debug, Clone)]
pub struct ViewArgs {
    /// Scene file: NFF (.nff, .nff.gz) or Wavefront OBJ (.obj).
    pub scene: PathBuf,
    /// Image width (default: the scene's resolution); given alone, the height follows the
    /// scene's aspect ratio (rounded).
    #[arg(long, value_parser = whole(1, 8192), allow_negative_numbers = true)]
    pub width: Option<u32>,
    /// Image height (default: the scene's resolution); given alone, the width follows the
    /// scene's aspect ratio (rounded).
    #[arg(long, value_parser = whole(1, 8192), allow_negative_numbers = true)]
    pub height: Option<u32>,
    /// Antialiasing: a still image converges to an AA x AA grid of rays per pixel
    /// (default 4; --frames renders one sample per pixel, so only 1 is taken with it).
    #[arg(long, value_parser = whole(1, knobs::MAX_AA), allow_negative_numbers = true)]
    pub aa: Option<u32>,
    /// Maximum ray depth (1 = eye rays only).
    #[arg(long, default_value_t = 5, value_parser = whole(1, knobs::MAX_DEPTH), allow_negative_numbers = true)]
    pub depth: u32,
    /// Adaptive termination: skip secondary rays whose weight is below T (0 = off).
    #[arg(long, default_value_t = 0.0, value_parser = parse_threshold, allow_negative_numbers = true)]
    pub threshold: f64,
    /// Rendering threads (default: all cores).
    #[arg(long, value_parser = whole(1, knobs::MAX_THREADS as u32), allow_negative_numbers = true)]
    pub threads: Option<u32>,
    /// Arithmetic precision of the whole tracer.
    #[arg(long, value_enum, default_value_t = Precision::F32)]
    pub precision: Precision,
    /// Renderer: compiled for the scene's effects (auto) or the general one (all).
    #[arg(long, value_enum, default_value_t = EffectsMode::Auto)]
    pub effects: EffectsMode,
    /// Trace without the BVH (brute force).
    #[arg(long)]
    pub no_bvh: bool,
    /// The camera: frames an OBJ scene, overrides an NFF scene's.
    #[command(flatten)]
    pub camera: CameraArgs,
    /// Play a camera path (one command a line, one frame each), let the last view
    /// converge, write --screenshot if given, and exit.
    #[arg(long, value_name = "FILE")]
    pub script: Option<PathBuf>,
    /// Benchmark: render N frames at one sample per pixel, each from a new camera
    /// position, print the median frame time, and exit.
    #[arg(long, value_name = "N", value_parser = whole(1, 100000), allow_negative_numbers = true)]
    pub frames: Option<u32>,
    /// PNG written at the end of --script or --frames, and by the screenshot key.
    #[arg(long, value_name = "OUT.png")]
    pub screenshot: Option<PathBuf>,
    /// Run --script or --frames without opening a window.
    #[arg(long)]
    pub no_window: bool,
}

impl ViewArgs {
    /// The knobs the viewer starts with.
    pub fn knobs(&self) -> Knobs {
        Knobs {
            aa: self.aa.unwrap_or(Knobs::default().aa),
            depth: self.depth,
            threshold: self.threshold,
            precision: self.precision,
            threads: self
                .threads
                .map_or_else(|| Knobs::default().threads, |t| t as usize),
            effects: self.effects,
        }
    }
}

/// What a run needs besides the window: the engine, the camera and the mode.
pub(crate) struct Setup {
    pub engine: Engine,
    pub camera: FlyCamera,
    pub script: Option<Vec<script::Step>>,
    pub frames: Option<u32>,
    pub screenshot: Option<PathBuf>,
    pub scene_name: String,
}

/// Runs `tracer view`.
///
/// # Errors
/// One line `FILE:LINE: message` or `FILE: message` for bad input, a failed write or a
/// window that cannot be opened.
pub fn run(args: &ViewArgs) -> Result<(), String> {
    if args.no_window && args.script.is_none() && args.frames.is_none() {
        return Err("--no-window needs --script or --frames".into());
    }
    if let (Some(_), Some(aa @ 2..)) = (args.frames, args.aa) {
        return Err(format!(
            "--aa {aa} has no effect with --frames (benchmark frames are one sample per pixel)"
        ));
    }
    if let Some(p) = &args.screenshot {
        let ext = p
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        if ext.as_deref() != Some("png") {
            return Err(format!("{}: screenshot must end in .png", p.display()));
        }
        // Its directory exists and takes a file (a temporary one, removed at once).
        drop(crate::output::Staged::new(&[p.as_path()])?);
    }
    let script = args.script.as_deref().map(script::load).transpose()?;
    let (desc, warning) = load_scene_with_camera(&args.scene, &args.camera, args.precision)?;
    if let Some(w) = warning {
        eprintln!("{w}");
    }
    let (w, h) = image_size(args.width, args.height, desc.camera.resolution, 8192)
        .map_err(|e| format!("{}: {e}", args.scene.display()))?;
    let accel = AccelOptions {
        use_bvh: !args.no_bvh,
        ..AccelOptions::default()
    };
    let camera = FlyCamera::new(&desc.camera);
    let mut knobs = args.knobs();
    if args.frames.is_some() {
        // Benchmark frames are single passes: a new camera every frame.
        knobs.aa = 1;
    }
    let engine = Engine::new(desc, accel, w, h, knobs)?;
    let setup = Setup {
        engine,
        camera,
        script,
        frames: args.frames,
        screenshot: args.screenshot.clone(),
        scene_name: args
            .scene
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default(),
    };
    if args.no_window {
        headless(setup)
    } else {
        window::run(setup)
    }
}

/// `--no-window`: the script or benchmark without a window.
fn headless(mut s: Setup) -> Result<(), String> {
    let mut knobs = *s.engine.knobs();
    if let Some(frames) = s.frames {
        let mut bench = Bench::new(frames);
        while !bench.done() {
            let cam = bench.camera(&s.camera);
            s.engine.set_view(&cam.desc(), &knobs)?;
            s.engine.restart();
            let t = std::time::Instant::now();
            let stats = s.engine.step();
            let image = s.engine.image();
            let frame: Vec<u32> = image.pixels.iter().map(|&p| engine::pack_rgb(p)).collect();
            std::hint::black_box(&frame);
            bench.record(stats, t.elapsed().as_secs_f64() * 1e3);
        }
        let report = bench.report(&s.scene_name, s.engine.size(), &knobs, "no window");
        println!("{report}");
    } else if let Some(steps) = &s.script {
        for step in steps {
            step.apply(&mut s.camera, &mut knobs);
            s.engine.set_view(&s.camera.desc(), &knobs)?;
            s.engine.step();
        }
        while !s.engine.converged() {
            s.engine.step();
        }
    }
    if let Some(path) = &s.screenshot {
        save_png(&s.engine.image(), path)?;
    }
    Ok(())
}

/// Writes `image` as PNG, atomically.
pub(crate) fn save_png(image: &tracer::Image, path: &Path) -> Result<(), String> {
    image
        .save(path)
        .map_err(|e| format!("{}: cannot write screenshot: {e}", path.display()))
}

/// The `--frames N` benchmark: frame times and rays, then the medians.
pub(crate) struct Bench {
    frames: u32,
    frame_ms: Vec<f64>,
    trace_ms: Vec<f64>,
    rays: tracer::RayCounts,
}

impl Bench {
    pub(crate) fn new(frames: u32) -> Self {
        Self {
            frames,
            frame_ms: Vec::new(),
            trace_ms: Vec::new(),
            rays: tracer::RayCounts::default(),
        }
    }

    pub(crate) fn done(&self) -> bool {
        self.frame_ms.len() >= self.frames as usize
    }

    /// The camera of the next frame: the scene's, strafed right and back by a thousandth
    /// of its viewing distance on every other frame, so each frame starts afresh at one
    /// sample per pixel, as while the user moves, and sees the scene's own view.
    pub(crate) fn camera(&self, home: &FlyCamera) -> FlyCamera {
        let mut c = home.clone();
        if self.frame_ms.len() % 2 == 1 {
            c.translate(0.0, 1e-3 * c.scale(), 0.0);
        }
        c
    }

    /// Records one frame: its pass statistics and the wall time from the start of its
    /// render to the frame being ready (or shown).
    pub(crate) fn record(&mut self, stats: PassStats, frame_ms: f64) {
        self.frame_ms.push(frame_ms);
        self.trace_ms.push(stats.trace_ms);
        self.rays += stats.rays;
    }

    pub(crate) fn report(&self, scene: &str, (w, h): (u32, u32), k: &Knobs, how: &str) -> String {
        let n = self.frame_ms.len().max(1) as u64;
        let med = median(&self.frame_ms);
        let trace = median(&self.trace_ms);
        let r = self.rays;
        format!(
            "{scene}: {w}x{h}, {} frames at 1 sample per pixel ({how}), depth {}, threshold {}, {}, {} threads\n\
             median frame {med:.1} ms ({:.1} fps), median trace {trace:.1} ms, other {:.1} ms; \
             min {:.1} ms, max {:.1} ms\n\
             rays per frame: eye {} reflection {} refraction {} shadow {} total {}; {:.2} Mrays/s at the median trace time",
            self.frame_ms.len(),
            k.depth,
            k.threshold,
            k.precision,
            k.threads,
            1e3 / med.max(1e-9),
            med - trace,
            self.frame_ms.iter().copied().fold(f64::INFINITY, f64::min),
            self.frame_ms.iter().copied().fold(0.0, f64::max),
            r.eye / n,
            r.reflection / n,
            r.refraction / n,
            r.shadow / n,
            r.total() / n,
            r.total() as f64 / n as f64 / (trace.max(1e-9) * 1e3),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn benchmark_frames_alternate_between_two_close_views() {
        let desc = tracer::scene::desc::CameraDesc {
            from: [0.0, -10.0, 0.0],
            at: [0.0, 0.0, 0.0],
            up: [0.0, 0.0, 1.0],
            angle_deg: 45.0,
            hither: 0.0,
            resolution: (8, 8),
        };
        let home = FlyCamera::new(&desc);
        let mut b = Bench::new(3);
        let first = b.camera(&home);
        b.record(PassStats::default(), 1.0);
        let second = b.camera(&home);
        b.record(PassStats::default(), 3.0);
        assert_eq!(first, home);
        assert_ne!(second, home);
        let dx = second.desc().from[0] - desc.from[0];
        assert!((dx - 0.01).abs() < 1e-12, "{dx}");
        assert!(!b.done());
        b.record(PassStats::default(), 2.0);
        assert!(b.done());
        assert_eq!(median(&b.frame_ms), 2.0);
    }
}
