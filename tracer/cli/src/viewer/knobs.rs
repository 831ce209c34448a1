//! The live knobs: every setting a user can change while the viewer runs.
//!
//! [`KNOBS`] is a table with one entry per knob: its name, what it does, and how to step,
//! set and show it. The window cycles through the table (Tab), steps the selected knob
//! (`[` and `]`), and camera scripts set knobs by name (`set NAME VALUE`), so a new knob is
//! one field in [`Knobs`] and one entry in the table.

use crate::args::parse_threshold;
use crate::Precision;
use tracer::effects::EffectsMode;

/// The current value of every knob.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Knobs {
    /// Antialiasing: the image converges to an `aa` x `aa` grid of rays per pixel.
    pub aa: u32,
    /// Maximum ray depth (1 = eye rays only).
    pub depth: u32,
    /// Adaptive termination threshold on a secondary ray's weight (0 = off).
    pub threshold: f64,
    /// Arithmetic precision.
    pub precision: Precision,
    /// Rendering threads.
    pub threads: usize,
    /// The renderer compiled for the scene's effects (`auto`) or the general one (`all`);
    /// the image is the same, only the time differs.
    pub effects: EffectsMode,
}

impl Default for Knobs {
    fn default() -> Self {
        Self {
            aa: 4,
            depth: 5,
            threshold: 0.0,
            precision: Precision::F32,
            threads: std::thread::available_parallelism().map_or(1, |n| n.get()),
            effects: EffectsMode::Auto,
        }
    }
}

/// One live knob.
pub struct Knob {
    /// Name, as the window title and `set NAME VALUE` in scripts spell it.
    pub name: &'static str,
    /// What the knob does, for the key help.
    pub help: &'static str,
    /// Moves the knob `delta` steps up (positive) or down, within its range.
    pub step: fn(&mut Knobs, i32),
    /// Sets the knob from text.
    pub set: fn(&mut Knobs, &str) -> Result<(), String>,
    /// Shows the knob's current value.
    pub show: fn(&Knobs) -> String,
}

/// Largest antialiasing grid (64 passes to converge).
pub const MAX_AA: u32 = 8;
/// Largest ray depth.
pub const MAX_DEPTH: u32 = 16;
/// Most rendering threads.
pub const MAX_THREADS: usize = 64;
/// The threshold values that stepping goes through.
pub const THRESHOLDS: [f64; 8] = [0.0, 0.001, 0.003, 0.01, 0.03, 0.1, 0.3, 1.0];

fn step_int(v: i64, delta: i32, lo: i64, hi: i64) -> i64 {
    (v + delta as i64).clamp(lo, hi)
}

fn parse_int(s: &str, lo: u64, hi: u64) -> Result<u64, String> {
    let v: u64 = s
        .parse()
        .map_err(|_| format!("`{s}` is not a whole number"))?;
    if !(lo..=hi).contains(&v) {
        return Err(format!("{v} is outside {lo}..={hi}"));
    }
    Ok(v)
}

