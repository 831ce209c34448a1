//! Truncated cones and cylinders without caps (NFF `c`).
//!
//! The surface is every point whose axial coordinate $s = (p - b) \cdot \hat a$ lies in
//! $[0, h]$ and whose distance from the axis equals $r(s) = r_0 + k s$, $k = (r_1 - r_0)/h$.
//! With $w = o - b$ split into axial and radial parts $w_s = w \cdot \hat a$,
//! $w_\perp = w - w_s \hat a$ (likewise $d_s$, $d_\perp$) and $\rho = r_0 + k w_s$, the
//! ray meets the infinite cone where
//! $$A t^2 + 2 B t + C = 0,\quad A = d_\perp^2 - k^2 d_s^2,\quad
//!   B = w_\perp \cdot d_\perp - k \rho d_s,\quad C = w_\perp^2 - \rho^2 .$$
//! As for spheres (Haines et al., Ray Tracing Gems ch. 7) the discriminant is not formed
//! as $B^2 - AC$, which cancels for a distant or thin cylinder, but expanded with
//! Lagrange's identity $|w_\perp|^2 |d_\perp|^2 - (w_\perp \cdot d_\perp)^2 = |w_\perp \times d_\perp|^2$:
//! $$B^2 - AC = \rho^2 d_\perp^2 - |w_\perp \times d_\perp|^2 +
//!   k d_s (k d_s w_\perp^2 - 2 \rho\, w_\perp \cdot d_\perp),$$
//! exact in the cylinder case $k = 0$. Roots use the same stable $q$ form; $A = 0$ (a ray
//! parallel to a generator line) leaves the single root $C/q$. Only $r(s) \ge 0$ occurs on
//! $[0, h]$, so the mirrored nappe of the double cone is excluded by the range test.
//!
//! The quadratic is solved from the point of the ray's line closest to the middle of the
//! axis rather than from the origin: a distant origin makes $\rho$ and $w_\perp$ large,
//! and then the three terms of the discriminant cancel even with the identity above.
//!
//! There is a single-ray kernel only: the packet queries ([`super::packet_query`]) test a
//! cone with it lane by lane. A lane version would be a second source of this kernel
//! (its range tests and single root for $A = 0$ branch per ray) for a primitive only
//! one classic scene has (rings-s7), whose shadow rays stay single anyway
//! (`crate::packets::shadow_packets`).

use super::ray_data::RayData;
use crate::ray::Ray;
use vecexpr::{Expr, Real, Vec3};

/// A cone or cylinder as the traversal sees it (36 bytes in `f32`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cone<T: Real> {
    /// Centre of the base disc.
    pub base: Vec3<T>,
    /// Unit axis from base to apex.
    pub axis: Vec3<T>,
    /// Distance from base to apex.
    pub height: T,
    /// Radius at the base.
    pub base_radius: T,
    /// $k = (r_1 - r_0) / h$: radius change per unit of height.
    pub slope: T,
}

impl<T: Real> Cone<T> {
    /// From base and apex centres and radii (non-negative); `None` if degenerate
    /// (coincident ends, both radii zero, or non-finite values).
    pub fn new(base: Vec3<T>, base_radius: T, apex: Vec3<T>, apex_radius: T) -> Option<Self> {
        // In f64 so that the f32 axis and slope are correctly rounded.
        let b: [f64; 3] = core::array::from_fn(|i| base[i].to_f64());
        let e: [f64; 3] = core::array::from_fn(|i| apex[i].to_f64() - b[i]);
        let h = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
        let (r0, r1) = (base_radius.to_f64(), apex_radius.to_f64());
        let finite = b.iter().chain(&e).all(|x| x.is_finite()) && r0.is_finite() && r1.is_finite();
        let valid = finite && h > 0.0 && r0 >= 0.0 && r1 >= 0.0 && (r0 > 0.0 || r1 > 0.0);
        if !valid {
            return None;
        }
        let c = |x: f64| <T as Real>::from_f64(x);
        let axis = vecexpr::vec3(c(e[0] / h), c(e[1] / h), c(e[2] / h));
        let height = c(h);
        if axis.length_squared() == T::ZERO || height == T::ZERO {
            return None;
        }
        Some(Self {
            base,
            axis,
            height,
            base_radius,
            slope: c((r1 - r0) / h),
        })
    }

    /// Radius at the apex end.
    pub fn apex_radius(&self) -> T {
        self.base_radius + self.slope * self.height
    }

