//! Closest hits and any hits of a packet of rays, one SIMD lane per ray, bit-identical
//! to [`Geometry::intersect`] and [`Geometry::occluded`] ray by ray.
//!
//! The packet walks the BVH together ([`crate::bvh::packet_traverse`]: the four-wide
//! tree, handing its rays over to their single-ray traversal of a subtree where at most
//! two of them (four of sixteen) reach it, or the binary tree with `--binary-bvh`;
//! without a BVH it meets every primitive); in a leaf, spheres, triangles and cones are
//! tested against every ray of the packet at once with the formulas of the single-ray
//! kernels ([`super::sphere`], [`super::triangle`], [`super::cone`]) written over the
//! lane type, operation for operation and in the same order (no fused multiply-add
//! where the scalar code has none), so each lane computes exactly the single ray's
//! value. What the packet kernels do not cover runs the single-ray kernel for each ray
//! concerned:
//! - planes;
//! - triangles when the rays' watertight shear axes differ (the axis of largest
//!   direction component), and the rays whose edge functions are exactly zero, which
//!   the single-ray test recomputes in `f64`;
//! - the Möller–Trumbore test, which traces each ray alone.
//!
//! The rays are set up over the lanes (the values the single-ray kernels precompute per
//! ray, computed with the same operations in SIMD registers); a ray's own scalar record
//! is made only when one of its single-ray kernels needs it. That, against making every
//! ray's record and moving it into lanes, cut the instructions of eye packets by 9 to
//! 22 % on five classic scenes (1.8 and 4.4 % more on rings-s7 and tree-s11, whose
//! cylinders then needed every ray's record; `tracer/JOURNAL.md`).
//!
//! Every hit is offered to the ray's closest-hit record in the single-ray way (closer,
//! or as close and earlier in the input), which makes the result independent of the
//! order the primitives are met in; the hit record is then filled in by the single-ray
//! code.
//!
//! The any-hit query of a packet (shadow rays) uses the same kernels: a ray leaves the
//! packet at its first hit, and the walk ends when every ray is blocked.
//!
//! Both packet queries run through the geometry's one query driver
//! (`geometry/query.rs`: planes, then the four-wide or binary tree, or without a BVH
//! every primitive) as `ClosestPacket` and `AnyPacket`: each supplies its primitive
//! loop (the lane kernels over all rays not yet done, which serves the planes and
//! brute force alike), its two walks ([`crate::bvh::Bvh::traverse4_packet`],
//! [`crate::bvh::Bvh::traverse_packet`]) and, as their visitor, its leaf tests and its
//! hand-over, which is the single-ray query's own walk (`RayQuery::wide_from`) from the
//! node handed over.

use super::cone::{cone_lanes_clear, cone_packet};
use super::query::{Query, RayQuery};
use super::ray_data::{PacketData, PacketShear, RayData, Shear, MAX_LANES};
use super::sphere::sphere_packet;
use super::storage::{make_ref, CONE, INDEX_MASK, SPHERE, TAG_SHIFT, TRIANGLE};
use super::triangle::{triangle_packet, TRI4_LANES};
use super::{kinds, Best, Geometry, Intersection, TriangleTest, NO_HIT};
use crate::bvh::packet_traverse::{PacketRay, PacketVisitor};
use crate::bvh::wide::Leaf;
use crate::bvh::Bvh;
use crate::ray::{Hit, Ray};
use core::cell::{Cell, UnsafeCell};
use core::mem::MaybeUninit;
use vecexpr::simd::{Isa, Kernel, SimdF32, SimdMask};
use vecexpr::Real;
use vecexpr::{vec3, Expr, Mask};

/// The closest candidates of a packet's lanes so far, in registers: what [`Best`] holds
/// for each lane, the reference's bits in a float lane (moved only by selects, loads
/// and stores, which keep every bit). The packet kernels' hits update it without
/// leaving the registers; the single-ray paths work on the records
/// ([`LaneBest::store`], then [`LaneBest::load`]).
#[derive(Clone, Copy)]
struct LaneBest<S: SimdF32> {
    /// The closest distances so far: the walk's `t_max`.
    t: S,
    b1: S,
    b2: S,
    /// The references' bits ([`NO_HIT`] where there is none).
    r: S,
    /// Lanes with a candidate (a reference other than [`NO_HIT`]).
    found: u32,
}

impl<S: SimdF32> LaneBest<S> {
    /// The lanes of `best`.
    #[inline(always)]
    fn load(best: &[Best<f32>; MAX_LANES]) -> Self {
        let mut v = [[0.0f32; MAX_LANES]; 4];
        let mut found = 0u32;
        for (l, b) in best[..S::LANES].iter().enumerate() {
            v[0][l] = b.t;
            v[1][l] = b.b1;
            v[2][l] = b.b2;
            v[3][l] = f32::from_bits(b.r);
            found |= u32::from(b.r != NO_HIT) << l;
        }
        Self {
            t: S::load(&v[0]),
            b1: S::load(&v[1]),
            b2: S::load(&v[2]),
            r: S::load(&v[3]),
            found,
        }
    }

    /// The lanes as arrays, in the order `t`, `b1`, `b2`, `r` (the references' bits);
    /// [`lane_record`] reads one lane's record out of them.
    #[inline(always)]
    fn arrays(&self) -> [[f32; MAX_LANES]; 4] {
        let mut v = [[0.0f32; MAX_LANES]; 4];
        self.t.store(&mut v[0]);
        self.b1.store(&mut v[1]);
        self.b2.store(&mut v[2]);
        self.r.store(&mut v[3]);
        v
    }

    /// Writes each lane's closest hit into `out`: `None` for a lane not in `valid` or
    /// without a candidate. (The records of [`LaneBest::store`] and the answers in one
    /// pass.)
    #[inline(always)]
    fn store_found(&self, valid: u32, out: &mut [Option<Intersection<f32>>]) {
        let v = self.arrays();
        for (l, o) in out[..S::LANES].iter_mut().enumerate() {
            let b = lane_record(&v, l);
            *o = (valid & (1 << l) != 0 && b.r != NO_HIT).then_some(Intersection(b));
        }
    }

    /// Writes the lanes into `best`.
    #[inline(always)]
    fn store(&self, best: &mut [Best<f32>; MAX_LANES]) {
        let v = self.arrays();
        for (l, b) in best[..S::LANES].iter_mut().enumerate() {
            *b = lane_record(&v, l);
        }
    }
}

