//! Packet traversal of the BVH: one SIMD lane per ray.
//!
//! In the style of I. Wald, P. Slusallek, C. Benthin, M. Wagner, "Interactive Rendering
//! with Coherent Ray Tracing", Eurographics 2001: a packet of coherent rays walks the
//! tree together, a node is visited when any ray of the packet may hit something in it,
//! and a mask carries which rays take part. Each node's box is tested against every ray
//! at once with the same conservative slab test as [`TraversalRay::hit_box`] (Ize 2013),
//! the one formula [`slab`] over the lane type, so lane `i` accepts a box exactly
//! when the single ray `i` does; the leaf sees the rays that accept its box.
//!
//! - [`Bvh::traverse4_packet`] (the default) walks the four-wide tree: the packet tests
//!   the children of a node one after the other, each against all its rays, pushes the
//!   children it does not visit first with their rays and entry distances, and hands
//!   the rays over to single-ray traversal of a subtree where only a few of them reach
//!   it. Compared with the binary walk: 8-14 % fewer instructions for packets of four
//!   (SSE2), the same within 3 % for packets of eight (AVX2) on the classic scenes.
//!   Where an octant's rays share their origin (eye rays of a pinhole camera), they
//!   walk as one beam instead (`Frustum`, as Embree's coherent packets do): one
//!   conservative test of a node's boxes against the beam, and each ray's own box test
//!   only at a leaf. Packets of eight or more lanes (AVX2, AVX-512) walk the beam over
//!   the eight-wide tree where the geometry has it, eight boxes in one AVX register:
//!   0.87 to 0.99 of the instructions per ray of the four-wide beam on the classic
//!   scenes (AVX2 packets of eight; `tracer/JOURNAL.md`, "Geometry loads at the
//!   leaves, and the beam on the eight-wide tree"). A beam whose rays are far apart
//!   compared with the leaves it reaches gives up, and its rays walk one by one; after
//!   two such beams in a row, a thread's next packets skip the beam (one in eight tries
//!   it again).
//! - [`Bvh::traverse_packet`] walks the binary tree (`--binary-bvh`): children are
//!   visited nearest first by the entry distance of the first ray that hits both; the
//!   other child is pushed with its mask and, on pop, its box is tested again with the
//!   rays' closest hits so far, so each ray leaves the mask when its hit lies before the
//!   box (a test at least as tight as the single-ray pop test, and as conservative).
//!
//! The closest hit the geometry reports does not depend on the visiting order (ties are
//! broken by primitive index), and a ray takes part in every leaf its own traversal
//! would reach with its current closest distance or a larger one, so each lane's result
//! is the single ray's, bit for bit.

use super::traverse::{slab, TraversalRay};
#[cfg(target_arch = "x86_64")]
use super::wide::GROUPED;
#[cfg(target_arch = "x86_64")]
use super::wide::WIDTH8;
use super::wide::{Leaf, Node4, WideNode, EMPTY_SLOT, WIDTH};
use super::Bvh;
use core::mem::MaybeUninit;
#[cfg(target_arch = "x86_64")]
use vecexpr::simd::F32x8;
use vecexpr::simd::{SimdF32, SimdMask};
use vecexpr::Mask;

/// A packet of rays prepared for box tests: per lane what [`TraversalRay`] holds.
#[derive(Clone, Copy, Debug)]
pub struct PacketRay<S: SimdF32> {
    /// Origins, per axis.
    pub origin: [S; 3],
    /// Inverse directions, per axis.
    pub inv_dir: [S; 3],
    /// Lanes whose direction is negative on the axis (near plane `hi`).
    pub neg: [S::Mask; 3],
    /// Smallest accepted parameters.
    pub t_min: S,
    /// $1 + 2\gamma_3$ (the same in every lane).
    pub slack: S,
    /// `inv_dir` times `slack`, for the far planes (as [`TraversalRay::inv_far`]).
    pub inv_far: [S; 3],
}

impl<S: SimdF32> PacketRay<S> {
    /// Gathers `rays[i]` into lane `i`; lanes without a ray get a copy of the first ray
    /// that exists (and must be left out of the active mask by the caller). `None` if no
    /// lane has a ray.
    ///
    /// # Panics
    /// If `rays` has fewer than `S::LANES` entries.
    #[inline(always)]
    pub fn gather(rays: &[Option<&TraversalRay<f32>>]) -> Option<Self> {
        let first = rays[..S::LANES].iter().flatten().next()?;
        let mut buf = [[0.0f32; 16]; 7];
        for (i, r) in rays[..S::LANES].iter().enumerate() {
            let r = r.unwrap_or(first);
            for a in 0..3 {
                buf[a][i] = r.origin[a];
                buf[3 + a][i] = r.inv_dir[a];
            }
            buf[6][i] = r.t_min;
        }
        Some(Self::from_lanes(
            [S::load(&buf[0]), S::load(&buf[1]), S::load(&buf[2])],
            [S::load(&buf[3]), S::load(&buf[4]), S::load(&buf[5])],
            S::load(&buf[6]),
            first.slack,
        ))
    }

