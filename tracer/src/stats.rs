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
