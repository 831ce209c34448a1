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
//! The single-ray test and its lane version (`cone_packet`, one cone against a packet of
//! rays, for [`super::packet_query`]) sit side by side below, the same operations in the
//! same order, as the sphere's do: the single ray leaves at a negative discriminant and
//! at the first root in range, while the lanes compute both roots and select.

use super::ray_data::{PacketData, RayData};
use crate::ray::Ray;
use vecexpr::simd::SimdF32;
use vecexpr::{vec3, Expr, Mask, Real, Scalar, Vec3};

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

    /// The widest radius of the cone, $\max(r_0, r_1)$.
    #[inline(always)]
    fn widest(&self) -> T {
        self.base_radius.max(self.apex_radius())
    }

    /// The nearest $t$ in $(t_{min}, t_{max}]$ on the lateral surface.
    #[inline(always)]
    pub(crate) fn intersect(&self, r: &RayData<T>, t_max: T) -> Option<T> {
        if clears(
            &self.base,
            &self.axis,
            self.widest(),
            &r.origin,
            &r.dir,
            r.dd,
        ) {
            return None;
        }
        self.intersect_exact(r, t_max)
    }

    /// [`Cone::intersect`] without the pre-test [`clears`].
    #[inline(always)]
    fn intersect_exact(&self, r: &RayData<T>, t_max: T) -> Option<T> {
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

/// Relative widening of the squared radius in [`clears`]: $(1 + 2^{-8})^2 (1 + 2^{-6})
/// \approx 1.024$, rounded up. See [`clears`].
const CLEAR_WIDE: f64 = 1.03125;
/// Weight of the absolute error term in [`clears`] ($2^{-29}$). See [`clears`].
const CLEAR_SLACK: f64 = 1.0 / (1u64 << 29) as f64;

/// The pre-test of [`Cone::intersect`] (one ray, `S` a [`Real`]) and of
/// [`cone_lanes_clear`] (lanes, `S` a [`SimdF32`]): whether the line of the ray with
/// origin `o`, direction `d` and $d \cdot d$ `dd` certainly passes farther than the
/// widest radius `widest` from the axis line through `base` along the unit `axis`. Such
/// a ray misses the infinite cylinder of that radius, and so the cone. A ray that
/// reaches a cone's leaf mostly passes wide of it, as rings-s7's thin cylinders fill a
/// small part of their boxes: its single shadow rays test 6.7 cones each, and this test
/// spares 79 % of those tests the exact one (about 56 instructions instead of 150), so
/// 1,741 instructions a shadow ray instead of 1,874, and 0.950 of the frame's
/// (`tracer/JOURNAL.md`, "Cones tested against their axis line first").
///
/// With $w = o - b$ and $n = d \times \hat a$ the distance between the lines is
/// $|w \cdot n| / |n|$, so the test is $(w \cdot n)^2 > R^2 |n|^2$. It is made
/// conservative, so that it never rejects a ray the exact test would hit, by two
/// margins (Higham, *Accuracy and Stability of Numerical Algorithms*, ch. 3, for the
/// bounds). With $u = 2^{-24}$, the computed $n$ is within $4u|d|$ of the exact one and
/// the computed $w \cdot n$ within $8.1u|w||d|$; so if the computed values satisfy
/// $|w \cdot n| > R'|n| + E$ with $E = 32u|d|(|w| + R')$, the exact ones satisfy
/// $|w \cdot n| > R'|n|$. Squared with $(x + y)^2 \le (1 + \eta) x^2 + (1 + 1/\eta)
/// y^2$, $\eta = 2^{-6}$, that is implied by
/// $(w \cdot n)^2 > 1.03125\, R^2 |n|^2 + 2^{-29} (d \cdot d)(w \cdot w + R^2)$, which
/// also covers the rounding of this comparison (a few $u$ relative) and takes
/// $R' = (1 + 2^{-8}) R$: the exact test's own error, which near a tangent ray is a few
/// $u$ of the radius, and from a distant origin a few $u$ of $|w|$, falls inside it.
/// NaN anywhere makes the comparison false: no rejection. `cone_pre_test_never_rejects_a_hit`
/// checks the promise on grazing rays, distant origins and rays along the axis.
#[inline(always)]
fn clears<S: Scalar>(
    base: &Vec3<S>,
    axis: &Vec3<S>,
    widest: S,
    o: &Vec3<S>,
    d: &Vec3<S>,
    dd: S,
) -> S::Mask {
    let w = (o - base).eval();
    let n = d.cross(axis);
    let wn = w.dot(&n);
    let rr = widest * widest;
    let bound = rr * n.length_squared() * S::splat_f64(CLEAR_WIDE)
        + dd * (w.length_squared() + rr) * S::splat_f64(CLEAR_SLACK);
    (wn * wn).gt(bound)
}

/// The lanes of a packet whose rays certainly miss cone `c` ([`clears`]): where they are
/// every lane of a packet, the packet skips [`cone_packet`].
#[inline(always)]
pub(crate) fn cone_lanes_clear<S: SimdF32>(c: &Cone<f32>, r: &PacketData<S>) -> S::Mask {
    let splat3 = |v: &Vec3<f32>| vec3(S::splat(v[0]), S::splat(v[1]), S::splat(v[2]));
    clears(
        &splat3(&c.base),
        &splat3(&c.axis),
        S::splat(c.widest()),
        &r.origin,
        &r.dir,
        r.dd,
    )
}

/// [`Cone::intersect`] in every lane: the lanes with a hit in `(t_min, t_max]`, and their
/// distances. Each step is the single ray's, over the lanes; where the single ray
/// returns early (a negative or NaN discriminant, the near root in range) the lanes
/// compute on and select.
#[inline(always)]
pub(crate) fn cone_packet<S: SimdF32>(c: &Cone<f32>, r: &PacketData<S>, t_max: S) -> (S::Mask, S) {
    let splat3 = |v: &Vec3<f32>| vec3(S::splat(v[0]), S::splat(v[1]), S::splat(v[2]));
    let k = S::splat(c.slope);
    let axis = splat3(&c.axis);
    let w0 = (r.origin - splat3(&c.base)).eval();
    let mid = splat3(&(&c.axis).scale(c.height * 0.5).eval());
    let t_c = (mid - &w0).dot(&r.dir) * r.inv_dd;
    let w = (w0 + (&r.dir).scale(t_c)).eval();
    let ws = w.dot(&axis);
    let ds = r.dir.dot(&axis);
    let wp = (w - (&axis).scale(ws)).eval();
    let dp = (r.dir - (&axis).scale(ds)).eval();
    let rho = S::splat(c.base_radius) + k * ws;
    let dpdp = dp.length_squared();
    let wpwp = wp.length_squared();
    let wpdp = wp.dot(&dp);
    let kds = k * ds;
    let cr = wp.cross(&dp);
    let disc =
        rho * rho * dpdp - cr.length_squared() + kds * (kds * wpwp - S::splat(2.0) * rho * wpdp);
    // `disc < 0 || disc.is_nan()` rejects exactly the lanes where `disc >= 0` is false.
    let real = disc.ge(S::zero());
    let a = dpdp - kds * kds;
    let b = wpdp - kds * rho;
    let cc = wpwp - rho * rho;
    let q = -(b + disc.sqrt().copysign(b));
    let (t0, t1) = (q / a, cc / q);
    let swap = t1.lt(t0);
    let (near, far) = (S::select(swap, t1, t0), S::select(swap, t0, t1));
    let (zero, height) = (S::zero(), S::splat(c.height));
    let (t_near, t_far) = (t_c + near, t_c + far);
    let (s_near, s_far) = (ws + near * ds, ws + far * ds);
    let near_ok =
        (t_near.gt(r.t_min).and(t_near.le(t_max))).and(s_near.ge(zero).and(s_near.le(height)));
    let far_ok = (t_far.gt(r.t_min).and(t_far.le(t_max))).and(s_far.ge(zero).and(s_far.le(height)));
    (
        real.and(near_ok.or(far_ok)),
        S::select(near_ok, t_near, t_far),
    )
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

    /// A cylinder, a cone with its tip at the apex, a slanted cone, and a thin cylinder
    /// far from the origin.
    fn sample_cones() -> [Cone<f32>; 4] {
        [
            Cone::new(vec3(0.0f32, 0.0, 0.0), 1.0, vec3(0.0, 0.0, 2.0), 1.0).unwrap(),
            Cone::new(vec3(0.0f32, 0.0, 0.0), 1.0, vec3(0.0, 0.0, 1.0), 0.0).unwrap(),
            Cone::new(vec3(1.0f32, -2.0, 0.5), 0.3, vec3(2.0, 1.0, 3.0), 0.7).unwrap(),
            Cone::new(
                vec3(1e4f32, 3e3, -2e3),
                0.05,
                vec3(1e4, 3e3 + 1.0, -2e3),
                0.05,
            )
            .unwrap(),
        ]
    }

    /// The pre-test never rejects a ray the exact test hits, and it does reject most
    /// rays that pass wide: over cylinders and cones of every size (thin and long, far
    /// from the origin, a tip at the apex), rays aimed at the surface and a relative
    /// `1e-7` to `1e-1` beside it, from near and distant origins, along and almost
    /// along the axis.
    #[test]
    fn cone_pre_test_never_rejects_a_hit() {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            // xorshift64*
            seed ^= seed >> 12;
            seed ^= seed << 25;
            seed ^= seed >> 27;
            (seed.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
        };
        let [cylinder, cone, slanted, far] = sample_cones();
        // Besides the sample cones, a thin cylinder and a tiny cone.
        let cones = [
            cylinder,
            cone,
            slanted,
            Cone::new(vec3(0.3f32, 0.2, 0.1), 0.01, vec3(0.9, 0.35, 0.4), 0.01).unwrap(),
            far,
            Cone::new(vec3(-5.0f32, 7.0, 2.0), 1e-3, vec3(-4.0, 7.5, 1.0), 2e-3).unwrap(),
        ];
        let (mut hits, mut wide, mut rejected) = (0, 0, 0);
        for c in &cones {
            let (u, v) = {
                let t = if c.axis[0].abs() < 0.9 {
                    vec3(1.0f32, 0.0, 0.0)
                } else {
                    vec3(0.0, 1.0, 0.0)
                };
                let u = c.axis.cross(&t).normalize();
                (u, c.axis.cross(&u))
            };
            let big = f64::from(c.widest());
            for i in 0..4000 {
                // A point at distance `beside` times the radius from the axis, at an
                // axial position inside or a little beyond the ends.
                let s = (next() * 1.2 - 0.1) * f64::from(c.height);
                let phi = next() * std::f64::consts::TAU;
                let beside = match i % 4 {
                    0 => 1.0 + 10f64.powf(-7.0 + 6.0 * next()),
                    1 => 1.0 - 10f64.powf(-7.0 + 6.0 * next()),
                    2 => 0.5 + next(),
                    _ => 1.0 + 3.0 * next(),
                };
                let radial = ((&u).scale(phi.cos() as f32) + (&v).scale(phi.sin() as f32)).eval();
                let target =
                    (c.base + (&c.axis).scale(s as f32) + (&radial).scale((beside * big) as f32))
                        .eval();
                // Directions mostly across the axis, some along it, some nearly along.
                let d = match i % 5 {
                    0 => (&c.axis)
                        .scale(if next() < 0.5 { 1.0 } else { -1.0 })
                        .eval(),
                    1 => ((&c.axis) + (&radial).scale(1e-4 * next() as f32)).eval(),
                    _ => {
                        let tangent = radial.cross(&c.axis);
                        ((&tangent).scale((next() * 2.0 - 1.0) as f32)
                            + (&c.axis).scale((next() * 2.0 - 1.0) as f32)
                            + (&radial).scale((next() * 0.2 - 0.1) as f32))
                        .eval()
                    }
                };
                let dist = [1e-2, 1.0, 1e2, 1e4][i % 4] * (0.5 + next());
                let o = (target - (&d).scale((dist / f64::from(d.length())) as f32)).eval();
                let Some(r) = RayData::new(&Ray::new(o, d)) else {
                    continue;
                };
                let exact = c.intersect_exact(&r, f32::MAX);
                let clear = clears(&c.base, &c.axis, c.widest(), &r.origin, &r.dir, r.dd);
                assert!(
                    !(clear && exact.is_some()),
                    "{c:?}: the pre-test rejects a hit at {exact:?}, ray {o:?} {d:?}"
                );
                hits += usize::from(exact.is_some());
                // The distance between the ray's line and the axis line, in f64.
                let f = |v: &Vec3<f32>| vec3(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]));
                let n = f(&d).cross(&f(&c.axis));
                let gap = (f(&o) - f(&c.base)).dot(&n).abs() / n.length();
                if gap > 1.05 * big && dist < 1e4 * big {
                    wide += 1;
                    rejected += usize::from(clear);
                }
                assert_eq!(c.intersect(&r, f32::MAX), if clear { None } else { exact });
            }
        }
        assert!(hits > 2000, "{hits} hits");
        // Rays whose lines pass more than 5 % beside the widest radius, from origins
        // within 10,000 radii: the pre-test spares nearly all of them the exact test.
        // (From farther, its margin for rounding, which grows with the distance, takes
        // over: for a radius of 0.05, beyond about 2,500 units.)
        assert!(rejected * 10 >= wide * 9, "{rejected} of {wide} rejected");
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

    /// `cone_packet` gives every lane the single-ray answer bit for bit, for each
    /// instruction set of the CPU: cylinders and cones (one a tip at the apex, one with a
    /// large offset from the origin), rays from outside, from inside, along the axis,
    /// parallel to a generator line, grazing, with short `t_max` and `t_min`.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn lanes_are_the_single_ray_answers() {
        use crate::geometry::ray_data::MAX_LANES;
        use vecexpr::simd::{Isa, Kernel, SimdMask};

        struct Lanes<'a> {
            cone: &'a Cone<f32>,
            rays: &'a [RayData<f32>],
            t_max: f32,
        }
        impl Kernel for Lanes<'_> {
            type Output = Vec<(Option<f32>, bool)>;
            fn run<S: SimdF32>(self) -> Self::Output {
                let mut out = Vec::new();
                for chunk in self.rays.chunks(S::LANES) {
                    let row = |f: &dyn Fn(&RayData<f32>) -> f32| {
                        let mut v = [0.0f32; MAX_LANES];
                        for (l, slot) in v.iter_mut().enumerate().take(S::LANES) {
                            *slot = f(&chunk[l.min(chunk.len() - 1)]);
                        }
                        S::load(&v)
                    };
                    let pd = PacketData {
                        origin: vec3(
                            row(&|r| r.origin[0]),
                            row(&|r| r.origin[1]),
                            row(&|r| r.origin[2]),
                        ),
                        dir: vec3(row(&|r| r.dir[0]), row(&|r| r.dir[1]), row(&|r| r.dir[2])),
                        t_min: row(&|r| r.t_min),
                        dd: row(&|r| r.dd),
                        inv_dd: row(&|r| r.inv_dd),
                        shear: None,
                    };
                    let (hit, t) = cone_packet(self.cone, &pd, S::splat(self.t_max));
                    let bits = hit.bitmask();
                    let clear = cone_lanes_clear(self.cone, &pd).bitmask();
                    let mut ts = [0.0f32; MAX_LANES];
                    t.store(&mut ts);
                    for (l, &t) in ts.iter().enumerate().take(chunk.len()) {
                        out.push(((bits >> l & 1 == 1).then_some(t), clear >> l & 1 == 1));
                    }
                }
                out
            }
        }

        let cones = sample_cones();
        let mut rays = Vec::new();
        let mut push = |o: Vec3<f32>, d: Vec3<f32>, t_min: f32| {
            if let Some(r) = RayData::new(&Ray {
                t_min,
                ..Ray::new(o, d)
            }) {
                rays.push(r);
            }
        };
        for c in &cones {
            let mid = (c.base + (&c.axis).scale(c.height * 0.5)).eval();
            let tip = (c.base + (&c.axis).scale(c.height)).eval();
            // Along the axis, and parallel to a generator line of the 45° cone.
            push((c.base - &c.axis).eval(), c.axis, 0.0);
            push(vec3(0.5, 0.0, -0.5), vec3(-1.0, 0.0, 1.0), 0.0);
            push(tip, (-&c.axis).eval(), 0.0);
            for i in 0..200 {
                let f = i as f32;
                let d = vec3((f * 1.7).sin(), (f * 2.3).cos(), (f * 0.9).sin());
                let far = (mid - (&d).scale(3.0 + f)).eval();
                push(far, d, 0.0);
                push(mid, d, 0.0);
                push(far, d, 2.0 + 0.02 * f);
                // Grazing: aimed at a point on the rim's circle and a little beside it.
                let off = vec3((f * 0.37).cos(), (f * 0.37).sin(), 0.0);
                let rim =
                    (c.base + (&off).scale(c.base_radius * (1.0 + 1e-6 * (f - 100.0)))).eval();
                push(far, (rim - &far).eval(), 0.0);
            }
        }
        let (mut hits, mut cleared) = (0, 0);
        for isa in Isa::available() {
            for c in &cones {
                for t_max in [f32::MAX, 3.0] {
                    let got = isa.dispatch(Lanes {
                        cone: c,
                        rays: &rays,
                        t_max,
                    });
                    for (r, (g, clear)) in rays.iter().zip(&got) {
                        let want = c.intersect(r, t_max);
                        assert_eq!(
                            g.map(f32::to_bits),
                            want.map(f32::to_bits),
                            "{isa} {c:?} {:?} {:?}",
                            r.origin,
                            r.dir
                        );
                        // The pre-test, too, gives each lane the single ray's answer.
                        let single = clears(&c.base, &c.axis, c.widest(), &r.origin, &r.dir, r.dd);
                        assert_eq!(*clear, single, "{isa} {c:?}");
                        hits += usize::from(want.is_some());
                        cleared += usize::from(*clear);
                    }
                }
            }
        }
        assert!(hits > 1000, "{hits} hits");
        assert!(cleared > 1000, "{cleared} rays cleared");
    }
}
