//! Per-ray values shared by all primitive tests, computed once per query: [`RayData`] for
//! one ray, [`PacketData`] for a packet of rays in SIMD lanes (the same values, lane by
//! lane).

use crate::bvh::TraversalRay;
use crate::ray::Ray;
use vecexpr::simd::SimdF32;
use vecexpr::{Expr, Real, Vec3};

/// The shear that maps the ray to the +z axis for the watertight triangle test (Woop,
/// Benthin, Wald 2013, section 3): `kz` is the axis of largest $|d|$, `kx`, `ky` the
/// next two in cyclic order, and $S = (d_{kx}/d_{kz}, d_{ky}/d_{kz}, 1/d_{kz})$.
///
/// The paper swaps `kx` and `ky` when $d_{kz} < 0$ to keep the winding; the tests here
/// are two-sided, and the swap only negates the edge functions, the determinant and
/// the scaled distance (each a difference or sum of the same products), so without it
/// the hits are the same and their distances and barycentrics too, up to the sign of a
/// zero (a ray through a vertex has $b_1 = -0$ where the swap gave $+0$, or the
/// reverse); the axes then depend on `kz` alone. (`triangle`'s test
/// `the_winding_swap_changes_no_answer` checks it.)
#[derive(Clone, Copy, Debug)]
pub(crate) struct Shear<T: Real> {
    pub kx: usize,
    pub ky: usize,
    pub kz: usize,
    pub sx: T,
    pub sy: T,
    pub sz: T,
}

impl<T: Real> Shear<T> {
    /// The shear of direction `d` along axis `kz` (which [`Shear::kz`] chooses).
    #[inline(always)]
    fn along(d: &Vec3<T>, kz: usize) -> Self {
        let (kx, ky, kz) = Self::axes_of(kz);
        let sz = d[kz].recip();
        Self {
            kx,
            ky,
            kz,
            sx: d[kx] * sz,
            sy: d[ky] * sz,
            sz,
        }
    }

    /// The axis of largest $|d|$ (of equal ones the later, as the comparisons fall;
    /// some axis for NaN).
    #[inline(always)]
    pub(crate) fn kz(d: &Vec3<T>) -> usize {
        let a = [d[0].abs(), d[1].abs(), d[2].abs()];
        if a[0] > a[1] {
            if a[0] > a[2] {
                0
            } else {
                2
            }
        } else if a[1] > a[2] {
            1
        } else {
            2
        }
    }

    /// `(kx, ky, kz)` for the shear along `kz`.
    #[inline(always)]
    fn axes_of(kz: usize) -> (usize, usize, usize) {
        let kz = kz.min(2);
        let kx = if kz == 2 { 0 } else { kz + 1 };
        let ky = if kx == 2 { 0 } else { kx + 1 };
        (kx, ky, kz)
    }

    /// The axes `(kx, ky, kz)` of the shear of direction `d`.
    #[inline(always)]
    pub(crate) fn axes(d: &Vec3<T>) -> (usize, usize, usize) {
        Self::axes_of(Self::kz(d))
    }
}

/// A validated ray with everything the kernels precompute.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RayData<T: Real> {
    pub origin: Vec3<T>,
    pub dir: Vec3<T>,
    /// Exclusive lower bound on `t`.
    pub t_min: T,
    /// Inclusive upper bound: the largest `T` below the ray's exclusive `t_max`. Hits are
    /// accepted at `t <= t_limit` so that equal distances can be ordered by primitive
    /// index.
    pub t_limit: T,
    /// $d \cdot d$.
    pub dd: T,
    /// $1 / (d \cdot d)$.
    pub inv_dd: T,
    pub shear: Shear<T>,
    /// The origin in the shear's axis order and the shear's factors in four lanes, for
    /// the four-triangle test.
    pub lanes: ShearLanes<T>,
    pub traversal: TraversalRay<T>,
}

/// A ray's values the four-triangle test reads ([`crate::geometry::triangle::Tri4`]),
/// each in four lanes, made once per query. Splatted in the test instead, the optimiser
/// moved the splats of the closest-hit walk's leaf test to the top of the walk's loop:
/// about 25 instructions at every node rather than at the leaves (teapot-s12: 1,095
/// instead of 954 instructions a single eye ray). Made here, in the ray's record, the
/// test loads them. (Made in the query as a separate value, the optimiser forwarded the
/// splats into the test again and the gain was gone.) The any-hit walk, which kept
/// the splats at its leaves, pays for making them: 3 to 4 % more instructions a shadow
/// ray.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ShearLanes<T: Real> {
    /// `origin[kx]`, `origin[ky]`, `origin[kz]`.
    pub origin: [[T; 4]; 3],
    /// `sx`, `sy`, `sz`.
    pub s: [[T; 4]; 3],
}

impl<T: Real> ShearLanes<T> {
    /// The lanes of a ray with `origin` and shear `s`.
    #[inline(always)]
    fn new(origin: &Vec3<T>, s: &Shear<T>) -> Self {
        Self {
            origin: [s.kx, s.ky, s.kz].map(|k| [origin[k]; 4]),
            s: [s.sx, s.sy, s.sz].map(|v| [v; 4]),
        }
    }
}

impl<T: Real> RayData<T> {
    /// `None` for rays that cannot hit anything: a non-finite origin or direction, a
    /// direction whose squared length is zero, subnormal or overflows, a NaN bound, or an
    /// empty interval.
    #[inline(always)]
    pub fn new(ray: &Ray<T>) -> Option<Self> {
        Self::along(ray, Shear::kz(&ray.dir))
    }