/// Lane `l`'s record out of [`LaneBest::arrays`].
#[inline(always)]
fn lane_record(v: &[[f32; MAX_LANES]; 4], l: usize) -> Best<f32> {
    Best {
        r: v[3][l].to_bits(),
        t: v[0][l],
        b1: v[1][l],
        b2: v[2][l],
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

/// Rows of the set-up buffer of [`Setup::new`]: the rays' own values, one row per value.
mod row {
    pub const ORIGIN: usize = 0;
    pub const DIR: usize = 3;
    pub const T_MIN: usize = 6;
    pub const T_MAX: usize = 7;
    pub const ROWS: usize = 8;
}

/// Each lane's [`RayData`], made on first use ([`Setup::lane`]): the single-ray kernels
/// and the hand-over need it, the packet kernels do not. Owned by the caller, so that
/// the records are written in place and never moved. (A bit per lane says which are
/// made: `OnceCell`s, with their out-of-line initialisation, cost 1 to 4 % more
/// instructions per packet on the classic scenes.)
struct LaneData {
    made: Cell<u32>,
    slots: [UnsafeCell<MaybeUninit<RayData<f32>>>; MAX_LANES],
}

impl LaneData {
    fn new() -> Self {
        Self {
            made: Cell::new(0),
            slots: [const { UnsafeCell::new(MaybeUninit::uninit()) }; MAX_LANES],
        }
    }

    /// Lane `l`'s record, made by `make` if it is the first request.
    #[inline(always)]
    fn get(&self, l: usize, make: impl FnOnce() -> RayData<f32>) -> &RayData<f32> {
        let bit = 1u32 << l;
        let slot = self.slots[l].get();
        if self.made.get() & bit == 0 {
            let v = make();
            // SAFETY: lane `l`'s slot is written only here, while its bit is clear, so no
            // reference to it exists yet; `LaneData` is not `Sync`, so no other thread
            // writes it.
            unsafe { (*slot).write(v) };
            self.made.set(self.made.get() | bit);
        }
        // SAFETY: the bit is set, so the slot was initialised above, and it is never
        // written again while `self` lives.
        unsafe { (*slot).assume_init_ref() }
    }
}

/// A packet's rays prepared once for all its tests: what [`RayData::new`] computes for
/// each ray, lane by lane, computed over the lanes with the same operations (so each
/// lane holds the single ray's values bit for bit), and each ray's own [`RayData`] on
/// demand.
struct Setup<'a, S: SimdF32> {
    rays: &'a [Option<Ray<f32>>],
    rd: &'a LaneData,
    /// Lanes with a valid ray.
    valid: u32,
    ray: PacketRay<S>,
    pd: PacketData<S>,
    /// Each ray's inclusive upper bound [`RayData::t_limit`].
    t_limit: S,
}

impl<'a, S: SimdF32> Setup<'a, S> {
    /// `None` when no lane of `rays[..S::LANES]` holds a valid ray (one [`RayData::new`]
    /// accepts). The rays' eight values are transposed into rows, one register per value
    /// ([`SimdF32::transpose8`]; lanes without a ray copy the first ray); validity,
    /// inverse directions and the shear are then computed over all lanes at once. (Filled
    /// value by value, the rows were compiled into gathers, which held 14 % of
    /// teapot-s12's eye packet samples on AVX-512.) Lanes whose ray is invalid are
    /// left out of `valid` and never read.
    #[inline(always)]
    fn new(rays: &'a [Option<Ray<f32>>], rd: &'a LaneData) -> Option<Self> {
        let n = S::LANES;
        let mut present = 0u32;
        for (l, r) in rays[..n].iter().enumerate() {
            present |= u32::from(r.is_some()) << l;
        }
        if present == 0 {
            return None;
        }
        let first = rays[present.trailing_zeros() as usize].as_ref()?.values();
        // Lanes without a ray copy the first ray.
        let mut recs = [first; MAX_LANES];
        for (rec, r) in recs.iter_mut().zip(&rays[..n]) {
            if let Some(r) = r {
                *rec = r.values();
            }
        }
        let rows = S::transpose8(&recs);
        // The rows as arrays too, for the lane-by-lane reads below.
        let mut buf = [[0.0f32; MAX_LANES]; row::ROWS];
        for (b, v) in buf.iter_mut().zip(rows) {
            v.store(b);
        }
        let origin = vec3(
            rows[row::ORIGIN],
            rows[row::ORIGIN + 1],
            rows[row::ORIGIN + 2],
        );
        let dir = vec3(rows[row::DIR], rows[row::DIR + 1], rows[row::DIR + 2]);
        let (t_min, t_max) = (rows[row::T_MIN], rows[row::T_MAX]);
        // `RayData::new`'s test, lane by lane.
        let dd = dir.length_squared();
        let mut ok = dd
            .ge(S::splat(f32::MIN_POSITIVE))
            .and(dd.le(S::splat(f32::MAX)))
            .and(t_min.is_nan_mask().not())
            .and(t_max.gt(t_min));
        for a in 0..3 {
            ok = ok
                .and(origin[a].is_finite_mask())
                .and(dir[a].is_finite_mask());
        }
        let valid = ok.bitmask() & present;
        if valid == 0 {
            return None;
        }

        let one = S::splat(1.0);
        let inv_dir = [one / dir[0], one / dir[1], one / dir[2]];
        let mut t_limits = [f32::MAX; MAX_LANES];
        // `next_down` lane by lane, as `RayData::new`; a packet of unbounded rays (every
        // eye packet) keeps `next_down(inf)`, `f32::MAX`, without the loop.
        if t_max.eq_mask(S::splat(f32::INFINITY)).bitmask() & valid != valid {
            for (t, &m) in t_limits[..n].iter_mut().zip(&buf[row::T_MAX]) {
                *t = Real::next_down(m);
            }
        }
        // The shear when every valid ray has the same axes: `Shear::axes` is fixed by
        // which of $|d|$ is largest, so the lanes agree when those masks do.
        let a = [dir[0].abs(), dir[1].abs(), dir[2].abs()];
        let (g01, g02, g12) = (a[0].gt(a[1]), a[0].gt(a[2]), a[1].gt(a[2]));
        let kz0 = g01.and(g02).bitmask() & valid;
        let kz1 = g01.not().and(g12).bitmask() & valid;
        let fl = valid.trailing_zeros() as usize;
        let k = Shear::axes(&vec3(
            buf[row::DIR][fl],
            buf[row::DIR + 1][fl],
            buf[row::DIR + 2][fl],
        ));
        let uniform = |m: u32| m == 0 || m == valid;
        let same_axes = uniform(kz0) && uniform(kz1);
        // Not `same_axes.then(|| ..)`: a closure left out of line is compiled without
        // the caller's instruction set, and its vector divisions and products became
        // calls (`_mm256_div_ps`, `_mm256_mul_ps`).
        let shear = if same_axes {
            let (kx, ky, kz) = k;
            let sz = one / dir[kz];
            Some(PacketShear {
                kx,
                ky,
                kz,
                sx: dir[kx] * sz,
                sy: dir[ky] * sz,
                sz,
                o: [origin[kx], origin[ky], origin[kz]],
            })
        } else {
            None
        };
        let ray = PacketRay::from_lanes(
            [origin[0], origin[1], origin[2]],
            inv_dir,
            t_min,
            crate::bvh::traverse::slack::<f32>(),
        );
        let pd = PacketData {
            origin,
            dir,
            t_min,
            dd,
            inv_dd: one / dd,
            shear,
        };
        Some(Self {
            rays,
            rd,
            valid,
            ray,
            pd,
            t_limit: S::load(&t_limits),
        })
    }

    /// The ray data of a valid lane, made on first use.
    #[inline(always)]
    fn lane(&self, l: usize) -> &RayData<f32> {
        self.rd.get(l, || {
            self.rays[l]
                .as_ref()
                .and_then(RayData::new)
                .expect("a valid lane has a valid ray")
        })
    }
}

impl Geometry<f32> {
    /// Can the packet kernels serve this geometry? They have the watertight triangle
    /// test only.
    #[inline(always)]
    fn packet_kernels(&self) -> bool {
        self.triangle_test == TriangleTest::Watertight
    }

    /// The closest-hit test of primitive `r` against the lanes `m` of the packet: each
    /// lane's hit is offered to its candidate in `lb` (`lb.t` is the lanes' `t_max`),
    /// through the records `best` where a single-ray test decides.
    #[inline(always)]
    fn packet_closest<S: SimdF32>(
        &self,
        r: u32,
        m: u32,
        su: &Setup<'_, S>,
        lb: &mut LaneBest<S>,
        best: &mut [Best<f32>; MAX_LANES],
    ) {
        let i = (r & INDEX_MASK) as usize;
        let pd = &su.pd;
        let zero = S::zero();
        match r >> TAG_SHIFT {
            SPHERE => {
                let (hit, t) = sphere_packet(&self.prims.spheres[i], pd, lb.t);
                self.offer_lanes(lb, r, hit.bitmask() & m, (t, zero, zero));
            }
            CONE => {
                let c = &self.prims.cones[i];
                if cone_lanes_clear(c, pd).bitmask() & m == m {
                    return;
                }
                let (hit, t) = cone_packet(c, pd, lb.t);
                self.offer_lanes(lb, r, hit.bitmask() & m, (t, zero, zero));
            }
            TRIANGLE => {
                let Some(sh) = &pd.shear else {
                    self.single_lanes(r, m, su, lb, best);
                    return;
                };
                let h = triangle_packet(&self.prims.triangles[i], pd, sh, lb.t);
                self.offer_lanes(lb, r, h.hit.bitmask() & m, (h.t, h.b1, h.b2));
                let exact = h.exact.bitmask() & m;
                if exact != 0 {
                    self.single_lanes(r, exact, su, lb, best);
                }
            }
            _ => self.single_lanes(r, m, su, lb, best),
        }
    }

    /// Offers the hits `(t, b1, b2)` of primitive `r` in the lanes `bits` to their
    /// candidates, as [`Geometry::offer`] does for one ray: a kernel hit lies within
    /// the lane's closest distance, so it wins where the lane has no candidate or the
    /// hit is nearer, and a tie goes to the smaller key.
    #[inline(always)]
    fn offer_lanes<S: SimdF32>(
        &self,
        lb: &mut LaneBest<S>,
        r: u32,
        bits: u32,
        (t, b1, b2): (S, S, S),
    ) {
        if bits == 0 {
            return;
        }
        let mut win = bits & (t.lt(lb.t).bitmask() | !lb.found);
        let ties = bits & !win;
        if ties != 0 {
            // The store stays here, inlined into the target-feature caller, so that
            // the cold function below holds no vector code.
            let mut refs = [0.0f32; MAX_LANES];
            lb.r.store(&mut refs);
            win |= self.tie_wins(r, ties, &refs);
        }
        if win != 0 {
            let m = S::Mask::from_bitmask(win);
            lb.t = S::select(m, t, lb.t);
            lb.b1 = S::select(m, b1, lb.b1);
            lb.b2 = S::select(m, b2, lb.b2);
            lb.r = S::select(m, S::splat(f32::from_bits(r)), lb.r);
            lb.found |= win;
        }
    }

    /// The lanes of `ties` where primitive `r` wins a tie of distances against the
    /// candidate whose reference bits are in `refs` (the smaller key wins, as in
    /// [`Geometry::offer`]). Rare: out of line.
    #[cold]
    #[inline(never)]
    fn tie_wins(&self, r: u32, ties: u32, refs: &[f32; MAX_LANES]) -> u32 {
        let key = self.prims.key(r);
        let mut win = 0u32;
        each_lane(ties, |l| {
            win |= u32::from(key < self.prims.key(refs[l].to_bits())) << l;
        });
        win
    }

    /// [`Geometry::single_closest`] for the lanes in `bits`, through the records
    /// `best`.
    #[inline(always)]
    fn single_lanes<S: SimdF32>(
        &self,
        r: u32,
        bits: u32,
        su: &Setup<'_, S>,
        lb: &mut LaneBest<S>,
        best: &mut [Best<f32>; MAX_LANES],
    ) {
        lb.store(best);
        if self.single_closest(r, bits, su, best) {
            *lb = LaneBest::load(best);
        }
    }

    /// The single-ray test and offer of primitive `r` for the lanes in `bits`; whether
    /// any record changed. (Out of line: scalar code, called for the primitives the
    /// packet kernels do not cover, once for all lanes.)
    #[inline(never)]
    fn single_closest<S: SimdF32>(
        &self,
        r: u32,
        bits: u32,
        su: &Setup<'_, S>,
        best: &mut [Best<f32>; MAX_LANES],
    ) -> bool {
        let mut improved = false;
        let mut bits = bits;
        while bits != 0 {
            let l = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            let b = &mut best[l];
            if let Some(h) = self.test::<true, { kinds::ALL }>(r, su.lane(l), b.t) {
                improved |= self.offer(b, r, h);
            }
        }
        improved
    }

    /// The single-ray any-hit test of primitive `r` for the lanes in `bits`: the lanes
    /// it blocks.
    #[inline(never)]
    fn single_any<S: SimdF32>(&self, r: u32, bits: u32, su: &Setup<'_, S>) -> u32 {
        let mut found = 0u32;
        let mut bits = bits;
        while bits != 0 {
            let l = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            let rd = su.lane(l);
            let hit = self
                .test::<true, { kinds::ALL }>(r, rd, rd.t_limit)
                .is_some();
            found |= u32::from(hit) << l;
        }
        found
    }

    /// The closest-hit tests of one leaf against the lanes `m`.
    #[inline(always)]
    fn packet_leaf_closest<S: SimdF32>(
        &self,
        leaf: Leaf<'_>,
        m: u32,
        su: &Setup<'_, S>,
        lb: &mut LaneBest<S>,
        best: &mut [Best<f32>; MAX_LANES],
    ) {
        match leaf {
            Leaf::Refs(refs) => {
                for &r in refs {
                    self.packet_closest(r, m, su, lb, best);
                }
            }
            Leaf::Grouped { child, count } => {
                for (g, k) in self.groups(child, count).iter().zip((0..count).step_by(4)) {
                    for &i in &g.index[..(count - k).min(TRI4_LANES as u32) as usize] {
                        let r = make_ref(TRIANGLE, i as usize);
                        self.packet_closest(r, m, su, lb, best);
                    }
                }
            }
        }
    }

    /// The any-hit test of primitive `r` against the lanes `m`: the lanes it blocks.
    #[inline(always)]
    fn packet_any<S: SimdF32>(&self, r: u32, m: u32, su: &Setup<'_, S>) -> u32 {
        let i = (r & INDEX_MASK) as usize;
        let pd = &su.pd;
        let single = |bits: u32| self.single_any(r, bits, su);
        match r >> TAG_SHIFT {
            SPHERE => {
                let (hit, _) = sphere_packet(&self.prims.spheres[i], pd, su.t_limit);
                hit.bitmask() & m
            }
            CONE => {
                let c = &self.prims.cones[i];
                if cone_lanes_clear(c, pd).bitmask() & m == m {
                    return 0;
                }
                let (hit, _) = cone_packet(c, pd, su.t_limit);
                hit.bitmask() & m
            }
            TRIANGLE => match &pd.shear {
                Some(sh) => {
                    let h = triangle_packet(&self.prims.triangles[i], pd, sh, su.t_limit);
                    let done = h.hit.bitmask() & m;
                    done | single(h.exact.bitmask() & m & !done)
                }
                None => single(m),
            },
            _ => single(m),
        }
    }

    /// The any-hit tests of one leaf against the lanes `m` (none of them blocked yet):
    /// the lanes it blocks. `*blocker` becomes the last primitive that blocked a lane.
    #[inline(always)]
    fn packet_leaf_any<S: SimdF32>(
        &self,
        leaf: Leaf<'_>,
        mut m: u32,
        su: &Setup<'_, S>,
        blocker: &mut u32,
    ) -> u32 {
        let mut done = 0u32;
        let mut test = |r: u32, m: &mut u32| {
            let d = self.packet_any(r, *m, su);
            if d != 0 {
                *blocker = r;
            }
            done |= d;
            *m &= !d;
        };
        match leaf {
            Leaf::Refs(refs) => {
                for &r in refs {
                    if m == 0 {
                        break;
                    }
                    test(r, &mut m);
                }
            }
            Leaf::Grouped { child, count } => {
                'groups: for (g, k) in self.groups(child, count).iter().zip((0..count).step_by(4)) {
                    for &i in &g.index[..(count - k).min(TRI4_LANES as u32) as usize] {
                        if m == 0 {
                            break 'groups;
                        }
                        test(make_ref(TRIANGLE, i as usize), &mut m);
                    }
                }
            }
        }
        done
    }

    /// The closest hit of each ray of a packet of `S::LANES` rays: `out[i]` is what
    /// [`Geometry::intersect`] returns for `rays[i]` (`None` where `rays[i]` is `None`),
    /// bit for bit. Meant to be called inside [`vecexpr::simd::Isa::dispatch`], so the
    /// lane operations compile to the instruction set's registers.
    ///
    /// # Panics
    /// If `rays` or `out` is shorter than `S::LANES`, or `S::LANES > 16`.
    #[inline(always)]
    pub fn intersect_lanes<S: SimdF32>(
        &self,
        rays: &[Option<Ray<f32>>],
        out: &mut [Option<Hit<f32>>],
    ) {
        self.intersect_packet_switch::<S>(rays, out, SWITCH, true);
    }

    /// [`Geometry::intersect_lanes`], handing rays over to single-ray traversal where
    /// at most `switch` of them are left, and with `frustum` walking rays of one origin
    /// as a beam ([`crate::bvh::Bvh::traverse4_packet`]).
    #[inline(always)]
    pub(crate) fn intersect_packet_switch<S: SimdF32>(
        &self,
        rays: &[Option<Ray<f32>>],
        out: &mut [Option<Hit<f32>>],
        switch: u32,
        frustum: bool,
    ) {
        let mut found = [None; MAX_LANES];
        self.cast_packet_switch::<S>(rays, &mut found, switch, frustum);
        for ((o, r), f) in out[..S::LANES].iter_mut().zip(rays).zip(&found) {
            *o = r.as_ref().zip(f.as_ref()).map(|(r, f)| self.hit(r, f));
        }
    }

    /// The closest hit of each ray of a packet of `S::LANES` rays without its hit
    /// record: `out[i]` is what [`Geometry::cast`] returns for `rays[i]` (`None` where
    /// `rays[i]` is `None`), bit for bit. Called inside
    /// [`vecexpr::simd::Isa::dispatch`], as [`Geometry::intersect_lanes`].
    ///
    /// # Panics
    /// If `rays` or `out` is shorter than `S::LANES`, or `S::LANES > 16`.
    #[inline(always)]
    pub fn cast_lanes<S: SimdF32>(
        &self,
        rays: &[Option<Ray<f32>>],
        out: &mut [Option<Intersection<f32>>],
    ) {
        self.cast_packet_switch::<S>(rays, out, SWITCH, true);
    }

    /// [`Geometry::cast_lanes`] with the hand-over threshold `switch` and the beam walk
    /// `frustum` of [`Geometry::intersect_packet_switch`].
    #[inline(always)]
    fn cast_packet_switch<S: SimdF32>(
        &self,
        rays: &[Option<Ray<f32>>],
        out: &mut [Option<Intersection<f32>>],
        switch: u32,
        frustum: bool,
    ) {
        let n = S::LANES;
        assert!(n <= MAX_LANES && rays.len() >= n && out.len() >= n);
        if !self.packet_kernels() {
            // Möller-Trumbore, one ray at a time, out of line (inlined here, the
            // single-ray queries grew the packet kernel and its register pressure).
            for (o, r) in out[..n].iter_mut().zip(&rays[..n]) {
                *o = r
                    .as_ref()
                    .and_then(|r| self.cast_moller_trumbore(r))
                    .map(Intersection);
            }
            return;
        }
        match self.closest_packet::<S>(rays, switch, frustum) {
            Some((valid, lanes)) => lanes.store_found(valid, &mut out[..n]),
            None => out[..n].fill(None),
        }
    }

    /// The packet walk of the closest hits: the valid lanes as bits and each lane's
    /// winning candidate ([`NO_HIT`] for none), `None` if no lane is valid. Needs
    /// [`Geometry::packet_kernels`].
    #[inline(always)]
    fn closest_packet<S: SimdF32>(
        &self,
        rays: &[Option<Ray<f32>>],
        switch: u32,
        frustum: bool,
    ) -> Option<(u32, LaneBest<S>)> {
        let rd = LaneData::new();
        let su = Setup::<S>::new(rays, &rd)?;
        // The records of the single-ray paths; each writes them before it reads them.
        let mut best = [Best::none(0.0); MAX_LANES];
        let mut q = ClosestPacket {
            geometry: self,
            su: &su,
            best: &mut best,
            lanes: LaneBest {
                t: su.t_limit,
                b1: S::zero(),
                b2: S::zero(),
                r: S::splat(f32::from_bits(NO_HIT)),
                found: 0,
            },
            switch,
            frustum,
        };
        self.query(&mut q);
        Some((su.valid, q.lanes))
    }

    /// Is each ray of a packet of `S::LANES` rays blocked: `out[i]` is what
    /// [`Geometry::occluded`] returns for `rays[i]` (`false` where `rays[i]` is `None`).
    /// An any-hit query: a lane leaves the traversal at its first hit, and the traversal
    /// ends when every lane is blocked. Meant to be called inside
    /// [`vecexpr::simd::Isa::dispatch`], as [`Geometry::intersect_lanes`].
    ///
    /// # Panics
    /// If `rays` or `out` is shorter than `S::LANES`, or `S::LANES > 16`.
    #[inline(always)]
    pub fn occluded_lanes<S: SimdF32>(&self, rays: &[Option<Ray<f32>>], out: &mut [bool]) {
        let mut no_hint = NO_HIT;
        self.occluded_packet_switch::<S>(rays, out, SWITCH, &mut no_hint);
    }

    /// [`Geometry::occluded_lanes`] with the hand-over threshold `switch` and a shadow
    /// cache entry `hint`, as [`Geometry::occluded_hint_kinds`] takes one for a single
    /// ray: the primitive `*hint` is tested against every lane first, and the lanes it
    /// blocks do not walk the tree (when it blocks them all, nothing does). `*hint`
    /// becomes the last occluder found (itself, if nothing else blocked); it stays as it
    /// was when the only blocked lanes were traced one by one after their beam gave up
    /// ([`PacketVisitor::scatter`] records no occluder), and becomes
    /// [`NO_HINT`](super::NO_HINT) when no lane is blocked. Any value is safe, and the
    /// answer never depends on it. (A geometry without the packet kernels answers the
    /// rays one by one and leaves `*hint` as it is, as does a packet without rays.)
    #[inline(always)]
    pub(crate) fn occluded_packet_switch<S: SimdF32>(
        &self,
        rays: &[Option<Ray<f32>>],
        out: &mut [bool],
        switch: u32,
        hint: &mut u32,
    ) {
        let n = S::LANES;
        assert!(n <= MAX_LANES && rays.len() >= n && out.len() >= n);
        if !self.packet_kernels() {
            // As in `cast_lanes`.
            for (o, r) in out[..n].iter_mut().zip(&rays[..n]) {
                *o = r.as_ref().is_some_and(|r| self.any_moller_trumbore(r));
            }
            return;
        }
        out[..n].fill(false);
        let rd = LaneData::new();
        let Some(su) = Setup::<S>::new(rays, &rd) else {
            return;
        };
        let cached = *hint;
        let mut q = AnyPacket {
            geometry: self,
            su: &su,
            done: 0,
            switch,
            cached,
            blocker: NO_HIT,
        };
        self.query(&mut q);
        *hint = match (q.done, q.blocker) {
            (0, _) => NO_HIT,
            (_, NO_HIT) => cached,
            (_, found) => found,
        };
        each_lane(q.done, |l| out[l] = true);
    }
}

