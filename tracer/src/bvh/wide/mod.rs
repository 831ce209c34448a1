//! Wide BVHs: the binary tree collapsed into nodes of up to four children, whose boxes
//! are tested against a ray in one pass over `vecexpr` packets of four lanes (one SSE
//! register), and, for single `f32` rays on CPUs with AVX2, into nodes of up to eight
//! children tested in one AVX register ([`Node8`], [`Bvh::traverse8`]).
//!
//! Both widths are one type, [`WideNode<W>`], one collapse and one walk. Single rays
//! walk the eight-wide tree where they can: it has about half the levels, and the box
//! test of eight children costs the instructions of four. On the seven classic scenes
//! a single eye ray runs 10 to 21 % fewer instructions than on the four-wide tree, and
//! single rays against Embree went from 0.93 to 1.03 (eye) and 0.86 to 1.01 (shadow)
//! on the geometric mean (`tracer/JOURNAL.md`, "An eight-wide tree for single rays").
//! Packets that test each child against their rays keep the four-wide tree (their box
//! test puts rays, not children, in the lanes); eye packets that walk as one beam
//! test a node's children against the beam, and take the eight-wide tree in AVX2 and
//! AVX-512 code ([`Bvh::traverse4_packet`]).
//!
//! # Layout of a [`Node4`] (128 bytes, two cache lines; a [`Node8`] is the same over
//! eight lanes, 256 bytes)
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
//! single eye ray on five of the seven (`tracer/JOURNAL.md`, "packets over the four-wide
//! tree"). Each wide level spans at least one binary level, so a
//! tree of binary depth [`super::build::MAX_DEPTH`] has at most as many wide levels,
//! which bounds the traversal stack ([`STACK_SIZE`]).
//!
//! The box test is the same conservative slab test as the binary traversal (Ize 2013,
//! see [`super::traverse`]), lane by lane: lane `i` of the packet computes exactly what
//! `TraversalRay::hit_box` computes for child `i`, so both trees report the same
//! candidate set up to the tree shape, and the closest-hit result (which the geometry
//! makes independent of traversal order) is bit-identical.

//!
//! | file | holds |
//! |---|---|
//! | `mod.rs` | the node type [`WideNode`] ([`Node4`], [`Node8`]), the leaf handle [`Leaf`] |
//! | [`collapse`](mod@collapse) | the binary tree collapsed into wide nodes |
//! | [`box_test`] | the slab test of a ray against the four or eight boxes of a node |
//! | [`traverse`](mod@traverse) | the single-ray walk ([`Bvh::traverse4`], [`Bvh::traverse8`]) |
//!
//! The walk of a packet over the same nodes is [`super::packet_traverse`].

pub mod box_test;
pub mod collapse;
pub mod traverse;

use super::Bvh;

pub use collapse::collapse;

/// Children per node of the four-wide tree.
pub const WIDTH: usize = 4;
/// Children per node of the eight-wide tree.
pub const WIDTH8: usize = 8;
/// `child` of an unused slot.
pub const EMPTY_SLOT: u32 = u32::MAX;
/// Flag in a leaf's `count`: `child` indexes the owner's grouped leaf data, not
/// `Bvh::refs` (see the module docs).
pub const GROUPED: u32 = 1 << 31;
/// Pending entries of the four-wide walk: at most three per wide level (the siblings of
/// the path), and at most `MAX_DEPTH` wide levels (each spans at least one binary level).
pub const STACK_SIZE: usize = (WIDTH - 1) * super::build::MAX_DEPTH + 1;
/// Pending entries of the eight-wide walk: at most seven per level.
pub const STACK_SIZE8: usize = (WIDTH8 - 1) * super::build::MAX_DEPTH + 1;

/// One node of a `W`-wide BVH (see the module docs for the layout of [`Node4`]; a
/// [`Node8`] has the same fields over eight lanes, 256 bytes).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub struct WideNode<const W: usize> {
    /// `[lo, hi][axis][child]`, rounded outward to `f32`.
    pub bounds: [[[f32; W]; 3]; 2],
    /// Leaf: first reference; interior: node index; unused: [`EMPTY_SLOT`].
    pub child: [u32; W],
    /// Leaf: number of primitives (at least 1); interior or unused: 0.
    pub count: [u32; W],
}

/// A node of the four-wide tree.
pub type Node4 = WideNode<WIDTH>;
/// A node of the eight-wide tree, which single rays walk where the CPU has AVX2
/// ([`mod@traverse`]).
pub type Node8 = WideNode<WIDTH8>;

const _: () = assert!(core::mem::size_of::<Node4>() == 128);
const _: () = assert!(core::mem::size_of::<Node8>() == 256);

impl<const W: usize> WideNode<W> {
    /// A node with every slot unused.
    pub const EMPTY: Self = Self {
        bounds: [[[f32::INFINITY; W]; 3], [[f32::NEG_INFINITY; W]; 3]],
        child: [EMPTY_SLOT; W],
        count: [0; W],
    };

    pub(crate) fn set(&mut self, lane: usize, b: &[[f32; 3]; 2], child: u32, count: u32) {
        for (dst, src) in self.bounds.iter_mut().zip(b) {
            for (d, &x) in dst.iter_mut().zip(src) {
                d[lane] = x;
            }
        }
        self.child[lane] = child;
        self.count[lane] = count;
    }
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

    /// The eight-wide tree (empty unless built by [`Bvh::build_with_eight_wide`]).
    pub fn wide8_nodes(&self) -> &[Node8] {
        &self.wide8
    }

    /// Visits every leaf of the four-wide tree in node order (and slot order within a
    /// node) with its references; where `f` returns `Some(child)` the leaf is marked
    /// [`GROUPED`] with that `child`, so [`Bvh::traverse4`] hands the leaf to its
    /// callback as [`Leaf::Grouped`]. The eight-wide tree, which has the same leaves,
    /// is marked alike. The binary tree and `refs` are kept.
    pub(crate) fn regroup_wide_leaves(&mut self, mut f: impl FnMut(&[u32]) -> Option<u32>) {
        // The grouped `child` of each leaf, by its first reference.
        let mut grouped = vec![
            EMPTY_SLOT;
            if self.wide8.is_empty() {
                0
            } else {
                self.refs.len()
            }
        ];
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
                    if let Some(g) = grouped.get_mut(first) {
                        *g = child;
                    }
                }
            }
        }
        for node in &mut self.wide8 {
            for lane in 0..WIDTH8 {
                let count = node.count[lane];
                if count == 0 || count & GROUPED != 0 {
                    continue;
                }
                let child = grouped[node.child[lane] as usize];
                if child != EMPTY_SLOT {
                    node.child[lane] = child;
                    node.count[lane] = count | GROUPED;
                }
            }
        }
    }
}
