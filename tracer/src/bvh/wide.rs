//! Four-wide BVH: the binary tree collapsed into nodes of up to four children, whose
//! boxes are tested against a ray in one pass over `vecexpr` packets of four lanes.
//!
//! # Layout (128 bytes, two cache lines)
//! ```text
//! bounds[side][axis][lane]  f32 x 24  96 bytes  side 0 = lo, 1 = hi; SoA over the children
//! child[lane]               u32 x 4   16 bytes  leaf: first index into `Bvh::refs`
//!                                               interior: index of the child node
//!                                               unused slot: EMPTY_SLOT
//! count[lane]               u32 x 4   16 bytes  leaf: number of primitives; else 0
//! ```
//! A leaf whose `count` has [`GROUPED`] set was rewritten by its owner
//! (`Bvh::regroup_wide_leaves`): its `child` then indexes the owner's own leaf data
//! (the geometry's groups of four triangles) instead of `Bvh::refs`, and the low bits
//! still count its primitives.
//! Unused slots get the empty box (`lo = +inf`, `hi = -inf`), which no ray can enter, so
//! the box test needs no special case for them.
//!
//! The collapse (Dammertz et al., "Shallow Bounding Volume Hierarchies for Fast SIMD Ray
//! Tracing of Incoherent Rays", EGSR 2008; Wald et al., "Getting Rid of Packets", RT
//! 2008, section 3, keeping the binary SAH tree) starts a wide node from the two
//! children of its binary node and opens the interior child of largest surface area
//! (the one a random ray most likely enters) into its two children, until four slots
//! are filled or only leaves remain. Nodes are thus full wherever the subtree allows
//! (the collapse of every second level left a slot empty wherever a child was a leaf):
//! 0 to 15 % fewer wide nodes on the classic scenes, and 2 to 5 % fewer instructions per
//! single eye ray on five of the seven (`tracer/RESULTS.md`, "Packets over the four-wide
//! tree"). Each wide level spans at least one binary level, so a
//! tree of binary depth [`super::build::MAX_DEPTH`] has at most as many wide levels,
//! which bounds the traversal stack ([`STACK_SIZE`]).
//!
//! The box test is the same conservative slab test as the binary traversal (Ize 2013,
//! see [`super::traverse`]), lane by lane: lane `i` of the packet computes exactly what
//! `TraversalRay::hit_box` computes for child `i`, so both trees report the same
//! candidate set up to the tree shape, and the closest-hit result (which the geometry
//! makes independent of traversal order) is bit-identical.

use super::node::{Bounds3, Node};
use super::traverse::TraversalRay;
use super::Bvh;
use core::mem::MaybeUninit;
use vecexpr::typenum::U4;
use vecexpr::{Mask, Packet, Real, Scalar};

/// Children per node.
pub const WIDTH: usize = 4;
/// `child` of an unused slot.
pub const EMPTY_SLOT: u32 = u32::MAX;
/// Flag in a leaf's `count`: `child` indexes the owner's grouped leaf data, not
/// `Bvh::refs` (see the module docs).
pub const GROUPED: u32 = 1 << 31;
/// Pending entries: at most three per wide level (the siblings of the path), and at
/// most `MAX_DEPTH` wide levels (each spans at least one binary level).
pub const STACK_SIZE: usize = (WIDTH - 1) * super::build::MAX_DEPTH + 1;

/// One node of the four-wide BVH (see the module docs for the layout).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub struct Node4 {
    /// `[lo, hi][axis][child]`, rounded outward to `f32`.
    pub bounds: [[[f32; WIDTH]; 3]; 2],
    /// Leaf: first reference; interior: node index; unused: [`EMPTY_SLOT`].
    pub child: [u32; WIDTH],
    /// Leaf: number of primitives (at least 1); interior or unused: 0.
    pub count: [u32; WIDTH],
}

