//! `tracer accuracy`: how much image quality each millisecond of render time buys.
//!
//! For a scene, [`measure`] renders a high-accuracy reference (by default `f64`, depth
//! 10, 8x8 rays per pixel, exact arithmetic) and then, one knob at a time with every
//! other knob at its reference value, each cheaper setting:
//!
//! - precision: `f32` against the `f64` reference;
//! - recursion: fixed depths `1 ..= 9`, and adaptive thresholds `1e-1 ..= 1e-4` (with the
//!   reference's depth as the cap);
//! - arithmetic: each approximation of [`Arith`] alone and all together, in `f32` and in
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

use crate::arith::{Arith, HARDWARE_FMA};
use crate::geometry::AccelOptions;
use crate::image::{write_atomic, Image};
use crate::render::{render_with_stats, Settings};
use crate::scene::{self, desc::SceneDesc};
use crate::stats::process_cpu_ms;
use crate::world::Scene;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Arithmetic precision of a render.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Precision {
    /// Single precision.
    F32,
    /// Double precision.
    F64,
}

impl Precision {
    /// `f32` or `f64`.
    pub fn name(self) -> &'static str {
        match self {
            Precision::F32 => "f32",
            Precision::F64 => "f64",
        }
    }
}

/// One combination of the knobs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Config {
    /// Arithmetic precision.
    pub precision: Precision,
    /// Maximum ray depth (eye rays are depth 1).
    pub depth: u32,
    /// Adaptive termination threshold as `f64` bits (0 is off), so configs hash.
    pub threshold_bits: u64,
    /// An `aa` x `aa` grid of rays per pixel.
    pub aa: u32,
    /// Approximate arithmetic.
    pub arith: Arith,
}

impl Config {
    /// The adaptive termination threshold (0: off).
    pub fn threshold(&self) -> f64 {
        f64::from_bits(self.threshold_bits)
    }

    /// This config with another threshold.
    pub fn with_threshold(self, t: f64) -> Self {
        Self {
            threshold_bits: t.to_bits(),
            ..self
        }
    }
}

/// Which knob a row varies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Knob {
    /// The reference itself, re-rendered.
    Reference,
    /// `f32` instead of `f64`.
    Precision,
    /// A fixed maximum depth.
    Depth,
    /// An adaptive contribution threshold.
    Threshold,
    /// Approximate arithmetic.
    Arithmetic,
    /// Rays per pixel (against the fine reference).
    Antialiasing,
}

impl Knob {
    /// Lower-case name used in tables.
    pub fn name(self) -> &'static str {
        match self {
            Knob::Reference => "reference",
            Knob::Precision => "precision",
            Knob::Depth => "depth",
            Knob::Threshold => "threshold",
            Knob::Arithmetic => "arithmetic",
            Knob::Antialiasing => "antialiasing",
        }
    }

    fn colour(self) -> &'static str {
        match self {
            Knob::Reference => "#000000",
            Knob::Precision => "#d62728",
            Knob::Depth => "#1f77b4",
            Knob::Threshold => "#2ca02c",
            Knob::Arithmetic => "#9467bd",
            Knob::Antialiasing => "#ff7f0e",
        }
    }
}

/// What a setting's time is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Clock {
    /// CPU time of the whole process (all threads) during the trace: on a machine shared
    /// with other work it counts only this process's computing, not its waiting.
    Cpu,
    /// Wall-clock trace time.
    Wall,
}

impl Clock {
    /// `cpu` or `wall`.
    pub fn name(self) -> &'static str {
        match self {
            Clock::Cpu => "cpu",
            Clock::Wall => "wall",
        }
    }
}

/// Options of a measurement.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// Image width in pixels.
    pub width: u32,
    /// Image height (`None`: keep the scene's aspect ratio).
    pub height: Option<u32>,
    /// Timed runs per setting (the median is reported).
    pub runs: usize,
    /// Worker threads (`None`: all cores).
    pub threads: Option<usize>,
    /// Reference depth (and the depth cap of the threshold settings).
    pub ref_depth: u32,
    /// Reference antialiasing grid (also used by every non-antialiasing setting).
    pub ref_aa: u32,
    /// Grid of the fine reference that the antialiasing settings are compared with.
    pub fine_aa: u32,
    /// Largest antialiasing grid measured (`1 ..= max_aa`).
    pub max_aa: u32,
    /// Adaptive thresholds measured.
    pub thresholds: Vec<f64>,
    /// The clock that times settings (CPU falls back to wall where unavailable).
    pub clock: Clock,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            width: 64,
            height: None,
            runs: 3,
            threads: None,
            ref_depth: 10,
            ref_aa: 8,
            fine_aa: 16,
            max_aa: 4,
            thresholds: vec![1e-1, 1e-2, 1e-3, 1e-4],
            clock: Clock::Cpu,
        }
    }
}

impl Options {
    /// The reference configuration.
    pub fn reference(&self) -> Config {
        Config {
            precision: Precision::F64,
            depth: self.ref_depth,
            threshold_bits: 0f64.to_bits(),
            aa: self.ref_aa,
            arith: Arith::EXACT,
        }
    }

    /// The configuration of the fine reference for the antialiasing knob.
    pub fn fine_reference(&self) -> Config {
        Config {
            aa: self.fine_aa,
            ..self.reference()
        }
    }

