//! Binned SAH construction.
//!
//! I. Wald, "On fast Construction of SAH-based Bounding Volume Hierarchies", IEEE
//! Symposium on Interactive Ray Tracing 2007: instead of sorting, primitive centroids
//! are dropped into up to [`NUM_BINS`] equal bins along each axis of the node's centroid
//! bounds, and the surface area heuristic
//! $C = C_{trav} + C_{isect} (A_L N_L + A_R N_R) / A$ is evaluated only at the bin
//! boundaries, with two sweeps over the bins. All three axes are binned in the same
//! pass over the primitives.
//!
//! A node becomes a leaf when it holds one primitive, or at most `max_leaf_size` and the
//! SAH finds no split cheaper than intersecting them all. When the centroids coincide
//! (no bin split exists), the node is split at the object median instead.
//!
//! The depth of every leaf is at most [`MAX_DEPTH`], which sizes the traversal stack: a
//! node at depth $d$ with $n$ primitives may use the SAH only while
//! $d + 1 + \lceil \log_2 n \rceil \le$ `MAX_DEPTH`, else it splits at the median. Median
//! splits keep $d + \lceil \log_2 n \rceil$ constant, so by induction no leaf goes deeper
//! (the root starts at $\lceil \log_2 n \rceil \le 32$). SAH trees of real scenes stay far
//! above the limit (depth 28 for 600k spheres), so it only guards degenerate input.
//!
//! Subtrees of at least [`PARALLEL_MIN`] primitives are built with `rayon::join`. The
//! split decisions depend only on the data, each subtree is built into its own node
//! array, and the arrays are concatenated depth-first at the end, so the result is
//! bit-identical for any number of threads.

use super::node::{Bounds3, Node};
use vecexpr::Scalar;

/// Bins per axis.
pub const NUM_BINS: usize = 32;
/// Fewest bins per axis; a node of `n` primitives uses `n` bins, up to [`NUM_BINS`].
pub const MIN_BINS: usize = 2;
/// Default SAH cost of visiting a node (two box tests), relative to one primitive test.
/// Measured on the SPD scenes, 1 to 3 trace equally fast, while 2 needs about 60 % fewer
/// nodes than 1 (58 instead of 96 bytes per sphere in `balls`) and builds faster.
pub const TRAVERSAL_COST: f32 = 2.0;
/// Deepest leaf (edges from the root); see the module docs.
pub const MAX_DEPTH: usize = 64;
/// Smallest subtree (in primitives) built as a separate parallel task.
pub const PARALLEL_MIN: usize = 4096;

/// A box as four-lane arrays (lane 3 unused, kept 0), so that unions compile to one
/// `minps`/`maxps` pair.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(16))]
struct Box4 {
    lo: [f32; 4],
    hi: [f32; 4],
}

impl Box4 {
    const EMPTY: Self = Self {
        lo: [f32::INFINITY, f32::INFINITY, f32::INFINITY, 0.0],
        hi: [f32::NEG_INFINITY, f32::NEG_INFINITY, f32::NEG_INFINITY, 0.0],
    };

    #[inline(always)]
    fn union(&mut self, o: &Self) {
        for i in 0..4 {
            self.lo[i] = Scalar::min(o.lo[i], self.lo[i]);
            self.hi[i] = Scalar::max(o.hi[i], self.hi[i]);
        }
    }

    #[inline(always)]
    fn half_area(&self) -> f32 {
        let d: [f32; 3] = core::array::from_fn(|i| (self.hi[i] - self.lo[i]).max(0.0));
        d[0] * d[1] + d[1] * d[2] + d[2] * d[0]
    }

    fn to_array(self) -> [[f32; 3]; 2] {
        [
            [self.lo[0], self.lo[1], self.lo[2]],
            [self.hi[0], self.hi[1], self.hi[2]],
        ]
    }
}

