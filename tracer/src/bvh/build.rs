//! Binned SAH construction.
//!
//! I. Wald, "On fast Construction of SAH-based Bounding Volume Hierarchies", IEEE
//! Symposium on Interactive Ray Tracing 2007: instead of sorting, primitive centroids
//! are dropped into up to [`NUM_BINS`] equal bins along each axis of the node's centroid
//! bounds, and the surface area heuristic
//! $C = C_{trav} + C_{isect} (A_L N_L + A_R N_R) / A$ is evaluated only at the bin
//! boundaries, with two sweeps over the bins. All three axes are binned in the same
//! pass over the primitives, and swept side by side. A node of $n$ primitives uses
//! $\min(32, 4 + n/20)$ bins (Embree's count), so that the sweeps stay cheap next to
//! the binning for the many small and mid-sized nodes.
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
//! Subtrees of at least [`PARALLEL_MIN`] primitives are built with `rayon::join`, and
//! the top nodes (at least [`PARALLEL_BIN_MIN`] primitives), where there are fewer
//! subtrees than threads, bin their primitives in parallel chunks whose bins are then
//! merged. The split decisions depend only on the data (merging bins takes minima,
//! maxima and sums, which no chunking changes), each subtree is built into its own node
//! array, and the arrays are concatenated depth-first at the end, so the result is
//! bit-identical for any number of threads.

use super::node::{Bounds3, Node};
use vecexpr::{Mask, Scalar};

