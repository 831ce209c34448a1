//! Ray counters and the `--stats` JSON report.

use serde::Serialize;
use std::ops::{Add, AddAssign};

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
