//! The experiment: the settings measured ([`Options::cases`]), their interleaved timed
//! renders and their errors ([`measure`]).

use super::metrics::{compare, pareto, Metrics};
use super::report::short;
use crate::Precision;
use tracer::arith::Arith;
use tracer::geometry::AccelOptions;
use tracer::image::Image;
use tracer::render::{render_with_stats, Settings};
use tracer::scene::desc::SceneDesc;
use tracer::stats::{median, process_cpu_ms};
use tracer::world::Scene;

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

    pub(crate) fn colour(self) -> &'static str {
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

    pub(crate) fn check(&self) -> Result<(), String> {
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
