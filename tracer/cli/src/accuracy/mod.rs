//! `tracer accuracy`: how much image quality each millisecond of render time buys.
//!
//! For a scene, [`measure`] renders a high-accuracy reference (by default `f64`, depth
//! 10, 8x8 rays per pixel, exact arithmetic) and then, one knob at a time with every
//! other knob at its reference value, each cheaper setting:
//!
//! - precision: `f32` against the `f64` reference;
//! - recursion: fixed depths `1 ..= 9`, and adaptive thresholds `1e-1 ..= 1e-4` (with the
//!   reference's depth as the cap);
//! - arithmetic: each approximation of [`Arith`](tracer::arith::Arith) alone and all together, in `f32` and in
//!   `f64`;
//! - antialiasing: an `a` x `a` grid for `a = 1 ..= 4` (and the reference's 8), compared
//!   with a finer 16x16 render instead.
//!
//! Every setting is rendered `runs` times, interleaved (run 1 of every setting, then run
//! 2, ..., each run starting at a different setting) so that load on the machine affects
//! all settings alike, and timed by its trace
//! time (scene parsing and BVH build excluded); the median is reported. Images are
//! deterministic, so the error of a setting is that of any of its runs.
//!
//! Errors ([`Metrics`]) are computed on the displayed values, each channel clamped to
//! [0, 1] as the PNG output does: RMSE over all channels, PSNR with peak 1, the largest
//! absolute channel difference, and the share of pixels where some channel differs by
//! more than 1/255 (one 8-bit step).
//!
//! [`write_report`] writes per scene a Markdown table with findings, the same table as
//! CSV, an SVG plot of error against time with the Pareto front marked, and the reference
//! image, and for all scenes a summary table (Markdown and CSV).
//!
//! The pieces: [`experiment`] (the settings and their timed renders), [`metrics`] (image
//! error, Pareto front), [`report`] (tables, findings, files) and [`plot`] (the SVG).

pub mod experiment;
pub mod metrics;
pub mod plot;
pub mod report;

pub use experiment::{measure, Case, Clock, Config, Knob, Options, Row, SceneReport};
pub use metrics::{compare, pareto, Metrics};
pub use report::{scene_name, summary, write_report};

use crate::args::{load_scene, whole};
use crate::Precision;
use std::path::PathBuf;

/// Arguments of `tracer accuracy`.
#[derive(clap::Args, Debug, Clone)]
pub struct AccuracyArgs {
    /// Scene files (.nff, .nff.gz, .obj); each gets its own table and plot.
    #[arg(required = true)]
    pub scenes: Vec<PathBuf>,
    /// Report directory (created if missing).
    #[arg(short, long, default_value = "accuracy-report")]
    pub output: PathBuf,
    /// Image width in pixels.
    #[arg(long, default_value_t = 64, value_parser = whole(1, 4096), allow_negative_numbers = true)]
    pub width: u32,
    /// Image height (default: keep the scene's aspect ratio).
    #[arg(long, value_parser = whole(1, 4096), allow_negative_numbers = true)]
    pub height: Option<u32>,
    /// Timed runs per setting; the median is reported.
    #[arg(long, default_value_t = 3, value_parser = whole(1, 100), allow_negative_numbers = true)]
    pub runs: u32,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = whole(1, 1024), allow_negative_numbers = true)]
    pub threads: Option<u32>,
    /// Depth of the reference; depths 1 to this minus one are measured.
    #[arg(long, default_value_t = 10, value_parser = whole(1, 64), allow_negative_numbers = true)]
    pub ref_depth: u32,
    /// Rays per pixel of the reference, as an A x A grid.
    #[arg(long, default_value_t = 8, value_parser = whole(1, 64), allow_negative_numbers = true)]
    pub ref_aa: u32,
    /// Grid of the fine reference for the antialiasing knob.
    #[arg(long, default_value_t = 16, value_parser = whole(1, 64), allow_negative_numbers = true)]
    pub fine_aa: u32,
    /// Largest antialiasing grid measured (1 to this).
    #[arg(long, default_value_t = 4, value_parser = whole(1, 64), allow_negative_numbers = true)]
    pub max_aa: u32,
    /// Time settings by process CPU time (robust on a shared machine) or wall clock.
    #[arg(long, value_enum, default_value_t = Clock::Cpu)]
    pub clock: Clock,
}

impl AccuracyArgs {
    /// The measurement options these arguments give.
    pub fn options(&self) -> Options {
        Options {
            width: self.width,
            height: self.height,
            runs: self.runs as usize,
            threads: self.threads.map(|t| t as usize),
            ref_depth: self.ref_depth,
            ref_aa: self.ref_aa,
            fine_aa: self.fine_aa,
            max_aa: self.max_aa,
            clock: self.clock,
            ..Options::default()
        }
    }
}

/// A scene of `tracer accuracy`: its name in the report, its path, and its description.
pub type NamedScene = (String, String, tracer::scene::desc::SceneDesc);

/// Every check of `tracer accuracy` before the first render: the options, every scene
/// read, no two scenes with one report name, and a report path that is not a file.
///
/// # Errors
/// One line naming the file or option.
pub fn prepare(args: &AccuracyArgs) -> Result<(Options, Vec<NamedScene>), String> {
    let options = args.options();
    options.check()?;
    let mut scenes: Vec<NamedScene> = Vec::new();
    for path in &args.scenes {
        // Strict for f32: the experiments render in both precisions.
        let desc = load_scene(path, &Default::default(), Precision::F32)?;
        let name = scene_name(path);
        if scenes.iter().any(|(n, _, _)| *n == name) {
            return Err(format!(
                "{}: two scenes named `{name}` would write the same report files",
                path.display()
            ));
        }
        scenes.push((name, path.display().to_string(), desc));
    }
    if args.output.exists() && !args.output.is_dir() {
        return Err(format!(
            "{}: the report directory is a file",
            args.output.display()
        ));
    }
    Ok((options, scenes))
}

/// Runs `tracer accuracy`: loads every scene first (so bad input fails before any
/// rendering, [`prepare`]), measures each, and writes the report. Errors are one line.
pub fn run(args: &AccuracyArgs) -> Result<(), String> {
    let (options, scenes) = prepare(args)?;
    std::fs::create_dir_all(&args.output).map_err(|e| {
        format!(
            "{}: cannot create the report directory: {e}",
            args.output.display()
        )
    })?;
    let mut reports = Vec::new();
    for (name, path, desc) in &scenes {
        reports.push(measure(name, path, desc, &options, |line| {
            eprintln!("{line}")
        })?);
    }
    write_report(&args.output, &reports)
}