    /// The packet of the rays whose [`TraversalRay`] fields are, lane by lane, `origin`,
    /// `inv_dir` and `t_min`, with the slack factor `slack` of every [`TraversalRay`].
    #[inline(always)]
    pub fn from_lanes(origin: [S; 3], inv_dir: [S; 3], t_min: S, slack: f32) -> Self {
        let zero = S::zero();
        let s = S::splat(slack);
        Self {
            // Lane by lane the product `TraversalRay::new` computes.
            inv_far: [inv_dir[0] * s, inv_dir[1] * s, inv_dir[2] * s],
            origin,
            inv_dir,
            // As `TraversalRay::new`: 1/-0 = -inf picks `hi` as the near plane too.
            neg: [
                inv_dir[0].lt(zero),
                inv_dir[1].lt(zero),
                inv_dir[2].lt(zero),
            ],
            t_min,
            slack: s,
        }
    }

    /// [`TraversalRay::hit_box`] in every lane: which lanes overlap the box within
    /// `(t_min, t_max]` (conservatively), and their entry distances.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // the axis indexes four arrays, as in `hit_box`
    pub fn hit_box(&self, b: &[[f32; 3]; 2], t_max: S) -> (S::Mask, S) {
        let mut t = (self.t_min, t_max * self.slack);
        for a in 0..3 {
            let (lo, hi) = (S::splat(b[0][a]), S::splat(b[1][a]));
            let near = S::select(self.neg[a], hi, lo);
            let far = S::select(self.neg[a], lo, hi);
            t = slab(t, near, far, self.axis(a));
        }
        (t.0.le(t.1), t.0)
    }

    /// The rays' `(origin, inv_dir, inv_far)` on axis `a`, as [`slab`] takes them.
    #[inline(always)]
    fn axis(&self, a: usize) -> (S, S, S) {
        (self.origin[a], self.inv_dir[a], self.inv_far[a])
    }
}

/// Pending nodes of the packet traversal (one per level, as for single rays).
const STACK_SIZE: usize = super::build::MAX_DEPTH;

impl Bvh {
    /// Walks the binary tree with a packet: calls `visit.leaf` for each leaf whose box
    /// some active ray overlaps before its `t_max`, with the lanes of those rays (as
    /// [`Bvh::traverse4_packet`] does; the binary walk never hands rays over). Rays
    /// outside `active` never take part. Returns the final `t_max`.
    #[inline(always)]
    pub fn traverse_packet<S: SimdF32>(
        &self,
        ray: &PacketRay<S>,
        active: S::Mask,
        mut t_max: S,
        visit: &mut impl PacketVisitor<S>,
    ) -> S {
        let nodes = self.nodes();
        let Some(root) = nodes.first() else {
            return t_max;
        };
        let (hit, _) = ray.hit_box(&root.bounds, t_max);
        let mut mask = hit.and(active);
        if !mask.any() {
            return t_max;
        }
        let mut stack_node = [0u32; STACK_SIZE];
        let mut stack_mask = [0u32; STACK_SIZE];
        let mut sp = 0usize;
        let mut at = 0usize;
        loop {
            let node = &nodes[at];
            if node.is_leaf() {
                let first = node.offset as usize;
                let refs = &self.refs()[first..first + node.count as usize];
                match visit.leaf(Leaf::Refs(refs), mask.bitmask(), t_max) {
                    Some(t) => t_max = t,
                    None => return t_max,
                }
            } else {
                let (l, r) = (at + 1, node.offset as usize);
                let (hl, tl) = ray.hit_box(&nodes[l].bounds, t_max);
                let (hr, tr) = ray.hit_box(&nodes[r].bounds, t_max);
                let (ml, mr) = (hl.and(mask), hr.and(mask));
                match (ml.any(), mr.any()) {
                    (true, true) => {
                        // Order by the first ray that enters both.
                        let both = ml.and(mr).bitmask();
                        let left_first = if both != 0 {
                            let i = both.trailing_zeros() as usize;
                            tr.lane(i) >= tl.lane(i)
                        } else {
                            true
                        };
                        let (near, nm, far, fm) = if left_first {
                            (l, ml, r, mr)
                        } else {
                            (r, mr, l, ml)
                        };
                        stack_node[sp] = far as u32;
                        stack_mask[sp] = fm.bitmask();
                        sp += 1;
                        at = near;
                        mask = nm;
                        continue;
                    }
                    (true, false) => {
                        at = l;
                        mask = ml;
                        continue;
                    }
                    (false, true) => {
                        at = r;
                        mask = mr;
                        continue;
                    }
                    (false, false) => {}
                }
            }
            // Pop the nearest pending node that some ray may still find a closer hit in.
            loop {
                if sp == 0 {
                    return t_max;
                }
                sp -= 1;
                let n = stack_node[sp] as usize;
                let (still, _) = ray.hit_box(&nodes[n].bounds, t_max);
                let m = S::Mask::from_bitmask(stack_mask[sp]).and(still);
                if m.any() {
                    at = n;
                    mask = m;
                    break;
                }
            }
        }
    }
}

