//! Closest hits of a packet of rays, one SIMD lane per ray, bit-identical to
//! [`Geometry::intersect`] ray by ray.
//!
//! The packet walks the binary BVH together ([`crate::bvh::packet`]); in a leaf, spheres
//! and triangles are tested against every ray of the packet at once with the formulas
//! of the single-ray kernels ([`super::sphere`], [`super::triangle`]) written over the
//! lane type, operation for operation and in the same order (no fused multiply-add
//! where the scalar code has none), so each lane computes exactly the single ray's
//! value. What the packet kernels do not cover runs the single-ray kernel for each ray
//! concerned:
//! - cones and planes;
//! - triangles when the rays' watertight shear axes differ (the axis of largest
//!   direction component), and the rays whose edge functions are exactly zero, which
//!   the single-ray test recomputes in `f64`;
//! - the Möller–Trumbore test and the brute-force mode, which trace each ray alone.
//!
//! Every hit is offered to the ray's closest-hit record in the single-ray way (closer,
//! or as close and earlier in the input), which makes the result independent of the
//! order the primitives are met in; the hit record is then filled in by the single-ray
//! code.

use super::ray_data::RayData;
use super::storage::{make_ref, INDEX_MASK, PLANE, SPHERE, TAG_SHIFT, TRIANGLE};
use super::{kinds, Best, Geometry, Sphere, Triangle, TriangleTest, NO_HIT};
use crate::bvh::packet::PacketRay;
use crate::bvh::TraversalRay;
use crate::ray::{Hit, Ray};
use vecexpr::simd::{SimdF32, SimdMask};
use vecexpr::{vec3, Expr, Mask, Vec3};

/// The widest packet (AVX-512: sixteen `f32` lanes).
pub const MAX_LANES: usize = 16;

/// Per-lane ray values of the packet kernels (what [`RayData`] holds for one ray).
struct PacketData<S: SimdF32> {
    origin: Vec3<S>,
    dir: Vec3<S>,
    t_min: S,
    dd: S,
    inv_dd: S,
    /// The watertight shear when every ray of the packet has the same axes.
    shear: Option<PacketShear<S>>,
}

struct PacketShear<S: SimdF32> {
    kx: usize,
    ky: usize,
    kz: usize,
    sx: S,
    sy: S,
    sz: S,
}

/// Lane `i` of the packet is `f(rd[i])`, or `f(fill)` where lane `i` has no ray.
#[inline(always)]
fn lanes<S: SimdF32>(
    rd: &[Option<RayData<f32>>; MAX_LANES],
    fill: &RayData<f32>,
    f: impl Fn(&RayData<f32>) -> f32,
) -> S {
    let buf: [f32; MAX_LANES] = core::array::from_fn(|i| f(rd[i].as_ref().unwrap_or(fill)));
    S::load(&buf)
}

