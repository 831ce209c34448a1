//! Bounding volume hierarchy over opaque primitive references.
//!
//! The BVH knows nothing about primitive types: it is built from conservative `f32`
//! boxes with a `u32` id each ([`BuildPrim`]) and stores those ids in leaf order
//! ([`Bvh::refs`]); [`crate::geometry`] gives the ids their meaning and reorders its
//! primitive arrays to match, so a leaf's primitives are contiguous in memory.
//!
//! - [`build`]: binned SAH construction (Wald 2007), parallel and deterministic.
//! - [`node`]: the 32-byte node and its layout.
//! - [`traverse`]: ordered closest-hit and early-exit any-hit traversal with a
//!   conservative slab test (Ize 2013).
//! - [`wide`]: the same tree collapsed into four-wide nodes whose boxes are tested in
//!   one packet, with the same ordered and early-exit traversals; and, for single
//!   rays and beams of eye rays on CPUs with AVX2, into eight-wide nodes tested in one
//!   AVX register.
//! - [`packet_traverse`]: packets of rays in SIMD lanes over either tree.
//!
//! Every box test is the one slab formula [`traverse::slab`] (the four-box test of a
//! wide node writes its operations out, for speed: see [`wide::box_test`]).

pub mod build;
pub mod node;
pub mod packet_traverse;
pub mod traverse;
pub mod wide;

pub use build::{BuildConfig, BuildPrim};
pub use node::{Bounds3, Node};
pub use traverse::TraversalRay;
pub use wide::{Node4, Node8};

/// A flattened BVH: depth-first nodes plus the primitive ids in leaf order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bvh {
    nodes: Vec<Node>,
    wide: Vec<Node4>,
    wide8: Vec<Node8>,
    refs: Vec<u32>,
    depth: usize,
    wide_depth: usize,
}

impl Bvh {
    /// Builds over the given primitives (reordered in place).
    ///
    /// # Panics
    /// If there are more than `u32::MAX` primitives.
    pub fn build(prims: &mut [BuildPrim], cfg: &BuildConfig) -> Self {
        Self::build_beside(prims, cfg, false, |_| ()).0
    }

    /// [`Bvh::build`], with the eight-wide tree as well, which single rays walk where
    /// the CPU has AVX2 ([`Bvh::traverse8`]): the binary tree collapsed a second time,
    /// beside the four-wide collapse on the rayon pool when `cfg.parallel`.
    ///
    /// # Panics
    /// If there are more than `u32::MAX` primitives.
    pub fn build_with_eight_wide(prims: &mut [BuildPrim], cfg: &BuildConfig) -> Self {
        Self::build_beside(prims, cfg, true, |_| ()).0
    }

    /// [`Bvh::build`], or [`Bvh::build_with_eight_wide`] when `eight`, calling `side` on
    /// the primitive ids in leaf order (the future [`Bvh::refs`]) while the binary tree
    /// is collapsed into the wide ones. `side` may rewrite the ids: a caller that moves
    /// its primitives into leaf order points them at their new places there. Its result
    /// is returned beside the tree.
    ///
    /// With `cfg.parallel` the three run as rayon tasks: the eight-wide collapse (the
    /// longest) on this thread at once, the four-wide collapse and then `side` on
    /// another, so that on two threads the collapses and the caller's reordering end
    /// close together instead of one after the other. Each task's result depends only
    /// on the tree, so the outcome is the same for any number of threads.
    ///
    /// # Panics
    /// If there are more than `u32::MAX` primitives.
    pub fn build_beside<R: Send>(
        prims: &mut [BuildPrim],
        cfg: &BuildConfig,
        eight: bool,
        side: impl FnOnce(&mut [u32]) -> R + Send,
    ) -> (Self, R) {
        assert!(
            u32::try_from(prims.len()).is_ok(),
            "too many primitives for a BVH"
        );
        let (nodes, depth) = build::build(prims, cfg);
        let prims = &*prims;
        let four = || wide::collapse(&nodes);
        let eight = || {
            if eight {
                wide::collapse(&nodes).0
            } else {
                Vec::new()
            }
        };
        let refs = || {
            let mut refs: Vec<u32> = prims.iter().map(|p| p.id).collect();
            let r = side(&mut refs);
            (refs, r)
        };
        let (wide8, ((wide, wide_depth), (refs, r))) = if cfg.parallel {
            rayon::join(eight, || rayon::join(four, refs))
        } else {
            (eight(), (four(), refs()))
        };
        let bvh = Self {
            nodes,
            wide,
            wide8,
            refs,
            depth,
            wide_depth,
        };
        (bvh, r)
    }

    /// The nodes, depth-first; the root is `nodes()[0]` (empty for no primitives).
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// Primitive ids in leaf order: a leaf covers `refs()[offset..offset + count]`.
    pub fn refs(&self) -> &[u32] {
        &self.refs
    }

    /// Number of levels (1 for a single leaf, 0 when empty).
    pub fn depth(&self) -> usize {
        self.depth
    }

    /// Levels of the four-wide tree (0 when empty).
    pub fn wide_depth(&self) -> usize {
        self.wide_depth
    }

    /// Bytes of the binary nodes plus references.
    pub fn bytes(&self) -> usize {
        self.nodes.len() * core::mem::size_of::<Node>() + self.refs.len() * 4
    }

    /// Bytes of the four-wide nodes plus references.
    pub fn wide_bytes(&self) -> usize {
        self.wide.len() * core::mem::size_of::<Node4>() + self.refs.len() * 4
    }

    /// Bytes of the eight-wide nodes (0 unless built).
    pub fn wide8_bytes(&self) -> usize {
        self.wide8.len() * core::mem::size_of::<Node8>()
    }

    /// SAH cost of the binary tree (MacDonald and Booth 1990):
    /// $\left(C_{trav} \sum_{interior} A(n) + \sum_{leaves} A(l) N(l)\right) / A(root)$,
    /// with $A$ the surface area and one primitive test costing 1; 0 when empty. Lower
    /// is a better tree for random rays.
    pub fn sah_cost(&self, traversal_cost: f32) -> f64 {
        let area = |n: &Node| {
            let d: [f64; 3] =
                core::array::from_fn(|a| f64::from((n.bounds[1][a] - n.bounds[0][a]).max(0.0)));
            d[0] * d[1] + d[1] * d[2] + d[2] * d[0]
        };
        let Some(root) = self.nodes.first() else {
            return 0.0;
        };
        let sum: f64 = self
            .nodes
            .iter()
            .map(|n| {
                if n.is_leaf() {
                    area(n) * f64::from(n.count)
                } else {
                    area(n) * f64::from(traversal_cost)
                }
            })
            .sum();
        let a = area(root);
        if a > 0.0 {
            sum / a
        } else {
            0.0
        }
    }
}