/// A primitive as the builder sees it: conservative bounds, their centroid, and an
/// opaque id that ends up in the BVH's reference array (48 bytes).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(16))]
pub struct BuildPrim {
    bounds: Box4,
    centroid: [f32; 3],
    /// The caller's id for the primitive.
    pub id: u32,
}

impl BuildPrim {
    /// A primitive with bounds `b` (rounded outward to `f32`) and id `id`.
    pub fn new(b: Bounds3, id: u32) -> Self {
        Self {
            bounds: Box4 {
                lo: [b.lo[0], b.lo[1], b.lo[2], 0.0],
                hi: [b.hi[0], b.hi[1], b.hi[2], 0.0],
            },
            centroid: b.centroid(),
            id,
        }
    }

    /// The bounds.
    pub fn bounds(&self) -> Bounds3 {
        let [lo, hi] = self.bounds.to_array();
        Bounds3 { lo, hi }
    }
}

/// Builder settings.
#[derive(Clone, Copy, Debug)]
pub struct BuildConfig {
    /// Largest leaf the SAH may choose (at least 1).
    pub max_leaf_size: usize,
    /// Build large subtrees in parallel with rayon.
    pub parallel: bool,
    /// SAH cost of visiting a node relative to one primitive test; larger values give
    /// fewer, larger leaves.
    pub traversal_cost: f32,
}

/// A built subtree: either a finished depth-first node array whose interior `offset`s
/// are relative to its own start, or a node whose two subtrees were built in parallel.
enum Subtree {
    Flat {
        nodes: Vec<Node>,
        depth: usize,
    },
    Split {
        node: Node,
        children: Box<(Subtree, Subtree)>,
    },
}

/// Builds over `prims`, reordering them in place so that every leaf covers a contiguous
/// range. Returns the depth-first node array and the depth (number of levels; 0 for no
/// primitives).
pub fn build(prims: &mut [BuildPrim], cfg: &BuildConfig) -> (Vec<Node>, usize) {
    if prims.is_empty() {
        return (Vec::new(), 0);
    }
    let cfg = BuildConfig {
        max_leaf_size: cfg.max_leaf_size.max(1),
        ..*cfg
    };
    let ext = measure(prims);
    let tree = build_subtree(&cfg, prims, ext, 0, 0);
    let mut nodes = Vec::with_capacity(count_nodes(&tree));
    let depth = flatten(tree, &mut nodes);
    (nodes, depth)
}

fn count_nodes(tree: &Subtree) -> usize {
    match tree {
        Subtree::Flat { nodes, .. } => nodes.len(),
        Subtree::Split { children, .. } => 1 + count_nodes(&children.0) + count_nodes(&children.1),
    }
}

/// Concatenates a subtree depth-first into `out`, fixing up the second-child indices.
fn flatten(tree: Subtree, out: &mut Vec<Node>) -> usize {
    match tree {
        Subtree::Flat { nodes, depth } => {
            let base = out.len() as u32;
            out.extend(nodes.into_iter().map(|mut n| {
                if !n.is_leaf() {
                    n.offset += base;
                }
                n
            }));
            depth
        }
        Subtree::Split { node, children } => {
            let at = out.len();
            out.push(node);
            let (left, right) = *children;
            let dl = flatten(left, out);
            out[at].offset = out.len() as u32;
            let dr = flatten(right, out);
            1 + dl.max(dr)
        }
    }
}