const _: () = assert!(core::mem::size_of::<Node4>() == 128);

impl Node4 {
    /// A node with every slot unused.
    pub const EMPTY: Self = Self {
        bounds: [[[f32::INFINITY; WIDTH]; 3], [[f32::NEG_INFINITY; WIDTH]; 3]],
        child: [EMPTY_SLOT; WIDTH],
        count: [0; WIDTH],
    };

    fn set(&mut self, lane: usize, b: &[[f32; 3]; 2], child: u32, count: u32) {
        for (dst, src) in self.bounds.iter_mut().zip(b) {
            for (d, &x) in dst.iter_mut().zip(src) {
                d[lane] = x;
            }
        }
        self.child[lane] = child;
        self.count[lane] = count;
    }
}

/// Collapses a depth-first binary tree (root at 0) into wide nodes, depth-first, root
/// at 0. Returns the nodes and the depth in wide levels.
pub fn collapse(bin: &[Node]) -> (Vec<Node4>, usize) {
    let mut out = Vec::with_capacity(bin.len() / 2 + 1);
    if bin.is_empty() {
        return (out, 0);
    }
    let depth = emit(bin, 0, &mut out);
    (out, depth)
}

/// Emits the wide node of binary node `at` and, recursively, its interior children.
/// Returns the depth (levels) of the emitted subtree.
fn emit(bin: &[Node], at: usize, out: &mut Vec<Node4>) -> usize {
    let idx = out.len();
    out.push(Node4::EMPTY);
    let mut slots = [0usize; WIDTH];
    let mut n;
    let node = &bin[at];
    if node.is_leaf() {
        slots[0] = at;
        n = 1;
    } else {
        // Start from the two children and open the interior child of largest surface
        // area until four slots are filled or only leaves are left.
        slots[0] = at + 1;
        slots[1] = node.offset as usize;
        n = 2;
        while n < WIDTH {
            let mut open: Option<(usize, f32)> = None;
            for (i, &c) in slots[..n].iter().enumerate() {
                if bin[c].is_leaf() {
                    continue;
                }
                let b = &bin[c].bounds;
                let area = Bounds3 { lo: b[0], hi: b[1] }.half_area();
                if open.is_none_or(|(_, a)| area > a) {
                    open = Some((i, area));
                }
            }
            let Some((i, _)) = open else {
                break;
            };
            let c = slots[i];
            slots[i] = c + 1;
            slots[n] = bin[c].offset as usize;
            n += 1;
        }
    }
    let mut wide = Node4::EMPTY;
    let mut depth = 1;
    for (lane, &c) in slots[..n].iter().enumerate() {
        let b = &bin[c];
        if b.is_leaf() {
            wide.set(lane, &b.bounds, b.offset, b.count);
        } else {
            let child = out.len() as u32;
            depth = depth.max(1 + emit(bin, c, out));
            wide.set(lane, &b.bounds, child, 0);
        }
    }
    out[idx] = wide;
    depth
}

type P4<T> = Packet<T, U4>;

impl<T: Real> TraversalRay<T> {
    /// The slab test of [`TraversalRay::hit_box`] for the four children of `node` at
    /// once: per lane, whether the ray overlaps the box within `(t_min, t_max]`
    /// (conservatively) and the entry distance.
    #[inline(always)]
    pub fn hit_box4(&self, node: &Node4, t_max: T) -> ([bool; WIDTH], [T; WIDTH]) {
        let (bits, t_near) = self.hit_box4_bits(node, t_max);
        (core::array::from_fn(|i| bits & (1 << i) != 0), t_near)
    }

