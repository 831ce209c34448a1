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
//!
//! [`Tri4`] holds up to four triangles of one BVH leaf in structure-of-arrays form and
//! runs the watertight test on all four against one ray in one pass over `vecexpr`
//! packets of four lanes (the layout of Embree's `Triangle4`, Wald et al., "Embree: A
//! Kernel Framework for Efficient CPU Ray Tracing", ACM TOG 33(4), 2014). Each lane
//! performs exactly the operations of `Triangle::intersect_watertight` in the same
//! order, with the same `f64` fallback on an exact zero, so its result is bit-identical
//! to the scalar test of that triangle.
//!
//! # One formula, two sources
//! The two lane versions of the watertight test, four triangles against one ray
//! (`Tri4`) and one triangle against a packet of rays (`triangle_packet`, used by
//! `packet_query`), are one source over `vecexpr`'s `SimdF32` lanes (`sheared_edges`,
//! `watertight_finish`); they differ only in which operands are splatted. The
//! single-ray test stays a separate source: it leaves at the first failed test (the
//! sign test rejects most triangles before the division), recomputes an exact zero in
//! `f64` inline and reads the shear axes by index, none of which a lane version can do
//! for all lanes at once; written over a one-lane type it would compute every step for
//! every triangle.

use super::ray_data::{PacketData, PacketShear, RayData};
use crate::float::{Family, Float, ScalarOf};
use vecexpr::simd::{SimdF32, SimdMask};
use vecexpr::{vec3, Expr, Mask, Real, Vec3};

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

/// Lanes of a [`Tri4`].
pub const TRI4_LANES: usize = 4;

/// Up to four triangles in structure-of-arrays form (160 bytes in `f32`): `v[vertex]
/// [axis][lane]`, and the index of each lane's triangle in the triangle array. A group
/// with fewer than four triangles repeats its last one in the unused lanes, which
/// reports the same hit twice and so changes no result.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(16))]
pub struct Tri4<T: Real> {
    /// Vertex `k`, axis `a`, lane `i`: `v[k][a][i]`.
    pub v: [[[T; TRI4_LANES]; 3]; 3],
    /// Index of lane `i`'s triangle in the triangle array.
    pub index: [u32; TRI4_LANES],
}

/// What `Tri4::intersect_watertight` found: hit lanes as bits (`1 << lane`) and the
/// per-lane $(t, b_1, b_2)$, valid for the hit lanes.
#[derive(Clone, Copy, Debug)]
pub struct Tri4Hits<T: Real> {
    /// Bit `i` set: lane `i` is hit with $t \in (t_{min}, t_{max}]$.
    pub bits: u32,
    /// Distance per lane.
    pub t: [T; TRI4_LANES],
    /// Barycentric of vertex 1 per lane.
    pub b1: [T; TRI4_LANES],
    /// Barycentric of vertex 2 per lane.
    pub b2: [T; TRI4_LANES],
}

impl<T: Real> Tri4<T> {
    /// Groups `tris` (one to four triangles, with their indices) into lanes, repeating
    /// the last one in unused lanes.
    pub fn new(tris: &[(u32, Triangle<T>)]) -> Self {
        assert!(!tris.is_empty() && tris.len() <= TRI4_LANES);
        let lane = |i: usize| &tris[i.min(tris.len() - 1)];
        Self {
            v: core::array::from_fn(|k| {
                core::array::from_fn(|a| core::array::from_fn(|i| lane(i).1.v[k][a]))
            }),
            index: core::array::from_fn(|i| lane(i).0),
        }
    }

    /// Lane `i`'s triangle.
    #[inline(always)]
    fn triangle(&self, i: usize) -> Triangle<T> {
        Triangle {
            v: core::array::from_fn(|k| vec3(self.v[k][0][i], self.v[k][1][i], self.v[k][2][i])),
        }
    }
}