    /// Every measured setting, reference first.
    pub fn cases(&self) -> Vec<Case> {
        let r = self.reference();
        let mut cases = vec![Case::new(Knob::Reference, "reference", r)];
        cases.push(Case::new(
            Knob::Precision,
            "f32",
            Config {
                precision: Precision::F32,
                ..r
            },
        ));
        for d in 1..self.ref_depth {
            cases.push(Case::new(
                Knob::Depth,
                &format!("depth {d}"),
                Config { depth: d, ..r },
            ));
        }
        for &t in &self.thresholds {
            cases.push(Case::new(
                Knob::Threshold,
                &format!("threshold {}", short(t)),
                r.with_threshold(t),
            ));
        }
        let ariths = [
            Arith {
                rsqrt: true,
                ..Arith::EXACT
            },
            Arith {
                int_pow: true,
                ..Arith::EXACT
            },
            Arith {
                fma: true,
                ..Arith::EXACT
            },
            Arith {
                rsqrt: true,
                int_pow: true,
                fma: true,
            },
        ];
        for precision in [Precision::F32, Precision::F64] {
            for arith in ariths {
                cases.push(Case::new(
                    Knob::Arithmetic,
                    &format!("{} {}", precision.name(), arith.label()),
                    Config {
                        precision,
                        arith,
                        ..r
                    },
                ));
            }
        }
        let mut grids: Vec<u32> = (1..=self.max_aa).collect();
        if !grids.contains(&self.ref_aa) && self.ref_aa < self.fine_aa {
            grids.push(self.ref_aa);
        }
        for a in grids {
            cases.push(Case {
                fine: true,
                ..Case::new(
                    Knob::Antialiasing,
                    &format!("aa {a}x{a}"),
                    Config { aa: a, ..r },
                )
            });
        }
        cases
    }

    fn check(&self) -> Result<(), String> {
        let bad = |what: &str| Err(format!("accuracy: {what}"));
        if self.width == 0 || self.height == Some(0) {
            return bad("the image size must be at least 1x1");
        }
        if self.runs == 0 {
            return bad("--runs must be at least 1");
        }
        if self.ref_depth < 1 || self.ref_aa < 1 || self.fine_aa < 1 || self.max_aa < 1 {
            return bad("depths and antialiasing grids must be at least 1");
        }
        if self.thresholds.iter().any(|t| !(*t > 0.0 && *t <= 1.0)) {
            return bad("thresholds must be in (0, 1]");
        }
        Ok(())
    }
}

/// One measured setting.
#[derive(Clone, Debug, PartialEq)]
pub struct Case {
    /// The knob it varies.
    pub knob: Knob,
    /// Its name in tables (`depth 3`, `f32 rsqrt`, ...).
    pub label: String,
    /// The settings rendered.
    pub config: Config,
    /// Compared with the fine reference (antialiasing) instead of the reference.
    pub fine: bool,
}

impl Case {
    fn new(knob: Knob, label: &str, config: Config) -> Self {
        Self {
            knob,
            label: label.to_string(),
            config,
            fine: false,
        }
    }
}

/// The error of an image against a reference, on values clamped to [0, 1].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Metrics {
    /// Root-mean-square error over all channels of all pixels.
    pub rmse: f64,
    /// Peak signal-to-noise ratio in dB, peak 1 ($+\infty$ for identical images).
    pub psnr: f64,
    /// Largest absolute difference of a channel.
    pub max_abs: f64,
    /// Share of pixels (0 to 1) where some channel differs by more than 1/255.
    pub over_1_255: f64,
}

/// Compares `image` with `reference`, channel values clamped to [0, 1].
///
/// # Panics
/// If the sizes differ.
pub fn compare(image: &Image, reference: &Image) -> Metrics {
    assert_eq!(
        (image.width, image.height),
        (reference.width, reference.height),
        "images of different sizes"
    );
    let (mut sq, mut max_abs, mut over) = (0.0f64, 0.0f64, 0usize);
    for (a, b) in image.pixels.iter().zip(&reference.pixels) {
        let mut pixel_max = 0.0f64;
        for c in 0..3 {
            let d = (f64::from(a[c].clamp(0.0, 1.0)) - f64::from(b[c].clamp(0.0, 1.0))).abs();
            sq += d * d;
            pixel_max = pixel_max.max(d);
        }
        max_abs = max_abs.max(pixel_max);
        if pixel_max > 1.0 / 255.0 {
            over += 1;
        }
    }
    let n = image.pixels.len().max(1) as f64;
    let mse = sq / (3.0 * n);
    Metrics {
        rmse: mse.sqrt(),
        psnr: if mse > 0.0 {
            -10.0 * mse.log10()
        } else {
            f64::INFINITY
        },
        max_abs,
        over_1_255: over as f64 / n,
    }
}

/// The points of `(time, error)` on the Pareto front: no other point is at least as fast
/// and at least as accurate while strictly better in one of the two.
pub fn pareto(points: &[(f64, f64)]) -> Vec<bool> {
    points
        .iter()
        .map(|&(t, e)| {
            !points
                .iter()
                .any(|&(t2, e2)| t2 <= t && e2 <= e && (t2 < t || e2 < e))
        })
        .collect()
}