impl Geometry<f32> {
    /// The closest hits of the first [`Isa::lanes`] rays of `rays` (`None` lanes are
    /// skipped), traced together as one packet by the kernel of `isa`; the rest of the
    /// result is `None`. Lane `i` is bit for bit what [`Geometry::intersect`] returns for
    /// `rays[i]`. The rays need not share an origin, but packets pay off when they are
    /// coherent (neighbouring eye rays).
    ///
    /// # Panics
    /// If the CPU lacks `isa` ([`Isa::is_available`]) or off x86-64.
    pub fn intersect_packet(
        &self,
        isa: Isa,
        rays: &[Option<Ray<f32>>; MAX_LANES],
    ) -> [Option<Hit<f32>>; MAX_LANES] {
        let mut hits = [None; MAX_LANES];
        self.intersect_packet_into(isa, rays, &mut hits);
        hits
    }

    /// [`Geometry::intersect_packet`] into `out`. (An out-parameter: the kilobyte of
    /// hit records is written once, where the caller keeps it.)
    #[inline]
    pub(crate) fn intersect_packet_into(
        &self,
        isa: Isa,
        rays: &[Option<Ray<f32>>; MAX_LANES],
        out: &mut [Option<Hit<f32>>; MAX_LANES],
    ) {
        dispatch(
            isa,
            ClosestKernel {
                geometry: self,
                rays,
                out,
            },
        );
    }