impl<T: Float> Tri4<T> {
    /// The watertight test of `Triangle::intersect_watertight` on all four lanes:
    /// lane `i` of the result is bit for bit what the scalar test returns for lane
    /// `i`'s triangle. In `f32` on x86-64 the lanes are one SSE register
    /// ([`vecexpr::simd::F32x4`], [`Tri4::intersect_lanes`]); `vecexpr` has no `f64`
    /// lane type, so in `f64` (and off x86-64) the scalar test runs lane by lane.
    #[inline(always)]
    pub(crate) fn intersect_watertight(&self, r: &RayData<T>, t_max: T) -> Tri4Hits<T> {
        #[cfg(target_arch = "x86_64")]
        if let Some(p) = T::AS_F32 {
            let g = T::to_f32::<Tri4Of>(p, self);
            let rf = T::to_f32::<RayDataOf>(p, r);
            let t_max = *T::to_f32::<ScalarOf>(p, &t_max);
            let h = g.intersect_lanes::<vecexpr::simd::F32x4>(rf, t_max);
            return T::from_f32::<Tri4HitsOf>(p, h);
        }
        let mut h = Tri4Hits {
            bits: 0,
            t: [T::ZERO; TRI4_LANES],
            b1: [T::ZERO; TRI4_LANES],
            b2: [T::ZERO; TRI4_LANES],
        };
        for i in 0..TRI4_LANES {
            if let Some((t, b1, b2)) = self.triangle(i).intersect_watertight(r, t_max) {
                h.bits |= 1 << i;
                (h.t[i], h.b1[i], h.b2[i]) = (t, b1, b2);
            }
        }
        h
    }
}

impl Tri4<f32> {
    /// `Tri4::intersect_watertight` over the `f32` lanes `S` (four of them).
    #[inline(always)]
    fn intersect_lanes<S: SimdF32>(&self, r: &RayData<f32>, t_max: f32) -> Tri4Hits<f32> {
        let (a, b, c) = (
            relative(&self.v[0], r),
            relative(&self.v[1], r),
            relative(&self.v[2], r),
        );
        // The ray's lanes are loaded, not splatted here (see `ShearLanes`).
        let [sx, sy, sz] = r.lanes.s.map(|l| S::load(&l));
        let e = sheared_edges(&a, &b, &c, sx, sy);
        let zero = S::zero();
        let [u, v, w] = e.uvw;
        let any_zero = u
            .eq_mask(zero)
            .or(v.eq_mask(zero))
            .or(w.eq_mask(zero))
            .bitmask();
        let uvw = if any_zero != 0 {
            exact_edges(any_zero, e.xy, e.uvw)
        } else {
            e.uvw
        };
        let (t_min, t_max) = (S::splat(r.t_min), S::splat(t_max));
        let h = watertight_finish::<S, false>(uvw, [a[2], b[2], c[2]], sz, t_min, t_max);
        Tri4Hits {
            bits: h.hit.bitmask(),
            t: lanes4(h.t),
            b1: lanes4(h.b1),
            b2: lanes4(h.b2),
        }
    }
}

/// The watertight test of one triangle against a packet of rays sharing their shear
/// axes (`f32` lanes, one ray a lane): [`Triangle::intersect_watertight`] lane by lane,
/// except that the lanes with an edge function exactly zero are not decided here but
/// returned in [`TriangleLanes::exact`], for the single-ray test to decide in `f64`.
#[inline(always)]
pub(crate) fn triangle_packet<S: SimdF32>(
    tri: &Triangle<f32>,
    r: &PacketData<S>,
    s: &PacketShear<S>,
    t_max: S,
) -> TriangleLanes<S> {
    let (a, b, c) = (rel(&tri.v[0], s), rel(&tri.v[1], s), rel(&tri.v[2], s));
    let e = sheared_edges(&a, &b, &c, s.sx, s.sy);
    let zero = S::zero();
    let [u, v, w] = e.uvw;
    let exact = u.eq_mask(zero).or(v.eq_mask(zero)).or(w.eq_mask(zero));
    let h = watertight_finish::<S, true>(e.uvw, [a[2], b[2], c[2]], s.sz, r.t_min, t_max);
    TriangleLanes {
        hit: h.hit.and(exact.not()),
        exact,
        t: h.t,
        b1: h.b1,
        b2: h.b2,
    }
}

/// One vertex of four triangles relative to the ray origin, in the sheared axis order.
#[inline(always)]
fn relative<S: SimdF32>(v: &[[f32; TRI4_LANES]; 3], r: &RayData<f32>) -> [S; 3] {
    let (s, o) = (&r.shear, &r.lanes.origin);
    [
        S::load(&v[s.kx]) - S::load(&o[0]),
        S::load(&v[s.ky]) - S::load(&o[1]),
        S::load(&v[s.kz]) - S::load(&o[2]),
    ]
}

/// The four lanes of `x`.
#[inline(always)]
fn lanes4<S: SimdF32>(x: S) -> [f32; TRI4_LANES] {
    let mut a = [0.0; TRI4_LANES];
    x.store(&mut a);
    a
}

