//! Axis-aligned boxes in the scene's precision.

use crate::bvh::Bounds3;
use vecexpr::{vec3, Expr, Real, Vec3};

/// An axis-aligned box $[min, max]$. Empty when any `min > max`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb<T: Real> {
    /// Lower corner.
    pub min: Vec3<T>,
    /// Upper corner.
    pub max: Vec3<T>,
}

impl<T: Real> Aabb<T> {
    /// The empty box ($+\infty$ to $-\infty$).
    pub fn empty() -> Self {
        Self {
            min: Vec3::splat(T::INFINITY),
            max: Vec3::splat(T::NEG_INFINITY),
        }
    }

    /// Does it contain no point?
    pub fn is_empty(&self) -> bool {
        !(0..3).all(|a| self.min[a] <= self.max[a])
    }

    /// Centre (meaningless when empty).
    pub fn center(&self) -> Vec3<T> {
        (self.min + self.max)
            .scale(<T as Real>::from_f64(0.5))
            .eval()
    }

    /// `max - min` (meaningless when empty).
    pub fn diagonal(&self) -> Vec3<T> {
        (self.max - self.min).eval()
    }

    /// Does it contain `p` (boundary included)?
    pub fn contains(&self, p: &Vec3<T>) -> bool {
        (0..3).all(|a| self.min[a] <= p[a] && p[a] <= self.max[a])
    }

    /// From a conservative `f32` box (widening is exact).
    pub(crate) fn from_bounds(b: &Bounds3) -> Self {
        if b.is_empty() {
            return Self::empty();
        }
        let c = |x: f32| <T as Real>::from_f64(f64::from(x));
        Self {
            min: vec3(c(b.lo[0]), c(b.lo[1]), c(b.lo[2])),
            max: vec3(c(b.hi[0]), c(b.hi[1]), c(b.hi[2])),
        }
    }
}