/// The four-wide traversal's stack: entries pushed with the packet's lanes that hit
/// them and those lanes' entry distances.
const STACK4_SIZE: usize = super::wide::STACK_SIZE;
/// The eight-wide tree's (the beam walk over it, [`Bvh::frustum_walk`]).
#[cfg(target_arch = "x86_64")]
const STACK8_SIZE: usize = super::wide::STACK_SIZE8;

/// What [`Bvh::traverse4_packet`] asks of its caller: each method returns the rays' new
/// `t_max` (a lane set to $-\infty$ takes no further part), or `None` to end the
/// traversal (every ray done).
///
/// A trait rather than closures so that the methods can be `#[inline(always)]`: a
/// closure is inlined at the compiler's discretion, and one left out of line is not
/// compiled for the instruction set of the `#[target_feature]` entry point it was
/// written in, so its lane operations become calls.
pub trait PacketVisitor<S: SimdF32> {
    /// Tests a leaf against the rays of `lanes` (bits), those that reach it.
    fn leaf(&mut self, leaf: Leaf<'_>, lanes: u32, t_max: S) -> Option<S>;
    /// Traces the rays of `lanes` alone through the subtree of wide node `node` of
    /// `bvh` ([`Bvh::traverse4_from`]): few rays of the packet are left.
    fn handover(&mut self, bvh: &Bvh, node: u32, lanes: u32, t_max: S) -> Option<S>;
    /// Traces the rays of `lanes` alone through the whole tree, each with the
    /// geometry's fastest single-ray walk, as if they had never been in the packet
    /// (a beam of them gave up, [`Bvh::traverse4_packet`]): the leaves already tested
    /// are tested again, which changes no result.
    fn scatter(&mut self, lanes: u32) -> Option<S>;
}

/// A beam walk gives up ([`Bvh::traverse4_packet`]) once the leaves it reached that
/// none of its rays reach (each ray's own box test of the leaf fails) outnumber
/// `BEAM_EMPTY_MIN` plus `BEAM_EMPTY_PER_LEAF` times the leaves some ray reaches. Eye
/// packets of 4x4 pixels on balls-s6 at 64x64 (a pixel about 0.7 degrees) met 712
/// such leaves a packet and 9 leaves with a ray; on the seven classic scenes at 512x512
/// at most about one in four. The values were chosen by the instructions of AVX2 eye
/// packets (callgrind, `packet_walk --only wide`, balls-s4, gears-s4, teapot-s12,
/// tetra-s6 and balls-s6 at 64x64 to 512x512): lower ones gave up on coherent packets
/// too and cost up to 8 % on balls-s4 at 64x64, higher ones left balls-s6 at 128x128
/// walking as beams (`tracer/JOURNAL.md`, "Beams that give up").
const BEAM_EMPTY_MIN: u32 = 4;
/// See [`BEAM_EMPTY_MIN`].
const BEAM_EMPTY_PER_LEAF: u32 = 4;
/// After this many beams in a row gave up on a thread, the following packets skip the
/// beam and trace their rays one by one at once ([`PacketVisitor::scatter`]), but for
/// one packet in [`BEAM_RETRY_EVERY`], which tries the beam again (a beam that reaches
/// the end of its walk ends the streak). Eye packets come tile by tile, so consecutive
/// packets of a thread are neighbours: where the rays are too far apart for the leaves,
/// their neighbours' are too. Which way a packet goes never changes what it finds.
const BEAM_SKIP_AFTER: u32 = 2;
/// See [`BEAM_SKIP_AFTER`].
const BEAM_RETRY_EVERY: u32 = 8;

std::thread_local! {
    /// Beams that gave up in a row on this thread, skipped packets included
    /// ([`BEAM_SKIP_AFTER`]).
    static BEAM_STREAK: core::cell::Cell<u32> = const { core::cell::Cell::new(0) };
}

/// Should the next beam be skipped ([`BEAM_SKIP_AFTER`])? Counts the skip.
#[inline(always)]
fn skip_beam() -> bool {
    BEAM_STREAK.with(|s| {
        let n = s.get();
        let skip =
            n >= BEAM_SKIP_AFTER && !(n - BEAM_SKIP_AFTER + 1).is_multiple_of(BEAM_RETRY_EVERY);
        if skip {
            s.set(n.saturating_add(1));
        }
        skip
    })
}

/// Records whether a beam that was tried gave up ([`BEAM_SKIP_AFTER`]).
#[inline(always)]
fn beam_gave_up(gave_up: bool) {
    BEAM_STREAK.with(|s| {
        s.set(if gave_up {
            s.get().saturating_add(1)
        } else {
            0
        })
    });
}

/// Beams that gave up, for the tests that must reach that path.
#[cfg(test)]
pub(crate) static BEAMS_GIVEN_UP: core::sync::atomic::AtomicUsize =
    core::sync::atomic::AtomicUsize::new(0);
/// Beams skipped after others gave up ([`BEAM_SKIP_AFTER`]), for the same tests.
#[cfg(test)]
pub(crate) static BEAMS_SKIPPED: core::sync::atomic::AtomicUsize =
    core::sync::atomic::AtomicUsize::new(0);

impl<S: SimdF32> PacketRay<S> {
    /// [`PacketRay::hit_box`] for slot `i` of a wide node, for rays whose direction
    /// signs are `neg` on every lane (so near and far planes are picked once for all of
    /// them, with no per-lane select): lane by lane the operations of
    /// [`TraversalRay::hit_box`].
    #[inline(always)]
    fn hit_slot<const W: usize>(
        &self,
        neg: [usize; 3],
        node: &WideNode<W>,
        i: usize,
        t_max: S,
    ) -> (S::Mask, S) {
        let mut t = (self.t_min, t_max * self.slack);
        for (a, &n) in neg.iter().enumerate() {
            let near = S::splat(node.bounds[n][a][i]);
            let far = S::splat(node.bounds[1 - n][a][i]);
            t = slab(t, near, far, self.axis(a));
        }
        (t.0.le(t.1), t.0)
    }
}

impl Bvh {
    /// Walks the four-wide tree with a packet (Wald et al. 2001 over the wide nodes, as
    /// Embree's hybrid traversal does: I. Wald et al., "Embree: A Kernel Framework for
    /// Efficient CPU Ray Tracing", ACM TOG 33(4), 2014, section 5).
    ///
    /// The rays of `active` (bits) are split by octant (the signs of their direction),
    /// and each octant's rays walk together, so the near and far plane of every axis
    /// is the same for all of them. At a node the packet tests each child's box (one
    /// SIMD test over the rays per child); the children some ray hits are visited, one
    /// at once and the others pushed with the lanes that hit them and their entry
    /// distances. A child is visited before a pending one when it is nearer for some ray
    /// both contain. A popped entry keeps the lanes whose entry distance is within
    /// their closest hit so far (the single-ray pop test, lane by lane).
    ///
    /// `visit` is called with [`PacketVisitor::leaf`] for a leaf some of the rays
    /// reach, and with [`PacketVisitor::handover`] at an interior node reached by at
    /// most `switch` rays: the packet hands those rays over to traverse the subtree
    /// alone (their single-ray traversal, [`Bvh::traverse4_from`]), which pays where few
    /// rays are left (Benthin et al., "Combining Single and Packet-Ray Tracing for
    /// Arbitrary Ray Distributions on the Intel MIC Architecture", IEEE TVCG 18(9),
    /// 2012).
    ///
    /// With `frustum`, an octant's rays that share their origin walk as one beam
    /// instead (`Bvh::frustum_walk`, on x86-64; over the eight-wide tree, where there
    /// is one, for packets of eight or more lanes), without hand-over. A beam gives up
    /// once the leaves it reaches that none of its rays reach outnumber four plus four
    /// times the others: rays that far apart, compared with the leaves, are not
    /// coherent, and [`PacketVisitor::scatter`] traces them one by one. After two beams
    /// in a row gave up on a thread, the next packets go to `scatter` at once, without a
    /// beam, but for one in eight, which tries the beam again (`BEAM_SKIP_AFTER`).
    ///
    /// Every ray takes part in each leaf its own traversal would reach with its current
    /// closest distance or a larger one, so what the geometry finds for each lane is
    /// the single ray's result. Returns the final `t_max`.
    #[inline(always)]
    pub fn traverse4_packet<S: SimdF32>(
        &self,
        ray: &PacketRay<S>,
        active: u32,
        mut t_max: S,
        switch: u32,
        frustum: bool,
        visit: &mut impl PacketVisitor<S>,
    ) -> S {
        let nodes: &[Node4] = self.wide_nodes();
        if nodes.is_empty() {
            return t_max;
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = frustum;
        let neg_bits = [
            ray.neg[0].bitmask(),
            ray.neg[1].bitmask(),
            ray.neg[2].bitmask(),
        ];
        // Left uninitialised: only the entries below `sp` are ever read.
        let mut stack_t = [const { MaybeUninit::<S>::uninit() }; STACK4_SIZE];
        let mut stack_e = [const { MaybeUninit::<(u32, u32, u32)>::uninit() }; STACK4_SIZE];
        let mut rest = active;
        while rest != 0 {
            // The lanes of the first remaining ray's octant.
            let l = rest.trailing_zeros();
            let neg = neg_bits.map(|b| (b >> l & 1) as usize);
            let mut lanes = rest;
            for (&b, &n) in neg_bits.iter().zip(&neg) {
                lanes &= if n == 1 { b } else { !b };
            }
            rest &= !lanes;
            #[cfg(target_arch = "x86_64")]
            if frustum {
                if let Some(f) = Frustum::new(ray, lanes) {
                    let walked = if skip_beam() {
                        // The last beams of this thread gave up: no beam this time.
                        #[cfg(test)]
                        BEAMS_SKIPPED.fetch_add(1, core::sync::atomic::Ordering::Relaxed);
                        Err(())
                    } else {
                        // Packets of eight or more lanes run in code compiled for AVX2,
                        // where the beam walks the eight-wide tree when there is one.
                        let walked = if S::LANES >= 8 && !self.wide8_nodes().is_empty() {
                            let beam = Beam::<F32x8>::new(&f, neg);
                            self.frustum_walk::<S, _, WIDTH8, { STACK8_SIZE + WIDTH8 }>(
                                self.wide8_nodes(),
                                &beam,
                                ray,
                                neg,
                                lanes,
                                t_max,
                                visit,
                            )
                        } else {
                            let beam = Beam::<vecexpr::simd::F32x4>::new(&f, neg);
                            self.frustum_walk::<S, _, WIDTH, { STACK4_SIZE + WIDTH }>(
                                nodes, &beam, ray, neg, lanes, t_max, visit,
                            )
                        };
                        beam_gave_up(walked.is_err());
                        walked
                    };
                    let walked = match walked {
                        Ok(w) => w,
                        // The beam met (or the last beams met) more leaves than its rays
                        // reach: they are not coherent at the scale of the tree's leaves,
                        // and walk alone.
                        Err(_) => visit.scatter(lanes),
                    };
                    match walked {
                        Some(t) => t_max = t,
                        None => return t_max,
                    }
                    continue;
                }
            }
            // The entry being visited: (child, count, lanes).
            let (mut child, mut count, mut mask) = (0u32, 0u32, lanes);
            let mut sp = 0usize;
            loop {
                if count == 0 {
                    if mask.count_ones() <= switch {
                        match visit.handover(self, child, mask, t_max) {
                            Some(t) => t_max = t,
                            None => return t_max,
                        }
                    } else {
                        let node = &nodes[child as usize];
                        // The child to visit next: (child, count, lanes) and distances.
                        let mut next: Option<((u32, u32, u32), S)> = None;
                        for i in 0..WIDTH {
                            if node.child[i] == EMPTY_SLOT {
                                break;
                            }
                            let (hit, tn) = ray.hit_slot(neg, node, i, t_max);
                            let hm = hit.bitmask() & mask;
                            if hm == 0 {
                                continue;
                            }
                            let e = ((node.child[i], node.count[i], hm), tn);
                            let push = match next {
                                None => {
                                    next = Some(e);
                                    continue;
                                }
                                // Visit the new child first when it is nearer for some
                                // ray that hits both.
                                Some(cur) if tn.lt(cur.1).bitmask() & hm & cur.0 .2 != 0 => {
                                    next = Some(e);
                                    cur
                                }
                                Some(_) => e,
                            };
                            stack_e[sp].write(push.0);
                            stack_t[sp].write(push.1);
                            sp += 1;
                        }
                        if let Some(((c, n, m), _)) = next {
                            (child, count, mask) = (c, n, m);
                            continue;
                        }
                    }
                } else {
                    match visit.leaf(self.leaf(child, count), mask, t_max) {
                        Some(t) => t_max = t,
                        None => return t_max,
                    }
                }
                // Pop the next pending entry some of whose rays may still find a
                // closer hit in it.
                let limit = t_max * ray.slack;
                let mut popped = false;
                loop {
                    if sp == 0 {
                        break;
                    }
                    sp -= 1;
                    // SAFETY: every slot below `sp` was written by a push above, and
                    // both types are `Copy`, so reading them out leaves the slots valid.
                    let (t, (c, n, m)) = unsafe {
                        (
                            stack_t[sp].assume_init_read(),
                            stack_e[sp].assume_init_read(),
                        )
                    };
                    let m = m & t.le(limit).bitmask();
                    if m != 0 {
                        (child, count, mask) = (c, n, m);
                        popped = true;
                        break;
                    }
                }
                if !popped {
                    break;
                }
            }
        }
        t_max
    }
}

/// The rays of one octant of a packet that share their origin, bounded as one beam
/// for the box tests of [`Bvh::frustum_walk`]: per axis the common origin and the
/// smallest and largest inverse direction (of the near planes' factor, `inv_dir`, and
/// of the far planes', `inv_far`) over the rays, and their smallest `t_min`.
///
/// For one ray, [`slab`] computes a near distance $(p - o) \cdot r$ per axis, where
/// $p - o$ is the same for every ray of the beam (the origin is common) and the
/// rounded product is monotonic in $r$. So the smaller of the two products with the
/// extreme factors is at most every ray's near distance, and the larger of the far
/// products at least every ray's far distance: a box some ray of the beam accepts is
/// accepted by the beam's test, which is conservative exactly, rounding included
/// (Reshetov et al., "Multi-Level Ray Tracing Algorithm", SIGGRAPH 2005, bound whole
/// beams the same way; Embree's coherent packets walk with such a frustum, see
/// I. Wald et al., "Embree: A Kernel Framework for Efficient CPU Ray Tracing", 2014).
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy, Debug)]
struct Frustum {
    origin: [f32; 3],
    inv_lo: [f32; 3],
    inv_hi: [f32; 3],
    far_lo: [f32; 3],
    far_hi: [f32; 3],
    t_min: f32,
}