/// Builds the subtree over `prims` (which start at reference index `first`), forking
/// into parallel tasks while it is large.
fn build_subtree(
    cfg: &BuildConfig,
    prims: &mut [BuildPrim],
    ext: Extent,
    first: usize,
    depth: usize,
) -> Subtree {
    if !cfg.parallel || prims.len() < PARALLEL_MIN {
        // About one node per primitive for the default SAH costs; grows if needed.
        let mut nodes = Vec::with_capacity(prims.len());
        let mut scratch = Box::new(Scratch::new());
        let d = build_serial(cfg, prims, ext, first, depth, &mut nodes, &mut scratch);
        return Subtree::Flat {
            nodes,
            depth: d - depth,
        };
    }
    match split(cfg, prims, &ext, depth, &mut Scratch::new()) {
        None => Subtree::Flat {
            nodes: vec![Node::leaf(
                ext.bounds.to_array(),
                first as u32,
                prims.len() as u32,
            )],
            depth: 1,
        },
        Some((mid, le, re)) => {
            let (l, r) = prims.split_at_mut(mid);
            let (a, b) = rayon::join(
                || build_subtree(cfg, l, le, first, depth + 1),
                || build_subtree(cfg, r, re, first + mid, depth + 1),
            );
            Subtree::Split {
                node: Node::interior(ext.bounds.to_array()),
                children: Box::new((a, b)),
            }
        }
    }
}

/// Serial recursive build appending to `nodes`; interior offsets are relative to the
/// start of `nodes`. Returns the depth (levels from the root of the whole tree) of the
/// deepest leaf.
fn build_serial(
    cfg: &BuildConfig,
    prims: &mut [BuildPrim],
    ext: Extent,
    first: usize,
    depth: usize,
    nodes: &mut Vec<Node>,
    scratch: &mut Scratch,
) -> usize {
    let at = nodes.len();
    match split(cfg, prims, &ext, depth, scratch) {
        None => {
            nodes.push(Node::leaf(
                ext.bounds.to_array(),
                first as u32,
                prims.len() as u32,
            ));
            depth + 1
        }
        Some((mid, le, re)) => {
            nodes.push(Node::interior(ext.bounds.to_array()));
            let (l, r) = prims.split_at_mut(mid);
            let dl = build_serial(cfg, l, le, first, depth + 1, nodes, scratch);
            nodes[at].offset = nodes.len() as u32;
            let dr = build_serial(cfg, r, re, first + mid, depth + 1, nodes, scratch);
            dl.max(dr)
        }
    }
}

/// What a node needs to know about its primitives: their bounds and the bounds of their
/// centroids. The parent computes both for its children while splitting (from the bins
/// and during the partition), so no node makes a separate pass for them.
#[derive(Clone, Copy, Debug)]
struct Extent {
    bounds: Box4,
    centroids: Bounds3,
}

/// Bounds of the primitives and of their centroids, by one pass.
fn measure(prims: &[BuildPrim]) -> Extent {
    let mut bounds = Box4::EMPTY;
    let mut centroids = Bounds3::EMPTY;
    for p in prims {
        bounds.union(&p.bounds);
        centroids.add_point(p.centroid);
    }
    Extent { bounds, centroids }
}

#[derive(Clone, Copy)]
struct Bin {
    bounds: Box4,
    count: u32,
}

/// Per-thread working memory of [`split`], reused across nodes: clearing 96 bins for
/// every node would cost more than binning the small ones.
struct Scratch {
    bins: [[Bin; NUM_BINS]; 3],
    right_cost: [f32; NUM_BINS],
    right_count: [u32; NUM_BINS],
}

impl Scratch {
    fn new() -> Self {
        Self {
            bins: [[EMPTY_BIN; NUM_BINS]; 3],
            right_cost: [0.0; NUM_BINS],
            right_count: [0; NUM_BINS],
        }
    }
}

const EMPTY_BIN: Bin = Bin {
    bounds: Box4::EMPTY,
    count: 0,
};

/// Maps a centroid coordinate to its bin: $\lfloor (c - c_{min}) k \rfloor$ with
/// $k = B (1 - 10^{-6}) / (c_{max} - c_{min})$, clamped (the cast saturates).
#[inline(always)]
fn bin_of(c: f32, cmin: f32, k: f32, nb: usize) -> usize {
    // `as i32` saturates (NaN to 0), and is cheaper than a cast to usize.
    (((c - cmin) * k) as i32).clamp(0, nb as i32 - 1) as usize
}