/// What [`triangle_packet`] found: hit lanes, lanes the single-ray test must decide
/// (an edge function exactly zero), and the hits' `t`, `b1`, `b2`.
pub(crate) struct TriangleLanes<S: SimdF32> {
    pub(crate) hit: S::Mask,
    pub(crate) exact: S::Mask,
    pub(crate) t: S,
    pub(crate) b1: S,
    pub(crate) b2: S,
}

/// Vertex `v` relative to the origins, in the sheared axis order: lane by lane the
/// single-ray test's `a[kx]`, `a[ky]`, `a[kz]`. (Functions, not closures, carry the
/// lane operations throughout: a closure does not inherit the instruction set of the
/// `#[target_feature]` entry point and may be left out of line with calls to the
/// intrinsics inside.)
#[inline(always)]
fn rel<S: SimdF32>(v: &Vec3<f32>, s: &PacketShear<S>) -> [S; 3] {
    [
        S::splat(v[s.kx]) - s.o[0],
        S::splat(v[s.ky]) - s.o[1],
        S::splat(v[s.kz]) - s.o[2],
    ]
}

/// The sheared `x`, `y` of the three vertices and the edge functions, lane by lane as
/// `Triangle::intersect_watertight` computes them.
struct Edges<S> {
    /// `[ax, ay, bx, by, cx, cy]`.
    xy: [S; 6],
    /// `[u, v, w]`.
    uvw: [S; 3],
}

/// The lanes' edge functions of vertices `a`, `b`, `c` (relative to the ray origin, in
/// the sheared axis order) with the shear `sx`, `sy`: the one source of both lane
/// versions of the watertight test (four triangles against one ray, one triangle
/// against a packet of rays).
#[inline(always)]
fn sheared_edges<S: SimdF32>(a: &[S; 3], b: &[S; 3], c: &[S; 3], sx: S, sy: S) -> Edges<S> {
    let (ax, ay) = (a[0] - sx * a[2], a[1] - sy * a[2]);
    let (bx, by) = (b[0] - sx * b[2], b[1] - sy * b[2]);
    let (cx, cy) = (c[0] - sx * c[2], c[1] - sy * c[2]);
    Edges {
        xy: [ax, ay, bx, by, cx, cy],
        uvw: [cx * by - cy * bx, ax * cy - ay * cx, bx * ay - by * ax],
    }
}

/// What [`watertight_finish`] found.
struct WatertightLanes<S: SimdF32> {
    hit: S::Mask,
    t: S,
    b1: S,
    b2: S,
}

/// The rest of the watertight test over lanes, from the edge functions `uvw` and the
/// unscaled sheared `z` of the vertices: the sign test (two-sided, zeros allowed on
/// edges), the determinant and the distance in `(t_min, t_max]`. With `EARLY`, the
/// distance is skipped where the sign test fails in every lane (no lane is hit then,
/// and the other values are not read): one triangle against a packet of rays, where
/// that is most tests, 0.972 to 0.984 of the eye packets' instructions on the seven
/// classic scenes. Four triangles against one ray do without it: there the extra branch
/// cost more than it saved (1.006 to 1.014 of the single eye rays' instructions on the
/// triangle scenes; `tracer/JOURNAL.md`, "The node's last cache line fetched early, and
/// where the per-ray instructions go").
#[inline(always)]
fn watertight_finish<S: SimdF32, const EARLY: bool>(
    [u, v, w]: [S; 3],
    [az, bz, cz]: [S; 3],
    sz: S,
    t_min: S,
    t_max: S,
) -> WatertightLanes<S> {
    let zero = S::zero();
    let neg = u.lt(zero).or(v.lt(zero)).or(w.lt(zero));
    let pos = u.gt(zero).or(v.gt(zero)).or(w.gt(zero));
    let det = u + v + w;
    let inside = neg.and(pos).not().and(det.eq_mask(zero).not());
    if EARLY && !inside.any() {
        // No lane's ray passes inside the triangle: the distance, with its division,
        // is not needed.
        return WatertightLanes {
            hit: inside,
            t: zero,
            b1: zero,
            b2: zero,
        };
    }
    let t_scaled = u * (sz * az) + v * (sz * bz) + w * (sz * cz);
    let inv = det.recip();
    let t = t_scaled * inv;
    let accept = t.gt(t_min).and(t.le(t_max));
    WatertightLanes {
        hit: inside.and(accept),
        t,
        b1: v * inv,
        b2: w * inv,
    }
}