/// The knob table. Pending, to be added as an entry when the renderer has it: the
/// instruction set (ISA) of the tracing kernels.
pub const KNOBS: &[Knob] = &[
    Knob {
        name: "aa",
        help: "antialiasing: converge to an AA x AA grid of rays per pixel",
        step: |k, d| k.aa = step_int(k.aa as i64, d, 1, MAX_AA as i64) as u32,
        set: |k, s| {
            k.aa = parse_int(s, 1, MAX_AA as u64)? as u32;
            Ok(())
        },
        show: |k| format!("{}x{}", k.aa, k.aa),
    },
    Knob {
        name: "depth",
        help: "maximum ray depth (1 = eye rays only)",
        step: |k, d| k.depth = step_int(k.depth as i64, d, 1, MAX_DEPTH as i64) as u32,
        set: |k, s| {
            k.depth = parse_int(s, 1, MAX_DEPTH as u64)? as u32;
            Ok(())
        },
        show: |k| k.depth.to_string(),
    },
    Knob {
        name: "threshold",
        help: "adaptive termination: skip secondary rays of weight below T",
        step: |k, d| {
            // The nearest listed value at or below the current one, then `d` steps.
            let at = THRESHOLDS
                .iter()
                .rposition(|&t| t <= k.threshold)
                .unwrap_or(0);
            let i = step_int(at as i64, d, 0, THRESHOLDS.len() as i64 - 1);
            k.threshold = THRESHOLDS[i as usize];
        },
        set: |k, s| {
            k.threshold = parse_threshold(s)?;
            Ok(())
        },
        show: |k| k.threshold.to_string(),
    },
    Knob {
        name: "precision",
        help: "arithmetic precision, f32 or f64",
        step: |k, d| {
            if d != 0 {
                k.precision = match k.precision {
                    Precision::F32 => Precision::F64,
                    Precision::F64 => Precision::F32,
                }
            }
        },
        set: |k, s| {
            k.precision = match s {
                "f32" => Precision::F32,
                "f64" => Precision::F64,
                _ => return Err(format!("precision must be f32 or f64, got `{s}`")),
            };
            Ok(())
        },
        show: |k| k.precision.to_string(),
    },
    Knob {
        name: "threads",
        help: "rendering threads",
        step: |k, d| k.threads = step_int(k.threads as i64, d, 1, MAX_THREADS as i64) as usize,
        set: |k, s| {
            k.threads = parse_int(s, 1, MAX_THREADS as u64)? as usize;
            Ok(())
        },
        show: |k| k.threads.to_string(),
    },
    Knob {
        name: "effects",
        help: "renderer: compiled for the scene's effects (auto) or general (all)",
        step: |k, d| {
            if d != 0 {
                k.effects = match k.effects {
                    EffectsMode::Auto => EffectsMode::All,
                    EffectsMode::All => EffectsMode::Auto,
                }
            }
        },
        set: |k, s| {
            k.effects = match s {
                "auto" => EffectsMode::Auto,
                "all" => EffectsMode::All,
                _ => return Err(format!("effects must be auto or all, got `{s}`")),
            };
            Ok(())
        },
        show: |k| k.effects.name().to_string(),
    },
];

/// The knob called `name`.
pub fn find(name: &str) -> Option<&'static Knob> {
    KNOBS.iter().find(|k| k.name == name)
}

/// All knobs as `name value` pairs, for the window title.
pub fn summary(k: &Knobs) -> String {
    KNOBS
        .iter()
        .map(|knob| format!("{} {}", knob.name, (knob.show)(k)))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_stay_in_range() {
        let mut k = Knobs {
            threads: 2,
            ..Knobs::default()
        };
        for knob in KNOBS {
            for _ in 0..100 {
                (knob.step)(&mut k, 1);
            }
        }
        assert_eq!((k.aa, k.depth, k.threads), (MAX_AA, MAX_DEPTH, MAX_THREADS));
        assert_eq!(k.threshold, 1.0);
        for knob in KNOBS {
            for _ in 0..100 {
                (knob.step)(&mut k, -1);
            }
        }
        assert_eq!((k.aa, k.depth, k.threads, k.threshold), (1, 1, 1, 0.0));
    }

    #[test]
    fn threshold_steps_from_any_value() {
        let mut k = Knobs {
            threshold: 0.02,
            ..Knobs::default()
        };
        (find("threshold").unwrap().step)(&mut k, 1);
        assert_eq!(k.threshold, 0.03);
        (find("threshold").unwrap().step)(&mut k, -1);
        assert_eq!(k.threshold, 0.01);
    }

    #[test]
    fn set_parses_and_rejects() {
        let mut k = Knobs::default();
        (find("aa").unwrap().set)(&mut k, "3").unwrap();
        (find("precision").unwrap().set)(&mut k, "f64").unwrap();
        (find("effects").unwrap().set)(&mut k, "all").unwrap();
        assert_eq!(
            (k.aa, k.precision, k.effects),
            (3, Precision::F64, EffectsMode::All)
        );
        assert!((find("effects").unwrap().set)(&mut k, "some").is_err());
        assert!((find("aa").unwrap().set)(&mut k, "0").is_err());
        assert!((find("depth").unwrap().set)(&mut k, "x").is_err());
        assert!((find("threshold").unwrap().set)(&mut k, "2").is_err());
        assert!(find("isa").is_none());
        assert!(summary(&k).starts_with("aa 3x3, depth 5"));
    }
}