#[cfg(target_arch = "x86_64")]
impl Frustum {
    /// The beam of the rays of `lanes` (of one octant), or `None`
    /// when their origins differ or an inverse direction is not finite (a direction
    /// component of zero, whose products may be NaN, which [`slab`] skips per ray).
    #[inline(always)]
    fn new<S: SimdF32>(ray: &PacketRay<S>, lanes: u32) -> Option<Self> {
        let m = S::Mask::from_bitmask(lanes);
        let first = lanes.trailing_zeros() as usize;
        let inf = S::splat(f32::INFINITY);
        let slack = ray.slack.lane(0);
        let mut f = Self {
            origin: [0.0; 3],
            inv_lo: [0.0; 3],
            inv_hi: [0.0; 3],
            far_lo: [0.0; 3],
            far_hi: [0.0; 3],
            t_min: 0.0,
        };
        for a in 0..3 {
            let (o, inv) = (ray.origin[a], ray.inv_dir[a]);
            f.origin[a] = o.lane(first);
            // One origin, and finite factors.
            let same = o.eq_mask(S::splat(f.origin[a]));
            let finite = inv.abs().lt(inf);
            if same.and(finite).bitmask() & lanes != lanes {
                return None;
            }
            (f.inv_lo[a], f.inv_hi[a]) = (smallest(inv, m), largest(inv, m));
            // Each ray's far factor is its `inv_dir` times the positive `slack`, and a
            // rounded product with a positive factor is monotonic: the extremes of the
            // far factors are the products of the extreme `inv_dir`, bit for bit, with
            // no reduction over the lanes. They are finite exactly when every ray's
            // far factor is.
            (f.far_lo[a], f.far_hi[a]) = (f.inv_lo[a] * slack, f.inv_hi[a] * slack);
            debug_assert_eq!(
                (f.far_lo[a].to_bits(), f.far_hi[a].to_bits()),
                (
                    smallest(ray.inv_far[a], m).to_bits(),
                    largest(ray.inv_far[a], m).to_bits()
                ),
                "the far factors' extremes"
            );
            if !(f.far_lo[a].is_finite() && f.far_hi[a].is_finite()) {
                return None;
            }
        }
        f.t_min = smallest(ray.t_min, m);
        Some(f)
    }
}