    /// [`RayData::new`] with the shear along axis `kz`, which must be
    /// `Shear::kz(&ray.dir)`: the single-ray walks choose the axis first and are
    /// compiled once per axis, so that every vertex coordinate the triangle tests read
    /// sits at a constant offset.
    #[inline(always)]
    pub fn along(ray: &Ray<T>, kz: usize) -> Option<Self> {
        // `x * 0` is zero for finite `x` and NaN for an infinite or NaN one, so the sum
        // of the three products is zero exactly when every coordinate of the origin is
        // finite: one test instead of three. The direction needs no such test: an
        // infinite or NaN coordinate makes `dd` infinite or NaN, which the range test
        // of `dd` rejects (six instructions a ray fewer). The tests are combined
        // without short-circuits (`&`), so that a valid ray takes one branch here.
        let (o, zero) = (&ray.origin, T::ZERO);
        let finite = (o[0] * zero + o[1] * zero) + o[2] * zero == zero;
        let dd = ray.dir.length_squared();
        // `t_max > t_min` is false when either is NaN.
        let valid = finite & (dd >= T::MIN_POSITIVE) & (dd <= T::MAX) & (ray.t_max > ray.t_min);
        if !valid {
            return None;
        }
        let t_min = ray.t_min;
        let shear = Shear::along(&ray.dir, kz);
        Some(Self {
            origin: ray.origin,
            dir: ray.dir,
            t_min,
            // `next_down(inf)` is `MAX` too, but written out for an unbounded ray (every
            // eye ray) the single eye ray ran 15 to 22 instructions fewer (teapot-s12
            // 687 against 705, callgrind).
            t_limit: if ray.t_max == T::INFINITY {
                T::MAX
            } else {
                ray.t_max.next_down()
            },
            dd,
            inv_dd: dd.recip(),
            shear,
            lanes: ShearLanes::new(&ray.origin, &shear),
            traversal: TraversalRay::new(&ray.origin, &ray.dir, t_min),
        })
    }

    /// Is `t` in the accepted interval $(t_{min}, t_{max}]$ with `t_max` inclusive?
    #[inline(always)]
    pub fn accepts(&self, t: T, t_max: T) -> bool {
        t > self.t_min && t <= t_max
    }
}

/// The widest packet (AVX-512: sixteen `f32` lanes).
pub const MAX_LANES: usize = 16;

/// Per-lane ray values of the packet kernels (what [`RayData`] holds for one ray).
pub(crate) struct PacketData<S: SimdF32> {
    pub(crate) origin: Vec3<S>,
    pub(crate) dir: Vec3<S>,
    pub(crate) t_min: S,
    pub(crate) dd: S,
    pub(crate) inv_dd: S,
    /// The watertight shear when every ray of the packet has the same axes.
    pub(crate) shear: Option<PacketShear<S>>,
}

/// The watertight shear of a packet whose rays share their axes.
///
/// The origin is kept in the sheared axis order too, so a triangle test picks its
/// vertex coordinates by axis from memory (scalars, before the splat) and never indexes
/// a vector of registers by a run-time axis (which costs a round trip through memory).
pub(crate) struct PacketShear<S: SimdF32> {
    pub(crate) kx: usize,
    pub(crate) ky: usize,
    pub(crate) kz: usize,
    pub(crate) sx: S,
    pub(crate) sy: S,
    pub(crate) sz: S,
    /// The origins' `kx`, `ky`, `kz` coordinates.
    pub(crate) o: [S; 3],
}

#[cfg(test)]
mod tests {
    use super::*;
    use vecexpr::vec3;

    #[test]
    fn shear_axes() {
        let new = |d: Vec3<f64>| Shear::along(&d, Shear::kz(&d));
        let s = new(vec3(0.1, -0.2, 0.9));
        assert_eq!((s.kx, s.ky, s.kz), (0, 1, 2));
        let s = new(vec3(0.1, -0.2, -0.9));
        assert_eq!((s.kx, s.ky, s.kz), (0, 1, 2));
        let s = new(vec3(0.1, -0.95, -0.9));
        assert_eq!((s.kx, s.ky, s.kz), (2, 0, 1));
        let s = new(vec3(-3.0f64, 1.0, 1.0));
        assert_eq!((s.kx, s.ky, s.kz), (1, 2, 0));
        assert_eq!(s.sz, -1.0 / 3.0);
    }

    #[test]
    fn invalid_rays() {
        let o = vec3(0.0f32, 0.0, 0.0);
        let d = vec3(0.0f32, 0.0, 1.0);
        assert!(RayData::new(&Ray::new(o, d)).is_some());
        // Every coordinate of origin and direction, infinite or NaN, alone.
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            for k in 0..3 {
                let (mut ob, mut db) = (o, vec3(0.3f32, -0.4, 0.5));
                ob[k] = bad;
                db[k] = bad;
                assert!(RayData::new(&Ray::new(ob, d)).is_none(), "origin {ob:?}");
                assert!(RayData::new(&Ray::new(o, db)).is_none(), "direction {db:?}");
            }
        }
        // A direction whose squared length overflows or underflows.
        assert!(RayData::new(&Ray::new(o, vec3(3e19, 0.0, 0.0))).is_none());
        assert!(RayData::new(&Ray::new(o, vec3(1e-20, 0.0, 0.0))).is_none());
        assert!(RayData::new(&Ray::new(o, vec3(0.0, 0.0, 0.0))).is_none());
        assert!(RayData::new(&Ray {
            t_max: f32::NAN,
            ..Ray::new(o, d)
        })
        .is_none());
        assert!(RayData::new(&Ray {
            t_min: 2.0,
            t_max: 1.0,
            ..Ray::new(o, d)
        })
        .is_none());
        assert_eq!(RayData::new(&Ray::new(o, d)).unwrap().t_limit, f32::MAX);
    }
}
