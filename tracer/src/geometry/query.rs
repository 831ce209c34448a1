//! The one query driver, and the query of one ray.
//!
//! Every query of the geometry, the closest hit or any hit, of one ray or of a packet
//! ([`super::packet_query`]), meets the geometry in the order written once in
//! [`Geometry::query`]: the planes first (they lie outside the BVH), then the four-wide
//! tree or, with `--binary-bvh`, the binary one, or without a BVH (`--no-bvh`) every
//! primitive; an any-hit query stops at the step that answers it. A query supplies its
//! side of each step by implementing [`Query`]:
//!
//! | query | [`Query::refs`] (planes, brute force) | [`Query::wide`], [`Query::binary`] |
//! |---|---|---|
//! | [`RayQuery`], `ANY = false` | single-ray test, hit offered to the best | [`Bvh::traverse4`], [`Bvh::traverse`]; leaves by `Geometry::leaf_closest` |
//! | [`RayQuery`], `ANY = true` | single-ray test, stops at the first hit | the same walks with `ANY_HIT`; leaves by `Geometry::leaf_any` |
//! | `ClosestPacket` | lane kernels (single-ray kernels lane by lane for planes) | [`Bvh::traverse4_packet`], [`Bvh::traverse_packet`]; hand-over to [`RayQuery::wide_from`] |
//! | `AnyPacket` | the same, for the lanes not yet blocked | the same walks; hand-over to [`RayQuery::wide_from`] with `ANY` |
//!
//! Everything is `#[inline(always)]` and the kind of walk is a const parameter
//! (`ANY` is passed on as the walks' `ANY_HIT`), so each instance compiles to the code
//! of a query written out alone: the leaf test the walks call is the hand-written
//! queries' (any hit: `Some(t_max)` on a hit, the occluder in the query's local
//! record), given to them as a [`LeafVisitor`], whose method is always inlined (a
//! closure was not, see [`LeafVisitor`]). The instruction counts per frame are in
//! [`super`]'s docs, section "Queries".
//!
//! [`Bvh::traverse4_packet`]: crate::bvh::Bvh::traverse4_packet
//! [`Bvh::traverse_packet`]: crate::bvh::Bvh::traverse_packet

use super::ray_data::RayData;
use super::storage::{make_ref, PLANE};
use super::{kinds, Best, Geometry};
use crate::bvh::traverse::LeafVisitor;
use crate::bvh::wide::Leaf;
use crate::bvh::Bvh;
use crate::float::Float;

/// One query's side of each step of [`Geometry::query`].
pub(super) trait Query {
    /// The primitive kinds the query is compiled for (a [`kinds`] mask): planes are
    /// tested only when it has them.
    const KINDS: u32;
    /// Tests the primitives `refs` (the planes, and every primitive when there is no
    /// BVH); `true` once the query is answered (an any-hit query's rays all blocked).
    fn refs(&mut self, refs: impl Iterator<Item = u32>) -> bool;
    /// Walks the four-wide tree; `true` once the query is answered.
    fn wide(&mut self, bvh: &Bvh) -> bool;
    /// Walks the binary tree; `true` once the query is answered.
    fn binary(&mut self, bvh: &Bvh) -> bool;
}

impl<T: Float> Geometry<T> {
    /// The query driver, the one place that says in which order a query meets the
    /// geometry: the planes, then the BVH ([`super::AccelOptions::wide`] picks the
    /// tree) or, without one, every primitive. Whether the query was answered early
    /// (an any-hit query's rays all blocked).
    #[inline(always)]
    pub(super) fn query<Q: Query>(&self, q: &mut Q) -> bool {
        let planes = if Q::KINDS & kinds::PLANES != 0 {
            self.prims.planes.len()
        } else {
            0
        };
        if q.refs((0..planes).map(|i| make_ref(PLANE, i))) {
            return true;
        }
        match &self.bvh {
            Some(bvh) if self.wide => q.wide(bvh),
            Some(bvh) => q.binary(bvh),
            None => q.refs(self.all_refs()),
        }
    }
}

/// The query of one ray: with `ANY`, is it blocked (the walk stops at the first hit);
/// else its closest hit, every hit within `best.t` offered to `best`
/// ([`Geometry::offer`]: the closest, and the earliest in the input among equally close
/// ones). `WATERTIGHT` and `KINDS` as for `Geometry::test`.
///
/// With `EIGHT` the walk is that of the eight-wide tree ([`Bvh::traverse8`]): such a
/// query must only be made inside code compiled for AVX2 and FMA, on a CPU that has
/// them, for an `f32` geometry with the eight-wide tree (`Geometry::eight`).
pub(super) struct RayQuery<
    'a,
    T: Float,
    const ANY: bool,
    const WATERTIGHT: bool,
    const KINDS: u32,
    const EIGHT: bool,
> {
    pub(super) g: &'a Geometry<T>,
    pub(super) rd: &'a RayData<T>,
    /// The hit found so far: for the closest hit the best candidate, whose `t` bounds
    /// the hits still looked for; for any hit `r` is the occluder found (or
    /// [`super::NO_HIT`]) and `t` stays the ray's bound [`RayData::t_limit`].
    pub(super) best: &'a mut Best<T>,
}