/// A measured setting.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// What was rendered.
    pub case: Case,
    /// Time of each run by the report's clock, in milliseconds.
    pub times_ms: Vec<f64>,
    /// Wall-clock trace time of each run, in milliseconds.
    pub wall_ms: Vec<f64>,
    /// All rays traced in one render.
    pub rays: u64,
    /// Error against the reference (or the fine reference for antialiasing).
    pub metrics: Metrics,
    /// On the Pareto front of error against time (among the rows with the same
    /// reference).
    pub pareto: bool,
}

impl Row {
    /// Median trace time in milliseconds.
    pub fn median_ms(&self) -> f64 {
        median(&self.times_ms)
    }
}

/// The median (mean of the middle two for an even count; 0 for none).
pub fn median(xs: &[f64]) -> f64 {
    let mut v = xs.to_vec();
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => 0.0,
        n if n % 2 == 1 => v[n / 2],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

/// Everything measured for one scene.
#[derive(Clone, Debug)]
pub struct SceneReport {
    /// Scene name (file name without extensions).
    pub name: String,
    /// The scene file.
    pub path: String,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Options used.
    pub options: Options,
    /// The measured settings, in [`Options::cases`] order.
    pub rows: Vec<Row>,
    /// Time of the single render of the fine reference.
    pub fine_ms: f64,
    /// The clock actually used.
    pub clock: Clock,
    /// The reference image.
    pub reference: Image,
}

fn settings(cfg: &Config, w: u32, h: u32, threads: Option<usize>) -> Settings {
    Settings {
        width: Some(w),
        height: Some(h),
        aa: cfg.aa,
        depth: cfg.depth,
        threshold: cfg.threshold(),
        threads,
        arith: cfg.arith,
        ..Settings::default()
    }
}

/// Renders every case of `options` for the scene `desc` and measures time and error.
/// `progress` receives a line of text before each round of runs.
pub fn measure(
    name: &str,
    path: &str,
    desc: &SceneDesc,
    options: &Options,
    mut progress: impl FnMut(&str),
) -> Result<SceneReport, String> {
    options.check()?;
    let accel = AccelOptions::default();
    let s32 = Scene::<f32>::from_desc(desc, &accel);
    let s64 = Scene::<f64>::from_desc(desc, &accel);
    let (sw, sh) = desc.camera.resolution;
    let w = options.width;
    let h = options.height.unwrap_or_else(|| {
        ((f64::from(w) * f64::from(sh.max(1)) / f64::from(sw.max(1))).round() as u32).max(1)
    });
    let clock = match options.clock {
        Clock::Cpu if process_cpu_ms().is_some() => Clock::Cpu,
        _ => Clock::Wall,
    };
    // The image, the rays, the wall trace time and the time by `clock`.
    let render = |cfg: &Config| {
        let s = settings(cfg, w, h, options.threads);
        let cpu0 = process_cpu_ms();
        let (image, stats) = match cfg.precision {
            Precision::F32 => render_with_stats(&s32, &s),
            Precision::F64 => render_with_stats(&s64, &s),
        };
        let t = match (clock, cpu0, process_cpu_ms()) {
            (Clock::Cpu, Some(a), Some(b)) => b - a,
            _ => stats.trace_ms,
        };
        (image, stats, t)
    };

    let cases = options.cases();
    // Distinct configurations, each rendered once per run.
    let mut configs: Vec<Config> = Vec::new();
    let index: Vec<usize> = cases
        .iter()
        .map(|c| match configs.iter().position(|k| *k == c.config) {
            Some(i) => i,
            None => {
                configs.push(c.config);
                configs.len() - 1
            }
        })
        .collect();

    progress(&format!(
        "{name}: fine reference ({0}x{0} rays per pixel, {w}x{h})",
        options.fine_aa
    ));
    let (fine, _, fine_ms) = render(&options.fine_reference());

    let mut times = vec![Vec::with_capacity(options.runs); configs.len()];
    let mut walls = times.clone();
    let mut first: Vec<Option<(Image, u64)>> = vec![None; configs.len()];
    let mut rerendered_reference = None;
    for run in 0..options.runs {
        progress(&format!(
            "{name}: run {}/{} of {} settings",
            run + 1,
            options.runs,
            configs.len()
        ));
        // Each run starts at a different setting, so no setting is always the one
        // after a slow or a fast neighbour.
        let n = configs.len();
        for j in 0..n {
            let i = (j + run * n / options.runs) % n;
            let (image, stats, t) = render(&configs[i]);
            times[i].push(t);
            walls[i].push(stats.trace_ms);
            if first[i].is_none() {
                first[i] = Some((image, stats.rays.total()));
            } else if i == index[0] {
                rerendered_reference = Some(image);
            }
        }
    }
    let images: Vec<(Image, u64)> = first.into_iter().flatten().collect();
    let reference = images[index[0]].0.clone();

    let mut rows: Vec<Row> = cases
        .into_iter()
        .zip(&index)
        .map(|(case, &i)| {
            let (image, rays) = &images[i];
            let metrics = match case.knob {
                // The reference against itself, re-rendered when there was more than
                // one run.
                Knob::Reference => compare(rerendered_reference.as_ref().unwrap_or(image), image),
                _ if case.fine => compare(image, &fine),
                _ => compare(image, &reference),
            };
            Row {
                case,
                times_ms: times[i].clone(),
                wall_ms: walls[i].clone(),
                rays: *rays,
                metrics,
                pareto: false,
            }
        })
        .collect();
    for fine_group in [false, true] {
        let members: Vec<usize> = (0..rows.len())
            .filter(|&i| rows[i].case.fine == fine_group)
            .collect();
        let points: Vec<(f64, f64)> = members
            .iter()
            .map(|&i| (rows[i].median_ms(), rows[i].metrics.rmse))
            .collect();
        for (&i, on) in members.iter().zip(pareto(&points)) {
            rows[i].pareto = on;
        }
    }
    Ok(SceneReport {
        name: name.to_string(),
        path: path.to_string(),
        width: w,
        height: h,
        options: options.clone(),
        rows,
        fine_ms,
        clock,
        reference,
    })
}

/// A number in short form: `0.1`, `0.01`, `1e-3`, `2.5e-4`, `12.5`.
fn short(x: f64) -> String {
    let trim = |s: String| {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    if x.abs() >= 0.01 && x.abs() < 1e5 {
        trim(format!("{x:.4}"))
    } else {
        let e = x.abs().log10().floor();
        let m = x / 10f64.powf(e);
        format!("{}e{e}", trim(format!("{m:.2}")))
    }
}

/// A value with three significant digits.
fn sig3(x: f64) -> String {
    if !x.is_finite() {
        return if x > 0.0 {
            "inf".into()
        } else {
            format!("{x}")
        };
    }
    if x == 0.0 {
        return "0".into();
    }
    let e = x.abs().log10().floor() as i32;
    if (-3..5).contains(&e) {
        let decimals = (2 - e).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        format!("{x:.2e}")
    }
}

impl SceneReport {
    fn row(&self, label: &str) -> Option<&Row> {
        self.rows.iter().find(|r| r.case.label == label)
    }

    fn clock_text(&self) -> &'static str {
        match self.clock {
            Clock::Cpu => "the process's CPU time (all threads) during the trace",
            Clock::Wall => "the wall-clock trace time",
        }
    }

    fn reference_ms(&self) -> f64 {
        self.rows[0].median_ms()
    }

    /// The table as CSV (one header line, one line per setting).
    pub fn to_csv(&self) -> String {
        let mut s = String::from(
            "scene,width,height,knob,setting,precision,depth,threshold,aa,rsqrt,int_pow,fma,\
             against,runs,clock,median_ms,min_ms,max_ms,median_wall_ms,time_vs_reference,rays,rmse,psnr_db,\
             max_abs,share_over_1_255,pareto\n",
        );
        let ref_ms = self.reference_ms();
        for r in &self.rows {
            let c = &r.case.config;
            let min = r.times_ms.iter().copied().fold(f64::INFINITY, f64::min);
            let max = r.times_ms.iter().copied().fold(0.0, f64::max);
            let _ = writeln!(
                s,
                "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{:.3},{:.3},{:.3},{:.3},{:.4},{},{:.6e},{},{:.6e},{:.6},{}",
                self.name,
                self.width,
                self.height,
                r.case.knob.name(),
                r.case.label,
                c.precision.name(),
                c.depth,
                c.threshold(),
                c.aa,
                c.arith.rsqrt,
                c.arith.int_pow,
                c.arith.fma,
                if r.case.fine { "fine" } else { "reference" },
                r.times_ms.len(),
                self.clock.name(),
                r.median_ms(),
                min,
                max,
                median(&r.wall_ms),
                r.median_ms() / ref_ms,
                r.rays,
                r.metrics.rmse,
                if r.metrics.psnr.is_finite() {
                    format!("{:.3}", r.metrics.psnr)
                } else {
                    "inf".into()
                },
                r.metrics.max_abs,
                r.metrics.over_1_255,
                r.pareto
            );
        }
        s
    }

    /// Plain-language findings drawn from the measured numbers.
    pub fn findings(&self) -> Vec<String> {
        let mut out = Vec::new();
        let o = &self.options;
        let pct = |x: f64| format!("{}%", sig3(100.0 * x));
        // Threshold against depth 5.
        if let Some(d5) = self.row("depth 5") {
            let matching: Vec<&Row> = self
                .rows
                .iter()
                .filter(|r| r.case.knob == Knob::Threshold && r.metrics.rmse <= d5.metrics.rmse)
                .collect();
            let best = matching.iter().max_by(|a, b| {
                a.case
                    .config
                    .threshold()
                    .total_cmp(&b.case.config.threshold())
            });
            let mut line = match best {
                Some(t) => format!(
                    "Threshold vs depth 5: the largest threshold at least as accurate as depth 5 \
                     (RMSE {}) is {} (RMSE {}), at {}x the time of depth 5.",
                    sig3(d5.metrics.rmse),
                    short(t.case.config.threshold()),
                    sig3(t.metrics.rmse),
                    sig3(t.median_ms() / d5.median_ms())
                ),
                None => format!(
                    "Threshold vs depth 5: no threshold measured is as accurate as depth 5 \
                     (RMSE {}).",
                    sig3(d5.metrics.rmse)
                ),
            };
            // The next larger threshold: cheaper, less accurate than depth 5.
            let limit = best.map_or(f64::NEG_INFINITY, |b| b.case.config.threshold());
            let coarser = self
                .rows
                .iter()
                .filter(|r| r.case.knob == Knob::Threshold && r.case.config.threshold() > limit)
                .min_by(|a, b| {
                    a.case
                        .config
                        .threshold()
                        .total_cmp(&b.case.config.threshold())
                });
            if let Some(c) = coarser {
                let _ = write!(
                    line,
                    " The next larger, {}, has RMSE {} at {}x the time of depth 5.",
                    short(c.case.config.threshold()),
                    sig3(c.metrics.rmse),
                    sig3(c.median_ms() / d5.median_ms())
                );
            }
            out.push(line);
        }
        if let Some(f32row) = self.row("f32") {
            out.push(format!(
                "Precision: f64 takes {}x the time of f32; f32 differs from the f64 reference \
                 by RMSE {}, at most {}, in {} of the pixels by more than 1/255.",
                sig3(self.reference_ms() / f32row.median_ms()),
                sig3(f32row.metrics.rmse),
                sig3(f32row.metrics.max_abs),
                pct(f32row.metrics.over_1_255)
            ));
        }
        let aa: Vec<&Row> = self
            .rows
            .iter()
            .filter(|r| r.case.knob == Knob::Antialiasing)
            .collect();
        if let Some(a1) = aa.iter().find(|r| r.case.config.aa == 1) {
            let parts: Vec<String> = aa
                .iter()
                .map(|r| {
                    format!(
                        "{0}x{0}: {1}x the time of 1x1, RMSE {2}, {3} of pixels off by more than 1/255",
                        r.case.config.aa,
                        sig3(r.median_ms() / a1.median_ms()),
                        sig3(r.metrics.rmse),
                        pct(r.metrics.over_1_255)
                    )
                })
                .collect();
            out.push(format!(
                "Antialiasing (against {0}x{0}): {1}.",
                o.fine_aa,
                parts.join("; ")
            ));
        }
        for p in [Precision::F32, Precision::F64] {
            let exact = self.rows.iter().find(|r| {
                r.case.config
                    == Config {
                        precision: p,
                        ..o.reference()
                    }
            });
            let Some(exact) = exact else { continue };
            let parts: Vec<String> = self
                .rows
                .iter()
                .filter(|r| r.case.knob == Knob::Arithmetic && r.case.config.precision == p)
                .map(|r| {
                    format!(
                        "{}: {}x the time, RMSE {} (exact {}: {}), {} of pixels off by more than 1/255",
                        r.case.config.arith.label(),
                        sig3(r.median_ms() / exact.median_ms()),
                        sig3(r.metrics.rmse),
                        p.name(),
                        sig3(exact.metrics.rmse),
                        pct(r.metrics.over_1_255)
                    )
                })
                .collect();
            if !parts.is_empty() {
                out.push(format!(
                    "Approximations in {} (time against exact {}): {}.",
                    p.name(),
                    p.name(),
                    parts.join("; ")
                ));
            }
        }
        out
    }

    /// The table and findings as Markdown.
    pub fn to_markdown(&self) -> String {
        let o = &self.options;
        let mut s = String::new();
        let _ = writeln!(s, "# Accuracy against time: {}\n", self.name);
        let _ = writeln!(
            s,
            "Scene `{}`, {}x{} pixels, {} timed runs per setting (interleaved), threads: {}. \
             Times are medians of {}. Reference: f64, depth {}, {}x{} rays per pixel, \
             exact arithmetic ({} ms). Antialiasing rows are compared with a {}x{} render \
             instead ({} ms, one run). Every other row changes one knob of the reference. \
             Hardware FMA in this build: {}.\n",
            self.path,
            self.width,
            self.height,
            o.runs,
            o.threads
                .map_or_else(|| "all cores".to_string(), |t| t.to_string()),
            self.clock_text(),
            o.ref_depth,
            o.ref_aa,
            o.ref_aa,
            sig3(self.reference_ms()),
            o.fine_aa,
            o.fine_aa,
            sig3(self.fine_ms),
            if HARDWARE_FMA {
                "yes"
            } else {
                "no (mul_add is a library call)"
            }
        );
        let _ = writeln!(s, "## Findings\n");
        for f in self.findings() {
            let _ = writeln!(s, "- {f}");
        }
        let _ = writeln!(
            s,
            "\n## Table\n\n`ms`: median {} time; `wall ms`: median wall-clock trace time; \
             `time`: `ms` relative to the reference; \
             `>1/255` the share of pixels with a channel off by more than one 8-bit step; \
             `spread`: (slowest - fastest run) / median; \
             `front`: on the Pareto front of RMSE against time (antialiasing rows among \
             themselves).\n",
            self.clock.name()
        );
        let _ = writeln!(
            s,
            "| knob | setting | ms | spread | wall ms | time | rays | RMSE | PSNR dB | max abs | >1/255 | front |"
        );
        let _ = writeln!(
            s,
            "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|:---:|"
        );
        let ref_ms = self.reference_ms();
        for r in &self.rows {
            let m = &r.metrics;
            let lo = r.times_ms.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = r.times_ms.iter().copied().fold(0.0, f64::max);
            let _ = writeln!(
                s,
                "| {} | {} | {} | {}% | {} | {} | {} | {} | {} | {} | {}% | {} |",
                r.case.knob.name(),
                r.case.label,
                sig3(r.median_ms()),
                sig3(100.0 * (hi - lo) / r.median_ms()),
                sig3(median(&r.wall_ms)),
                sig3(r.median_ms() / ref_ms),
                r.rays,
                sig3(m.rmse),
                sig3(m.psnr),
                sig3(m.max_abs),
                sig3(100.0 * m.over_1_255),
                if r.pareto { "●" } else { "" }
            );
        }
        s
    }

    /// Error (RMSE, log scale) against median time (log scale) as SVG: the one-knob
    /// settings against the reference on the left, antialiasing against the fine
    /// reference on the right, the Pareto front as a dashed staircase.
    pub fn to_svg(&self) -> String {
        let (pw, ph) = (460.0, 400.0);
        let mut s = String::new();
        let _ = writeln!(
            s,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" \
             font-family=\"sans-serif\" font-size=\"11\">",
            2.0 * pw,
            ph + 30.0
        );
        let _ = writeln!(
            s,
            "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n<text x=\"{}\" y=\"18\" \
             text-anchor=\"middle\" font-size=\"14\">{}: RMSE against median {} time \
             ({}x{} px)</text>",
            pw,
            xml(&self.name),
            self.clock.name(),
            self.width,
            self.height
        );
        for (k, fine) in [false, true].into_iter().enumerate() {
            let rows: Vec<&Row> = self.rows.iter().filter(|r| r.case.fine == fine).collect();
            let title = if fine {
                format!("antialiasing vs {0}x{0} reference", self.options.fine_aa)
            } else {
                format!(
                    "one knob changed vs reference (f64, depth {}, {}x{})",
                    self.options.ref_depth, self.options.ref_aa, self.options.ref_aa
                )
            };
            let axis = format!("median {} time, ms (log)", self.clock.name());
            plot_panel(&mut s, (k as f64 * pw, 30.0, pw, ph), &title, &axis, &rows);
        }
        s.push_str("</svg>\n");
        s
    }
}

fn xml(t: &str) -> String {
    t.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Log-scale ticks covering `[lo, hi]`: 1, 2, 5 times powers of ten.
fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let ticks = |ms: &[f64]| {
        let mut t = Vec::new();
        let mut e = lo.log10().floor() as i32 - 1;
        while 10f64.powi(e) <= hi * 1.0001 {
            for m in ms {
                let v = m * 10f64.powi(e);
                if v >= lo * 0.9999 && v <= hi * 1.0001 {
                    t.push(v);
                }
            }
            e += 1;
        }
        t
    };
    let t = ticks(&[1.0, 2.0, 5.0]);
    if t.len() >= 4 {
        t
    } else {
        ticks(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0])
    }
}