    /// The nearest $t$ in $(t_{min}, t_{max}]$ on the lateral surface.
    #[inline(always)]
    pub(crate) fn intersect(&self, r: &RayData<T>, t_max: T) -> Option<T> {
        let k = self.slope;
        // Solve from the point of the ray's line closest to the middle of the axis, then
        // add that point's parameter back: with a distant origin, $\rho = r_0 + k w_s$
        // and $w_\perp$ are large and the terms of the discriminant cancel (Haines et al.,
        // RTG ch. 7, discuss moving the origin closer for spheres).
        let w0 = (r.origin - self.base).eval();
        let mid = (&self.axis).scale(self.height * <T as Real>::from_f64(0.5));
        let t_c = (mid - &w0).dot(&r.dir) * r.inv_dd;
        let w = (w0 + (&r.dir).scale(t_c)).eval();
        let ws = w.dot(&self.axis);
        let ds = r.dir.dot(&self.axis);
        let wp = (w - (&self.axis).scale(ws)).eval();
        let dp = (r.dir - (&self.axis).scale(ds)).eval();
        let rho = self.base_radius + k * ws;
        let dpdp = dp.length_squared();
        let wpwp = wp.length_squared();
        let wpdp = wp.dot(&dp);
        let kds = k * ds;
        let cr = wp.cross(&dp);
        let disc = rho * rho * dpdp - cr.length_squared()
            + kds * (kds * wpwp - <T as Real>::from_f64(2.0) * rho * wpdp);
        if disc < T::ZERO || disc.is_nan() {
            return None;
        }
        let a = dpdp - kds * kds;
        let b = wpdp - kds * rho;
        let c = wpwp - rho * rho;
        let q = -(b + disc.sqrt().copysign(b));
        let (t0, t1) = (q / a, c / q);
        // NaN/inf roots (a = 0 or q = 0) fail `accepts`.
        let (near, far) = if t1 < t0 { (t1, t0) } else { (t0, t1) };
        for tl in [near, far] {
            let t = t_c + tl;
            if r.accepts(t, t_max) {
                let s = ws + tl * ds;
                if s >= T::ZERO && s <= self.height {
                    return Some(t);
                }
            }
        }
        None
    }

    /// The unit outward normal at the hit `origin + t dir`: the gradient
    /// $q - r(s)\,k\,\hat a$ with $q$ the radial offset, taken as $\hat q - k \hat a$.
    #[inline]
    pub(crate) fn normal(&self, r: &Ray<T>, t: T) -> Vec3<T> {
        let rel = (r.origin - self.base + (&r.dir).scale(t)).eval();
        let s = rel.dot(&self.axis);
        let q = (rel - (&self.axis).scale(s)).normalize();
        let n = (q - (&self.axis).scale(self.slope)).normalize();
        if n.length_squared() > T::ZERO {
            return n;
        }
        // At the tip of a cone: along the axis, away from the wide end.
        let tip = (&self.axis).scale(-self.slope).normalize();
        if tip.length_squared() > T::ZERO {
            tip
        } else {
            (-&r.dir).normalize()
        }
    }

    /// The hit point `origin + t dir` projected back onto the surface: its radial part is
    /// rescaled to the radius $r(s)$ at its axial coordinate, computed relative to the
    /// base so that a distant origin's rounding does not stay in the point (as pbrt-v4
    /// refines its cylinder hits). This is what lets [`super::offset_ray`] use an offset
    /// relative to the point's own coordinates.
    #[inline]
    pub(crate) fn point(&self, r: &Ray<T>, t: T) -> Vec3<T> {
        let rel = (r.origin - self.base + (&r.dir).scale(t)).eval();
        let s = rel.dot(&self.axis);
        let q = (rel - (&self.axis).scale(s)).eval();
        let len = q.length();
        let radius = self.base_radius + self.slope * s;
        if len > T::ZERO && len.is_finite() && radius >= T::ZERO {
            (self.base + (&self.axis).scale(s) + (&q).scale(radius / len)).eval()
        } else {
            (r.origin + (&r.dir).scale(t)).eval()
        }
    }