/// The smallest lane of `v` among the lanes of `m` (there is at least one).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn smallest<S: SimdF32>(v: S, m: S::Mask) -> f32 {
    S::select(m, v, S::splat(f32::INFINITY)).reduce_min()
}

/// The largest lane of `v` among the lanes of `m`, or $-\infty$ when `m` is empty.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn largest<S: SimdF32>(v: S, m: S::Mask) -> f32 {
    S::select(m, v, S::splat(f32::NEG_INFINITY)).reduce_max()
}

#[cfg(target_arch = "x86_64")]
impl Bvh {
    /// The walk of one octant's rays that share their origin, bounded as one beam
    /// ([`Frustum`]), over the `W`-wide `nodes` (the four-wide tree, or the eight-wide
    /// one for packets of eight or more lanes): each node's boxes are tested against
    /// the beam at once (`beam`, one SSE or AVX test instead of one test per box over
    /// the rays), and children are visited nearest first by the beam's entry distance.
    /// At a leaf the rays are tested against its box one by one
    /// ([`PacketRay::hit_slot`], the single-ray test), so a ray takes part in a leaf
    /// exactly when its own test with its current closest distance accepts the box:
    /// what [`Bvh::traverse4_packet`] guarantees, and so each lane's result is the
    /// single ray's. `STACK` is the bound of the width's stack plus `W`. `Ok(None)`
    /// when `visit` ends the walk, `Err(())` when the beam gives up
    /// ([`BEAM_EMPTY_MIN`]; the hits found so far stay valid, the rays' walks are not
    /// finished).
    #[allow(clippy::too_many_arguments)] // the walk's state, all of it used per node
    #[inline(always)]
    fn frustum_walk<S: SimdF32, V: SimdF32, const W: usize, const STACK: usize>(
        &self,
        nodes: &[WideNode<W>],
        beam: &Beam<V>,
        ray: &PacketRay<S>,
        neg: [usize; 3],
        lanes: u32,
        mut t_max: S,
        visit: &mut impl PacketVisitor<S>,
    ) -> Result<Option<S>, ()> {
        let slack = ray.slack.lane(0);
        let in_play = S::Mask::from_bitmask(lanes);
        // Leaves the beam reached that none of its rays' own box tests accept, and
        // leaves some ray reaches.
        let (mut empty, mut reached) = (0u32, 0u32);
        // The pending slots: (node, slot) and the beam's entry distance. A node pushes
        // all its hit slots before one is popped, one more than the other walk's
        // stack allows for; left uninitialised, only the entries below `sp` are read.
        let mut stack = [const { MaybeUninit::<(u32, u32, f32)>::uninit() }; STACK];
        let mut sp = 0usize;
        let mut limit = largest(t_max, in_play) * slack;
        let mut node = 0u32;
        loop {
            // An interior node: test its boxes against the beam.
            let (mut hits, tn) = beam.hits(&nodes[node as usize], limit);
            // Push the hit slots farthest first, so the nearest is on top.
            let base = sp;
            while hits != 0 {
                let i = hits.trailing_zeros();
                hits &= hits - 1;
                let t = tn[i as usize];
                let mut k = sp;
                // SAFETY: entries `base..sp` were written by this loop, and the tuple is
                // `Copy`, so reading one out leaves it valid.
                while k > base && unsafe { stack[k - 1].assume_init_read() }.2 < t {
                    stack[k] = stack[k - 1];
                    k -= 1;
                }
                stack[k].write((node, i, t));
                sp += 1;
                self.fetch_slot(nodes, &nodes[node as usize], i as usize);
            }
            // Pop until an interior node to descend into.
            loop {
                if sp == 0 {
                    return Ok(Some(t_max));
                }
                sp -= 1;
                // SAFETY: every entry below `sp` was written by a push above, and the
                // tuple is `Copy`, so reading it out leaves the slot valid.
                let (p, i, t) = unsafe { stack[sp].assume_init_read() };
                if t > limit {
                    continue;
                }
                let pn = &nodes[p as usize];
                let (child, count) = (pn.child[i as usize], pn.count[i as usize]);
                if count == 0 {
                    node = child;
                    break;
                }
                let (hit, _) = ray.hit_slot(neg, pn, i as usize, t_max);
                let m = hit.bitmask() & lanes;
                if m == 0 {
                    empty += 1;
                    if empty > BEAM_EMPTY_MIN + BEAM_EMPTY_PER_LEAF * reached {
                        #[cfg(test)]
                        BEAMS_GIVEN_UP.fetch_add(1, core::sync::atomic::Ordering::Relaxed);
                        return Err(());
                    }
                } else {
                    reached += 1;
                    match visit.leaf(self.leaf(child, count), m, t_max) {
                        Some(t) => t_max = t,
                        None => return Ok(None),
                    }
                    limit = largest(t_max, in_play) * slack;
                }
            }
        }
    }
}