fn plot_panel(s: &mut String, frame: (f64, f64, f64, f64), title: &str, axis: &str, rows: &[&Row]) {
    let (x0, y0, w, h) = frame;
    let (ml, mr, mt, mb) = (62.0, 14.0, 24.0, 40.0);
    let (left, right, top, bottom) = (x0 + ml, x0 + w - mr, y0 + mt, y0 + h - mb);
    let _ = writeln!(
        s,
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\" font-size=\"12\">{}</text>",
        (left + right) / 2.0,
        y0 + 14.0,
        xml(title)
    );
    let _ = writeln!(
        s,
        "<rect x=\"{left}\" y=\"{top}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#444\"/>",
        right - left,
        bottom - top
    );
    if rows.is_empty() {
        return;
    }
    let times: Vec<f64> = rows.iter().map(|r| r.median_ms().max(1e-6)).collect();
    let errs: Vec<f64> = rows.iter().map(|r| r.metrics.rmse).collect();
    let (tmin, tmax) = times
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &t| (a.min(t), b.max(t)));
    let (tlo, thi) = (tmin / 1.25, tmax * 1.25);
    let pos: Vec<f64> = errs.iter().copied().filter(|&e| e > 0.0).collect();
    let emin = pos.iter().copied().fold(f64::INFINITY, f64::min);
    let emax = pos.iter().copied().fold(0.0f64, f64::max);
    let (elo, ehi) = if pos.is_empty() {
        (1e-6, 1.0)
    } else if emax / emin < 10.0 {
        let mid = (emin * emax).sqrt();
        (mid / 10.0, mid * 30.0)
    } else {
        // Room above the highest point for the legend.
        (emin / 2.0, emax * 8.0)
    };
    let fx = |t: f64| left + (t / tlo).log10() / (thi / tlo).log10() * (right - left);
    let fy = |e: f64| {
        if e <= 0.0 {
            bottom
        } else {
            bottom - (e / elo).log10() / (ehi / elo).log10() * (bottom - top)
        }
    };
    for t in log_ticks(tlo, thi) {
        let x = fx(t);
        let _ = writeln!(
            s,
            "<line x1=\"{x:.1}\" y1=\"{top}\" x2=\"{x:.1}\" y2=\"{bottom}\" stroke=\"#ddd\"/>\
             <text x=\"{x:.1}\" y=\"{}\" text-anchor=\"middle\">{}</text>",
            bottom + 13.0,
            short(t)
        );
    }
    for e in log_ticks(elo, ehi) {
        let y = fy(e);
        let _ = writeln!(
            s,
            "<line x1=\"{left}\" y1=\"{y:.1}\" x2=\"{right}\" y2=\"{y:.1}\" stroke=\"#ddd\"/>\
             <text x=\"{}\" y=\"{:.1}\" text-anchor=\"end\">{}</text>",
            left - 4.0,
            y + 4.0,
            short(e)
        );
    }
    let _ = writeln!(
        s,
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\
         <text x=\"{}\" y=\"{}\" text-anchor=\"middle\" transform=\"rotate(-90 {} {})\">RMSE (log; 0 on the axis)</text>",
        (left + right) / 2.0,
        bottom + 30.0,
        xml(axis),
        x0 + 14.0,
        (top + bottom) / 2.0,
        x0 + 14.0,
        (top + bottom) / 2.0
    );
    // Pareto staircase through the front, fastest first.
    let mut front: Vec<(f64, f64)> = rows
        .iter()
        .zip(times.iter().zip(&errs))
        .filter(|(r, _)| r.pareto)
        .map(|(_, (&t, &e))| (t, e))
        .collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    if !front.is_empty() {
        let mut d = format!("M{:.1},{:.1}", fx(front[0].0), fy(front[0].1));
        for w2 in front.windows(2) {
            let _ = write!(d, " H{:.1} V{:.1}", fx(w2[1].0), fy(w2[1].1));
        }
        let _ = writeln!(
            s,
            "<path d=\"{d}\" fill=\"none\" stroke=\"#000\" stroke-dasharray=\"5,3\"/>"
        );
    }
    for (r, (&t, &e)) in rows.iter().zip(times.iter().zip(&errs)) {
        let (x, y) = (fx(t), fy(e));
        let colour = r.case.knob.colour();
        if r.pareto {
            let _ = writeln!(
                s,
                "<circle cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"6\" fill=\"none\" stroke=\"#000\"/>"
            );
        }
        let _ = writeln!(
            s,
            "<circle cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"3.2\" fill=\"{colour}\"><title>{}: {} ms, RMSE {}</title></circle>\
             <text x=\"{:.1}\" y=\"{:.1}\" font-size=\"8\" fill=\"{colour}\">{}</text>",
            xml(&r.case.label),
            sig3(t),
            sig3(e),
            x + 5.0,
            y - 4.0,
            xml(&r.case.label)
        );
    }
    // Legend.
    let mut knobs: Vec<Knob> = Vec::new();
    for r in rows {
        if !knobs.contains(&r.case.knob) {
            knobs.push(r.case.knob);
        }
    }
    for (i, k) in knobs.iter().enumerate() {
        let y = top + 12.0 + 13.0 * i as f64;
        let _ = writeln!(
            s,
            "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"3.2\" fill=\"{}\"/><text x=\"{:.1}\" y=\"{:.1}\">{}</text>",
            right - 90.0,
            y - 3.5,
            k.colour(),
            right - 83.0,
            y,
            k.name()
        );
    }
    let y = top + 12.0 + 13.0 * knobs.len() as f64;
    let _ = writeln!(
        s,
        "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"6\" fill=\"none\" stroke=\"#000\"/><text x=\"{:.1}\" y=\"{:.1}\">Pareto front</text>",
        right - 90.0,
        y - 3.5,
        right - 83.0,
        y
    );
}