    /// [`TraversalRay::hit_box4`] with the hit lanes as bits (`1 << lane`), which the
    /// traversal branches on once instead of once per lane.
    #[inline(always)]
    pub fn hit_box4_bits(&self, node: &Node4, t_max: T) -> (u32, [T; WIDTH]) {
        let lanes = |v: &[f32; WIDTH]| P4::<T>::from_fn(|i| T::from_f64(f64::from(v[i])));
        let mut t_near = P4::<T>::splat(self.t_min);
        let mut t_far = P4::<T>::splat(t_max * self.slack);
        for a in 0..3 {
            let n = self.neg[a] as usize;
            let near = lanes(&node.bounds[n][a]);
            let far = lanes(&node.bounds[1 - n][a]);
            let o = P4::<T>::splat(self.origin[a]);
            let inv = P4::<T>::splat(self.inv_dir[a]);
            let tn = (near - o) * inv;
            let tf = (far - o) * P4::<T>::splat(self.inv_far[a]);
            // minps/maxps rule per lane: a NaN `tn`/`tf` leaves the running value.
            t_near = Scalar::max(tn, t_near);
            t_far = Scalar::min(tf, t_far);
        }
        let hit = t_near.le(t_far);
        let mut bits = 0;
        for i in 0..WIDTH {
            bits |= (hit.test(i) as u32) << i;
        }
        (bits, core::array::from_fn(|i| t_near.lane(i)))
    }
}

/// A pending subtree: child (node index or first reference), count (0 for an interior
/// node) and entry distance.
#[derive(Clone, Copy)]
struct Entry<T> {
    child: u32,
    count: u32,
    t: T,
}

/// A leaf of the four-wide tree as [`Bvh::traverse4`] hands it out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Leaf<'a> {
    /// Primitive references (a run of `Bvh::refs`).
    Refs(&'a [u32]),
    /// A leaf rewritten by `Bvh::regroup_wide_leaves`: the owner's `child` and the
    /// number of primitives.
    Grouped {
        /// What the owner's callback returned for this leaf.
        child: u32,
        /// Primitives in the leaf.
        count: u32,
    },
}