/// Decides the node: `None` for a leaf, or `Some((mid, left, right))` after
/// partitioning `prims` into `[..mid]` and `[mid..]` (both non-empty) with the extents
/// of the two halves.
fn split(
    cfg: &BuildConfig,
    prims: &mut [BuildPrim],
    ext: &Extent,
    depth: usize,
    scratch: &mut Scratch,
) -> Option<(usize, Extent, Extent)> {
    let centroids = &ext.centroids;
    let n = prims.len();
    if n <= 1 {
        return None;
    }
    let may_be_leaf = n <= cfg.max_leaf_size;
    if !sah_allowed(depth, n) {
        return if may_be_leaf {
            None
        } else {
            Some(median_split(prims, centroids))
        };
    }

    // Bin all three axes in one pass. Small nodes use fewer bins: the sweeps cost
    // O(bins) per node, which would otherwise dominate near the leaves.
    let nb = n.clamp(MIN_BINS, NUM_BINS);
    let extent: [f32; 3] = core::array::from_fn(|a| centroids.hi[a] - centroids.lo[a]);
    let scale: [f32; 3] = core::array::from_fn(|a| {
        if extent[a] > 0.0 && extent[a].is_finite() {
            nb as f32 * (1.0 - 1e-6) / extent[a]
        } else {
            0.0
        }
    });
    let bins = &mut scratch.bins;
    for axis in bins.iter_mut() {
        axis[..nb].fill(EMPTY_BIN);
    }
    // A flat axis has scale 0, puts everything in bin 0 and is skipped by the sweep. The
    // partition below must use the very same `bin_of`, so that each child's bounds are
    // exactly the union of its bins.
    for p in prims.iter() {
        let idx: [usize; 3] =
            core::array::from_fn(|a| bin_of(p.centroid[a], centroids.lo[a], scale[a], nb));
        for a in 0..3 {
            let bin = &mut bins[a][idx[a]];
            bin.count += 1;
            bin.bounds.union(&p.bounds);
        }
    }

    // Sweep: cost of splitting after bin i is N_L A_L + N_R A_R.
    let mut best: Option<(f32, usize, usize)> = None;
    for a in 0..3 {
        if scale[a] == 0.0 {
            continue;
        }
        let bins = &bins[a];
        let right_cost = &mut scratch.right_cost;
        let right_count = &mut scratch.right_count;
        let mut acc = Box4::EMPTY;
        let mut count = 0u32;
        for i in (1..nb).rev() {
            acc.union(&bins[i].bounds);
            count += bins[i].count;
            right_count[i - 1] = count;
            right_cost[i - 1] = count as f32 * acc.half_area();
        }
        let mut acc = Box4::EMPTY;
        let mut count = 0u32;
        for i in 0..nb - 1 {
            acc.union(&bins[i].bounds);
            count += bins[i].count;
            if count == 0 || right_count[i] == 0 {
                continue;
            }
            let cost = count as f32 * acc.half_area() + right_cost[i];
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, a, i));
            }
        }
    }

    let area = ext.bounds.half_area();
    if let Some((cost, axis, bin)) = best {
        let leaf_cost = n as f32;
        let split_cost = cfg.traversal_cost + cost / area;
        let split_pays = split_cost < leaf_cost;
        if may_be_leaf && !split_pays {
            return None;
        }
        if split_cost.is_finite() || !may_be_leaf {
            let (cmin, k) = (centroids.lo[axis], scale[axis]);
            let (mid, lc, rc) = partition(prims, |p| bin_of(p.centroid[axis], cmin, k, nb) <= bin);
            debug_assert!(mid > 0 && mid < n);
            let (mut lb, mut rb) = (Box4::EMPTY, Box4::EMPTY);
            for b in &scratch.bins[axis][..=bin] {
                lb.union(&b.bounds);
            }
            for b in &scratch.bins[axis][bin + 1..nb] {
                rb.union(&b.bounds);
            }
            let left = Extent {
                bounds: lb,
                centroids: lc,
            };
            let right = Extent {
                bounds: rb,
                centroids: rc,
            };
            debug_assert_eq!(left.bounds, measure(&prims[..mid]).bounds);
            debug_assert_eq!(right.centroids, measure(&prims[mid..]).centroids);
            return Some((mid, left, right));
        }
    }
    if may_be_leaf {
        None
    } else {
        Some(median_split(prims, centroids))
    }
}