/// The scalar test's `f64` recomputation of the edge functions, on the lanes of
/// `lanes` (bits) where one of them is exactly zero; `p = [ax, ay, bx, by, cx, cy]`.
#[cold]
#[inline(never)]
fn exact_edges<S: SimdF32>(lanes: u32, p: [S; 6], uvw: [S; 3]) -> [S; 3] {
    let [ax, ay, bx, by, cx, cy] = p.map(lanes4);
    let [mut u, mut v, mut w] = uvw.map(lanes4);
    let e = |p: f32, q: f32, r: f32, s: f32| {
        (f64::from(p) * f64::from(q) - f64::from(r) * f64::from(s)) as f32
    };
    for i in 0..TRI4_LANES {
        if lanes & (1 << i) != 0 {
            u[i] = e(cx[i], by[i], cy[i], bx[i]);
            v[i] = e(ax[i], cy[i], ay[i], cx[i]);
            w[i] = e(bx[i], ay[i], by[i], ax[i]);
        }
    }
    [S::load(&u), S::load(&v), S::load(&w)]
}

/// [`Family`]s of the types [`Tri4::intersect_watertight`] views as `f32`.
struct Tri4Of;
impl Family for Tri4Of {
    type Of<T: Float> = Tri4<T>;
}
struct Tri4HitsOf;
impl Family for Tri4HitsOf {
    type Of<T: Float> = Tri4Hits<T>;
}
struct RayDataOf;
impl Family for RayDataOf {
    type Of<T: Float> = RayData<T>;
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

    /// Lane by lane, `Tri4` must return exactly what the scalar test returns.
    fn check_tri4<T: Float>(tris: &[Triangle<T>], r: &RayData<T>, t_max: T) {
        for chunk in tris.chunks(TRI4_LANES) {
            let lanes: Vec<(u32, Triangle<T>)> = chunk
                .iter()
                .enumerate()
                .map(|(i, t)| (i as u32, *t))
                .collect();
            let g = Tri4::new(&lanes);
            let h = g.intersect_watertight(r, t_max);
            for i in 0..TRI4_LANES {
                let scalar = chunk[i.min(chunk.len() - 1)].intersect_watertight(r, t_max);
                assert_eq!(h.bits & (1 << i) != 0, scalar.is_some(), "lane {i}");
                if let Some((t, b1, b2)) = scalar {
                    let bits = |x: T| x.to_f64().to_bits();
                    assert_eq!(
                        (bits(h.t[i]), bits(h.b1[i]), bits(h.b2[i])),
                        (bits(t), bits(b1), bits(b2)),
                        "lane {i}"
                    );
                }
            }
        }
    }