/// Summary across scenes as (Markdown, CSV).
pub fn summary(reports: &[SceneReport]) -> (String, String) {
    let mut md = String::from(
        "# Accuracy against time: summary\n\n\
         Times are medians (of the clock each scene's table names) relative to the named \
         baseline; errors are RMSE \
         against the reference (antialiasing: against the fine reference).\n\n\
         | scene | image | reference ms | f64 / f32 time | f32 RMSE | f32 >1/255 | depth 5 RMSE | \
         threshold ≈ depth 5 (time vs depth 5) | aa 1 : 2 : 3 : 4 time | aa 1 → 4 RMSE | \
         f32 rsqrt / int-pow / fma time |\n\
         |---|---|---:|---:|---:|---:|---:|---|---|---|---|\n",
    );
    let mut csv = String::from(
        "scene,width,height,reference_ms,f64_over_f32_time,f32_rmse,f32_share_over_1_255,\
         depth5_rmse,threshold_matching_depth5,threshold_time_vs_depth5,aa_time_vs_aa1,\
         aa_rmse,f32_rsqrt_time,f32_int_pow_time,f32_fma_time\n",
    );
    for r in reports {
        let ref_ms = r.reference_ms();
        let f32row = r.row("f32");
        let f64_over_f32 = f32row.map(|x| ref_ms / x.median_ms());
        let d5 = r.row("depth 5");
        let thr = d5.and_then(|d5| {
            r.rows
                .iter()
                .filter(|x| x.case.knob == Knob::Threshold && x.metrics.rmse <= d5.metrics.rmse)
                .max_by(|a, b| {
                    a.case
                        .config
                        .threshold()
                        .total_cmp(&b.case.config.threshold())
                })
                .map(|t| (t.case.config.threshold(), t.median_ms() / d5.median_ms()))
        });
        let aa: Vec<&Row> = r
            .rows
            .iter()
            .filter(|x| x.case.knob == Knob::Antialiasing && x.case.config.aa <= r.options.max_aa)
            .collect();
        let aa1 = aa.first().map_or(1.0, |x| x.median_ms());
        let aa_time: Vec<String> = aa.iter().map(|x| sig3(x.median_ms() / aa1)).collect();
        let aa_err: Vec<String> = aa.iter().map(|x| sig3(x.metrics.rmse)).collect();
        let f32_exact = f32row.map_or(f64::NAN, |x| x.median_ms());
        let ar = |label: &str| r.row(label).map_or(f64::NAN, |x| x.median_ms() / f32_exact);
        let approx = [ar("f32 rsqrt"), ar("f32 int-pow"), ar("f32 fma")];
        let opt = |x: Option<f64>| x.map_or("-".to_string(), sig3);
        let _ = writeln!(
            md,
            "| {} | {}x{} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.name,
            r.width,
            r.height,
            sig3(ref_ms),
            opt(f64_over_f32),
            opt(f32row.map(|x| x.metrics.rmse)),
            f32row.map_or("-".into(), |x| format!(
                "{}%",
                sig3(100.0 * x.metrics.over_1_255)
            )),
            opt(d5.map(|x| x.metrics.rmse)),
            thr.map_or("none".into(), |(t, q)| format!(
                "{} ({}x)",
                short(t),
                sig3(q)
            )),
            aa_time.join(" : "),
            aa_err.join(" → "),
            approx.map(sig3).join(" / ")
        );
        let _ = writeln!(
            csv,
            "{},{},{},{:.3},{},{},{},{},{},{},{},{},{},{},{}",
            r.name,
            r.width,
            r.height,
            ref_ms,
            opt(f64_over_f32),
            f32row.map_or(String::new(), |x| format!("{:.6e}", x.metrics.rmse)),
            f32row.map_or(String::new(), |x| format!("{:.6}", x.metrics.over_1_255)),
            d5.map_or(String::new(), |x| format!("{:.6e}", x.metrics.rmse)),
            thr.map_or(String::new(), |(t, _)| t.to_string()),
            thr.map_or(String::new(), |(_, q)| format!("{q:.4}")),
            aa_time.join(";"),
            aa_err.join(";"),
            sig3(approx[0]),
            sig3(approx[1]),
            sig3(approx[2])
        );
    }
    (md, csv)
}

