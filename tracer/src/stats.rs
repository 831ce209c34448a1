//! Ray counters, timers and the `--stats` JSON report.

use crate::cycles;
use serde::Serialize;
use std::ops::{Add, AddAssign};
use std::time::Instant;

/// Rays traced, by kind (SPD's counting: every ray cast, hit or not).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct RayCounts {
    /// Primary rays from the camera.
    pub eye: u64,
    /// Mirror-reflection rays.
    pub reflection: u64,
    /// Refraction (transmission) rays.
    pub refraction: u64,
    /// Shadow rays toward lights.
    pub shadow: u64,
}

impl RayCounts {
    /// All rays.
    pub fn total(&self) -> u64 {
        self.eye + self.reflection + self.refraction + self.shadow
    }
}

impl Add for RayCounts {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self {
            eye: self.eye + o.eye,
            reflection: self.reflection + o.reflection,
            refraction: self.refraction + o.refraction,
            shadow: self.shadow + o.shadow,
        }
    }
}

impl AddAssign for RayCounts {
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

/// Wall-clock times of the phases, in milliseconds.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct Times {
    /// Reading and parsing the scene file.
    pub parse: f64,
    /// Building primitives and the BVH.
    pub build: f64,
    /// Tracing all rays.
    pub trace: f64,
    /// Everything, including writing the image.
    pub total: f64,
}

/// The phases of [`Times`] in ticks of the cycle counter ([`crate::cycles`]): TSC
/// reference cycles where the processor has an invariant TSC, else nanoseconds.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct Cycles {
    /// Reading and parsing the scene file.
    pub parse: u64,
    /// Building primitives and the BVH.
    pub build: u64,
    /// Tracing all rays.
    pub trace: u64,
    /// Everything, including writing the image.
    pub total: u64,
}

/// What the ticks of [`Cycles`] are, for the `--stats` JSON.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct CycleClock {
    /// `"tsc"` or `"instant"` (the nanosecond fallback).
    pub source: &'static str,
    /// Ticks per second, as calibrated against the wall clock.
    pub ticks_per_second: f64,
}

impl CycleClock {
    /// The process-wide clock (calibrated on first use).
    pub fn get() -> Self {
        let c = cycles::clock();
        Self {
            source: c.source().name(),
            ticks_per_second: c.ticks_per_second(),
        }
    }
}

/// A moment on both clocks, the wall clock and the cycle counter, to time a phase by.
#[derive(Clone, Copy, Debug)]
pub struct Mark {
    instant: Instant,
    ticks: u64,
}

impl Mark {
    /// Now.
    #[inline]
    pub fn now() -> Self {
        Self {
            instant: Instant::now(),
            ticks: cycles::start(),
        }
    }

    /// Milliseconds of wall-clock time since this mark.
    pub fn ms(&self) -> f64 {
        self.instant.elapsed().as_secs_f64() * 1e3
    }

    /// Cycle-counter ticks since this mark.
    pub fn cycles(&self) -> u64 {
        cycles::since(self.ticks)
    }
}

/// CPU time consumed so far by all threads of this process (including threads that have
/// exited), in milliseconds, or `None` where the clock is not available.
pub fn process_cpu_ms() -> Option<f64> {
    #[cfg(unix)]
    {
        let mut ts = libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        // SAFETY: `ts` is a valid, writable `timespec` for the duration of the call, and
        // CLOCK_PROCESS_CPUTIME_ID is a clock id every POSIX system accepts.
        let rc = unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut ts) };
        (rc == 0).then_some(ts.tv_sec as f64 * 1e3 + ts.tv_nsec as f64 * 1e-6)
    }
    #[cfg(not(unix))]
    {
        None
    }
}

/// The median of `xs` (the mean of the middle two for an even count; 0 for none), the
/// statistic every timing of the tracer's front ends and examples reports.
///
/// ```
/// use tracer::stats::median;
/// assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
/// assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), 2.5);
/// assert_eq!(median(&[]), 0.0);
/// ```
pub fn median(xs: &[f64]) -> f64 {
    let mut v = xs.to_vec();
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => 0.0,
        n if n % 2 == 1 => v[n / 2],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}