impl Bvh {
    /// The leaf of a wide node's slot, from its `child` and `count`.
    #[inline(always)]
    pub(crate) fn leaf(&self, child: u32, count: u32) -> Leaf<'_> {
        if count & GROUPED != 0 {
            Leaf::Grouped {
                child,
                count: count & !GROUPED,
            }
        } else {
            let first = child as usize;
            Leaf::Refs(&self.refs[first..first + count as usize])
        }
    }

    /// The four-wide tree, if one was built.
    pub fn wide_nodes(&self) -> &[Node4] {
        &self.wide
    }

    /// Visits every leaf of the four-wide tree in node order (and slot order within a
    /// node) with its references; where `f` returns `Some(child)` the leaf is marked
    /// [`GROUPED`] with that `child`, so [`Bvh::traverse4`] hands the leaf to its
    /// callback as [`Leaf::Grouped`]. The binary tree and `refs` are kept.
    pub(crate) fn regroup_wide_leaves(&mut self, mut f: impl FnMut(&[u32]) -> Option<u32>) {
        for node in &mut self.wide {
            for lane in 0..WIDTH {
                let count = node.count[lane];
                if count == 0 || count & GROUPED != 0 {
                    continue;
                }
                let first = node.child[lane] as usize;
                if let Some(child) = f(&self.refs[first..first + count as usize]) {
                    node.child[lane] = child;
                    node.count[lane] = count | GROUPED;
                }
            }
        }
    }

    /// As [`Bvh::traverse`], over the four-wide tree: at each node the four child boxes
    /// are tested in one packet, the hit children are visited nearest first and the
    /// others pushed with their entry distances. With `ANY_HIT` the hit children are
    /// visited in slot order instead: the walk stops at the first hit anyway, and
    /// `t_max` never shrinks, so neither sorting nor the distance check on pop pays.
    ///
    /// `leaf(leaf, t_max)` is called with [`Leaf::Refs`] for a leaf of references and
    /// with [`Leaf::Grouped`] for one rewritten by `Bvh::regroup_wide_leaves`.
    #[inline(always)]
    pub fn traverse4<T: Real, const ANY_HIT: bool>(
        &self,
        ray: &TraversalRay<T>,
        t_max: T,
        leaf: impl FnMut(Leaf<'_>, T) -> Option<T>,
    ) -> bool {
        self.traverse4_from::<T, ANY_HIT>(0, ray, t_max, leaf)
    }

    /// [`Bvh::traverse4`] over the subtree of wide node `start` only (0 is the root):
    /// the packet traversal hands its rays over to it one by one where few rays of a
    /// packet remain ([`Bvh::traverse4_packet`]).
    #[inline(always)]
    pub fn traverse4_from<T: Real, const ANY_HIT: bool>(
        &self,
        start: u32,
        ray: &TraversalRay<T>,
        mut t_max: T,
        mut leaf: impl FnMut(Leaf<'_>, T) -> Option<T>,
    ) -> bool {
        let nodes: &[Node4] = &self.wide;
        if nodes.is_empty() {
            return false;
        }
        // Left uninitialised: only the entries below `sp` are ever read, and zeroing
        // the whole array cost more than a typical query's box tests.
        let mut stack = [const { MaybeUninit::<Entry<T>>::uninit() }; STACK_SIZE];
        let mut sp = 0usize;
        let mut found = false;
        let mut at = start as usize;
        'walk: loop {
            let node = &nodes[at];
            let (mut bits, tn) = ray.hit_box4_bits(node, t_max);
            let mut entry = None;
            if bits != 0 {
                let first = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                if bits == 0 {
                    // One child hit (the common case): no ordering.
                    entry = Some((node.child[first], node.count[first]));
                } else if ANY_HIT {
                    entry = Some((node.child[first], node.count[first]));
                    while bits != 0 {
                        let i = bits.trailing_zeros() as usize;
                        bits &= bits - 1;
                        stack[sp].write(Entry {
                            child: node.child[i],
                            count: node.count[i],
                            t: tn[i],
                        });
                        sp += 1;
                    }
                } else if bits & (bits - 1) == 0 {
                    // Two children hit: visit the nearer, push the farther.
                    let second = bits.trailing_zeros() as usize;
                    let (near, far) = if tn[second] < tn[first] {
                        (second, first)
                    } else {
                        (first, second)
                    };
                    stack[sp].write(Entry {
                        child: node.child[far],
                        count: node.count[far],
                        t: tn[far],
                    });
                    sp += 1;
                    entry = Some((node.child[near], node.count[near]));
                } else {
                    // Hit children sorted by entry distance (insertion sort of 3 or 4),
                    // pushed farthest first so that pops come nearest first.
                    let mut order = [first; WIDTH];
                    let mut k = 1;
                    while bits != 0 {
                        let i = bits.trailing_zeros() as usize;
                        bits &= bits - 1;
                        let mut j = k;
                        while j > 0 && tn[i] < tn[order[j - 1]] {
                            order[j] = order[j - 1];
                            j -= 1;
                        }
                        order[j] = i;
                        k += 1;
                    }
                    for &i in order[1..k].iter().rev() {
                        stack[sp].write(Entry {
                            child: node.child[i],
                            count: node.count[i],
                            t: tn[i],
                        });
                        sp += 1;
                    }
                    let i = order[0];
                    entry = Some((node.child[i], node.count[i]));
                }
            }
            loop {
                match entry {
                    Some((child, 0)) => {
                        at = child as usize;
                        continue 'walk;
                    }
                    Some((first, count)) => {
                        let l = self.leaf(first, count);
                        if let Some(t) = leaf(l, t_max) {
                            found = true;
                            if ANY_HIT {
                                return true;
                            }
                            t_max = t;
                        }
                    }
                    None => {}
                }
                // Pop the nearest pending entry that may still hold a closer hit.
                entry = None;
                while sp > 0 {
                    sp -= 1;
                    // SAFETY: every slot below `sp` was written by a push above, and
                    // `Entry` is `Copy`, so reading it out leaves the slot valid.
                    let e = unsafe { stack[sp].assume_init_read() };
                    if ANY_HIT || e.t <= t_max * ray.slack {
                        entry = Some((e.child, e.count));
                        break;
                    }
                }
                if entry.is_none() {
                    return found;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vecexpr::vec3;

    #[test]
    fn packet_test_matches_the_scalar_test() {
        let boxes = [
            [[0.0f32, 0.0, 0.0], [1.0, 1.0, 1.0]],
            [[2.0, -1.0, 0.0], [3.0, 1.0, 0.0]],
            [[-5.0, -5.0, -5.0], [-4.0, -4.0, -4.0]],
            [[0.0, 0.5, -1.0], [0.0, 0.5, 1.0]],
        ];
        let mut node = Node4::EMPTY;
        for (i, b) in boxes.iter().enumerate() {
            node.set(i, b, i as u32, 1);
        }
        for (o, d) in [
            (vec3(-1.0f32, 0.5, 0.5), vec3(1.0, 0.0, 0.0)),
            (vec3(-1.0, 0.5, 0.0), vec3(1.0, 0.0, 0.0)),
            (vec3(0.0, 0.5, -2.0), vec3(0.0, 0.0, 1.0)),
            (vec3(10.0, 10.0, 10.0), vec3(-1.0, -1.0, -1.0)),
        ] {
            let r = TraversalRay::new(&o, &d, 0.0);
            for t_max in [f32::INFINITY, 1.5] {
                let (hit, tn) = r.hit_box4(&node, t_max);
                for (i, b) in boxes.iter().enumerate() {
                    let scalar = r.hit_box(b, t_max);
                    assert_eq!(scalar.is_some(), hit[i], "{o:?} {d:?} box {i}");
                    if let Some(t) = scalar {
                        assert_eq!(t, tn[i]);
                    }
                }
            }
        }
        let r = TraversalRay::new(&vec3(0.0f64, 0.0, 0.0), &vec3(1.0, 1.0, 1.0), 0.0);
        assert_eq!(r.hit_box4(&Node4::EMPTY, f64::INFINITY).0, [false; 4]);
    }

    #[test]
    fn collapse_keeps_every_leaf_once() {
        use crate::bvh::{Bounds3, BuildConfig, BuildPrim};
        let mut prims: Vec<BuildPrim> = (0..300)
            .map(|i| {
                let x = (i * 7919 % 300) as f32;
                BuildPrim::new(
                    Bounds3 {
                        lo: [x, (i % 17) as f32, 0.0],
                        hi: [x + 0.5, (i % 17) as f32 + 0.5, 1.0],
                    },
                    i,
                )
            })
            .collect();
        let cfg = BuildConfig {
            max_leaf_size: 4,
            parallel: false,
            traversal_cost: 2.0,
        };
        let bvh = Bvh::build(&mut prims, &cfg);
        let mut seen = vec![0u32; prims.len()];
        for n in bvh.wide_nodes() {
            for i in 0..WIDTH {
                if n.count[i] > 0 {
                    for r in n.child[i]..n.child[i] + n.count[i] {
                        seen[r as usize] += 1;
                    }
                }
            }
        }
        assert!(seen.iter().all(|&s| s == 1));
        // Every wide level spans one or two binary levels.
        assert!(bvh.wide_depth() * 2 >= bvh.depth() - 1);
        assert!(bvh.wide_depth() <= bvh.depth());
        // A node has fewer than four slots only when nothing is left to open: all its
        // children are leaves.
        for n in bvh.wide_nodes() {
            let used = n.child.iter().filter(|&&c| c != EMPTY_SLOT).count();
            if used < WIDTH {
                assert!((0..used).all(|i| n.count[i] > 0), "{n:?}");
            }
        }
    }
}