/// Most bins per axis.
pub const NUM_BINS: usize = 32;
/// Fewest bins per axis (see `bin_count` for how many a node uses).
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

    /// Grows to contain `o`: per lane `o < self ? o : self` (the rule of [`Scalar::min`]),
    /// and likewise for the maxima, on whole registers.
    #[inline(always)]
    fn union(&mut self, o: &Self) {
        self.lo = to_lanes(Scalar::min(lanes(o.lo), lanes(self.lo)));
        self.hi = to_lanes(Scalar::max(lanes(o.hi), lanes(self.hi)));
    }

    /// Grows to contain the point `c` (the same rule per lane as [`Bounds3::add_point`],
    /// in one `minps`/`maxps` pair).
    #[inline(always)]
    fn add_point(&mut self, c: &[f32; 3]) {
        let p = lanes([c[0], c[1], c[2], 0.0]);
        self.lo = to_lanes(Scalar::min(p, lanes(self.lo)));
        self.hi = to_lanes(Scalar::max(p, lanes(self.hi)));
    }

    fn to_bounds(self) -> Bounds3 {
        let [lo, hi] = self.to_array();
        Bounds3 { lo, hi }
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

/// Four `f32` lanes, the three axes side by side in the sweeps: an SSE register on
/// x86-64, an array elsewhere.
#[cfg(target_arch = "x86_64")]
type Lanes = vecexpr::simd::F32x4;
#[cfg(not(target_arch = "x86_64"))]
type Lanes = vecexpr::Packet<f32, vecexpr::typenum::U4>;

/// [`Lanes`] from an array.
#[inline(always)]
fn lanes(a: [f32; 4]) -> Lanes {
    #[cfg(target_arch = "x86_64")]
    return Lanes::from_array(a);
    #[cfg(not(target_arch = "x86_64"))]
    return Lanes::from_fn(|i| a[i]);
}

/// The lanes of `l` as an array.
#[inline(always)]
fn to_lanes(l: Lanes) -> [f32; 4] {
    #[cfg(target_arch = "x86_64")]
    return l.to_array();
    #[cfg(not(target_arch = "x86_64"))]
    return core::array::from_fn(|i| l.lane(i));
}

/// One step of a sweep: grows the accumulated boxes and counts of the three axes by
/// their bins `i`, and returns the counts as `f32` lanes (exact below 2^24, and rounded
/// as `u32 as f32` beyond).
#[inline(always)]
fn sweep_step(acc: &mut [Box4; 3], count: &mut [u32; 4], bins: &Bins, i: usize) -> Lanes {
    for (a, acc) in acc.iter_mut().enumerate() {
        acc.union(&bins.bounds[a][i]);
    }
    for (c, b) in count.iter_mut().zip(&bins.counts[i]) {
        *c += b;
    }
    lanes(count.map(|c| c as f32))
}

/// The half surface areas of three boxes, box `a` in lane `a` (lane 3 is 0): per box
/// the operations of [`Box4::half_area`], over the lanes.
#[inline(always)]
fn half_areas(b: &[Box4; 3]) -> Lanes {
    // Each box's extents, clamped at 0 (`max` keeps 0 for NaN, as `f32::max` does),
    // transposed so that `e[k]` holds the three boxes' extents along axis `k`.
    let zero = Lanes::zero();
    let d = b.map(|b| Scalar::max(lanes(b.hi) - lanes(b.lo), zero));
    let e: [Lanes; 3] =
        core::array::from_fn(|k| lanes([d[0].lane(k), d[1].lane(k), d[2].lane(k), 0.0]));
    e[0] * e[1] + e[1] * e[2] + e[2] * e[0]
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

    /// The centroid in lanes 0 to 2 and the id's bits in lane 3 (one load; what lane 3
    /// holds is never read).
    #[inline(always)]
    fn centroid_lanes(&self) -> Lanes {
        let c = &self.centroid;
        lanes([c[0], c[1], c[2], f32::from_bits(self.id)])
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
    let ext = if cfg.parallel && prims.len() >= PARALLEL_BIN_MIN {
        use rayon::prelude::*;
        prims
            .par_chunks(BIN_CHUNK)
            .map(measure)
            .reduce_with(|mut a, b| {
                a.bounds.union(&b.bounds);
                a.centroids.union(&b.centroids);
                a
            })
            .unwrap_or_else(|| measure(prims))
    } else {
        measure(prims)
    };
    let tree = build_subtree(&cfg, prims, ext, 0, 0);
    let mut nodes = crate::pages::vec_with_capacity(count_nodes(&tree));
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
    let mut centroids = Box4::EMPTY;
    for p in prims {
        bounds.union(&p.bounds);
        centroids.add_point(&p.centroid);
    }
    Extent {
        bounds,
        centroids: centroids.to_bounds(),
    }
}

/// Bins of one node for all three axes: bounds per axis and bin, and primitive counts per
/// bin with the axis as lane (lanes 3 to 7 unused, kept 0), which the sweeps read as one
/// four-lane array. A bin's counts take 32 bytes, as its box does, so that binning
/// addresses both with the same scaled index.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Bins {
    bounds: [[Box4; NUM_BINS]; 3],
    counts: [[u32; COUNT_LANES]; NUM_BINS],
}

/// Lanes of one bin's counts (see [`Bins`]).
const COUNT_LANES: usize = 8;
const _: () = assert!(COUNT_LANES * 4 == core::mem::size_of::<Box4>());

impl Bins {
    const EMPTY: Self = Self {
        bounds: [[Box4::EMPTY; NUM_BINS]; 3],
        counts: [[0; COUNT_LANES]; NUM_BINS],
    };

    /// Empties the first `nb` bins of every axis.
    #[inline(always)]
    fn clear(&mut self, nb: usize) {
        for a in 0..3 {
            self.bounds[a][..nb].fill(Box4::EMPTY);
        }
        self.counts[..nb].fill([0; COUNT_LANES]);
    }

    /// Adds one primitive to its bin on every axis.
    #[inline(always)]
    fn add(&mut self, p: &BuildPrim, m: &BinMap) {
        let idx = m.bins(p);
        for (a, &i) in idx.iter().enumerate() {
            self.counts[i][a] += 1;
            self.bounds[a][i].union(&p.bounds);
        }
    }

    /// Merges the first `nb` bins of `o` into these (exact: min, max and sums).
    #[inline(always)]
    fn merge(&mut self, o: &Self, nb: usize) {
        for a in 0..3 {
            for i in 0..nb {
                self.bounds[a][i].union(&o.bounds[a][i]);
            }
        }
        for (c, o) in self.counts[..nb].iter_mut().zip(&o.counts) {
            for (c, o) in c.iter_mut().zip(o) {
                *c += o;
            }
        }
    }

    /// Bins `prims` into these (cleared first). Consecutive primitives tend to fall into
    /// the same bins (the input is partitioned, so spatially coherent), and each update
    /// of a bin waits for the previous one through memory; large nodes therefore bin
    /// even and odd primitives into two sets, merged at the end, so that two chains of
    /// updates run side by side.
    fn fill(&mut self, prims: &[BuildPrim], m: &BinMap, other: &mut Self) {
        self.clear(m.nb);
        if prims.len() < DUAL_BINS_MIN {
            for p in prims {
                self.add(p, m);
            }
            return;
        }
        other.clear(m.nb);
        let mut pairs = prims.chunks_exact(2);
        for pair in &mut pairs {
            self.add(&pair[0], m);
            other.add(&pair[1], m);
        }
        for p in pairs.remainder() {
            self.add(p, m);
        }
        self.merge(other, m.nb);
    }
}

/// Fewest primitives for which [`Bins::fill`] uses two sets of bins.
const DUAL_BINS_MIN: usize = 64;
/// Fewest primitives of a node whose binning is split over parallel tasks.
pub const PARALLEL_BIN_MIN: usize = 1 << 16;
/// Primitives per task of a parallel binning. The merged bins are exact (minima, maxima
/// and counts), so the chunking cannot change the result.
const BIN_CHUNK: usize = 1 << 14;

/// Bins per axis for a node of `n` primitives: $4 + n/20$, between [`MIN_BINS`] and
/// [`NUM_BINS`] (the count of Embree's binned builder, `min(BINS, 4 + 0.05 n)`). The
/// sweeps cost $O(bins)$ per node; with 32 bins for every node above 32 primitives they
/// took about a fifth of the build. Against a floor of $\min(n, 16)$ bins for the small
/// nodes, which an earlier build kept for the SAH cost (up to 0.6 % lower on the triangle
/// scenes), this count runs 13.7 % fewer instructions in balls-s6's binary build, while
/// the single eye rays of every classic scene, balls-s6, mount-s8 and teapot-s40 run
/// within 0.5 % of the same instructions (rings-s7 1.9 % fewer) (`RESULTS.md`, "The
/// build overlaps its reordering and bins as Embree does").
fn bin_count(n: usize) -> usize {
    (4 + n / 20).clamp(MIN_BINS, NUM_BINS)
}

/// The centroid-to-bin mapping of one node: the values of [`bin_of`] for the three
/// axes, in lanes 0 to 2 (lane 3 maps everything to bin 0).
#[derive(Clone, Copy)]
struct BinMap {
    lo: Lanes,
    scale: Lanes,
    /// `nb - 1` in every lane.
    top: Lanes,
    nb: usize,
}

impl BinMap {
    fn new(centroids: &Bounds3, nb: usize) -> Self {
        let scale: [f32; 3] = core::array::from_fn(|a| {
            let extent = centroids.hi[a] - centroids.lo[a];
            if extent > 0.0 && extent.is_finite() {
                nb as f32 * (1.0 - 1e-6) / extent
            } else {
                0.0
            }
        });
        let lo = centroids.lo;
        Self {
            lo: lanes([lo[0], lo[1], lo[2], 0.0]),
            scale: lanes([scale[0], scale[1], scale[2], 0.0]),
            top: Lanes::splat((nb - 1) as f32),
            nb,
        }
    }

    /// The scale of `axis`.
    fn scale(&self, axis: usize) -> f32 {
        self.scale.lane(axis)
    }

    /// The bins of primitive `p` on the three axes: [`bin_of`] over the lanes, with the
    /// same operations in the same order (`maxps` and `minps` follow its comparisons,
    /// NaN included).
    #[inline(always)]
    fn bins(&self, p: &BuildPrim) -> [usize; 3] {
        // Lane 3 holds the id's bits, which may be a subnormal or a NaN: it is zeroed
        // before any arithmetic (a subnormal operand can be slow).
        let c = Scalar::select(lane3_off(), p.centroid_lanes(), Lanes::zero());
        let v = (c - self.lo) * self.scale;
        let v = Scalar::min(Scalar::max(v, Lanes::zero()), self.top);
        let v = to_lanes(v);
        core::array::from_fn(|a| {
            // SAFETY: as in `bin_of`, `v[a]` is not NaN and lies in `[0, nb - 1]`.
            let i = unsafe { v[a].to_int_unchecked::<i32>() } as usize;
            i & (NUM_BINS - 1)
        })
    }
}

/// The mask of lanes 0 to 2.
#[inline(always)]
fn lane3_off() -> <Lanes as Scalar>::Mask {
    Lanes::splat(1.0).lt(lanes([2.0, 2.0, 2.0, 0.0]))
}

/// Per-thread working memory of [`split`], reused across nodes: clearing 96 bins for
/// every node would cost more than binning the small ones.
struct Scratch {
    bins: Bins,
    other: Bins,
    sweep: SweepScratch,
}

/// The right-to-left sweep's results of [`best_split`], per bin.
struct SweepScratch {
    right_cost: [Lanes; NUM_BINS],
    right_count: [Lanes; NUM_BINS],
}

impl Scratch {
    fn new() -> Self {
        Self {
            bins: Bins::EMPTY,
            other: Bins::EMPTY,
            sweep: SweepScratch {
                right_cost: [Lanes::zero(); NUM_BINS],
                right_count: [Lanes::zero(); NUM_BINS],
            },
        }
    }
}

/// Maps a centroid coordinate to its bin: $\lfloor (c - c_{min}) k \rfloor$ with
/// $k = B (1 - 10^{-6}) / (c_{max} - c_{min})$, clamped to `[0, nb - 1]` (NaN to 0).
#[inline(always)]
fn bin_of(c: f32, cmin: f32, k: f32, nb: usize) -> usize {
    // Clamping in `f32` first (`maxss`/`minss` rules: NaN gives 0) leaves the truncation
    // a value in range; the result equals clamping the truncated value.
    let top = (nb - 1) as f32;
    let v = (c - cmin) * k;
    let v = if v > 0.0 { v } else { 0.0 };
    let v = if v < top { v } else { top };
    // SAFETY: `v` is not NaN and lies in `[0, nb - 1]` with `nb <= NUM_BINS`, so it is
    // representable as an `i32` after truncation.
    let i = unsafe { v.to_int_unchecked::<i32>() } as usize;
    // A no-op (i < NUM_BINS, a power of two) that lets the compiler drop bounds checks.
    i & (NUM_BINS - 1)
}

const _: () = assert!(NUM_BINS.is_power_of_two());

/// Bins `prims` into `scratch.bins`, over parallel tasks for large nodes.
fn bin_prims(cfg: &BuildConfig, prims: &[BuildPrim], m: &BinMap, scratch: &mut Scratch) {
    if !cfg.parallel || prims.len() < PARALLEL_BIN_MIN {
        scratch.bins.fill(prims, m, &mut scratch.other);
        return;
    }
    use rayon::prelude::*;
    let nb = m.nb;
    let merged = prims
        .par_chunks(BIN_CHUNK)
        .map(|chunk| {
            let mut b = Box::new(Bins::EMPTY);
            let mut o = Box::new(Bins::EMPTY);
            b.fill(chunk, m, &mut o);
            b
        })
        .reduce_with(|mut a, b| {
            a.merge(&b, nb);
            a
        });
    if let Some(b) = merged {
        scratch.bins = *b;
    }
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

    let area = ext.bounds.half_area();
    if may_be_leaf && no_split_pays(cfg, prims, area) {
        return None;
    }

    // Bin all three axes in one pass. A flat axis has scale 0, puts everything in bin 0
    // and so has no candidate split. The partition below must use the very same
    // `bin_of`, so that each child's bounds are exactly the union of its bins.
    let nb = bin_count(n);
    let map = BinMap::new(centroids, nb);
    bin_prims(cfg, prims, &map, scratch);
    let bins = &scratch.bins;

    let best = best_split(bins, nb, &mut scratch.sweep);

    if let Some((cost, axis, bin)) = best {
        let leaf_cost = n as f32;
        let split_cost = cfg.traversal_cost + cost / area;
        let split_pays = split_cost < leaf_cost;
        if may_be_leaf && !split_pays {
            return None;
        }
        if split_cost.is_finite() || !may_be_leaf {
            let (cmin, cmax, k) = (centroids.lo[axis], centroids.hi[axis], map.scale(axis));
            let (mid, lc, rc) = partition(prims, axis, (cmin, cmax, k, nb), bin);
            debug_assert!(mid > 0 && mid < n);
            let (mut lb, mut rb) = (Box4::EMPTY, Box4::EMPTY);
            for b in &scratch.bins.bounds[axis][..=bin] {
                lb.union(b);
            }
            for b in &scratch.bins.bounds[axis][bin + 1..nb] {
                rb.union(b);
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

/// The cheapest split of binned bins `0..nb`: `Some((N_L A_L + N_R A_R, axis, bin))`
/// for the split after `bin`, the first of equals on the lowest axis, or `None` when no
/// axis has a split with primitives on both sides.
///
/// The three axes go side by side in the lanes of one register (lane 3 holds no
/// primitives, so it never has a valid split): the right-to-left sweep stores $N_R A_R$
/// and $N_R$, the left-to-right one adds $N_L A_L$ and keeps, per axis, the first of the
/// cheapest. Without branches, builds take 9 to 13 % fewer instructions than with the
/// same sweeps axis by axis, and the trees are the same (`JOURNAL.md`, "Builds").
#[inline(always)]
fn best_split(bins: &Bins, nb: usize, scratch: &mut SweepScratch) -> Option<(f32, usize, usize)> {
    let right_cost = &mut scratch.right_cost;
    let right_count = &mut scratch.right_count;
    let mut acc = [Box4::EMPTY; 3];
    let mut count = [0u32; 4];
    for i in (1..nb).rev() {
        let n_r = sweep_step(&mut acc, &mut count, bins, i);
        right_count[i - 1] = n_r;
        right_cost[i - 1] = n_r * half_areas(&acc);
    }
    let zero = Lanes::zero();
    let mut acc = [Box4::EMPTY; 3];
    let mut count = [0u32; 4];
    let mut best_cost = zero;
    // The best bin (exact in `f32`), -1 while an axis has no valid split.
    let mut best_bin = Lanes::splat(-1.0);
    for i in 0..nb - 1 {
        let n_l = sweep_step(&mut acc, &mut count, bins, i);
        let cost = n_l * half_areas(&acc) + right_cost[i];
        let valid = n_l.eq_mask(zero).or(right_count[i].eq_mask(zero)).not();
        let take = valid.and(best_bin.lt(zero).or(cost.lt(best_cost)));
        best_cost = Lanes::select(take, cost, best_cost);
        best_bin = Lanes::select(take, Lanes::splat(i as f32), best_bin);
    }
    let mut best: Option<(f32, usize, usize)> = None;
    for a in 0..3 {
        let (cost, bin) = (best_cost.lane(a), best_bin.lane(a));
        if bin >= 0.0 && best.is_none_or(|(c, _, _)| cost < c) {
            best = Some((cost, a, bin as usize));
        }
    }
    best
}

/// Is every split of `prims` (whose bounds have half area `area`) at least as costly as
/// a leaf, so that binning cannot change the decision? Each primitive lies in one child,
/// whose box contains the primitive's, so $N_L A_L + N_R A_R \ge \sum_i A_i$ and every
/// split costs at least $C_{trav} + \sum_i A_i / A$; a leaf costs $n$. With the default
/// costs this settles every node of two primitives (the bound is $C_{trav} = 2$) and a
/// few of three: on balls-s6 a quarter of all binnings (`RESULTS.md`). The sum is taken
/// 0.1 % short, far more than the rounding of the sweeps' sums, so that a split this
/// bound rules out could never have paid in `f32` either; a bound that is not a number
/// (a flat node) rules nothing out.
#[inline(always)]
fn no_split_pays(cfg: &BuildConfig, prims: &[BuildPrim], area: f32) -> bool {
    let n = prims.len() as f32;
    if cfg.traversal_cost >= n {
        return true;
    }
    let sum: f32 = prims.iter().map(|p| p.bounds.half_area()).sum();
    cfg.traversal_cost + 0.999 * sum / area >= n
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

/// Moves the primitives whose centroid falls into bins `0..=bin` of `axis` (by
/// [`bin_of`] with `cmin`, `k` and `nb`; `cmax` is the centroids' top along `axis`) to
/// the front; returns how many there are and the centroid bounds of both groups. The
/// test is one comparison with [`first_beyond`]'s bound, or the mapping itself where
/// there is no bound.
///
/// The mapping's values are copies, not references, and the centroid bounds stay in
/// registers: written as a closure over the caller's values, the loop reloaded them
/// (and converted `nb - 1` to `f32` again) at every primitive, and moved the bounds
/// through shuffles, about 44 instructions a primitive (callgrind, balls-s6).
fn partition(
    prims: &mut [BuildPrim],
    axis: usize,
    (cmin, cmax, k, nb): (f32, f32, f32, usize),
    bin: usize,
) -> (usize, Bounds3, Bounds3) {
    assert!(axis < 3, "an axis of three");
    match first_beyond(cmin, cmax, k, nb, bin) {
        Some(t) => partition_by(prims, move |p| p.centroid[axis] < t),
        None => partition_by(prims, move |p| bin_of(p.centroid[axis], cmin, k, nb) <= bin),
    }
}

/// The least `f32` whose bin ([`bin_of`] with `cmin`, `k` and `nb`) comes after `bin`,
/// where `cmax` (the centroid bounds' top along the axis) lies beyond it. `bin_of` never
/// decreases as its coordinate grows (a difference, a product by a positive factor,
/// clamps and a truncation, each monotone in IEEE arithmetic), so a coordinate lies in
/// bins `0..=bin` exactly when it is below that bound: one comparison a primitive in the
/// partition instead of the mapping. Centroids are finite ([`Bounds3::centroid`]), so NaN
/// cannot reach the comparison. The division's estimate is usually within an ulp or two;
/// where it is not (a bound near 0 with `cmin` far from it, whose ulps are far finer than
/// the mapping's rounding), bisection over the ordered `f32`s between `cmin` (bin 0)
/// and `cmax` finds the bound in at most 32 steps.
fn first_beyond(cmin: f32, cmax: f32, k: f32, nb: usize, bin: usize) -> Option<f32> {
    let beyond = |x: f32| bin_of(x, cmin, k, nb) > bin;
    if beyond(cmin) || !beyond(cmax) {
        return None;
    }
    let mut x = cmin + (bin + 1) as f32 / k;
    if x > cmin && x <= cmax {
        for _ in 0..4 {
            if beyond(x) {
                let below = x.next_down();
                if !beyond(below) {
                    return Some(x);
                }
                x = below;
            } else {
                x = x.next_up();
            }
        }
    }
    // `f32`s ordered as integers: flipping the magnitude bits of the negative ones puts
    // them below the non-negative ones, in order (-0.0 just below +0.0). The flip is its
    // own inverse.
    let ordered = |b: i32| b ^ ((b >> 31) & i32::MAX);
    let key = |x: f32| i64::from(ordered(x.to_bits() as i32));
    let value = |k: i64| f32::from_bits(ordered(k as i32) as u32);
    // Invariant: `value(lo)` is not beyond, `value(hi)` is.
    let (mut lo, mut hi) = (key(cmin), key(cmax));
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if beyond(value(mid)) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some(value(hi))
}

/// Moves the primitives for which `left` holds to the front, as [`partition`] describes.
#[inline(always)]
fn partition_by(
    prims: &mut [BuildPrim],
    left: impl Fn(&BuildPrim) -> bool,
) -> (usize, Bounds3, Bounds3) {
    let empty = Box4::EMPTY;
    let (mut l_lo, mut l_hi) = (lanes(empty.lo), lanes(empty.hi));
    let (mut r_lo, mut r_hi) = (l_lo, l_hi);
    let (mut i, mut j) = (0, prims.len());
    loop {
        while i < j && left(&prims[i]) {
            let c = prims[i].centroid_lanes();
            (l_lo, l_hi) = (Scalar::min(c, l_lo), Scalar::max(c, l_hi));
            i += 1;
        }
        while i < j && !left(&prims[j - 1]) {
            let c = prims[j - 1].centroid_lanes();
            (r_lo, r_hi) = (Scalar::min(c, r_lo), Scalar::max(c, r_hi));
            j -= 1;
        }
        if i >= j {
            let bounds = |lo: Lanes, hi: Lanes| {
                let (lo, hi) = (to_lanes(lo), to_lanes(hi));
                Bounds3 {
                    lo: [lo[0], lo[1], lo[2]],
                    hi: [hi[0], hi[1], hi[2]],
                }
            };
            return (i, bounds(l_lo, l_hi), bounds(r_lo, r_hi));
        }
        prims.swap(i, j - 1);
        let (c, d) = (prims[i].centroid_lanes(), prims[j - 1].centroid_lanes());
        (l_lo, l_hi) = (Scalar::min(c, l_lo), Scalar::max(c, l_hi));
        (r_lo, r_hi) = (Scalar::min(d, r_lo), Scalar::max(d, r_hi));
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
    /// Uniform `f32`s in `[0, 1)` from a xorshift generator seeded with `seed`.
    fn unit_floats(mut s: u64) -> impl FnMut() -> f32 {
        move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    fn cloud(n: usize) -> Vec<BuildPrim> {
        let mut next = unit_floats(0x2545_f491_4f6c_dd1d);
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
    fn parallel_binning_equals_serial_binning() {
        let prims = cloud(PARALLEL_BIN_MIN + 3 * BIN_CHUNK / 2 + 1);
        let ext = measure(&prims);
        let map = BinMap::new(&ext.centroids, NUM_BINS);
        let cfg = |parallel| BuildConfig {
            max_leaf_size: 8,
            parallel,
            traversal_cost: TRAVERSAL_COST,
        };
        let (mut a, mut b) = (Box::new(Scratch::new()), Box::new(Scratch::new()));
        bin_prims(&cfg(false), &prims, &map, &mut a);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        pool.install(|| bin_prims(&cfg(true), &prims, &map, &mut b));
        assert_eq!(a.bins, b.bins);
        let total: u32 = a.bins.counts.iter().map(|c| c[0]).sum();
        assert_eq!(total as usize, prims.len());
        // Each axis's bins hold the primitives whose centroids `bin_of` maps there.
        for axis in 0..3 {
            let mut counts = [0u32; NUM_BINS];
            for p in &prims {
                let lo = map.lo.lane(axis);
                counts[map.bins(p)[axis]] += 1;
                assert_eq!(
                    map.bins(p)[axis],
                    bin_of(p.centroid[axis], lo, map.scale(axis), NUM_BINS)
                );
                // The id's bits, read with the centroid, never reach a bin: not as a
                // NaN, an infinity or a subnormal.
                for id in [0x7fc0_0001, 0xff80_0000, 1, u32::MAX] {
                    assert_eq!(map.bins(&BuildPrim { id, ..*p }), map.bins(p));
                }
            }
            let binned: [u32; NUM_BINS] = core::array::from_fn(|i| a.bins.counts[i][axis]);
            assert_eq!(counts, binned);
        }
    }

    /// The SAH rule of [`best_split`] written axis by axis and split by split, with the
    /// same `f32` operations in the same order.
    fn best_split_reference(bins: &Bins, nb: usize) -> Option<(f32, usize, usize)> {
        let mut best: Option<(f32, usize, usize)> = None;
        for a in 0..3 {
            for i in 0..nb - 1 {
                let (mut left, mut right) = (Box4::EMPTY, Box4::EMPTY);
                let (mut n_l, mut n_r) = (0u32, 0u32);
                for j in 0..=i {
                    left.union(&bins.bounds[a][j]);
                    n_l += bins.counts[j][a];
                }
                for j in (i + 1..nb).rev() {
                    right.union(&bins.bounds[a][j]);
                    n_r += bins.counts[j][a];
                }
                if n_l == 0 || n_r == 0 {
                    continue;
                }
                let cost = n_l as f32 * left.half_area() + n_r as f32 * right.half_area();
                if best.is_none_or(|(c, _, _)| cost < c) {
                    best = Some((cost, a, i));
                }
            }
        }
        best
    }

    #[test]
    fn sweeps_over_lanes_follow_the_sah_rule() {
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move |m: u64| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s % m
        };
        let mut scratch = Box::new(Scratch::new());
        let mut found = 0;
        for round in 0..2000 {
            let nb = 2 + next(NUM_BINS as u64 - 1) as usize;
            let mut bins = Bins::EMPTY;
            for a in 0..3 {
                for i in 0..nb {
                    // Empty bins, and repeated boxes (equal costs) now and then.
                    if next(4) == 0 {
                        continue;
                    }
                    let k = if round % 3 == 0 { next(3) } else { next(1000) } as f32;
                    let lo = [k, 0.5 * k + next(7) as f32, -k];
                    let size = [1.0 + next(5) as f32, 2.0, 0.25 * next(9) as f32];
                    bins.bounds[a][i] = Box4 {
                        lo: [lo[0], lo[1], lo[2], 0.0],
                        hi: [lo[0] + size[0], lo[1] + size[1], lo[2] + size[2], 0.0],
                    };
                    bins.counts[i][a] = 1 + next(40) as u32;
                }
            }
            let got = best_split(&bins, nb, &mut scratch.sweep);
            assert_eq!(
                got,
                best_split_reference(&bins, nb),
                "round {round}, {nb} bins"
            );
            found += usize::from(got.is_some());
        }
        assert!(found > 1500, "{found} rounds with a split");
    }

    #[test]
    fn a_node_the_bound_makes_a_leaf_never_has_a_split_that_pays() {
        let mut next = unit_floats(0x51_7cc1_b727_220a);
        let mut scratch = Box::new(Scratch::new());
        let (mut ruled_out, mut left_to_bins) = ([0; 9], [0; 9]);
        for round in 0..6000 {
            let n = 2 + round % 7;
            let traversal_cost = [1.0, 2.0, 3.5][round % 3];
            // Clusters from touching boxes (spread 0.5) to scattered ones (spread 8).
            let spread = 0.5 + 7.5 * next();
            let prims: Vec<BuildPrim> = (0..n)
                .map(|i| {
                    let c = [next(), next(), next()].map(|x| x * spread);
                    cube(c, 0.5 + 0.5 * next(), i as u32)
                })
                .collect();
            let cfg = BuildConfig {
                max_leaf_size: 8,
                parallel: false,
                traversal_cost,
            };
            let ext = measure(&prims);
            let area = ext.bounds.half_area();
            if !no_split_pays(&cfg, &prims, area) {
                left_to_bins[n] += 1;
                continue;
            }
            ruled_out[n] += 1;
            let nb = bin_count(n);
            let map = BinMap::new(&ext.centroids, nb);
            scratch.bins.fill(&prims, &map, &mut scratch.other);
            if let Some((cost, axis, bin)) = best_split(&scratch.bins, nb, &mut scratch.sweep) {
                assert!(
                    traversal_cost + cost / area >= n as f32,
                    "round {round}: {n} primitives, the split after bin {bin} of axis {axis} pays"
                );
            }
        }
        // The bound settles some nodes of three and leaves others, and most nodes of
        // eight, to the bins.
        assert!(
            ruled_out[3] > 50 && left_to_bins[3] > 50,
            "{ruled_out:?} {left_to_bins:?}"
        );
        assert!(left_to_bins[8] > 500, "{left_to_bins:?}");
    }

    #[test]
    fn the_first_coordinate_beyond_a_bin_splits_as_the_mapping_does() {
        let mut next = unit_floats(0x9e37_79b9_7f4a_7c15);
        let mut found = 0;
        for round in 0..3000 {
            let nb = MIN_BINS + round % (NUM_BINS - MIN_BINS + 1);
            // Extents from tiny to huge, placed anywhere, negative included.
            let extent = 10f32.powf(-6.0 + 12.0 * next());
            let lo = (next() - 0.5) * 10f32.powf(6.0 * next());
            let b = BinMap::new(
                &Bounds3 {
                    lo: [lo; 3],
                    hi: [lo + extent; 3],
                },
                nb,
            );
            let (cmin, k) = (lo, b.scale(0));
            let bin = (next() * (nb - 1) as f32) as usize;
            if lo + extent == lo {
                // A flat axis: no split, no bound.
                continue;
            }
            let t = first_beyond(cmin, lo + extent, k, nb, bin)
                .unwrap_or_else(|| panic!("round {round}: no bound for bin {bin} of {nb}"));
            found += 1;
            let mut probes = vec![t, t.next_down(), t.next_up(), cmin, lo + extent];
            probes.extend((0..20).map(|_| lo + extent * (next() * 1.2 - 0.1)));
            for c in probes {
                assert_eq!(
                    c < t,
                    bin_of(c, cmin, k, nb) <= bin,
                    "round {round}: coordinate {c}, bound {t}, bin {bin} of {nb}"
                );
            }
        }
        assert!(found > 2500, "{found} rounds with a bound");
    }

    #[test]
    fn large_parallel_and_serial_builds_are_identical() {
        // Above PARALLEL_BIN_MIN, so the top nodes bin in parallel chunks.
        let base = cloud(2 * PARALLEL_BIN_MIN + 777);
        let (mut a, mut b) = (base.clone(), base);
        let cfg = |parallel| BuildConfig {
            max_leaf_size: 8,
            parallel,
            traversal_cost: TRAVERSAL_COST,
        };
        let serial = build(&mut a, &cfg(false));
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let parallel = pool.install(|| build(&mut b, &cfg(true)));
        assert_eq!(serial, parallel);
        assert_eq!(a, b);
        check(&serial.0, &a, 8);
    }

    #[test]
    fn bin_counts_grow_with_the_node() {
        assert_eq!(bin_count(2), 4);
        assert_eq!(bin_count(19), 4);
        assert_eq!(bin_count(39), 5);
        assert_eq!(bin_count(40), 6);
        assert_eq!(bin_count(100), 9);
        assert_eq!(bin_count(400), 24);
        assert_eq!(bin_count(560), NUM_BINS);
        assert_eq!(bin_count(1000), NUM_BINS);
        assert_eq!(bin_of(f32::NAN, 0.0, 1.0, 4), 0);
        assert_eq!(bin_of(-5.0, 0.0, 1.0, 4), 0);
        assert_eq!(bin_of(2.5, 0.0, 1.0, 4), 2);
        assert_eq!(bin_of(1e30, 0.0, 1.0, 4), 3);
        assert_eq!(bin_of(f32::INFINITY, 0.0, 1.0, 32), 31);
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