    /// [`Geometry::intersect_packet`] without the hit records: lane `i` is bit for bit
    /// what [`Geometry::cast`] returns for `rays[i]`.
    ///
    /// # Panics
    /// If the CPU lacks `isa` ([`Isa::is_available`]) or off x86-64.
    #[inline]
    pub fn cast_packet(
        &self,
        isa: Isa,
        rays: &[Option<Ray<f32>>; MAX_LANES],
    ) -> [Option<Intersection<f32>>; MAX_LANES] {
        let mut out = [None; MAX_LANES];
        self.cast_packet_into(isa, rays, &mut out);
        out
    }

    /// [`Geometry::cast_packet`] into `out`, where the caller keeps it: the first
    /// [`Isa::lanes`] entries are written, the rest left as they are. (An out-parameter,
    /// as Embree's `rtcIntersect16` writes its caller's hit structure: returned by value,
    /// the 320-byte array was copied once more per packet.)
    ///
    /// # Panics
    /// If the CPU lacks `isa` ([`Isa::is_available`]) or off x86-64.
    #[inline]
    pub fn cast_packet_into(
        &self,
        isa: Isa,
        rays: &[Option<Ray<f32>>; MAX_LANES],
        out: &mut [Option<Intersection<f32>>; MAX_LANES],
    ) {
        dispatch(
            isa,
            CastKernel {
                geometry: self,
                rays,
                out,
            },
        );
    }