    fn tri4_matches_scalar<T: Float>() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = move |range: f64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            ((seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) * range
        };
        let f = <T as Real>::from_f64;
        // Random triangles and rays.
        let mut random = || vec3(f(next(2.0)), f(next(2.0)), f(next(2.0)));
        let tris: Vec<Triangle<T>> = (0..64)
            .map(|_| Triangle {
                v: [random(), random(), random()],
            })
            .collect();
        for _ in 0..200 {
            let o = vec3(f(next(4.0)), f(next(4.0)), f(next(4.0)));
            let d = vec3(f(next(1.0)), f(next(1.0)), f(next(1.0)));
            if let Some(r) = RayData::new(&Ray::new(o, d)) {
                check_tri4(&tris, &r, r.t_limit);
                check_tri4(&tris, &r, f(1.5));
            }
        }
        // A grid of integer triangles sharing edges and vertices, and axis-aligned and
        // diagonal rays through those edges and vertices: edge functions exactly zero,
        // so the f64 recomputation runs in some lanes and not in others.
        let mut grid = Vec::new();
        for i in 0..3 {
            for j in 0..3 {
                let p = |x: i32, y: i32| vec3(f(x as f64), f(y as f64), f(((x + y) % 2) as f64));
                grid.push(Triangle {
                    v: [p(i, j), p(i + 1, j), p(i + 1, j + 1)],
                });
                grid.push(Triangle {
                    v: [p(i, j), p(i + 1, j + 1), p(i, j + 1)],
                });
            }
        }
        for x in 0..7 {
            for y in 0..7 {
                let (px, py) = (f(x as f64 * 0.5), f(y as f64 * 0.5));
                for d in [
                    vec3(f(0.0), f(0.0), f(-1.0)),
                    vec3(f(0.0), f(0.0), f(1.0)),
                    vec3(f(0.25), f(0.25), f(-1.0)),
                    vec3(f(1.0), f(0.0), f(0.0)),
                    vec3(f(1.0), f(1.0), f(0.0)),
                ] {
                    let o = vec3(px, py, f(3.0)) - (&d).scale(f(2.0));
                    let r = RayData::new(&Ray::new(o.eval(), d)).unwrap();
                    check_tri4(&grid, &r, r.t_limit);
                }
            }
        }
    }

    #[test]
    fn tri4_lanes_match_the_scalar_test_bit_for_bit() {
        tri4_matches_scalar::<f32>();
        tri4_matches_scalar::<f64>();
    }

    /// `RayData` with the paper's winding swap (`kx`, `ky` exchanged where the
    /// direction's `kz` component is negative).
    fn swapped<T: Float>(r: &RayData<T>) -> RayData<T> {
        let mut w = *r;
        if r.dir[r.shear.kz] < T::ZERO {
            let s = &mut w.shear;
            (s.kx, s.ky, s.sx, s.sy) = (s.ky, s.kx, s.sy, s.sx);
            w.lanes.origin.swap(0, 1);
            w.lanes.s.swap(0, 1);
        }
        w
    }

    /// The shear without the winding swap gives the same answers as with it, bit for
    /// bit up to the sign of a zero (see `Shear`): random triangles and rays, and rays
    /// through shared edges and vertices of a grid (edge functions exactly zero), in
    /// the scalar and the four-lane test.
    fn swap_changes_nothing<T: Float>() {
        let f = <T as Real>::from_f64;
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = |range: f64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            ((seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) * range
        };
        let mut tris = Vec::new();
        for _ in 0..64 {
            let mut p = || vec3(f(next(2.0)), f(next(2.0)), f(next(2.0)));
            tris.push(Triangle { v: [p(), p(), p()] });
        }
        for i in 0..3 {
            for j in 0..3 {
                let p = |x: i32, y: i32| vec3(f(x as f64), f(y as f64), f(((x + y) % 2) as f64));
                tris.push(Triangle {
                    v: [p(i, j), p(i + 1, j), p(i + 1, j + 1)],
                });
            }
        }
        // `x + 0` is `x`, with `-0` made `+0`.
        let canonical = |x: T| (x + T::ZERO).to_f64().to_bits();
        let bits = |h: Option<(T, T, T)>| h.map(|(t, b1, b2)| [t, b1, b2].map(canonical));
        let mut rays = Vec::new();
        for _ in 0..400 {
            let o = vec3(f(next(4.0)), f(next(4.0)), f(next(4.0)));
            rays.push((o, vec3(f(next(1.0)), f(next(1.0)), f(next(1.0)))));
        }
        for x in 0..7 {
            for y in 0..7 {
                let d = vec3(f(0.0), f(0.0), f(if (x + y) % 2 == 0 { -1.0 } else { 1.0 }));
                let o = vec3(f(x as f64 * 0.5), f(y as f64 * 0.5), f(3.0)) - (&d).scale(f(2.0));
                rays.push((o.eval(), d));
            }
        }
        let mut negative = 0;
        for (o, d) in rays {
            let Some(r) = RayData::new(&Ray::new(o, d)) else {
                continue;
            };
            let w = swapped(&r);
            negative += usize::from(r.dir[r.shear.kz] < T::ZERO);
            for t in &tris {
                let (a, b) = (
                    t.intersect_watertight(&r, r.t_limit),
                    t.intersect_watertight(&w, w.t_limit),
                );
                assert_eq!(bits(a), bits(b), "{t:?} {o:?} {d:?}");
            }
            for g in tris.chunks_exact(TRI4_LANES) {
                let quad: [(u32, Triangle<T>); TRI4_LANES] =
                    core::array::from_fn(|i| (i as u32, g[i]));
                let g = Tri4::new(&quad);
                let (a, b) = (
                    g.intersect_watertight(&r, r.t_limit),
                    g.intersect_watertight(&w, w.t_limit),
                );
                assert_eq!(a.bits, b.bits);
                for i in 0..TRI4_LANES {
                    if a.bits & (1u32 << i) != 0 {
                        let l = |h: &Tri4Hits<T>| [h.t[i], h.b1[i], h.b2[i]].map(canonical);
                        assert_eq!(l(&a), l(&b));
                    }
                }
            }
        }
        assert!(
            negative > 100,
            "rays with a negative kz component: {negative}"
        );
    }

    #[test]
    fn the_winding_swap_changes_no_answer() {
        swap_changes_nothing::<f32>();
        swap_changes_nothing::<f64>();
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
