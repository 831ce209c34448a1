//! Triangles: the watertight test (default) and Möller–Trumbore.
//!
//! - S. Woop, C. Benthin, I. Wald, "Watertight Ray/Triangle Intersection", JCGT 2(1),
//!   2013. The vertices are translated to the ray origin and sheared so the ray becomes
//!   the +z axis; the 2D edge functions $U, V, W$ of the sheared vertices then decide
//!   inside/outside. An edge shared by two triangles is evaluated from the same two
//!   vertices with the same operations (only the sign differs), so a ray can never slip
//!   between them. When an edge function is exactly zero it is recomputed in `f64` (their
//!   section 4) so the decision on the edge itself is consistent too.
//! - T. Möller, B. Trumbore, "Fast, Minimum Storage Ray/Triangle Intersection", Journal
//!   of Graphics Tools 2(1), 1997. Faster to set up, but not watertight.
//!
//! Both are two-sided (no culling) and report barycentrics $(b_1, b_2)$ of vertices 1
//! and 2. The triangle stores its three vertices rather than edges: the watertight
//! test needs the exact shared vertex values.

use super::ray_data::RayData;
use vecexpr::{Expr, Real, Vec3};

/// A triangle as the traversal sees it (36 bytes in `f32`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle<T: Real> {
    /// Vertices, counter-clockwise seen from the front.
    pub v: [Vec3<T>; 3],
}

impl<T: Real> Triangle<T> {
    /// Watertight test: $(t, b_1, b_2)$ for $t \in (t_{min}, t_{max}]$.
    #[inline(always)]
    pub(crate) fn intersect_watertight(&self, r: &RayData<T>, t_max: T) -> Option<(T, T, T)> {
        let s = &r.shear;
        // Vertices relative to the origin.
        let a = (self.v[0] - r.origin).eval();
        let b = (self.v[1] - r.origin).eval();
        let c = (self.v[2] - r.origin).eval();
        // Shear in x and y (z is scaled only when needed, below).
        let (ax, ay) = (a[s.kx] - s.sx * a[s.kz], a[s.ky] - s.sy * a[s.kz]);
        let (bx, by) = (b[s.kx] - s.sx * b[s.kz], b[s.ky] - s.sy * b[s.kz]);
        let (cx, cy) = (c[s.kx] - s.sx * c[s.kz], c[s.ky] - s.sy * c[s.kz]);
        // Scaled barycentrics: U for vertex 0 (edge 1-2), V for 1, W for 2.
        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        if u == T::ZERO || v == T::ZERO || w == T::ZERO {
            let e = |p: T, q: T, r: T, s: T| {
                <T as Real>::from_f64(p.to_f64() * q.to_f64() - r.to_f64() * s.to_f64())
            };
            u = e(cx, by, cy, bx);
            v = e(ax, cy, ay, cx);
            w = e(bx, ay, by, ax);
        }
        // Two-sided: all of one sign (zeros allowed on edges).
        let zero = T::ZERO;
        if (u < zero || v < zero || w < zero) && (u > zero || v > zero || w > zero) {
            return None;
        }
        let det = u + v + w;
        if det == zero {
            return None;
        }
        let (az, bz, cz) = (s.sz * a[s.kz], s.sz * b[s.kz], s.sz * c[s.kz]);
        let t_scaled = u * az + v * bz + w * cz;
        let inv = det.recip();
        let t = t_scaled * inv;
        if !r.accepts(t, t_max) {
            return None;
        }
        Some((t, v * inv, w * inv))
    }

    /// Möller–Trumbore: $(t, b_1, b_2)$ for $t \in (t_{min}, t_{max}]$.
    #[inline(always)]
    pub(crate) fn intersect_moller_trumbore(&self, r: &RayData<T>, t_max: T) -> Option<(T, T, T)> {
        let e1 = (self.v[1] - self.v[0]).eval();
        let e2 = (self.v[2] - self.v[0]).eval();
        let p = r.dir.cross(&e2);
        let det = e1.dot(&p);
        if det == T::ZERO || !det.is_finite() {
            return None;
        }
        let inv = det.recip();
        let s = (r.origin - self.v[0]).eval();
        let u = s.dot(&p) * inv;
        if !(u >= T::ZERO && u <= T::ONE) {
            return None;
        }
        let q = s.cross(&e1);
        let v = r.dir.dot(&q) * inv;
        if !(v >= T::ZERO && u + v <= T::ONE) {
            return None;
        }
        let t = e2.dot(&q) * inv;
        if !r.accepts(t, t_max) {
            return None;
        }
        Some((t, u, v))
    }