    /// Whether each of the first [`Isa::lanes`] rays of `rays` is blocked (`None` lanes
    /// are `false`), traced together as one any-hit packet by the kernel of `isa`; the
    /// rest of the result is `false`. Lane `i` is what [`Geometry::occluded`] returns for
    /// `rays[i]`. Pays off for coherent rays, such as the shadow rays of neighbouring
    /// eye hits toward one light.
    ///
    /// # Panics
    /// If the CPU lacks `isa` ([`Isa::is_available`]) or off x86-64.
    #[inline]
    pub fn occluded_packet(
        &self,
        isa: Isa,
        rays: &[Option<Ray<f32>>; MAX_LANES],
    ) -> [bool; MAX_LANES] {
        let mut no_hint = NO_HIT;
        self.occluded_packet_hint(isa, rays, &mut no_hint)
    }

    /// [`Geometry::occluded_packet`] with a shadow cache entry `hint`, tested against
    /// every ray first and updated as [`Geometry::occluded_hint_kinds`] updates its
    /// own; the answer does not depend on it.
    ///
    /// # Panics
    /// If the CPU lacks `isa` ([`Isa::is_available`]) or off x86-64.
    #[inline]
    pub fn occluded_packet_hint(
        &self,
        isa: Isa,
        rays: &[Option<Ray<f32>>; MAX_LANES],
        hint: &mut u32,
    ) -> [bool; MAX_LANES] {
        let mut out = [false; MAX_LANES];
        dispatch(
            isa,
            AnyKernel {
                geometry: self,
                rays,
                out: &mut out,
                hint,
            },
        );
        out
    }
}

