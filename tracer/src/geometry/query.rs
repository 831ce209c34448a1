//! The one query driver, and the queries of one ray.
//!
//! Every query of the geometry, the closest hit or any hit, of one ray or of a packet
//! ([`super::packet_query`]), meets the geometry in the same order, written once in
//! [`Geometry::query`]: the planes first (they lie outside the BVH), then the BVH (the
//! four-wide tree or, with `--binary-bvh`, the binary one) or, without a BVH (`--no-bvh`),
//! every primitive. A query says what each step does by implementing [`Query`]:
//!
//! | query | [`Query::refs`] (planes, brute force) | [`Query::walk`] |
//! |---|---|---|
//! | [`ClosestRay`] | single-ray test, hit offered to the best | [`Bvh::walk`], leaves by [`ClosestRay::leaf`] |
//! | [`AnyRay`] | single-ray test, stops at the first hit | [`Bvh::walk`], leaves by [`AnyRay::leaf`] |
//! | `ClosestPacket` | single-ray test of each lane | [`Bvh::walk_packet`], leaves by the lane kernels |
//! | `AnyPacket` | single-ray test of each lane not yet blocked | [`Bvh::walk_packet`], leaves by the lane kernels |
//!
//! Everything is `#[inline(always)]`, so each query compiles to the code it would be
//! if written out alone; the packet queries hand their few remaining rays over to the
//! single-ray queries' own walk ([`ClosestRay::walk_from`], [`AnyRay::walk_from`]).

use super::ray_data::RayData;
use super::storage::{make_ref, PLANE, TRIANGLE};
use super::{kind_in, Best, Geometry};
use crate::bvh::wide::Leaf;
use crate::bvh::Bvh;
use crate::float::Float;

/// One query of the geometry: its side of each step of [`Geometry::query`].
pub(super) trait Query<T: Float> {
    /// The primitive kinds the query is compiled for (a [`super::kinds`] mask).
    const KINDS: u32;
    /// Tests the primitives `refs` with the single-ray kernels: the planes, and every
    /// primitive when there is no BVH. `true` once the query is answered (every ray of
    /// an any-hit query blocked); the driver then stops.
    fn refs(&mut self, refs: impl Iterator<Item = u32>) -> bool;
    /// Walks the BVH: the four-wide tree when `wide`, else the binary one.
    fn walk(&mut self, bvh: &Bvh, wide: bool);
}

impl<T: Float> Geometry<T> {
    /// The query driver: the planes first, then the BVH ([`AccelOptions::wide`] picks
    /// the tree) or, without one, every primitive. The only place that says in which
    /// order any query meets the geometry.
    ///
    /// [`AccelOptions::wide`]: super::AccelOptions::wide
    #[inline(always)]
    pub(super) fn query<Q: Query<T>>(&self, q: &mut Q) {
        let planes = if Q::KINDS & (1 << PLANE) != 0 {
            self.prims.planes.len()
        } else {
            0
        };
        if q.refs((0..planes).map(|i| make_ref(PLANE, i))) {
            return;
        }
        match &self.bvh {
            Some(bvh) => q.walk(bvh, self.wide),
            None => {
                q.refs(self.all_refs());
            }
        }
    }
}

/// The closest hit of one ray: every hit within `best.t` is offered to `best`
/// ([`Geometry::offer`]), which keeps the closest, and the earliest in the input among
/// equally close ones.
pub(super) struct ClosestRay<'a, T: Float, const WATERTIGHT: bool, const KINDS: u32> {
    pub(super) g: &'a Geometry<T>,
    pub(super) rd: &'a RayData<T>,
    pub(super) best: &'a mut Best<T>,
}

impl<T: Float, const WATERTIGHT: bool, const KINDS: u32> Query<T>
    for ClosestRay<'_, T, WATERTIGHT, KINDS>
{
    const KINDS: u32 = KINDS;

    #[inline(always)]
    fn refs(&mut self, refs: impl Iterator<Item = u32>) -> bool {
        for r in refs {
            self.test(r);
        }
        false
    }

    #[inline(always)]
    fn walk(&mut self, bvh: &Bvh, wide: bool) {
        self.walk_from(bvh, wide, 0);
    }
}