/// The scene's name for file names: the file name without `.gz`, `.nff` or `.obj`.
pub fn scene_name(path: &Path) -> String {
    let mut n = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into());
    for ext in [".gz", ".nff", ".obj"] {
        if n.to_ascii_lowercase().ends_with(ext) && n.len() > ext.len() {
            n.truncate(n.len() - ext.len());
        }
    }
    n
}

fn write_text(path: &Path, text: &str) -> Result<(), String> {
    write_atomic(path, |w| std::io::Write::write_all(w, text.as_bytes()))
        .map_err(|e| format!("{}: cannot write: {e}", path.display()))
}

/// Writes `<name>.md`, `<name>.csv`, `<name>.svg` and `<name>-reference.png` into `dir`
/// for every report, and `summary.md` and `summary.csv`. Each file is written to a
/// temporary file and renamed.
pub fn write_report(dir: &Path, reports: &[SceneReport]) -> Result<(), String> {
    for r in reports {
        let file = |ext: &str| dir.join(format!("{}.{ext}", r.name));
        write_text(&file("md"), &r.to_markdown())?;
        write_text(&file("csv"), &r.to_csv())?;
        write_text(&file("svg"), &r.to_svg())?;
        let png = dir.join(format!("{}-reference.png", r.name));
        r.reference
            .save(&png)
            .map_err(|e| format!("{}: cannot write image: {e}", png.display()))?;
    }
    let (md, csv) = summary(reports);
    write_text(&dir.join("summary.md"), &md)?;
    write_text(&dir.join("summary.csv"), &csv)
}

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
    #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub width: u32,
    /// Image height (default: keep the scene's aspect ratio).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub height: Option<u32>,
    /// Timed runs per setting; the median is reported.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=100))]
    pub runs: u32,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// Depth of the reference; depths 1 to this minus one are measured.
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub ref_depth: u32,
    /// Rays per pixel of the reference, as an A x A grid.
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub ref_aa: u32,
    /// Grid of the fine reference for the antialiasing knob.
    #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub fine_aa: u32,
    /// Largest antialiasing grid measured (1 to this).
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=64))]
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

/// Runs `tracer accuracy`: loads every scene first (so bad input fails before any
/// rendering), measures each, and writes the report. Errors are one line.
pub fn run(args: &AccuracyArgs) -> Result<(), String> {
    let options = args.options();
    options.check()?;
    let mut scenes = Vec::new();
    for path in &args.scenes {
        let desc = scene::load(path).map_err(|e| e.to_string())?;
        let name = scene_name(path);
        if scenes.iter().any(|(n, _, _): &(String, _, _)| *n == name) {
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