#[cfg(target_arch = "x86_64")]
impl Bvh {
    /// Asks the CPU for what visiting slot `i` of `node` will read first: the whole node
    /// of an interior child, or the references of a leaf. The beam walk pushes every
    /// slot its beam hits, and pops most of them (a slot is dropped only when it lies
    /// beyond every ray's closest hit), so the fetches are rarely wasted, and on a tree
    /// larger than the caches the walk no longer waits for each node in turn. (In the
    /// single-ray walk, whose pushed slots are mostly dropped, the same fetches cost 4
    /// to 5 % more instructions and gained nothing; `tracer/RESULTS.md`.)
    #[inline(always)]
    fn fetch_slot<const W: usize>(&self, nodes: &[WideNode<W>], node: &WideNode<W>, i: usize) {
        let (child, count) = (node.child[i] as usize, node.count[i]);
        if count == 0 {
            let p = nodes.as_ptr().wrapping_add(child).cast::<u8>();
            // One fetch per 64-byte cache line of the node.
            for line in (0..core::mem::size_of::<WideNode<W>>()).step_by(64) {
                vecexpr::simd::prefetch(p.wrapping_add(line));
            }
        } else if count & GROUPED == 0 {
            vecexpr::simd::prefetch(self.refs.as_ptr().wrapping_add(child));
        }
    }
}

