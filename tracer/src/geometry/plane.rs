//! Infinite planes. They have no finite bounds, so they live outside the BVH and are
//! tested before it on every ray (a ground plane then also tightens `t_max` early).
//!
//! There is a single-ray kernel only: every query tests the planes once per ray before
//! the walk, and a packet tests them with this kernel lane by lane, so a lane version
//! would be a second source for one test per ray.

use super::ray_data::RayData;
use crate::ray::Ray;
use vecexpr::{Expr, Real, Vec3};

/// The plane through `point` with unit `normal`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane<T: Real> {
    /// A point on the plane.
    pub point: Vec3<T>,
    /// Unit normal (the front side).
    pub normal: Vec3<T>,
}

impl<T: Real> Plane<T> {
    /// `None` if the normal is zero or a value is not finite.
    pub fn new(point: Vec3<T>, normal: Vec3<T>) -> Option<Self> {
        let normal = normal.normalize();
        let finite = point.iter().chain(normal.iter()).all(|x| x.is_finite());
        (finite && normal.length_squared() > T::ZERO).then_some(Self { point, normal })
    }

    /// $t = ((p - o) \cdot n) / (d \cdot n)$ if in $(t_{min}, t_{max}]$.
    #[inline(always)]
    pub(crate) fn intersect(&self, r: &RayData<T>, t_max: T) -> Option<T> {
        let denom = r.dir.dot(&self.normal);
        if denom == T::ZERO {
            return None;
        }
        let t = (self.point - r.origin).dot(&self.normal) / denom;
        r.accepts(t, t_max).then_some(t)
    }

    /// The hit point `origin + t dir` projected onto the plane, so that its error is
    /// relative to the point's own coordinates, not to a distant ray origin.
    #[inline]
    pub(crate) fn point(&self, r: &Ray<T>, t: T) -> Vec3<T> {
        let x = (r.origin + (&r.dir).scale(t)).eval();
        let h = (x - self.point).dot(&self.normal);
        (x - (&self.normal).scale(h)).eval()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ray::Ray;
    use vecexpr::vec3;

    #[test]
    fn plane_hit() {
        let p = Plane::new(vec3(0.0f32, -1.0, 0.0), vec3(0.0, 2.0, 0.0)).unwrap();
        assert_eq!(p.normal, vec3(0.0, 1.0, 0.0));
        let r = RayData::new(&Ray::new(vec3(0.0, 1.0, 0.0), vec3(0.0, -1.0, 0.0))).unwrap();
        assert_eq!(p.intersect(&r, f32::MAX), Some(2.0));
        let r = RayData::new(&Ray::new(vec3(0.0, 1.0, 0.0), vec3(1.0, 0.0, 0.0))).unwrap();
        assert_eq!(p.intersect(&r, f32::MAX), None);
        assert!(Plane::new(vec3(0.0f32, 0.0, 0.0), vec3(0.0, 0.0, 0.0)).is_none());
    }
}