/// May a node at `depth` with `n` primitives split by the SAH (which may peel off a
/// single primitive) without risking a leaf deeper than [`MAX_DEPTH`]?
fn sah_allowed(depth: usize, n: usize) -> bool {
    depth + 1 + ceil_log2(n) <= MAX_DEPTH
}

/// $\lceil \log_2 n \rceil$ for $n \ge 1$.
fn ceil_log2(n: usize) -> usize {
    (usize::BITS - (n - 1).leading_zeros()) as usize
}

/// Splits at the object median along the widest centroid axis (in input order when the
/// centroids all coincide).
fn median_split(prims: &mut [BuildPrim], centroids: &Bounds3) -> (usize, Extent, Extent) {
    let mid = prims.len() / 2;
    let extent: [f32; 3] = core::array::from_fn(|a| centroids.hi[a] - centroids.lo[a]);
    let axis = (0..3)
        .max_by(|&a, &b| extent[a].total_cmp(&extent[b]).then(b.cmp(&a)))
        .unwrap_or(0);
    if extent[axis] > 0.0 {
        prims.select_nth_unstable_by(mid, |p, q| p.centroid[axis].total_cmp(&q.centroid[axis]));
    }
    (mid, measure(&prims[..mid]), measure(&prims[mid..]))
}