impl<T: Float, const WATERTIGHT: bool, const KINDS: u32> ClosestRay<'_, T, WATERTIGHT, KINDS> {
    /// Tests primitive `r` and offers its hit; whether `best` changed.
    #[inline(always)]
    fn test(&mut self, r: u32) -> bool {
        match self.g.test::<WATERTIGHT, KINDS>(r, self.rd, self.best.t) {
            Some(h) => self.g.offer(self.best, r, h),
            None => false,
        }
    }

    /// [`Bvh::walk`] from wide node `start` (0 for the whole tree; the packet queries
    /// hand rays over at other nodes).
    #[inline(always)]
    pub(super) fn walk_from(&mut self, bvh: &Bvh, wide: bool, start: u32) {
        let rd = self.rd;
        let t_max = self.best.t;
        bvh.walk::<T, false>(wide, start, &rd.traversal, t_max, |l| {
            self.leaf(l).then_some(self.best.t)
        });
    }

    /// The tests of one leaf; whether `best` changed. A grouped leaf
    /// ([`super::storage::Prims::group_leaves`]) is tested four triangles at a time, and
    /// each hit lane still within `best.t` (an earlier lane of the group may have
    /// lowered it) is offered: the result is that of testing its triangles one by one,
    /// since `offer` keeps the smallest `(t, key)` in any order.
    #[inline(always)]
    fn leaf(&mut self, l: Leaf<'_>) -> bool {
        let mut improved = false;
        match l {
            Leaf::Refs(refs) => {
                for &r in refs {
                    improved |= self.test(r);
                }
            }
            Leaf::Grouped { child, count } => {
                if !kind_in::<KINDS>(TRIANGLE) {
                    return false;
                }
                let (g, rd) = (self.g, self.rd);
                for group in g.groups(child, count) {
                    if !WATERTIGHT {
                        for &i in &group.index {
                            improved |= self.test(make_ref(TRIANGLE, i as usize));
                        }
                        continue;
                    }
                    let h = group.intersect_watertight(rd, self.best.t);
                    let mut bits = h.bits;
                    while bits != 0 {
                        let i = bits.trailing_zeros() as usize;
                        bits &= bits - 1;
                        if h.t[i] <= self.best.t {
                            let r = make_ref(TRIANGLE, group.index[i] as usize);
                            improved |= g.offer(self.best, r, (h.t[i], h.b1[i], h.b2[i]));
                        }
                    }
                }
            }
        }
        improved
    }
}

/// Whether anything blocks one ray: the walk stops at the first hit, whose reference
/// is kept in `found` (for the shadow cache of [`Geometry::occluded_hint_kinds`]).
pub(super) struct AnyRay<'a, T: Float, const WATERTIGHT: bool, const KINDS: u32> {
    pub(super) g: &'a Geometry<T>,
    pub(super) rd: &'a RayData<T>,
    /// The primitive hit, or [`NO_HIT`](super::NO_HIT).
    pub(super) found: u32,
}

impl<T: Float, const WATERTIGHT: bool, const KINDS: u32> Query<T>
    for AnyRay<'_, T, WATERTIGHT, KINDS>
{
    const KINDS: u32 = KINDS;

    #[inline(always)]
    fn refs(&mut self, refs: impl Iterator<Item = u32>) -> bool {
        for r in refs {
            if self.hits(r) {
                self.found = r;
                return true;
            }
        }
        false
    }

    #[inline(always)]
    fn walk(&mut self, bvh: &Bvh, wide: bool) {
        self.walk_from(bvh, wide, 0);
    }
}

impl<T: Float, const WATERTIGHT: bool, const KINDS: u32> AnyRay<'_, T, WATERTIGHT, KINDS> {
    /// Does primitive `r` block the ray?
    #[inline(always)]
    pub(super) fn hits(&self, r: u32) -> bool {
        let rd = self.rd;
        self.g
            .test::<WATERTIGHT, KINDS>(r, rd, rd.t_limit)
            .is_some()
    }

    /// [`Bvh::walk`] from wide node `start`, as [`ClosestRay::walk_from`]; whether the
    /// ray is blocked.
    #[inline(always)]
    pub(super) fn walk_from(&mut self, bvh: &Bvh, wide: bool, start: u32) -> bool {
        let rd = self.rd;
        let limit = rd.t_limit;
        bvh.walk::<T, true>(wide, start, &rd.traversal, limit, |l| {
            self.found = self.leaf(l)?;
            Some(limit)
        })
    }

    /// The reference of a primitive of leaf `l` that blocks the ray, if any.
    #[inline(always)]
    fn leaf(&self, l: Leaf<'_>) -> Option<u32> {
        match l {
            Leaf::Refs(refs) => refs.iter().copied().find(|&r| self.hits(r)),
            Leaf::Grouped { child, count } => {
                if !kind_in::<KINDS>(TRIANGLE) {
                    return None;
                }
                for group in self.g.groups(child, count) {
                    if WATERTIGHT {
                        let bits = group.intersect_watertight(self.rd, self.rd.t_limit).bits;
                        if bits != 0 {
                            let i = bits.trailing_zeros() as usize;
                            return Some(make_ref(TRIANGLE, group.index[i] as usize));
                        }
                    } else if let Some(&i) = group
                        .index
                        .iter()
                        .find(|&&i| self.hits(make_ref(TRIANGLE, i as usize)))
                    {
                        return Some(make_ref(TRIANGLE, i as usize));
                    }
                }
                None
            }
        }
    }
}
