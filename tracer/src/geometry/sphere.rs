//! Spheres.
//!
//! E. Haines, J. Günther, T. Akenine-Möller, "Precision Improvements for Ray/Sphere
//! Intersection", Ray Tracing Gems (2019), chapter 7. With $f = o - c$ the quadratic is
//! $a t^2 + 2 b' t + c' = 0$, $a = d \cdot d$, $b' = f \cdot d$, $c' = f \cdot f - r^2$.
//! - The discriminant $b'^2 - a c'$ is computed as $a (r^2 - |f - (b'/a) d|^2)$: the
//!   squared distance from the centre to the line, which does not cancel
//!   catastrophically when the sphere is small and far away (their eq. 7.5).
//! - The roots are $t_0 = c'/q$, $t_1 = q/a$ with $q = -b' - \mathrm{sign}(b')\sqrt{\cdot}$,
//!   avoiding the subtraction of nearly equal numbers (their eq. 7.6, after Press et al.).
//!
//! The single-ray test and its lane version (`sphere_packet`, one sphere against a packet
//! of rays, for `packet_query`) sit side by side below, the same operations in the same
//! order. They are two sources because the single ray leaves as soon as the
//! discriminant is negative, while the lanes compute both roots for every ray and
//! select; one source over a one-lane type would give up that early exit.

use super::ray_data::{PacketData, RayData};
use crate::ray::Ray;
use vecexpr::simd::SimdF32;
use vecexpr::{vec3, Expr, Mask, Real, Vec3};

/// A sphere as the traversal sees it (16 bytes in `f32`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere<T: Real> {
    /// Centre.
    pub center: Vec3<T>,
    /// Radius (positive).
    pub radius: T,
}

impl<T: Real> Sphere<T> {
    /// The nearest $t$ in $(t_{min}, t_{max}]$ where the ray meets the sphere. A ray that
    /// starts inside finds the far wall.
    #[inline(always)]
    pub(crate) fn intersect(&self, r: &RayData<T>, t_max: T) -> Option<T> {
        let f = (r.origin - self.center).eval();
        let b = f.dot(&r.dir);
        let r2 = self.radius * self.radius;
        // Squared distance from the centre to the ray's line.
        let l = (f - (&r.dir).scale(b * r.inv_dd)).eval();
        let disc = r2 - l.length_squared();
        if disc < T::ZERO {
            return None;
        }
        let c = f.length_squared() - r2;
        let q = -b - (r.dd * disc).sqrt().copysign(b);
        let (t0, t1) = (c / q, q * r.inv_dd);
        let (near, far) = if t1 < t0 { (t1, t0) } else { (t0, t1) };
        if r.accepts(near, t_max) {
            Some(near)
        } else if r.accepts(far, t_max) {
            Some(far)
        } else {
            None
        }
    }

    /// The unit outward normal at the hit `origin + t dir`, and the hit point projected
    /// back onto the surface (which removes most of the error of $o + t d$).
    #[inline]
    pub(crate) fn normal_and_point(&self, r: &Ray<T>, t: T) -> (Vec3<T>, Vec3<T>) {
        // Relative to the centre, so the result does not lose digits to a large |c|.
        let rel = (r.origin - self.center + (&r.dir).scale(t)).eval();
        let n = rel.normalize();
        if n.length_squared() > T::ZERO {
            let p = (self.center + (&n).scale(self.radius)).eval();
            (n, p)
        } else {
            ((-&r.dir).normalize(), (r.origin + (&r.dir).scale(t)).eval())
        }
    }
}

/// [`Sphere::intersect`] in every lane: the lanes with a hit in `(t_min, t_max]`, and
/// their distances.
#[inline(always)]
pub(crate) fn sphere_packet<S: SimdF32>(
    s: &Sphere<f32>,
    r: &PacketData<S>,
    t_max: S,
) -> (S::Mask, S) {
    let center = vec3(
        S::splat(s.center[0]),
        S::splat(s.center[1]),
        S::splat(s.center[2]),
    );
    let f = (r.origin - center).eval();
    let b = f.dot(&r.dir);
    let r2 = S::splat(s.radius * s.radius);
    let l = (f - (&r.dir).scale(b * r.inv_dd)).eval();
    let disc = r2 - l.length_squared();
    let real = disc.lt(S::zero()).not();
    let c = f.length_squared() - r2;
    let q = -b - (r.dd * disc).sqrt().copysign(b);
    let (t0, t1) = (c / q, q * r.inv_dd);
    let swap = t1.lt(t0);
    let (near, far) = (S::select(swap, t1, t0), S::select(swap, t0, t1));
    let near_ok = near.gt(r.t_min).and(near.le(t_max));
    let far_ok = far.gt(r.t_min).and(far.le(t_max));
    (real.and(near_ok.or(far_ok)), S::select(near_ok, near, far))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ray::Ray;
    use vecexpr::vec3;

    fn data<T: Real>(o: Vec3<T>, d: Vec3<T>) -> RayData<T> {
        RayData::new(&Ray::new(o, d)).unwrap()
    }

    #[test]
    fn front_inside_and_behind() {
        let s = Sphere {
            center: vec3(0.0f64, 0.0, 0.0),
            radius: 1.0,
        };
        let r = data(vec3(0.0, 0.0, 5.0), vec3(0.0, 0.0, -1.0));
        assert_eq!(s.intersect(&r, f64::MAX), Some(4.0));
        assert_eq!(s.intersect(&r, 3.9), None);
        let inside = data(vec3(0.0, 0.5, 0.0), vec3(0.0, 1.0, 0.0));
        assert_eq!(s.intersect(&inside, f64::MAX), Some(0.5));
        let behind = data(vec3(0.0, 0.0, 5.0), vec3(0.0, 0.0, 1.0));
        assert_eq!(s.intersect(&behind, f64::MAX), None);
    }

    #[test]
    fn unnormalised_direction() {
        let s = Sphere {
            center: vec3(1.0f32, 2.0, 3.0),
            radius: 2.0,
        };
        let r = data(vec3(1.0, 2.0, -7.0), vec3(0.0, 0.0, 4.0));
        let t = s.intersect(&r, f32::MAX).unwrap();
        assert!((t - 2.0).abs() < 1e-6);
        let (n, p) = s.normal_and_point(&Ray::new(r.origin, r.dir), t);
        assert_eq!(n, vec3(0.0, 0.0, -1.0));
        assert_eq!(p, vec3(1.0, 2.0, 1.0));
    }

    #[test]
    fn small_far_sphere_in_f32() {
        // 1e4 units away, radius 1e-2: the naive b^2 - ac loses every digit in f32.
        let s = Sphere {
            center: vec3(0.0f32, 0.0, -1.0e4),
            radius: 1.0e-2,
        };
        for k in 0..10 {
            let y = 0.009f32 * k as f32 / 10.0;
            let r = data(vec3(0.0, y, 0.0), vec3(0.0, 0.0, -1.0));
            let t = s.intersect(&r, f32::MAX).expect("hit");
            let exact = 1.0e4 - (1.0e-4f64 - f64::from(y) * f64::from(y)).sqrt();
            assert!((f64::from(t) - exact).abs() < 2e-3, "{y}: {t} vs {exact}");
        }
        let miss = data(vec3(0.0, 0.0101, 0.0), vec3(0.0, 0.0, -1.0));
        assert_eq!(s.intersect(&miss, f32::MAX), None);
    }
}