/// Moves the elements satisfying `left` to the front; returns how many there are and
/// the centroid bounds of both groups.
fn partition(
    prims: &mut [BuildPrim],
    left: impl Fn(&BuildPrim) -> bool,
) -> (usize, Bounds3, Bounds3) {
    let (mut lc, mut rc) = (Bounds3::EMPTY, Bounds3::EMPTY);
    let (mut i, mut j) = (0, prims.len());
    loop {
        while i < j && left(&prims[i]) {
            lc.add_point(prims[i].centroid);
            i += 1;
        }
        while i < j && !left(&prims[j - 1]) {
            rc.add_point(prims[j - 1].centroid);
            j -= 1;
        }
        if i >= j {
            return (i, lc, rc);
        }
        prims.swap(i, j - 1);
        lc.add_point(prims[i].centroid);
        rc.add_point(prims[j - 1].centroid);
        i += 1;
        j -= 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube(p: [f32; 3], h: f32, id: u32) -> BuildPrim {
        BuildPrim::new(
            Bounds3 {
                lo: p.map(|x| x - h),
                hi: p.map(|x| x + h),
            },
            id,
        )
    }

    /// Pseudo-random points from a fixed-seed xorshift.
    fn cloud(n: usize) -> Vec<BuildPrim> {
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 40) as f32 / (1u64 << 24) as f32
        };
        (0..n)
            .map(|i| {
                cube(
                    [next() * 100.0, next() * 100.0, next() * 100.0],
                    next(),
                    i as u32,
                )
            })
            .collect()
    }

    /// Checks structure: every reference once, leaves within bounds, children inside
    /// parents.
    fn check(nodes: &[Node], prims: &[BuildPrim], max_leaf: usize) {
        let mut seen = vec![false; prims.len()];
        let mut stack = vec![0usize];
        while let Some(i) = stack.pop() {
            let n = &nodes[i];
            if n.is_leaf() {
                assert!(n.count as usize <= max_leaf.max(1) || n.count == 1);
                for p in &prims[n.offset as usize..(n.offset + n.count) as usize] {
                    assert!(!seen[p.id as usize]);
                    seen[p.id as usize] = true;
                    for a in 0..3 {
                        assert!(
                            n.bounds[0][a] <= p.bounds().lo[a]
                                && p.bounds().hi[a] <= n.bounds[1][a]
                        );
                    }
                }
            } else {
                for c in [i + 1, n.offset as usize] {
                    for a in 0..3 {
                        assert!(n.bounds[0][a] <= nodes[c].bounds[0][a]);
                        assert!(nodes[c].bounds[1][a] <= n.bounds[1][a]);
                    }
                    stack.push(c);
                }
            }
        }
        assert!(seen.iter().all(|&s| s));
    }

    #[test]
    fn builds_a_valid_tree() {
        let mut prims = cloud(5000);
        let cfg = BuildConfig {
            max_leaf_size: 4,
            parallel: true,
            traversal_cost: TRAVERSAL_COST,
        };
        let (nodes, depth) = build(&mut prims, &cfg);
        check(&nodes, &prims, 4);
        assert!(depth > 5 && depth < 64, "depth {depth}");
    }

    #[test]
    fn identical_centroids_still_split_to_leaf_size() {
        let mut prims: Vec<BuildPrim> = (0..1000).map(|i| cube([1.0; 3], 0.5, i)).collect();
        let cfg = BuildConfig {
            max_leaf_size: 3,
            parallel: false,
            traversal_cost: TRAVERSAL_COST,
        };
        let (nodes, depth) = build(&mut prims, &cfg);
        check(&nodes, &prims, 3);
        assert!(depth <= 11, "depth {depth}");
    }

    #[test]
    fn parallel_and_serial_builds_are_identical() {
        let base = cloud(3 * PARALLEL_MIN);
        let (mut a, mut b) = (base.clone(), base);
        let serial = build(
            &mut a,
            &BuildConfig {
                max_leaf_size: 8,
                parallel: false,
                traversal_cost: TRAVERSAL_COST,
            },
        );
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        let parallel = pool.install(|| {
            build(
                &mut b,
                &BuildConfig {
                    max_leaf_size: 8,
                    parallel: true,
                    traversal_cost: TRAVERSAL_COST,
                },
            )
        });
        assert_eq!(serial, parallel);
        assert_eq!(a, b);
    }

    #[test]
    fn depth_bound_holds_for_the_worst_splits() {
        // Follow the deepest possible path: the SAH peels off one primitive whenever it
        // is allowed, otherwise the median halves the node.
        for n in [
            1usize,
            2,
            3,
            7,
            100,
            1000,
            65_536,
            1_000_000,
            1 << 30,
            u32::MAX as usize,
        ] {
            let (mut d, mut m) = (0, n);
            while m > 1 {
                m = if sah_allowed(d, m) {
                    m - 1
                } else {
                    m.div_ceil(2)
                };
                d += 1;
            }
            assert!(d <= MAX_DEPTH, "n = {n}: leaf at depth {d}");
        }
        assert_eq!(ceil_log2(1), 0);
        assert_eq!(ceil_log2(2), 1);
        assert_eq!(ceil_log2(5), 3);
        assert_eq!(ceil_log2(1 << 20), 20);
    }

    #[test]
    fn single_and_empty() {
        let cfg = BuildConfig {
            max_leaf_size: 4,
            parallel: true,
            traversal_cost: TRAVERSAL_COST,
        };
        let mut none: Vec<BuildPrim> = Vec::new();
        assert_eq!(build(&mut none, &cfg).0.len(), 0);
        let mut one = vec![cube([0.0; 3], 1.0, 0)];
        let (nodes, depth) = build(&mut one, &cfg);
        assert_eq!((nodes.len(), depth), (1, 1));
        assert!(nodes[0].is_leaf());
    }
}