/// The beam of a [`Frustum`], splatted into the lanes of `V` (one lane per child of a
/// node: an SSE register for a [`Node4`], an AVX one for a
/// [`Node8`](super::wide::Node8), which only code compiled for AVX2 may make, the
/// contract of [`F32x8`]), with its near-plane side per axis.
#[cfg(target_arch = "x86_64")]
struct Beam<V> {
    o: [V; 3],
    inv_lo: [V; 3],
    inv_hi: [V; 3],
    far_lo: [V; 3],
    far_hi: [V; 3],
    t_min: V,
    neg: [usize; 3],
}

#[cfg(target_arch = "x86_64")]
impl<V: SimdF32> Beam<V> {
    #[inline(always)]
    fn new(f: &Frustum, neg: [usize; 3]) -> Self {
        let sp = |x: [f32; 3]| x.map(V::splat);
        Self {
            o: sp(f.origin),
            inv_lo: sp(f.inv_lo),
            inv_hi: sp(f.inv_hi),
            far_lo: sp(f.far_lo),
            far_hi: sp(f.far_hi),
            t_min: V::splat(f.t_min),
            neg,
        }
    }

    /// The test of the `W` boxes of `node` (`W` is `V::LANES`): the hit slots as bits
    /// and the beam's entry distance per slot. Per axis the near distance is the
    /// smaller product of $p - o$ with the extreme near factors, the far distance the
    /// larger product with the extreme far factors ([`Frustum`]).
    #[inline(always)]
    fn hits<const W: usize>(&self, node: &WideNode<W>, limit: f32) -> (u32, [f32; W]) {
        use vecexpr::Scalar;
        debug_assert_eq!(V::LANES, W, "one lane per child");
        let mut t_near = self.t_min;
        let mut t_far = V::splat(limit);
        for a in 0..3 {
            let n = self.neg[a];
            let x = V::load(&node.bounds[n][a]) - self.o[a];
            let tn = Scalar::min(x * self.inv_lo[a], x * self.inv_hi[a]);
            let y = V::load(&node.bounds[1 - n][a]) - self.o[a];
            let tf = Scalar::max(y * self.far_lo[a], y * self.far_hi[a]);
            t_near = Scalar::max(tn, t_near);
            t_far = Scalar::min(tf, t_far);
        }
        let mut tn = [0.0f32; W];
        t_near.store(&mut tn);
        (t_near.le(t_far).bitmask(), tn)
    }
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::*;
    use vecexpr::simd::{Isa, Kernel};
    use vecexpr::vec3;