/// Runs [`Geometry::intersect_lanes`] on one packet.
struct ClosestKernel<'a> {
    geometry: &'a Geometry<f32>,
    rays: &'a [Option<Ray<f32>>; MAX_LANES],
    out: &'a mut [Option<Hit<f32>>; MAX_LANES],
}

impl Kernel for ClosestKernel<'_> {
    type Output = ();
    #[inline(always)]
    fn run<S: SimdF32>(self) {
        self.geometry.intersect_lanes::<S>(self.rays, self.out);
    }
}

/// Runs [`Geometry::cast_lanes`] on one packet.
struct CastKernel<'a> {
    geometry: &'a Geometry<f32>,
    rays: &'a [Option<Ray<f32>>; MAX_LANES],
    out: &'a mut [Option<Intersection<f32>>; MAX_LANES],
}

impl Kernel for CastKernel<'_> {
    type Output = ();
    #[inline(always)]
    fn run<S: SimdF32>(self) {
        self.geometry.cast_lanes::<S>(self.rays, self.out);
    }
}

/// Runs [`Geometry::occluded_lanes`] on one packet.
struct AnyKernel<'a> {
    geometry: &'a Geometry<f32>,
    rays: &'a [Option<Ray<f32>>; MAX_LANES],
    out: &'a mut [bool; MAX_LANES],
    hint: &'a mut u32,
}

impl Kernel for AnyKernel<'_> {
    type Output = ();
    #[inline(always)]
    fn run<S: SimdF32>(self) {
        self.geometry
            .occluded_packet_switch::<S>(self.rays, self.out, SWITCH, self.hint);
    }
}

#[cfg(target_arch = "x86_64")]
#[inline]
fn dispatch<K: Kernel>(isa: Isa, kernel: K) -> K::Output {
    isa.dispatch(kernel)
}

#[cfg(not(target_arch = "x86_64"))]
fn dispatch<K: Kernel>(_isa: Isa, _kernel: K) -> K::Output {
    unreachable!("no SIMD instruction set off x86-64, so no packets");
}

/// The closest hits of a packet: every hit is offered to its lane's record in `best`,
/// as [`RayQuery`] does for one ray.
struct ClosestPacket<'a, S: SimdF32> {
    geometry: &'a Geometry<f32>,
    su: &'a Setup<'a, S>,
    /// The lanes' records, for the single-ray paths.
    best: &'a mut [Best<f32>; MAX_LANES],
    /// The lanes' candidates (their closest distances, once the planes are tested).
    lanes: LaneBest<S>,
    /// The hand-over threshold of [`crate::bvh::Bvh::traverse4_packet`].
    switch: u32,
    /// Whether rays of one origin walk as a beam ([`crate::bvh::Bvh::traverse4_packet`]).
    frustum: bool,
}

impl<S: SimdF32> Query for ClosestPacket<'_, S> {
    const KINDS: u32 = kinds::ALL;

    #[inline(always)]
    fn refs(&mut self, refs: impl Iterator<Item = u32>) -> bool {
        let (g, su) = (self.geometry, self.su);
        for r in refs {
            g.packet_closest(r, su.valid, su, &mut self.lanes, self.best);
        }
        false
    }

    #[inline(always)]
    fn wide(&mut self, bvh: &Bvh) -> bool {
        let (su, t_max, switch, frustum) = (self.su, self.lanes.t, self.switch, self.frustum);
        bvh.traverse4_packet(&su.ray, su.valid, t_max, switch, frustum, self);
        false
    }

    #[inline(always)]
    fn binary(&mut self, bvh: &Bvh) -> bool {
        let (su, t_max) = (self.su, self.lanes.t);
        bvh.traverse_packet(&su.ray, S::Mask::from_bitmask(su.valid), t_max, self);
        false
    }
}

impl<S: SimdF32> PacketVisitor<S> for ClosestPacket<'_, S> {
    #[inline(always)]
    fn leaf(&mut self, leaf: Leaf<'_>, lanes: u32, _t_max: S) -> Option<S> {
        // The walk's `t_max` is `self.lanes.t`: it changes only by what this returns.
        self.geometry
            .packet_leaf_closest(leaf, lanes, self.su, &mut self.lanes, self.best);
        Some(self.lanes.t)
    }

    #[inline(always)]
    fn handover(&mut self, bvh: &Bvh, node: u32, lanes: u32, _t_max: S) -> Option<S> {
        let (g, su) = (self.geometry, self.su);
        self.lanes.store(self.best);
        each_lane(lanes, |l| {
            RayQuery::<f32, false, true, { kinds::ALL }, false> {
                g,
                rd: su.lane(l),
                best: &mut self.best[l],
            }
            .wide_from(bvh, node);
        });
        self.lanes = LaneBest::load(self.best);
        Some(self.lanes.t)
    }

    #[inline(always)]
    fn scatter(&mut self, lanes: u32) -> Option<S> {
        let (g, su) = (self.geometry, self.su);
        self.lanes.store(self.best);
        each_lane(lanes, |l| {
            // The single ray's closest hit over every primitive: what its lane must end
            // with. No hit means none so far either (the tests are the same, bit for bit).
            if let Some(b) = su.rays[l]
                .as_ref()
                .and_then(|r| g.closest_best::<true, { kinds::ALL }>(r))
            {
                self.best[l] = b;
            }
        });
        self.lanes = LaneBest::load(self.best);
        Some(self.lanes.t)
    }
}

/// Whether each ray of a packet is blocked: a lane leaves the walk at its first hit, and
/// the walk ends when every lane is blocked.
struct AnyPacket<'a, S: SimdF32> {
    geometry: &'a Geometry<f32>,
    su: &'a Setup<'a, S>,
    /// The lanes blocked so far.
    done: u32,
    /// The hand-over threshold of [`crate::bvh::Bvh::traverse4_packet`].
    switch: u32,
    /// The shadow cache entry ([`Geometry::occluded_packet_switch`]), tested ahead of
    /// the first primitive loop and then cleared.
    cached: u32,
    /// The last primitive found to block a lane, or [`NO_HIT`].
    blocker: u32,
}