/// [`Sphere::intersect`] in every lane: the lanes with a hit in `(t_min, t_max]`, and
/// their distances.
#[inline(always)]
fn sphere_packet<S: SimdF32>(s: &Sphere<f32>, r: &PacketData<S>, t_max: S) -> (S::Mask, S) {
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

/// What [`triangle_packet`] found: hit lanes, lanes the single-ray test must decide
/// (an edge function exactly zero), and the hits' `t`, `b1`, `b2`.
struct TriangleLanes<S: SimdF32> {
    hit: S::Mask,
    exact: S::Mask,
    t: S,
    b1: S,
    b2: S,
}

/// [`Triangle::intersect_watertight`] in every lane, for rays sharing their shear axes.
#[inline(always)]
fn triangle_packet<S: SimdF32>(
    tri: &Triangle<f32>,
    r: &PacketData<S>,
    s: &PacketShear<S>,
    t_max: S,
) -> TriangleLanes<S> {
    let vertex = |v: &Vec3<f32>| vec3(S::splat(v[0]), S::splat(v[1]), S::splat(v[2]));
    let a = (vertex(&tri.v[0]) - r.origin).eval();
    let b = (vertex(&tri.v[1]) - r.origin).eval();
    let c = (vertex(&tri.v[2]) - r.origin).eval();
    let (ax, ay) = (a[s.kx] - s.sx * a[s.kz], a[s.ky] - s.sy * a[s.kz]);
    let (bx, by) = (b[s.kx] - s.sx * b[s.kz], b[s.ky] - s.sy * b[s.kz]);
    let (cx, cy) = (c[s.kx] - s.sx * c[s.kz], c[s.ky] - s.sy * c[s.kz]);
    let u = cx * by - cy * bx;
    let v = ax * cy - ay * cx;
    let w = bx * ay - by * ax;
    let zero = S::zero();
    let exact = u.eq_mask(zero).or(v.eq_mask(zero)).or(w.eq_mask(zero));
    let some_neg = u.lt(zero).or(v.lt(zero)).or(w.lt(zero));
    let some_pos = u.gt(zero).or(v.gt(zero)).or(w.gt(zero));
    let det = u + v + w;
    let inside = some_neg.and(some_pos).not().and(det.eq_mask(zero).not());
    let (az, bz, cz) = (s.sz * a[s.kz], s.sz * b[s.kz], s.sz * c[s.kz]);
    let t_scaled = u * az + v * bz + w * cz;
    let inv = det.recip();
    let t = t_scaled * inv;
    let accepted = t.gt(r.t_min).and(t.le(t_max));
    TriangleLanes {
        hit: inside.and(accepted).and(exact.not()),
        exact,
        t,
        b1: v * inv,
        b2: w * inv,
    }
}

/// The lanes set in `bits`, lowest first.
#[inline(always)]
fn each_lane(mut bits: u32, mut f: impl FnMut(usize)) {
    while bits != 0 {
        f(bits.trailing_zeros() as usize);
        bits &= bits - 1;
    }
}

impl Geometry<f32> {
    /// The closest hit of each ray of a packet of `S::LANES` rays: `out[i]` is what
    /// [`Geometry::intersect`] returns for `rays[i]` (`None` where `rays[i]` is `None`),
    /// bit for bit. Meant to be called inside [`vecexpr::simd::Isa::dispatch`], so the
    /// lane operations compile to the instruction set's registers.
    ///
    /// # Panics
    /// If `rays` or `out` is shorter than `S::LANES`, or `S::LANES > 16`.
    #[inline(always)]
    pub fn intersect_packet<S: SimdF32>(
        &self,
        rays: &[Option<Ray<f32>>],
        out: &mut [Option<Hit<f32>>],
    ) {
        let n = S::LANES;
        assert!(n <= MAX_LANES && rays.len() >= n && out.len() >= n);
        let bvh = match (&self.bvh, self.triangle_test) {
            (Some(bvh), TriangleTest::Watertight) => bvh,
            _ => {
                for (o, r) in out[..n].iter_mut().zip(&rays[..n]) {
                    *o = r.as_ref().and_then(|r| self.intersect(r));
                }
                return;
            }
        };
        let rd: [Option<RayData<f32>>; MAX_LANES] = core::array::from_fn(|i| {
            if i < n {
                rays[i].as_ref().and_then(RayData::new)
            } else {
                None
            }
        });
        let Some(fill) = rd.iter().flatten().next().copied() else {
            out[..n].fill(None);
            return;
        };
        let mut best: [Best<f32>; MAX_LANES] = core::array::from_fn(|i| Best {
            r: NO_HIT,
            t: rd[i].as_ref().map_or(0.0, |r| r.t_limit),
            b1: 0.0,
            b2: 0.0,
        });
        // Planes first, as the single-ray query does.
        for (b, r) in best.iter_mut().zip(&rd) {
            if let Some(r) = r {
                for i in 0..self.prims.planes.len() {
                    let p = make_ref(PLANE, i);
                    if let Some(h) = self.test::<true, { kinds::ALL }>(p, r, b.t) {
                        self.offer(b, p, h);
                    }
                }
            }
        }
        let valid = rd
            .iter()
            .enumerate()
            .fold(0u32, |m, (i, r)| m | (u32::from(r.is_some()) << i));
        let trav: [Option<&TraversalRay<f32>>; MAX_LANES] =
            core::array::from_fn(|i| rd[i].as_ref().map(|r| &r.traversal));
        let Some(ray) = PacketRay::<S>::gather(&trav) else {
            out[..n].fill(None);
            return;
        };
        let same_axes = rd.iter().flatten().all(|r| {
            (r.shear.kx, r.shear.ky, r.shear.kz) == (fill.shear.kx, fill.shear.ky, fill.shear.kz)
        });
        let pd = PacketData::<S> {
            origin: vec3(
                lanes(&rd, &fill, |r| r.origin[0]),
                lanes(&rd, &fill, |r| r.origin[1]),
                lanes(&rd, &fill, |r| r.origin[2]),
            ),
            dir: vec3(
                lanes(&rd, &fill, |r| r.dir[0]),
                lanes(&rd, &fill, |r| r.dir[1]),
                lanes(&rd, &fill, |r| r.dir[2]),
            ),
            t_min: lanes(&rd, &fill, |r| r.t_min),
            dd: lanes(&rd, &fill, |r| r.dd),
            inv_dd: lanes(&rd, &fill, |r| r.inv_dd),
            shear: same_axes.then(|| PacketShear {
                kx: fill.shear.kx,
                ky: fill.shear.ky,
                kz: fill.shear.kz,
                sx: lanes(&rd, &fill, |r| r.shear.sx),
                sy: lanes(&rd, &fill, |r| r.shear.sy),
                sz: lanes(&rd, &fill, |r| r.shear.sz),
            }),
        };
        let best_t = |best: &[Best<f32>; MAX_LANES]| {
            let t: [f32; MAX_LANES] = core::array::from_fn(|i| best[i].t);
            S::load(&t)
        };
        let t0 = best_t(&best);
        bvh.traverse_packet(
            &ray,
            S::Mask::from_bitmask(valid),
            t0,
            |refs, mask, mut t_max| {
                let m = mask.bitmask();
                for &r in refs {
                    let i = (r & INDEX_MASK) as usize;
                    let mut improved = false;
                    // The single-ray test and offer for the lanes in `bits`.
                    let single = |bits: u32, best: &mut [Best<f32>; MAX_LANES]| {
                        let mut improved = false;
                        each_lane(bits, |l| {
                            let rd = rd[l].as_ref().expect("an active lane has a ray");
                            if let Some(h) = self.test::<true, { kinds::ALL }>(r, rd, best[l].t) {
                                improved |= self.offer(&mut best[l], r, h);
                            }
                        });
                        improved
                    };
                    match r >> TAG_SHIFT {
                        SPHERE => {
                            let (hit, t) = sphere_packet(&self.prims.spheres[i], &pd, t_max);
                            each_lane(hit.bitmask() & m, |l| {
                                improved |= self.offer(&mut best[l], r, (t.lane(l), 0.0, 0.0));
                            });
                        }
                        TRIANGLE => match &pd.shear {
                            Some(sh) => {
                                let h = triangle_packet(&self.prims.triangles[i], &pd, sh, t_max);
                                each_lane(h.hit.bitmask() & m, |l| {
                                    let hit = (h.t.lane(l), h.b1.lane(l), h.b2.lane(l));
                                    improved |= self.offer(&mut best[l], r, hit);
                                });
                                improved |= single(h.exact.bitmask() & m, &mut best);
                            }
                            None => improved |= single(m, &mut best),
                        },
                        _ => improved |= single(m, &mut best),
                    }
                    if improved {
                        t_max = best_t(&best);
                    }
                }
                t_max
            },
        );
        for (l, o) in out[..n].iter_mut().enumerate() {
            *o = match &rd[l] {
                Some(r) if best[l].r != NO_HIT => {
                    Some(self.make_hit::<{ kinds::ALL }>(&best[l], r))
                }
                _ => None,
            };
        }
    }
}