    /// Conservative bounds in `f64`: the boxes of the two end discs, whose half-extent
    /// along axis $i$ is $r \sqrt{1 - a_i^2}$.
    pub fn bounds_f64(&self) -> ([f64; 3], [f64; 3]) {
        let r0 = self.base_radius.to_f64();
        let r1 = self.apex_radius().to_f64().max(0.0);
        let h = self.height.to_f64();
        let mut lo = [0.0; 3];
        let mut hi = [0.0; 3];
        for i in 0..3 {
            let a = self.axis[i].to_f64();
            let spread = (1.0 - a * a).max(0.0).sqrt();
            let b = self.base[i].to_f64();
            let e = b + a * h;
            lo[i] = (b - r0 * spread).min(e - r1 * spread);
            hi[i] = (b + r0 * spread).max(e + r1 * spread);
        }
        (lo, hi)
    }
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
    fn cylinder_hits_and_normals() {
        let c = Cone::new(vec3(0.0f64, 0.0, 0.0), 1.0, vec3(0.0, 0.0, 2.0), 1.0).unwrap();
        let r = data(vec3(5.0, 0.0, 1.0), vec3(-1.0, 0.0, 0.0));
        assert_eq!(c.intersect(&r, f64::MAX), Some(4.0));
        assert_eq!(
            c.normal(&Ray::new(r.origin, r.dir), 4.0),
            vec3(1.0, 0.0, 0.0)
        );
        // Above the top: miss; through the open end from inside: the far wall.
        let above = data(vec3(5.0, 0.0, 2.5), vec3(-1.0, 0.0, 0.0));
        assert_eq!(c.intersect(&above, f64::MAX), None);
        let inside = data(vec3(0.0, 0.0, 1.0), vec3(0.0, 1.0, 0.0));
        assert_eq!(c.intersect(&inside, f64::MAX), Some(1.0));
        // Along the axis: never meets the wall.
        let axial = data(vec3(0.0, 0.0, -1.0), vec3(0.0, 0.0, 1.0));
        assert_eq!(c.intersect(&axial, f64::MAX), None);
    }

    #[test]
    fn cone_hit_and_normal() {
        // Radius 1 at z = 0 down to 0 at z = 1: the 45° cone |(x, y)| = 1 - z.
        let c = Cone::new(vec3(0.0f64, 0.0, 0.0), 1.0, vec3(0.0, 0.0, 1.0), 0.0).unwrap();
        let r = data(vec3(5.0, 0.0, 0.5), vec3(-1.0, 0.0, 0.0));
        let t = c.intersect(&r, f64::MAX).unwrap();
        assert!((t - 4.5).abs() < 1e-12);
        let n = c.normal(&Ray::new(r.origin, r.dir), t);
        let s = 0.5f64.sqrt();
        assert!(n.approx_eq(vec3(s, 0.0, s), 1e-12), "{n:?}");
    }

    #[test]
    fn ray_parallel_to_a_generator_line() {
        // 45° cone; a ray parallel to the line from (1,0,0) to (0,0,1) has A = 0.
        let c = Cone::new(vec3(0.0f64, 0.0, 0.0), 1.0, vec3(0.0, 0.0, 1.0), 0.0).unwrap();
        let r = data(vec3(0.5, 0.0, -0.5), vec3(-1.0, 0.0, 1.0));
        let t = c.intersect(&r, f64::MAX).unwrap();
        let p = (r.origin + (&r.dir).scale(t)).eval();
        // The single root is on the far side: radius 1 - z at (-0.5, 0, 0.5).
        assert!((t - 1.0).abs() < 1e-12, "{t}");
        assert!((p[0].hypot(p[1]) - (1.0 - p[2])).abs() < 1e-12, "{p:?}");
    }

    #[test]
    fn degenerate_cones_are_rejected() {
        let o = vec3(0.0f32, 0.0, 0.0);
        assert!(Cone::new(o, 1.0, o, 1.0).is_none());
        assert!(Cone::new(o, 0.0, vec3(0.0, 0.0, 1.0), 0.0).is_none());
        assert!(Cone::new(o, f32::NAN, vec3(0.0, 0.0, 1.0), 1.0).is_none());
    }

    #[test]
    fn bounds_contain_rim_points() {
        let c = Cone::new(vec3(1.0f64, 2.0, 3.0), 0.5, vec3(2.0, 4.0, 3.5), 1.5).unwrap();
        let (lo, hi) = c.bounds_f64();
        // Build an orthonormal frame around the axis and sample both rims.
        let a = c.axis;
        let u = a.cross(vec3(0.0, 0.0, 1.0)).normalize();
        let v = a.cross(&u);
        for i in 0..64 {
            let phi = i as f64 / 64.0 * std::f64::consts::TAU;
            let dir = ((&u).scale(phi.cos()) + (&v).scale(phi.sin())).eval();
            for (s, r) in [(0.0, 0.5), (c.height, 1.5)] {
                let p = (c.base + (&a).scale(s) + (&dir).scale(r)).eval();
                for k in 0..3 {
                    assert!(lo[k] - 1e-12 <= p[k] && p[k] <= hi[k] + 1e-12);
                }
            }
        }
    }
}