impl<S: SimdF32> AnyPacket<'_, S> {
    /// Blocked lanes leave (their `t_max` becomes $-\infty$); `None` once every ray is
    /// blocked.
    #[inline(always)]
    fn update(&self, t_max: S) -> Option<S> {
        let gone = S::splat(f32::NEG_INFINITY);
        // Not `bool::then` with a closure, which could be left out of line without
        // the caller's instruction set (see `Setup::new`).
        if self.su.valid & !self.done != 0 {
            Some(S::select(S::Mask::from_bitmask(self.done), gone, t_max))
        } else {
            None
        }
    }
}

impl<S: SimdF32> Query for AnyPacket<'_, S> {
    const KINDS: u32 = kinds::ALL;

    #[inline(always)]
    fn refs(&mut self, refs: impl Iterator<Item = u32>) -> bool {
        let (g, su) = (self.geometry, self.su);
        let mut m = su.valid & !self.done;
        // The cached occluder goes first, in the same loop: a second call site of
        // `packet_any` made the kernel too large for the closures of the lane kernels
        // to be inlined (`asm-dumps/tests/intrinsic_calls.rs`).
        let cached = core::mem::replace(&mut self.cached, NO_HIT);
        let cached = (cached != NO_HIT && g.names_prim::<{ kinds::ALL }>(cached)).then_some(cached);
        for r in cached.into_iter().chain(refs) {
            if m == 0 {
                break;
            }
            let d = g.packet_any(r, m, su);
            if d != 0 {
                self.blocker = r;
            }
            self.done |= d;
            m &= !d;
        }
        m == 0
    }

    #[inline(always)]
    fn wide(&mut self, bvh: &Bvh) -> bool {
        let (su, switch) = (self.su, self.switch);
        let active = su.valid & !self.done;
        bvh.traverse4_packet(&su.ray, active, su.t_limit, switch, true, self);
        false
    }

    #[inline(always)]
    fn binary(&mut self, bvh: &Bvh) -> bool {
        let su = self.su;
        let active = S::Mask::from_bitmask(su.valid & !self.done);
        bvh.traverse_packet(&su.ray, active, su.t_limit, self);
        false
    }
}

impl<S: SimdF32> PacketVisitor<S> for AnyPacket<'_, S> {
    #[inline(always)]
    fn leaf(&mut self, leaf: Leaf<'_>, lanes: u32, t_max: S) -> Option<S> {
        self.done |=
            self.geometry
                .packet_leaf_any(leaf, lanes & !self.done, self.su, &mut self.blocker);
        self.update(t_max)
    }

    #[inline(always)]
    fn handover(&mut self, bvh: &Bvh, node: u32, lanes: u32, t_max: S) -> Option<S> {
        let (g, su) = (self.geometry, self.su);
        let (mut done, mut blocker) = (self.done, self.blocker);
        each_lane(lanes & !done, |l| {
            let rd = su.lane(l);
            let mut best = Best::none(rd.t_limit);
            let hit = RayQuery::<f32, true, true, { kinds::ALL }, false> {
                g,
                rd,
                best: &mut best,
            }
            .wide_from(bvh, node);
            if hit {
                blocker = best.r;
            }
            done |= u32::from(hit) << l;
        });
        (self.done, self.blocker) = (done, blocker);
        self.update(t_max)
    }

    #[inline(always)]
    fn scatter(&mut self, lanes: u32) -> Option<S> {
        let (g, su) = (self.geometry, self.su);
        let mut done = self.done;
        each_lane(lanes & !done, |l| {
            let blocked = su.rays[l]
                .as_ref()
                .is_some_and(|r| g.any::<true, { kinds::ALL }>(r));
            done |= u32::from(blocked) << l;
        });
        self.done = done;
        self.update(su.t_limit)
    }
}