impl<T: Float, const ANY: bool, const WATERTIGHT: bool, const KINDS: u32, const EIGHT: bool> Query
    for RayQuery<'_, T, ANY, WATERTIGHT, KINDS, EIGHT>
{
    const KINDS: u32 = KINDS;

    #[inline(always)]
    fn refs(&mut self, refs: impl Iterator<Item = u32>) -> bool {
        let (g, rd, best) = (self.g, self.rd, &mut *self.best);
        for r in refs {
            if let Some(h) = g.test::<WATERTIGHT, KINDS>(r, rd, best.t) {
                if ANY {
                    best.r = r;
                    return true;
                }
                g.offer(best, r, h);
            }
        }
        false
    }

    #[inline(always)]
    fn wide(&mut self, bvh: &Bvh) -> bool {
        #[cfg(target_arch = "x86_64")]
        if EIGHT {
            if let Some(proof) = T::AS_F32 {
                let (rd, t_max) = (self.rd, self.best.t);
                // SAFETY: an `EIGHT` query is made only inside code compiled for AVX2
                // and FMA on a CPU that has them (the contract of `EIGHT`, kept by
                // `Geometry::closest_best` and `Geometry::any_query`).
                return unsafe { bvh.traverse8::<T, ANY>(proof, &rd.traversal, t_max, self) };
            }
        }
        self.wide_from(bvh, 0)
    }

    #[inline(always)]
    fn binary(&mut self, bvh: &Bvh) -> bool {
        let (rd, t_max) = (self.rd, self.best.t);
        bvh.traverse::<T, ANY>(&rd.traversal, t_max, self)
    }
}

impl<T: Float, const ANY: bool, const WATERTIGHT: bool, const KINDS: u32, const EIGHT: bool>
    RayQuery<'_, T, ANY, WATERTIGHT, KINDS, EIGHT>
{
    /// The walk of the four-wide tree from wide node `start` (0 for the whole tree;
    /// the packet queries hand their last rays over at other nodes): whether the walk
    /// found a hit.
    #[inline(always)]
    pub(super) fn wide_from(&mut self, bvh: &Bvh, start: u32) -> bool {
        let (rd, t_max) = (self.rd, self.best.t);
        bvh.traverse4_from::<T, ANY>(start, &rd.traversal, t_max, self)
    }
}

impl<T: Float, const ANY: bool, const WATERTIGHT: bool, const KINDS: u32, const EIGHT: bool>
    LeafVisitor<T> for RayQuery<'_, T, ANY, WATERTIGHT, KINDS, EIGHT>
{
    /// The tests of one leaf: the walk's new `t_max` if the leaf holds a hit.
    #[inline(always)]
    fn leaf(&mut self, l: Leaf<'_>, _t_max: T) -> Option<T> {
        let (rd, best) = (self.rd, &mut *self.best);
        let g = if EIGHT && !ANY {
            opaque(self.g)
        } else {
            self.g
        };
        if ANY {
            best.r = g.leaf_any::<WATERTIGHT, KINDS>(l, rd, best.t)?;
            Some(best.t)
        } else {
            g.leaf_closest::<WATERTIGHT, KINDS>(l, rd, best)
                .then_some(best.t)
        }
    }
}

/// `g`, hidden from the optimiser at the point of use: the loads through it stay where
/// the code makes them instead of being hoisted.
///
/// The leaf tests of a walk read the geometry's primitive arrays (a pointer and a length
/// each). The walk's loop is the only loop around them, so the optimiser moved those
/// loads to the top of the query and, short of registers in the box tests, kept them on
/// the stack: about 30 loads and as many stores per ray, whether or not the ray reaches
/// a leaf. Behind `opaque`, which the optimiser cannot see through, each leaf reads what
/// it uses when it runs. The eight-wide closest-hit query uses it: 0.95 to 0.98 of the
/// instructions per single eye ray on six of the seven classic scenes (teapot-s12 711 to
/// 687, tetra-s6 516 to 488; rings-s7 1.003), and tetra-s6's eye rays went from 0.93 to
/// 0.99 of Embree's rate (`tracer/JOURNAL.md`, "Geometry loads at the leaves"). The
/// any-hit queries were slower with it, and the four-wide closest-hit query (the packets'
/// hand-over) took 1 to 2 % more instructions, so they do not use it.
#[inline(always)]
pub(super) fn opaque<G>(g: &G) -> &G {
    let mut p = g as *const G;
    // `nomem` is right: the pointer passes through the template, which never
    // dereferences it.
    #[cfg(any(target_arch = "x86_64", target_arch = "aarch64"))]
    #[allow(clippy::pointers_in_nomem_asm_block)]
    // SAFETY: the template is a comment, no instruction: `p` comes out unchanged, no
    // memory is touched, no stack used and no flag changed, as the options declare.
    unsafe {
        core::arch::asm!("/* {0} */", inout(reg) p, options(nomem, nostack, preserves_flags));
    }
    // SAFETY: `p` is `g`, a valid reference for the returned lifetime.
    unsafe { &*p }
}