    struct BoxTest;

    impl Kernel for BoxTest {
        type Output = usize;
        fn run<S: SimdF32>(self) -> usize {
            let boxes = [
                [[0.0f32, 0.0, 0.0], [1.0, 1.0, 1.0]],
                [[0.0, 0.5, -1.0], [0.0, 0.5, 1.0]],
                [[-5.0, -5.0, -5.0], [-4.0, -4.0, -4.0]],
            ];
            let rays: Vec<TraversalRay<f32>> = (0..S::LANES)
                .map(|i| {
                    let f = i as f32;
                    let d = vec3(1.0 - f * 0.2, if i % 3 == 0 { 0.0 } else { -0.1 * f }, 0.3);
                    let d = if i % 4 == 1 { vec3(-0.0, 0.0, 1.0) } else { d };
                    TraversalRay::new(&vec3(-1.0 + 0.1 * f, 0.5, 0.25 * f - 1.0), &d, 0.0)
                })
                .collect();
            let refs: Vec<Option<&TraversalRay<f32>>> = rays.iter().map(Some).collect();
            let p = PacketRay::<S>::gather(&refs).unwrap();
            let mut checked = 0;
            for b in &boxes {
                for t_max in [f32::INFINITY, 1.5] {
                    let (hit, tn) = p.hit_box(b, S::splat(t_max));
                    for (i, r) in rays.iter().enumerate() {
                        let single = r.hit_box(b, t_max);
                        assert_eq!(single.is_some(), hit.test(i), "lane {i}");
                        if let Some(t) = single {
                            assert_eq!(t.to_bits(), tn.lane(i).to_bits());
                        }
                        checked += 1;
                    }
                }
            }
            checked
        }
    }

    #[test]
    fn packet_box_test_is_the_single_ray_test_per_lane() {
        for isa in Isa::available() {
            assert_eq!(isa.dispatch(BoxTest), 6 * isa.lanes());
        }
    }
}