/// Rays at or below which a packet hands its rays over to single-ray traversal
/// ([`crate::bvh::Bvh::traverse4_packet`]), for every packet width. Four and eight
/// lanes: the instruction count of eye packets (callgrind, `tracer/examples/packet_walk.rs`)
/// was lowest at two on the classic scenes, within 1-3 % of one and of three. Sixteen
/// lanes (AVX-512, which callgrind cannot run): whole renders of the seven scenes were
/// 1.02 and 1.03 times as fast with two as with four (`tracer/RESULTS.md`), and one
/// or none were level with two.
pub(crate) const SWITCH: u32 = 2;

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::*;
    use crate::geometry::AccelOptions;
    use vecexpr::simd::{Isa, Kernel};
    use vecexpr::Expr;

    /// The packet queries of one packet with a given hand-over threshold.
    struct Queries<'a> {
        geometry: &'a Geometry<f32>,
        rays: &'a [Option<Ray<f32>>; MAX_LANES],
        switch: u32,
        frustum: bool,
    }

    impl Kernel for Queries<'_> {
        type Output = ([Option<Hit<f32>>; MAX_LANES], [bool; MAX_LANES]);
        fn run<S: SimdF32>(self) -> Self::Output {
            let mut hits = [None; MAX_LANES];
            let mut blocked = [false; MAX_LANES];
            self.geometry.intersect_packet_switch::<S>(
                self.rays,
                &mut hits,
                self.switch,
                self.frustum,
            );
            self.geometry
                .occluded_packet_switch::<S>(self.rays, &mut blocked, self.switch, &mut { NO_HIT });
            (hits, blocked)
        }
    }

    /// With every hand-over threshold, from never (0) to at once (all lanes), each lane
    /// of eye and shadow packets is the single ray's answer, bit for bit, with and
    /// without the beam walk of rays of one origin; and so over
    /// the binary tree and without a BVH (every step of [`Geometry::query`]).
    #[test]
    fn every_hand_over_threshold_gives_the_single_ray_answers() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
        let wide = AccelOptions::default();
        let binary = AccelOptions {
            wide: false,
            ..wide
        };
        let brute = AccelOptions {
            use_bvh: false,
            ..wide
        };
        let mut blocked_rays = [0usize; 3];
        for name in [
            "showcase.nff",
            "balls-s1.nff",
            "teapot-s1.nff",
            "tree-s1.nff",
        ] {
            let desc = crate::scene::load(&dir.join(name)).unwrap();
            for (k, opts) in [wide, binary, brute].iter().enumerate() {
                let g = &Geometry::<f32>::build(&desc.shapes, opts);
                let (w, h) = (23usize, 17usize);
                let cam = crate::camera::Camera::<f32>::new(&desc.camera, w as u32, h as u32);
                let light = desc.lights.first().map(|l| {
                    let p = l.position.map(|x| x as f32);
                    vec3(p[0], p[1], p[2])
                });
                for isa in Isa::available() {
                    let n = isa.lanes();
                    // The threshold and the beam walk matter to the four-wide walk only.
                    let switches: Vec<(u32, bool)> = if k == 0 {
                        [0, 1, 2, 4, n as u32]
                            .into_iter()
                            .flat_map(|s| [(s, false), (s, true)])
                            .collect()
                    } else {
                        vec![(super::SWITCH, true)]
                    };
                    for (switch, frustum) in switches {
                        // Eye rays in runs of `n` pixels, row-major, so some packets span
                        // two rows; then rays from their hits toward the first light.
                        for first in (0..w * h).step_by(n) {
                            let mut eye = [None; MAX_LANES];
                            for (l, r) in eye.iter_mut().enumerate().take(n) {
                                let k = first + l;
                                if k < w * h {
                                    let (x, y) = ((k % w) as f32 + 0.5, (k / w) as f32 + 0.5);
                                    *r = Some(Ray::new(cam.position, cam.direction(x, y)));
                                }
                            }
                            let (hits, _) = isa.dispatch(Queries {
                                geometry: g,
                                rays: &eye,
                                switch,
                                frustum,
                            });
                            let mut shadow = [None; MAX_LANES];
                            for l in 0..n {
                                let single = eye[l].as_ref().and_then(|r| g.intersect(r));
                                assert_eq!(
                                    hits[l].map(|h| (h.t.to_bits(), h.prim_id)),
                                    single.map(|h| (h.t.to_bits(), h.prim_id)),
                                    "{name} {opts:?} {isa} switch {switch} ray {}",
                                    first + l
                                );
                                if let (Some(hit), Some(p)) = (single, light) {
                                    let o = (hit.point + hit.geometric_normal.scale(1e-3)).eval();
                                    let d = (p - o).eval();
                                    shadow[l] = Some(Ray {
                                        t_max: 1.0,
                                        ..Ray::new(o, d)
                                    });
                                }
                            }
                            let (_, blocked) = isa.dispatch(Queries {
                                geometry: g,
                                rays: &shadow,
                                switch,
                                frustum,
                            });
                            for l in 0..n {
                                let single = shadow[l].as_ref().is_some_and(|r| g.occluded(r));
                                assert_eq!(
                                    blocked[l], single,
                                    "{name} {opts:?} {isa} switch {switch}"
                                );
                                blocked_rays[k] += usize::from(single);
                            }
                        }
                    }
                }
            }
        }
        assert!(
            blocked_rays.iter().all(|&b| b > 100),
            "too few blocked shadow rays: {blocked_rays:?}"
        );
    }

    /// Eye packets whose beams give up (a lattice of small spheres seen through a
    /// coarse camera, so most leaves a beam reaches lie between its rays): each lane
    /// still ends with the single ray's closest hit, and an any-hit query of the same
    /// rays (bounded, so some are blocked and some not) with the single ray's answer;
    /// the packets that skip the beam after others gave up as well.
    #[test]
    fn beams_that_give_up_give_the_single_ray_answers() {
        use core::sync::atomic::Ordering;
        let mut nff = String::from(
            "v\nfrom 40 31 36\nat 9 9 6\nup 0 0 1\nangle 70\nhither 0.01\n\
             resolution 12 12\nl 50 40 60\nf 1 0.5 0.2 1 0 0 0 0\n\
             p 4\n-100 -100 -1\n100 -100 -1\n100 100 -1\n-100 100 -1\n",
        );
        for i in 0..20 {
            for j in 0..20 {
                for k in 0..14 {
                    nff += &format!("s {i} {j} {k} 0.06\n");
                }
            }
        }
        let desc = crate::scene::nff::parse_nff(nff, "lattice.nff").unwrap();
        let g = &Geometry::<f32>::build(&desc.shapes, &AccelOptions::default());
        let (w, h) = (12usize, 12usize);
        let cam = crate::camera::Camera::<f32>::new(&desc.camera, w as u32, h as u32);
        use crate::bvh::packet_traverse::{BEAMS_GIVEN_UP, BEAMS_SKIPPED};
        let before = BEAMS_GIVEN_UP.load(Ordering::Relaxed);
        let skipped_before = BEAMS_SKIPPED.load(Ordering::Relaxed);
        let (mut hits_seen, mut blocked_seen) = (0, 0);
        for isa in Isa::available() {
            let n = isa.lanes();
            // Square tiles of packets where the width allows (4x4 for sixteen lanes),
            // runs of a row otherwise: the tiles' rays share their origin.
            let side = if n == 16 { 4 } else { 1 };
            for ty in (0..h).step_by(side) {
                for tx in (0..w).step_by(n / side) {
                    let mut eye = [None; MAX_LANES];
                    let mut bounded = [None; MAX_LANES];
                    for (l, (r, b)) in eye.iter_mut().zip(&mut bounded).enumerate().take(n) {
                        let (x, y) = (tx + l % (n / side), ty + l / (n / side));
                        if x < w && y < h {
                            let ray = Ray::new(
                                cam.position,
                                cam.direction(x as f32 + 0.5, y as f32 + 0.5),
                            );
                            *r = Some(ray);
                            *b = Some(Ray { t_max: 42.0, ..ray });
                        }
                    }
                    let (hits, _) = isa.dispatch(Queries {
                        geometry: g,
                        rays: &eye,
                        switch: super::SWITCH,
                        frustum: true,
                    });
                    let (_, blocked) = isa.dispatch(Queries {
                        geometry: g,
                        rays: &bounded,
                        switch: super::SWITCH,
                        frustum: true,
                    });
                    for l in 0..n {
                        let single = eye[l].as_ref().and_then(|r| g.intersect(r));
                        assert_eq!(
                            hits[l].map(|h| (h.t.to_bits(), h.prim_id)),
                            single.map(|h| (h.t.to_bits(), h.prim_id)),
                            "{isa} lane {l} of the packet at ({tx}, {ty})"
                        );
                        let single = bounded[l].as_ref().is_some_and(|r| g.occluded(r));
                        assert_eq!(blocked[l], single, "{isa} lane {l} at ({tx}, {ty})");
                        hits_seen += usize::from(hits[l].is_some());
                        blocked_seen += usize::from(single);
                    }
                }
            }
        }
        // Beams give up; after two in a row the next packets skip the beam (one in eight
        // tries it again) until a beam gets through, on this test's thread.
        let given_up = BEAMS_GIVEN_UP.load(Ordering::Relaxed) - before;
        let skipped = BEAMS_SKIPPED.load(Ordering::Relaxed) - skipped_before;
        assert!(given_up > 10, "only {given_up} beams gave up");
        assert!(
            skipped > given_up,
            "{skipped} beams skipped, {given_up} gave up"
        );
        assert!(
            hits_seen > 100 && blocked_seen > 10 && blocked_seen < hits_seen,
            "{hits_seen} hits, {blocked_seen} blocked"
        );
    }
}