    /// Twice the area vector $(v_1 - v_0) \times (v_2 - v_0)$.
    #[inline]
    pub fn area_vector(&self) -> Vec3<T> {
        (self.v[1] - self.v[0]).cross(self.v[2] - self.v[0])
    }

    /// The point with barycentrics $(1 - b_1 - b_2, b_1, b_2)$.
    #[inline]
    pub fn point(&self, b1: T, b2: T) -> Vec3<T> {
        let b0 = T::ONE - b1 - b2;
        ((&self.v[0]).scale(b0) + (&self.v[1]).scale(b1) + (&self.v[2]).scale(b2)).eval()
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

    fn tri() -> Triangle<f64> {
        Triangle {
            v: [
                vec3(0.0, 0.0, 0.0),
                vec3(2.0, 0.0, 0.0),
                vec3(0.0, 2.0, 0.0),
            ],
        }
    }

    #[test]
    fn both_tests_agree_on_barycentrics() {
        let t = tri();
        for (o, d) in [
            (vec3(0.5, 0.5, 3.0), vec3(0.0, 0.0, -1.0)),
            (vec3(0.5, 0.5, -3.0), vec3(0.0, 0.0, 1.0)),
            (vec3(-1.0, 0.25, 1.0), vec3(1.5, 0.25, -1.0)),
        ] {
            let r = data(o, d);
            let a = t.intersect_watertight(&r, f64::MAX).unwrap();
            let b = t.intersect_moller_trumbore(&r, f64::MAX).unwrap();
            assert!(
                (a.0 - b.0).abs() < 1e-12 && (a.1 - b.1).abs() < 1e-12 && (a.2 - b.2).abs() < 1e-12
            );
            let p = t.point(a.1, a.2);
            assert!(p.approx_eq(r.origin + (&r.dir).scale(a.0), 1e-12));
        }
        let r = data(vec3(0.5, 0.5, 3.0), vec3(0.0, 0.0, -1.0));
        let (t_hit, b1, b2) = t.intersect_watertight(&r, f64::MAX).unwrap();
        assert_eq!((t_hit, b1, b2), (3.0, 0.25, 0.25));
    }

    #[test]
    fn misses() {
        let t = tri();
        let outside = data(vec3(1.5, 1.5, 3.0), vec3(0.0, 0.0, -1.0));
        assert!(t.intersect_watertight(&outside, f64::MAX).is_none());
        assert!(t.intersect_moller_trumbore(&outside, f64::MAX).is_none());
        let parallel = data(vec3(0.5, 0.5, 1.0), vec3(1.0, 0.0, 0.0));
        assert!(t.intersect_watertight(&parallel, f64::MAX).is_none());
        assert!(t.intersect_moller_trumbore(&parallel, f64::MAX).is_none());
        let behind = data(vec3(0.5, 0.5, 3.0), vec3(0.0, 0.0, 1.0));
        assert!(t.intersect_watertight(&behind, f64::MAX).is_none());
        assert!(t.intersect_moller_trumbore(&behind, f64::MAX).is_none());
        let near = data(vec3(0.5, 0.5, 3.0), vec3(0.0, 0.0, -1.0));
        assert!(t.intersect_watertight(&near, 2.5).is_none());
    }

    #[test]
    fn shared_edge_is_hit_exactly_once_or_twice_never_zero() {
        // Two triangles sharing the diagonal of the unit square; rays straight through
        // the diagonal.
        let q = [
            vec3(0.0f32, 0.0, 0.0),
            vec3(1.0, 0.0, 0.0),
            vec3(1.0, 1.0, 0.0),
            vec3(0.0, 1.0, 0.0),
        ];
        let t1 = Triangle {
            v: [q[0], q[1], q[2]],
        };
        let t2 = Triangle {
            v: [q[0], q[2], q[3]],
        };
        for i in 1..64 {
            // Exactly through the diagonal point (x, x, 0), from two directions.
            let x = i as f32 / 64.0;
            let d = if i % 2 == 0 {
                vec3(0.25f32, 0.25, -1.0)
            } else {
                vec3(-0.375f32, 0.125, -1.0)
            };
            let r = data(vec3(x - d[0], x - d[1], 1.0), d);
            let hits = [&t1, &t2]
                .iter()
                .filter(|t| t.intersect_watertight(&r, f32::MAX).is_some())
                .count();
            assert!(hits >= 1, "ray {i} slipped through");
        }
    }
}
