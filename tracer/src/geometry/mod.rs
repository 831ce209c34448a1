//! Scene geometry: primitives, their intersection kernels, and the BVH over them.
//!
//! [`Geometry::build`] converts the parsed `f64` shapes to the precision `T`,
//! triangulates polygons, builds the BVH and reorders the primitives into leaf order.
//! [`Geometry::intersect`] returns the closest hit in the ray's open interval
//! $(t_{min}, t_{max})$ ([`Geometry::cast`] the same before its hit record is built,
//! [`Geometry::hit`] builds it); [`Geometry::occluded`] stops at the first hit.
//!
//! | NFF | stored as | kernel |
//! |---|---|---|
//! | `s` | [`Sphere`] | Haines et al., Ray Tracing Gems ch. 7 ([`sphere`]) |
//! | `c` | [`Cone`] | analytic, cancellation-free discriminant ([`cone`]) |
//! | `p` | [`Triangle`]s by ear clipping, polygon normal by Newell ([`polygon`]) | watertight (Woop et al. 2013) or Möller–Trumbore ([`triangle`]) |
//! | `pp` | the same, with vertex normals | the same |
//! | (API) | [`Plane`] outside the BVH | ray/plane ([`plane`]) |
//!
//! # Storage
//! One dense array per primitive type rather than an enum: an enum would be as large as
//! its largest variant plus a tag (a cone's 36 bytes in `f32` for every 16-byte sphere)
//! and would mix what the kernels read with ids and materials needed once per ray. Each
//! type keeps exactly its kernel's data (`Sphere`: centre and radius; `Triangle`: three
//! vertices; `Cone`: frame, height, radius, slope) in one array and the cold data (input
//! index, material, normals) in a parallel one. A BVH reference is a `u32` with a 2-bit
//! type tag and a 30-bit index. After the build the arrays are reordered into leaf
//! order, so a leaf's primitives are adjacent in memory, and since leaves are mostly of
//! one type the dispatch branch predicts well. The triangles of every leaf of the
//! four-wide tree that holds only triangles are also copied into structure-of-arrays
//! groups of four ([`triangle::Tri4`]), which that leaf points at instead of its
//! references, and are tested against a ray four at a time.
//!
//! # Queries
//! Every query, the closest hit ([`Geometry::intersect`]) or any hit
//! ([`Geometry::occluded`], [`Geometry::occluded_hint_kinds`] after its cached
//! occluder) of one ray or of a packet ([`packet_query`]), runs through one driver,
//! `Geometry::query` (`geometry/query.rs`): the planes first, then the four-wide or the
//! binary BVH or, without a BVH, every primitive; an any-hit query stops at the step
//! that answers it. A query supplies its side of those steps through the trait `Query`
//! (its loop over given primitives, which serves the planes and brute force, and its
//! walk of either tree). One ray's closest and any hit are one type, `RayQuery`, whose
//! const parameter `ANY` picks the leaf test and is the walks' `ANY_HIT`; the packet
//! queries `ClosestPacket` and `AnyPacket` bring their lane kernels and packet walks,
//! and hand their last rays over to `RayQuery`'s own walk.
//!
//! All of it is `#[inline(always)]`, the leaf tests are the hand-written drivers' (any
//! hit: `Some(t_max)` on a hit, the occluder in the query's local record), and the
//! single-ray walks take them as a [`crate::bvh::traverse::LeafVisitor`], so each
//! instance compiles to the code of a query written out alone. Instructions per frame
//! against the hand-written drivers (A, the commit before the driver; B, the driver),
//! `tracer/scripts/instructions.sh "A --packets off" "B --packets off"`, the same with
//! `--packets auto`, and both again with `SCENES="gears-s4 tetra-s6"` and `--depth 1`
//! (callgrind, 128×128, one thread; both
//! built with `cargo build --profile perf -p tracer-cli`):
//!
//! | scene | `--packets off` A | B | B / A | `--packets auto` A | B | B / A |
//! |---|---:|---:|---:|---:|---:|---:|
//! | balls-s4 | 107.28 M | 107.19 M | 0.9991 | 101.99 M | 101.58 M | 0.9960 |
//! | gears-s4 | 129.81 M | 130.25 M | 1.0034 | 131.06 M | 130.66 M | 0.9969 |
//! | mount-s6 | 112.58 M | 112.85 M | 1.0024 | 106.49 M | 106.89 M | 1.0038 |
//! | rings-s7 | 279.78 M | 276.20 M | 0.9872 | 271.10 M | 268.55 M | 0.9906 |
//! | teapot-s12 | 66.79 M | 66.91 M | 1.0018 | 64.14 M | 64.14 M | 0.9999 |
//! | tetra-s6 | 16.55 M | 16.05 M | 0.9695 | 17.31 M | 17.31 M | 0.9997 |
//! | tree-s11 | 87.48 M | 86.74 M | 0.9915 | 85.38 M | 84.81 M | 0.9933 |
//! | gears-s4, `--depth 1` | 77.96 M | 78.87 M | 1.0117 | 80.46 M | 80.61 M | 1.0020 |
//! | tetra-s6, `--depth 1` | 16.57 M | 16.06 M | 0.9693 | 17.31 M | 17.30 M | 0.9996 |
//!
//! Every row is within 0.5 % but one: gears-s4 at depth 1 with single rays, where the
//! shadow rays' any-hit queries are most of the work, runs 1.2 % more (callgrind puts the
//! difference in the shading function's inlined shadow queries: their ray set-up and box
//! tests; not resolved). Passing the leaf test to the walks as a closure, as the
//! hand-written drivers did, cost more: the shading's two shadow tests (with and without
//! a cache entry) are one query instance, so they shared one leaf closure, which the
//! compiler left out of line; gears-s4 at depth 1 ran 80.21 M against 77.96 M
//! instructions (1.029), teapot-s12 1.019, tree-s11 1.016 with single rays and 1.023 with
//! packets. The walks now take a `LeafVisitor` whose method is always inlined.
//!
//! # BVH
//! Binned SAH (Wald 2007) over conservative `f32` boxes, built in parallel and
//! deterministically; 32-byte nodes with `f32` bounds rounded outward for both
//! precisions, depth-first with the first child next to its parent; ordered traversal
//! with Ize's conservative slab test. See [`crate::bvh`].
//!
//! # Guarantees
//! - Degenerate input never panics and never produces a hit: zero or non-finite radii,
//!   zero-area triangles, polygons without area and coincident cone ends are skipped at
//!   build time ([`GeometryStats::skipped`]); rays with a non-finite origin or
//!   direction, a zero direction or a NaN interval hit nothing.
//! - Every hit has a finite `t` in the interval and unit normals.
//! - The BVH box test is conservative (Ize 2013) and primitive boxes are padded by a
//!   few ulps of `T`, so the BVH returns what brute force returns, bit for bit (tested
//!   on random scenes). When two primitives are hit at exactly the same `t`, the one
//!   given first in the input wins, independently of traversal order.

pub mod aabb;
pub mod builder;
pub mod cone;
pub mod offset;
pub mod packet_query;
pub mod plane;
pub mod polygon;
mod query;
pub(crate) mod ray_data;
pub mod sphere;
pub(crate) mod storage;
pub mod triangle;

pub use aabb::Aabb;
pub use builder::GeometryBuilder;
pub use cone::Cone;
pub use offset::{offset_ray, offset_ray_from};
pub use plane::Plane;
pub use ray_data::MAX_LANES;
pub use sphere::Sphere;
pub use triangle::Triangle;
use triangle::{Tri4, TRI4_LANES};

use crate::bvh::wide::Leaf;
use crate::bvh::{Bounds3, BuildConfig, Bvh};
use crate::float::Float;
use crate::ray::{Hit, Ray};
use crate::scene::desc::ShapeDesc;
use query::RayQuery;
use ray_data::{RayData, Shear};
use std::time::Instant;
use storage::{make_ref, Prims, CONE, INDEX_MASK, NO_SHADING, PLANE, SPHERE, TAG_SHIFT, TRIANGLE};
use vecexpr::{Expr, Real, Vec3};

/// Bit masks naming primitive kinds, for the `KINDS` parameter of
/// [`Geometry::intersect_kinds`] and [`Geometry::occluded_kinds`]. Kind `k`'s bit is
/// `1 << tag` of its references; bits above [`kinds::ALL`] are ignored, so a larger
/// mask (such as an effect set) can be passed as it is.
pub mod kinds {
    /// Spheres.
    pub const SPHERES: u32 = 1 << super::SPHERE;
    /// Triangles (polygons, patches, meshes).
    pub const TRIANGLES: u32 = 1 << super::TRIANGLE;
    /// Cones and cylinders.
    pub const CONES: u32 = 1 << super::CONE;
    /// Infinite planes.
    pub const PLANES: u32 = 1 << super::PLANE;
    /// Every kind.
    pub const ALL: u32 = SPHERES | TRIANGLES | CONES | PLANES;
}

/// The tag of reference `r` when it can only be one of the kinds in `KINDS`: a constant
/// when there is one kind, so the type dispatch disappears.
#[inline(always)]
const fn tag_of<const KINDS: u32>(r: u32) -> u32 {
    match KINDS & kinds::ALL {
        kinds::SPHERES => SPHERE,
        kinds::TRIANGLES => TRIANGLE,
        kinds::CONES => CONE,
        kinds::PLANES => PLANE,
        _ => r >> TAG_SHIFT,
    }
}

/// Code generic over a [`kinds`] mask, called through [`Geometry::by_kinds`].
trait KindsFn<T: Real, R> {
    /// Runs the instance for `KINDS` on `g`.
    fn call<const KINDS: u32>(self, g: &Geometry<T>) -> R;
}

/// Is the kind with reference tag `tag` in `KINDS`? (Folds to a constant.)
#[inline(always)]
const fn kind_in<const KINDS: u32>(tag: u32) -> bool {
    KINDS & (1 << tag) != 0
}

/// The kinds of mask `K`, its bits above [`kinds::ALL`] cleared (an effect set names its
/// effects there), as a constant of its own.
struct KindsOnly<const K: u32>;

impl<const K: u32> KindsOnly<K> {
    const MASK: u32 = K & kinds::ALL;
}

/// Runs `$body` with `$k` the constant [`KindsOnly`]`::<$kinds>::MASK`, so that the
/// queries taking a mask are compiled once per set of kinds and not once per effect
/// set that has the same kinds (eight effect sets name four sets of kinds). The match
/// is on a constant: only its one arm is compiled.
macro_rules! kinds_only {
    ($kinds:ident, $k:ident => $body:expr) => {
        kinds_only!(@arms KindsOnly::<$kinds>::MASK, $k, $body;
            0 1 2 3 4 5 6 7 8 9 10 11 12 13 14)
    };
    (@arms $mask:expr, $k:ident, $body:expr; $($m:literal)*) => {
        match $mask {
            $($m => {
                const $k: u32 = $m;
                $body
            })*
            _ => {
                const $k: u32 = kinds::ALL;
                $body
            }
        }
    };
}

/// Which ray/triangle test to use.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TriangleTest {
    /// Woop, Benthin, Wald 2013: no ray slips between triangles sharing an edge.
    #[default]
    Watertight,
    /// Möller, Trumbore 1997: slightly cheaper, may miss along shared edges.
    MollerTrumbore,
}

/// How to accelerate ray queries.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AccelOptions {
    /// Build and use a BVH; `false` tests every primitive (for comparison).
    pub use_bvh: bool,
    /// The ray/triangle test.
    pub triangle: TriangleTest,
    /// Largest leaf the SAH may choose (larger nodes are always split).
    pub max_leaf_size: usize,
    /// Build large subtrees in parallel on the rayon pool (the tree is identical either
    /// way).
    pub parallel_build: bool,
    /// SAH cost of visiting a BVH node relative to one primitive test: larger values
    /// give fewer nodes with more primitives each (less memory, faster build).
    pub traversal_cost: f32,
    /// Traverse the four-wide BVH (`true`) or the binary one.
    pub wide: bool,
    /// With `wide`, single rays of `f32` scenes walk an eight-wide BVH (the same tree
    /// collapsed into nodes of eight children) with AVX box tests, where the CPU has
    /// AVX2 and FMA, and so do eye packets of eight or sixteen lanes walking as one
    /// beam; other packets keep the four-wide tree. Results are the same either way.
    pub eight_wide: bool,
    /// The eight-wide walks of single rays run their AVX-512VL compilation where the
    /// CPU has it (the same operations with twice the vector registers); `false` keeps
    /// the AVX2 one. Results are the same either way.
    pub avx512: bool,
}

impl Default for AccelOptions {
    /// BVH, watertight triangles, leaves of up to 8, parallel build, traversal cost
    /// [`crate::bvh::build::TRAVERSAL_COST`].
    fn default() -> Self {
        Self {
            use_bvh: true,
            triangle: TriangleTest::Watertight,
            max_leaf_size: 8,
            parallel_build: true,
            traversal_cost: crate::bvh::build::TRAVERSAL_COST,
            wide: true,
            eight_wide: true,
            avx512: true,
        }
    }
}

/// The walk of single rays, chosen when a [`Geometry`] is built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum EightWalk {
    /// The four-wide tree: no eight-wide tree, or a CPU without AVX2 and FMA.
    Off,
    /// The eight-wide tree, with AVX box tests: an `f32` geometry with a BVH,
    /// [`AccelOptions::wide`] and [`AccelOptions::eight_wide`], on a CPU with AVX2 and
    /// FMA.
    Avx2,
    /// As `Avx2`, in the walk's AVX-512VL compilation, where the CPU has AVX-512F and
    /// AVX-512VL too and [`AccelOptions::avx512`] is set: the same operations, with 32
    /// vector registers instead of 16 (see [`Geometry::closest_best_avx512`]).
    Avx512,
}

/// Counts and costs of a built [`Geometry`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GeometryStats {
    /// Spheres stored.
    pub spheres: usize,
    /// Triangles stored, including those cut from polygons, patches and meshes.
    pub triangles: usize,
    /// Input polygons (NFF `p`), degenerate ones included.
    pub polygons: usize,
    /// Input patches (NFF `pp`), degenerate ones included.
    pub patches: usize,
    /// Cones and cylinders stored.
    pub cones: usize,
    /// Infinite planes (outside the BVH).
    pub planes: usize,
    /// Input primitives dropped as degenerate.
    pub skipped: usize,
    /// BVH nodes (0 without a BVH).
    pub bvh_nodes: usize,
    /// BVH levels (1 for a single leaf).
    pub bvh_depth: usize,
    /// Bytes of the binary BVH nodes and references.
    pub bvh_bytes: usize,
    /// Bytes of the four-wide BVH nodes and references.
    pub bvh_wide_bytes: usize,
    /// Bytes of the eight-wide BVH nodes (0 where single rays walk the four-wide tree;
    /// the references are shared).
    pub bvh_wide8_bytes: usize,
    /// Bytes of primitive data (kernel data, ids, materials, normals).
    pub prim_bytes: usize,
    /// Wall time of the whole build (conversion, triangulation, BVH, reordering), ms.
    pub build_ms: f64,
}

impl GeometryStats {
    /// BVH (every tree) plus primitive bytes per primitive in the BVH.
    pub fn bytes_per_primitive(&self) -> f64 {
        let n = self.spheres + self.triangles + self.cones;
        let wide_nodes = self.bvh_wide_bytes.saturating_sub(4 * n);
        (self.bvh_bytes + wide_nodes + self.bvh_wide8_bytes + self.prim_bytes) as f64
            / n.max(1) as f64
    }
}

/// The closest candidate so far: reference, distance, barycentrics.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Best<T: Real> {
    r: u32,
    t: T,
    b1: T,
    b2: T,
}

impl<T: Real> Best<T> {
    /// No candidate yet, hits looked for up to `t`.
    #[inline(always)]
    fn none(t: T) -> Self {
        Self {
            r: NO_HIT,
            t,
            b1: T::ZERO,
            b2: T::ZERO,
        }
    }
}

/// What a closest-hit query finds before any hit record is built: the distance, the
/// barycentrics and the primitive ([`Geometry::cast`]). Embree's `rtcIntersect` reports
/// the same (with an unnormalised geometric normal besides), and it is all a caller
/// needs who wants only the distance or will shade later; [`Geometry::hit`] makes the
/// full [`Hit`] from it, reading the arrays the traversal did not touch (vertex
/// positions, normals, materials).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Intersection<T: Real>(Best<T>);

impl<T: Real> Intersection<T> {
    /// Ray parameter of the hit, the same as [`Hit::t`].
    #[inline]
    pub fn t(&self) -> T {
        self.0.t
    }

    /// The barycentrics $(b_1, b_2)$ of vertices 1 and 2 of a hit triangle; zero for
    /// other primitives.
    #[inline]
    pub fn barycentrics(&self) -> (T, T) {
        (self.0.b1, self.0.b2)
    }
}

/// No candidate yet (never a valid reference: planes are capped below this index).
const NO_HIT: u32 = u32::MAX;

/// The empty shadow cache entry of [`Geometry::occluded_hint_kinds`].
pub const NO_HINT: u32 = NO_HIT;

/// All primitives of a scene in precision `T`, with their BVH.
///
/// # Examples
/// ```
/// use tracer::geometry::{AccelOptions, Geometry};
/// use tracer::scene::desc::{Shape, ShapeDesc};
/// use tracer::Ray;
/// use vecexpr::vec3;
///
/// let shapes = [ShapeDesc {
///     shape: Shape::Sphere { center: [0.0, 0.0, -5.0], radius: 1.0, inside_visible: false },
///     material: 0,
///     line: 1,
/// }];
/// let g = Geometry::<f64>::build(&shapes, &AccelOptions::default());
/// let hit = g.intersect(&Ray::new(vec3(0.0, 0.0, 0.0), vec3(0.0, 0.0, -1.0))).unwrap();
/// assert_eq!(hit.t, 4.0);
/// assert_eq!(hit.geometric_normal, vec3(0.0, 0.0, 1.0));
/// ```
#[derive(Clone, Debug)]
pub struct Geometry<T: Real> {
    prims: Prims<T>,
    /// The primitive kinds present, as a [`kinds`] mask ([`Geometry::kinds`]).
    kinds: u32,
    bvh: Option<Bvh>,
    wide: bool,
    /// Which walk single rays take ([`EightWalk`]).
    eight: EightWalk,
    triangle_test: TriangleTest,
    bounds: Aabb<T>,
    stats: GeometryStats,
}

/// Whether the single-ray walks for `T`, `WATERTIGHT` and `KINDS` are compiled once per
/// shear axis: only where they can meet watertight triangle tests in `f32`. Spheres-only
/// walks, Möller–Trumbore and `f64` gain nothing from a constant axis.
struct AxisWalks<T, const WATERTIGHT: bool, const KINDS: u32>(std::marker::PhantomData<T>);

impl<T: Float, const WATERTIGHT: bool, const KINDS: u32> AxisWalks<T, WATERTIGHT, KINDS> {
    const PER_AXIS: bool = WATERTIGHT && KINDS & kinds::TRIANGLES != 0 && T::AS_F32.is_some();
}

/// The `KZ` of a walk compiled for every axis, which takes the ray's axis as a value.
const ANY_AXIS: usize = 3;

/// The shear axis of direction `d` for a walk compiled for axis `KZ`: `KZ` itself, a
/// constant, or [`Shear::kz`] for [`ANY_AXIS`].
#[inline(always)]
fn axis_for<T: Real, const KZ: usize>(d: &Vec3<T>) -> usize {
    if KZ < ANY_AXIS {
        KZ
    } else {
        Shear::kz(d)
    }
}

/// Runs `$body` with `$kz` a constant: the shear axis of `$ray` ([`Shear::kz`]) where
/// [`AxisWalks::PER_AXIS`] holds for `$t`, `$watertight` and `$kinds`, [`ANY_AXIS`]
/// elsewhere. `$body` calls a walk compiled for axis `$kz`, out of line: each axis gets
/// a function of its own, in which the single-ray walk reads every vertex coordinate of
/// the triangle tests at a constant offset, instead of through ten addresses made per
/// ray. (Inlined into one function, the three walks made it three times as large, and
/// the optimiser's time grew faster than its size.) Both tests are on constants, so
/// only the functions called are compiled.
macro_rules! by_axis {
    ($watertight:expr, $kinds:expr, $t:ty, $ray:expr, $kz:ident => $body:expr) => {
        if AxisWalks::<$t, $watertight, $kinds>::PER_AXIS {
            match Shear::kz(&$ray.dir) {
                0 => {
                    const $kz: usize = 0;
                    $body
                }
                1 => {
                    const $kz: usize = 1;
                    $body
                }
                _ => {
                    const $kz: usize = 2;
                    $body
                }
            }
        } else {
            const $kz: usize = ANY_AXIS;
            $body
        }
    };
}

impl<T: Float> Geometry<T> {
    /// Converts the shapes to `T` and builds the acceleration structure. A hit's
    /// `prim_id` is the index of its shape in `shapes`.
    pub fn build(shapes: &[ShapeDesc], opts: &AccelOptions) -> Self {
        let start = Instant::now();
        let mut b = GeometryBuilder::new();
        b.reserve_for(shapes);
        for (i, s) in shapes.iter().enumerate() {
            b.push_shape(i as u32, s);
        }
        Self::from_builder(b, opts, start)
    }

    /// Starts a geometry in code.
    pub fn builder() -> GeometryBuilder<T> {
        GeometryBuilder::new()
    }

    fn from_builder(b: GeometryBuilder<T>, opts: &AccelOptions, start: Instant) -> Self {
        let mut prims = b.prims;
        let mut build_prims = prims.build_prims(opts.parallel_build);
        #[cfg(target_arch = "x86_64")]
        let avx2 = vecexpr::simd::Isa::Avx2.is_available();
        #[cfg(not(target_arch = "x86_64"))]
        let avx2 = false;
        let eight = opts.use_bvh && opts.wide && opts.eight_wide && T::AS_F32.is_some() && avx2;
        #[cfg(target_arch = "x86_64")]
        let avx512 = std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512vl");
        #[cfg(not(target_arch = "x86_64"))]
        let avx512 = false;
        let walk = match (eight, opts.avx512 && avx512) {
            (false, _) => EightWalk::Off,
            (true, false) => EightWalk::Avx2,
            (true, true) => EightWalk::Avx512,
        };
        let bvh = opts.use_bvh.then(|| {
            let cfg = BuildConfig {
                max_leaf_size: opts.max_leaf_size,
                parallel: opts.parallel_build,
                traversal_cost: opts.traversal_cost,
            };
            let (mut bvh, ()) = Bvh::build_beside(&mut build_prims, &cfg, eight, |refs| {
                prims.reorder(refs, opts.parallel_build)
            });
            prims.group_leaves(&mut bvh);
            bvh
        });
        // The bounds of every bounded primitive: the root box of the BVH, which is
        // their union, or, without a tree, one pass over them.
        let total = match bvh.as_ref().and_then(|b| b.nodes().first()) {
            Some(root) => Bounds3 {
                lo: root.bounds[0],
                hi: root.bounds[1],
            },
            None => build_prims.iter().fold(Bounds3::EMPTY, |mut t, p| {
                t.union(&p.bounds());
                t
            }),
        };
        drop(build_prims);
        let stats = GeometryStats {
            spheres: prims.spheres.len(),
            triangles: prims.triangles.len(),
            polygons: b.polygons,
            patches: b.patches,
            cones: prims.cones.len(),
            planes: prims.planes.len(),
            skipped: b.skipped,
            bvh_nodes: bvh.as_ref().map_or(0, |b| b.nodes().len()),
            bvh_depth: bvh.as_ref().map_or(0, |b| b.depth()),
            bvh_bytes: bvh.as_ref().map_or(0, |b| b.bytes()),
            bvh_wide_bytes: bvh.as_ref().map_or(0, |b| b.wide_bytes()),
            bvh_wide8_bytes: bvh.as_ref().map_or(0, |b| b.wide8_bytes()),
            prim_bytes: prims.bytes(),
            build_ms: start.elapsed().as_secs_f64() * 1e3,
        };
        let bit = |n: usize, k: u32| if n > 0 { k } else { 0 };
        let kinds = bit(prims.spheres.len(), kinds::SPHERES)
            | bit(prims.triangles.len(), kinds::TRIANGLES)
            | bit(prims.cones.len(), kinds::CONES)
            | bit(prims.planes.len(), kinds::PLANES);
        Self {
            prims,
            kinds,
            bvh,
            wide: opts.wide,
            eight: walk,
            triangle_test: opts.triangle,
            bounds: Aabb::from_bounds(&total),
            stats,
        }
    }

    /// Counts, BVH size and build time.
    pub fn stats(&self) -> &GeometryStats {
        &self.stats
    }

    /// The primitive kinds present, as a [`kinds`] mask.
    pub fn kinds(&self) -> u32 {
        self.kinds
    }

    /// Conservative bounds of all bounded primitives (planes excluded); empty if none.
    pub fn bounds(&self) -> Aabb<T> {
        self.bounds
    }

    /// The BVH, if one was built.
    pub fn bvh(&self) -> Option<&Bvh> {
        self.bvh.as_ref()
    }

    /// The ray/triangle test in use.
    pub fn triangle_test(&self) -> TriangleTest {
        self.triangle_test
    }

    /// The closest hit with $t \in (t_{min}, t_{max})$, or `None` (also for invalid
    /// rays: non-finite origin or direction, zero direction, NaN bounds).
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray<T>) -> Option<Hit<T>> {
        /// [`Geometry::closest`] for the kinds [`Geometry::by_kinds`] picks.
        struct Intersect<'a, T: Real>(&'a Ray<T>);
        impl<T: Float> KindsFn<T, Option<Hit<T>>> for Intersect<'_, T> {
            #[inline(always)]
            fn call<const KINDS: u32>(self, g: &Geometry<T>) -> Option<Hit<T>> {
                g.closest::<true, KINDS>(self.0)
            }
        }
        match self.triangle_test {
            TriangleTest::Watertight => self.by_kinds(Intersect(ray)),
            TriangleTest::MollerTrumbore => self.closest_moller_trumbore(ray),
        }
    }

    /// The closest hit of [`Geometry::intersect`] without its hit record: `cast(ray)`
    /// then [`Geometry::hit`] is `intersect(ray)`, bit for bit. Spares the record's
    /// memory reads and arithmetic where only the distance is wanted.
    #[inline(always)]
    pub fn cast(&self, ray: &Ray<T>) -> Option<Intersection<T>> {
        /// [`Geometry::closest_best`] for the kinds [`Geometry::by_kinds`] picks.
        struct Cast<'a, T: Real>(&'a Ray<T>);
        impl<T: Float> KindsFn<T, Option<Best<T>>> for Cast<'_, T> {
            #[inline(always)]
            fn call<const KINDS: u32>(self, g: &Geometry<T>) -> Option<Best<T>> {
                g.closest_best::<true, KINDS>(self.0)
            }
        }
        match self.triangle_test {
            TriangleTest::Watertight => self.by_kinds(Cast(ray)),
            TriangleTest::MollerTrumbore => self.cast_moller_trumbore(ray),
        }
        .map(Intersection)
    }

    /// Runs `f` compiled for this geometry's primitive kinds where they are one kind,
    /// and for every kind otherwise, for the queries called without an effect set
    /// ([`Geometry::intersect`], [`Geometry::cast`], [`Geometry::occluded`]); the
    /// renderer picks its kinds with its effect set instead ([`crate::effects`]). With
    /// one kind the type dispatch per primitive test and the other kinds' tests are
    /// left out: on the triangle scenes (teapot-s12, gears-s4, tetra-s6) single eye
    /// rays run 0.957 to 0.966 of the instructions and shadow rays 0.956 to 0.959
    /// (`tracer/JOURNAL.md`, "The public queries compiled for the scene's kinds"). The
    /// callers are inlined, or the hit record is returned through memory (+45
    /// instructions a ray).
    #[inline(always)]
    fn by_kinds<R>(&self, f: impl KindsFn<T, R>) -> R {
        match self.kinds {
            kinds::TRIANGLES => f.call::<{ kinds::TRIANGLES }>(self),
            kinds::SPHERES => f.call::<{ kinds::SPHERES }>(self),
            _ => f.call::<{ kinds::ALL }>(self),
        }
    }

    /// The full hit record of `found`, which [`Geometry::cast`] (or
    /// [`Geometry::cast_packet`]) returned for this `ray` on this geometry.
    ///
    /// # Panics
    /// May panic, or return a meaningless record, if `found` is from another geometry.
    #[inline]
    pub fn hit(&self, ray: &Ray<T>, found: &Intersection<T>) -> Hit<T> {
        self.make_hit::<{ kinds::ALL }>(&found.0, ray)
    }

    /// Is anything hit with $t \in (t_{min}, t_{max})$? Stops at the first hit found.
    #[inline(always)]
    pub fn occluded(&self, ray: &Ray<T>) -> bool {
        /// [`Geometry::any`] for the kinds [`Geometry::by_kinds`] picks.
        struct Occluded<'a, T: Real>(&'a Ray<T>);
        impl<T: Float> KindsFn<T, bool> for Occluded<'_, T> {
            #[inline(always)]
            fn call<const KINDS: u32>(self, g: &Geometry<T>) -> bool {
                g.any::<true, KINDS>(self.0)
            }
        }
        match self.triangle_test {
            TriangleTest::Watertight => self.by_kinds(Occluded(ray)),
            TriangleTest::MollerTrumbore => self.any_moller_trumbore(ray),
        }
    }

    /// [`Geometry::intersect`] compiled for the primitive kinds in `KINDS` only (a
    /// [`kinds`] mask, other bits ignored), which must contain [`Geometry::kinds`]:
    /// with one kind the type dispatch per primitive test is left out, and planes are
    /// only tested when `KINDS` has them. (Mixed kinds keep the general dispatch:
    /// leaving out the absent kinds' arms measured slower.) The result is the same as
    /// `intersect`'s.
    ///
    /// Only the default watertight triangle test is specialised; with Möller–Trumbore
    /// every `KINDS` calls one shared, out-of-line all-kinds query, so each kind set
    /// adds one copy of the traversal, not two.
    #[inline]
    pub fn intersect_kinds<const KINDS: u32>(&self, ray: &Ray<T>) -> Option<Hit<T>> {
        debug_assert_eq!(self.kinds() & !KINDS, 0, "primitive kinds left out");
        match self.triangle_test {
            TriangleTest::Watertight => kinds_only!(KINDS, K => self.closest::<true, K>(ray)),
            TriangleTest::MollerTrumbore => self.closest_moller_trumbore(ray),
        }
    }

    /// [`Geometry::occluded`] compiled for the primitive kinds in `KINDS` only, as for
    /// [`Geometry::intersect_kinds`].
    #[inline]
    pub fn occluded_kinds<const KINDS: u32>(&self, ray: &Ray<T>) -> bool {
        debug_assert_eq!(self.kinds() & !KINDS, 0, "primitive kinds left out");
        match self.triangle_test {
            TriangleTest::Watertight => kinds_only!(KINDS, K => self.any::<true, K>(ray)),
            TriangleTest::MollerTrumbore => self.any_moller_trumbore(ray),
        }
    }

    /// [`Geometry::occluded_kinds`] with a shadow cache entry (Haines and Greenberg,
    /// "The Light Buffer", IEEE CG&A 6(9), 1986: the object that last blocked a light is
    /// the likeliest to block it again). `*hint` is a primitive reference from an
    /// earlier call, or [`NO_HINT`]; that primitive is tested first. When it does not
    /// block the ray, `*hint` becomes the occluder found instead, or [`NO_HINT`] if the
    /// ray is unblocked. Any value of `*hint` is
    /// safe (one that names no primitive of this geometry is ignored), and the answer
    /// is always that of `occluded_kinds`: a hint only changes how soon it is found.
    #[inline(always)]
    pub fn occluded_hint_kinds<const KINDS: u32>(&self, ray: &Ray<T>, hint: &mut u32) -> bool {
        debug_assert_eq!(self.kinds() & !KINDS, 0, "primitive kinds left out");
        match self.triangle_test {
            TriangleTest::Watertight => {
                kinds_only!(KINDS, K => self.any_hint::<true, K>(ray, hint))
            }
            TriangleTest::MollerTrumbore => self.any_hint_moller_trumbore(ray, hint),
        }
    }

    #[inline(never)]
    fn any_hint_moller_trumbore(&self, ray: &Ray<T>, hint: &mut u32) -> bool {
        self.any_hint::<false, { kinds::ALL }>(ray, hint)
    }

    /// Does the primitive `r` exist in this geometry (with a kind in `KINDS`)?
    #[inline(always)]
    fn names_prim<const KINDS: u32>(&self, r: u32) -> bool {
        let tag = r >> TAG_SHIFT;
        let i = (r & INDEX_MASK) as usize;
        let p = &self.prims;
        kind_in::<KINDS>(tag)
            && i < match tag {
                SPHERE => p.spheres.len(),
                TRIANGLE => p.triangles.len(),
                CONE => p.cones.len(),
                _ => p.planes.len(),
            }
    }

    /// The cached occluder `*hint`, then the any-hit [`RayQuery`]; `*hint` becomes the
    /// occluder found. Over the eight-wide tree where the geometry has it.
    #[inline(always)]
    fn any_hint<const WATERTIGHT: bool, const KINDS: u32>(
        &self,
        ray: &Ray<T>,
        hint: &mut u32,
    ) -> bool {
        #[cfg(target_arch = "x86_64")]
        match self.eight {
            EightWalk::Avx512 => {
                // SAFETY: `Avx512` is chosen only where the CPU has AVX2, FMA, AVX-512F
                // and AVX-512VL, for a geometry with the eight-wide tree.
                return by_axis!(WATERTIGHT, KINDS, T, ray, KZ => unsafe {
                    self.any_hint_avx512::<WATERTIGHT, KINDS, KZ>(ray, hint)
                });
            }
            EightWalk::Avx2 => {
                // SAFETY: `Avx2` is chosen only where the CPU has AVX2 and FMA, for a
                // geometry with the eight-wide tree.
                return by_axis!(WATERTIGHT, KINDS, T, ray, KZ => unsafe {
                    self.any_hint_avx2::<WATERTIGHT, KINDS, KZ>(ray, hint)
                });
            }
            EightWalk::Off => {}
        }
        self.any_hint_four::<WATERTIGHT, KINDS>(ray, hint)
    }

    /// [`Geometry::any_hint`] over the four-wide tree, out of line (see
    /// [`Geometry::closest_best_four`]).
    #[inline(never)]
    fn any_hint_four<const WATERTIGHT: bool, const KINDS: u32>(
        &self,
        ray: &Ray<T>,
        hint: &mut u32,
    ) -> bool {
        self.any_hint_in::<WATERTIGHT, KINDS, false>(ray, hint, Shear::kz(&ray.dir))
    }

    /// [`Geometry::any_hint`] over the eight-wide tree, compiled for AVX2.
    ///
    /// # Safety
    /// As for [`Geometry::closest_best_avx2`].
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    #[inline(never)]
    unsafe fn any_hint_avx2<const WATERTIGHT: bool, const KINDS: u32, const KZ: usize>(
        &self,
        ray: &Ray<T>,
        hint: &mut u32,
    ) -> bool {
        self.any_hint_in::<WATERTIGHT, KINDS, true>(ray, hint, axis_for::<T, KZ>(&ray.dir))
    }

    /// [`Geometry::any_hint_avx2`] compiled for AVX-512VL too (see
    /// [`Geometry::closest_best_avx512`]).
    ///
    /// # Safety
    /// As for [`Geometry::closest_best_avx512`].
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,avx512f,avx512vl")]
    #[inline(never)]
    unsafe fn any_hint_avx512<const WATERTIGHT: bool, const KINDS: u32, const KZ: usize>(
        &self,
        ray: &Ray<T>,
        hint: &mut u32,
    ) -> bool {
        self.any_hint_in::<WATERTIGHT, KINDS, true>(ray, hint, axis_for::<T, KZ>(&ray.dir))
    }

    #[inline(always)]
    fn any_hint_in<const WATERTIGHT: bool, const KINDS: u32, const EIGHT: bool>(
        &self,
        ray: &Ray<T>,
        hint: &mut u32,
        kz: usize,
    ) -> bool {
        let Some(rd) = RayData::along(ray, kz) else {
            return false;
        };
        let cached = *hint;
        if cached != NO_HINT
            && self.names_prim::<KINDS>(cached)
            && self
                .test::<WATERTIGHT, KINDS>(cached, &rd, rd.t_limit)
                .is_some()
        {
            return true;
        }
        let (hit, found) = self.any_query::<WATERTIGHT, KINDS, EIGHT>(&rd);
        // An unblocked ray clears the entry: lit regions then pay no hint test.
        *hint = found;
        hit
    }

    #[inline(never)]
    fn closest_moller_trumbore(&self, ray: &Ray<T>) -> Option<Hit<T>> {
        self.closest::<false, { kinds::ALL }>(ray)
    }

    #[inline(never)]
    fn cast_moller_trumbore(&self, ray: &Ray<T>) -> Option<Best<T>> {
        self.closest_best::<false, { kinds::ALL }>(ray)
    }

    #[inline(never)]
    fn any_moller_trumbore(&self, ray: &Ray<T>) -> bool {
        self.any::<false, { kinds::ALL }>(ray)
    }

    /// Tests one primitive for a hit with $t \in (t_{min}, t_{max}]$.
    #[inline(always)]
    fn test<const WATERTIGHT: bool, const KINDS: u32>(
        &self,
        r: u32,
        rd: &RayData<T>,
        t_max: T,
    ) -> Option<(T, T, T)> {
        let i = (r & INDEX_MASK) as usize;
        let zero = T::ZERO;
        match tag_of::<KINDS>(r) {
            SPHERE => self.prims.spheres[i]
                .intersect(rd, t_max)
                .map(|t| (t, zero, zero)),
            TRIANGLE => {
                let tri = &self.prims.triangles[i];
                if WATERTIGHT {
                    tri.intersect_watertight(rd, t_max)
                } else {
                    tri.intersect_moller_trumbore(rd, t_max)
                }
            }
            CONE => self.prims.cones[i]
                .intersect(rd, t_max)
                .map(|t| (t, zero, zero)),
            _ => self.prims.planes[i]
                .intersect(rd, t_max)
                .map(|t| (t, zero, zero)),
        }
    }

    /// The groups of four triangles of a grouped leaf ([`storage::Prims::group_leaves`]).
    #[inline(always)]
    fn groups(&self, child: u32, count: u32) -> &[Tri4<T>] {
        let first = child as usize;
        &self.prims.tri4[first..first + count.div_ceil(TRI4_LANES as u32) as usize]
    }

    /// The closest-hit leaf loop over a grouped leaf: offers every hit lane that is
    /// still within `best.t` (an earlier lane of the same group may have lowered it).
    /// The result is that of the reference loop over the same triangles, since
    /// [`Geometry::offer`] keeps the smallest `(t, key)` in any order.
    #[inline(always)]
    fn closest_grouped<const WATERTIGHT: bool, const KINDS: u32>(
        &self,
        child: u32,
        count: u32,
        rd: &RayData<T>,
        best: &mut Best<T>,
    ) -> bool {
        let mut improved = false;
        if !kind_in::<KINDS>(TRIANGLE) {
            return false;
        }
        for g in self.groups(child, count) {
            if WATERTIGHT {
                let h = g.intersect_watertight(rd, best.t);
                let mut bits = h.bits;
                while bits != 0 {
                    let i = bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    if h.t[i] <= best.t {
                        let r = make_ref(TRIANGLE, g.index[i] as usize);
                        improved |= self.offer(best, r, (h.t[i], h.b1[i], h.b2[i]));
                    }
                }
            } else {
                for &i in &g.index {
                    let r = make_ref(TRIANGLE, i as usize);
                    if let Some(h) = self.test::<WATERTIGHT, KINDS>(r, rd, best.t) {
                        improved |= self.offer(best, r, h);
                    }
                }
            }
        }
        improved
    }

    /// The any-hit leaf loop over a grouped leaf: the reference of a triangle hit
    /// within `limit`, if any.
    #[inline(always)]
    fn any_grouped<const WATERTIGHT: bool, const KINDS: u32>(
        &self,
        child: u32,
        count: u32,
        rd: &RayData<T>,
        limit: T,
    ) -> Option<u32> {
        if !kind_in::<KINDS>(TRIANGLE) {
            return None;
        }
        for g in self.groups(child, count) {
            if WATERTIGHT {
                let bits = g.intersect_watertight(rd, limit).bits;
                if bits != 0 {
                    let i = bits.trailing_zeros() as usize;
                    return Some(make_ref(TRIANGLE, g.index[i] as usize));
                }
            } else {
                for &i in &g.index {
                    let r = make_ref(TRIANGLE, i as usize);
                    if self.test::<WATERTIGHT, KINDS>(r, rd, limit).is_some() {
                        return Some(r);
                    }
                }
            }
        }
        None
    }

    /// The closest-hit loop over one leaf: offers every hit within `best.t`; whether
    /// `best` changed.
    #[inline(always)]
    fn leaf_closest<const WATERTIGHT: bool, const KINDS: u32>(
        &self,
        l: Leaf<'_>,
        rd: &RayData<T>,
        best: &mut Best<T>,
    ) -> bool {
        match l {
            Leaf::Refs(refs) => {
                let mut improved = false;
                for &r in refs {
                    if let Some(h) = self.test::<WATERTIGHT, KINDS>(r, rd, best.t) {
                        improved |= self.offer(best, r, h);
                    }
                }
                improved
            }
            Leaf::Grouped { child, count } => {
                self.closest_grouped::<WATERTIGHT, KINDS>(child, count, rd, best)
            }
        }
    }

    /// The any-hit loop over one leaf: the reference of a primitive hit within
    /// `limit`, if any.
    #[inline(always)]
    fn leaf_any<const WATERTIGHT: bool, const KINDS: u32>(
        &self,
        l: Leaf<'_>,
        rd: &RayData<T>,
        limit: T,
    ) -> Option<u32> {
        match l {
            // A plain loop: `Iterator::find` here was compiled into an out-of-line
            // `try_fold` that held balls-s4's sphere tests (6 % of a render's samples).
            Leaf::Refs(refs) => {
                for &r in refs {
                    if self.test::<WATERTIGHT, KINDS>(r, rd, limit).is_some() {
                        return Some(r);
                    }
                }
                None
            }
            Leaf::Grouped { child, count } => {
                self.any_grouped::<WATERTIGHT, KINDS>(child, count, rd, limit)
            }
        }
    }

    /// Keeps the hit if it is closer, or equally close and given earlier.
    #[inline(always)]
    fn offer(&self, best: &mut Best<T>, r: u32, (t, b1, b2): (T, T, T)) -> bool {
        // The kernel already ensured t <= best.t.
        if best.r == NO_HIT || t < best.t || self.prims.key(r) < self.prims.key(best.r) {
            *best = Best { r, t, b1, b2 };
            true
        } else {
            false
        }
    }

    /// Every reference, for brute force.
    fn all_refs(&self) -> impl Iterator<Item = u32> + '_ {
        let p = &self.prims;
        (0..p.spheres.len())
            .map(|i| make_ref(SPHERE, i))
            .chain((0..p.triangles.len()).map(|i| make_ref(TRIANGLE, i)))
            .chain((0..p.cones.len()).map(|i| make_ref(CONE, i)))
    }

    /// The closest-hit [`RayQuery`] of one ray.
    #[inline(always)]
    fn closest<const WATERTIGHT: bool, const KINDS: u32>(&self, ray: &Ray<T>) -> Option<Hit<T>> {
        self.closest_best::<WATERTIGHT, KINDS>(ray)
            .map(|best| self.make_hit::<KINDS>(&best, ray))
    }

    /// The winning candidate of the closest-hit [`RayQuery`] of one ray, over the
    /// eight-wide tree where the geometry has it ([`Geometry::eight`]).
    #[inline(always)]
    fn closest_best<const WATERTIGHT: bool, const KINDS: u32>(
        &self,
        ray: &Ray<T>,
    ) -> Option<Best<T>> {
        #[cfg(target_arch = "x86_64")]
        match self.eight {
            EightWalk::Avx512 => {
                // SAFETY: `Avx512` is chosen only where the CPU has AVX2, FMA, AVX-512F
                // and AVX-512VL, for a geometry with the eight-wide tree.
                return by_axis!(WATERTIGHT, KINDS, T, ray, KZ => unsafe {
                    self.closest_best_avx512::<WATERTIGHT, KINDS, KZ>(ray)
                });
            }
            EightWalk::Avx2 => {
                // SAFETY: `Avx2` is chosen only where the CPU has AVX2 and FMA, for a
                // geometry with the eight-wide tree.
                return by_axis!(WATERTIGHT, KINDS, T, ray, KZ => unsafe {
                    self.closest_best_avx2::<WATERTIGHT, KINDS, KZ>(ray)
                });
            }
            EightWalk::Off => {}
        }
        self.closest_best_four::<WATERTIGHT, KINDS>(ray)
    }

    /// [`Geometry::closest_best`] over the four-wide tree, out of line like the
    /// eight-wide query, so that the choice between them stays small enough to inline.
    #[inline(never)]
    fn closest_best_four<const WATERTIGHT: bool, const KINDS: u32>(
        &self,
        ray: &Ray<T>,
    ) -> Option<Best<T>> {
        self.closest_best_in::<WATERTIGHT, KINDS, false>(ray, Shear::kz(&ray.dir))
    }

    /// [`Geometry::closest_best`] over the eight-wide tree, compiled for AVX2 and for
    /// shear axis `KZ` (chosen by [`by_axis!`]).
    ///
    /// # Safety
    /// The CPU has AVX2 and FMA, and the geometry the eight-wide tree
    /// ([`Geometry::eight`]). `KZ` is the ray's [`Shear::kz`] or [`ANY_AXIS`].
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    #[inline(never)]
    unsafe fn closest_best_avx2<const WATERTIGHT: bool, const KINDS: u32, const KZ: usize>(
        &self,
        ray: &Ray<T>,
    ) -> Option<Best<T>> {
        self.closest_best_in::<WATERTIGHT, KINDS, true>(ray, axis_for::<T, KZ>(&ray.dir))
    }

    /// [`Geometry::closest_best_avx2`] compiled for AVX-512VL too: the same operations
    /// on the same eight-wide registers (the box tests stay AVX, so every answer is
    /// the same), but with 32 vector registers instead of 16, so that the walk's
    /// splatted ray values and the four-triangle test's no longer evict each other
    /// (on gears-s4, 6 of the 8 reloads of the box test's registers after each triangle
    /// group are gone, and 4 of the triangle test's 7). On the AVX-512 machine (Zen 4),
    /// one thread, 512², medians of seven alternations against `avx512: false`: single
    /// eye rays 1.01 (gears-s4) to 1.16 (mount-s6) times as fast, shadow rays 1.00
    /// (mount-s6) to 1.14 (teapot-s12) on the seven classic scenes (`tracer/JOURNAL.md`,
    /// "The single-ray walks compiled for AVX-512VL"). Callgrind cannot count it:
    /// valgrind does not run AVX-512 code.
    ///
    /// # Safety
    /// As for [`Geometry::closest_best_avx2`], and the CPU has AVX-512F and AVX-512VL
    /// ([`EightWalk::Avx512`]).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,avx512f,avx512vl")]
    #[inline(never)]
    unsafe fn closest_best_avx512<const WATERTIGHT: bool, const KINDS: u32, const KZ: usize>(
        &self,
        ray: &Ray<T>,
    ) -> Option<Best<T>> {
        self.closest_best_in::<WATERTIGHT, KINDS, true>(ray, axis_for::<T, KZ>(&ray.dir))
    }

    /// [`Geometry::closest_best`] over the eight-wide tree (`EIGHT`, see [`RayQuery`])
    /// or the four-wide one.
    #[inline(always)]
    fn closest_best_in<const WATERTIGHT: bool, const KINDS: u32, const EIGHT: bool>(
        &self,
        ray: &Ray<T>,
        kz: usize,
    ) -> Option<Best<T>> {
        let rd = RayData::along(ray, kz)?;
        let mut best = Best::none(rd.t_limit);
        self.query(&mut RayQuery::<T, false, WATERTIGHT, KINDS, EIGHT> {
            g: self,
            rd: &rd,
            best: &mut best,
        });
        (best.r != NO_HIT).then_some(best)
    }

    /// Is the ray blocked? Over the eight-wide tree where the geometry has it.
    #[inline(always)]
    fn any<const WATERTIGHT: bool, const KINDS: u32>(&self, ray: &Ray<T>) -> bool {
        #[cfg(target_arch = "x86_64")]
        match self.eight {
            EightWalk::Avx512 => {
                // SAFETY: `Avx512` is chosen only where the CPU has AVX2, FMA, AVX-512F
                // and AVX-512VL, for a geometry with the eight-wide tree.
                return by_axis!(WATERTIGHT, KINDS, T, ray, KZ => unsafe {
                    self.any_avx512::<WATERTIGHT, KINDS, KZ>(ray)
                });
            }
            EightWalk::Avx2 => {
                // SAFETY: `Avx2` is chosen only where the CPU has AVX2 and FMA, for a
                // geometry with the eight-wide tree.
                return by_axis!(WATERTIGHT, KINDS, T, ray, KZ => unsafe {
                    self.any_avx2::<WATERTIGHT, KINDS, KZ>(ray)
                });
            }
            EightWalk::Off => {}
        }
        self.any_four::<WATERTIGHT, KINDS>(ray)
    }

    /// [`Geometry::any`] over the four-wide tree, out of line (see
    /// [`Geometry::closest_best_four`]).
    #[inline(never)]
    fn any_four<const WATERTIGHT: bool, const KINDS: u32>(&self, ray: &Ray<T>) -> bool {
        self.any_in::<WATERTIGHT, KINDS, false>(ray, Shear::kz(&ray.dir))
    }

    /// [`Geometry::any`] over the eight-wide tree, compiled for AVX2.
    ///
    /// # Safety
    /// As for [`Geometry::closest_best_avx2`].
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    #[inline(never)]
    unsafe fn any_avx2<const WATERTIGHT: bool, const KINDS: u32, const KZ: usize>(
        &self,
        ray: &Ray<T>,
    ) -> bool {
        self.any_in::<WATERTIGHT, KINDS, true>(ray, axis_for::<T, KZ>(&ray.dir))
    }

    /// [`Geometry::any_avx2`] compiled for AVX-512VL too (see
    /// [`Geometry::closest_best_avx512`]).
    ///
    /// # Safety
    /// As for [`Geometry::closest_best_avx512`].
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,avx512f,avx512vl")]
    #[inline(never)]
    unsafe fn any_avx512<const WATERTIGHT: bool, const KINDS: u32, const KZ: usize>(
        &self,
        ray: &Ray<T>,
    ) -> bool {
        self.any_in::<WATERTIGHT, KINDS, true>(ray, axis_for::<T, KZ>(&ray.dir))
    }

    #[inline(always)]
    fn any_in<const WATERTIGHT: bool, const KINDS: u32, const EIGHT: bool>(
        &self,
        ray: &Ray<T>,
        kz: usize,
    ) -> bool {
        let Some(rd) = RayData::along(ray, kz) else {
            return false;
        };
        self.any_query::<WATERTIGHT, KINDS, EIGHT>(&rd).0
    }

    /// The any-hit [`RayQuery`] of one ray: whether it is blocked, and the occluder
    /// found (or [`NO_HIT`]).
    #[inline(always)]
    fn any_query<const WATERTIGHT: bool, const KINDS: u32, const EIGHT: bool>(
        &self,
        rd: &RayData<T>,
    ) -> (bool, u32) {
        let mut best = Best::none(rd.t_limit);
        let hit = self.query(&mut RayQuery::<T, true, WATERTIGHT, KINDS, EIGHT> {
            g: self,
            rd,
            best: &mut best,
        });
        (hit, best.r)
    }

    /// Fills in the hit record for the winning candidate of `ray` (only its origin and
    /// direction are read). Inlined, so that the record is built where it goes rather
    /// than copied out of a call's return slot (render instructions 0.991 to 1.001 of
    /// the out-of-line call's on the seven classic scenes).
    #[inline(always)]
    fn make_hit<const KINDS: u32>(&self, b: &Best<T>, rd: &Ray<T>) -> Hit<T> {
        let i = (b.r & INDEX_MASK) as usize;
        let p = &self.prims;
        let flip = |n: Vec3<T>, inside: bool| if inside { (-&n).eval() } else { n };
        let (point, ng, ns, info_id, material) = match tag_of::<KINDS>(b.r) {
            SPHERE => {
                let info = &p.sphere_info[i];
                let (n, point) = p.spheres[i].normal_and_point(rd, b.t);
                let n = flip(n, info.inside_visible);
                (point, n, n, info.prim_id, info.material)
            }
            TRIANGLE => {
                let info = &p.triangle_info[i];
                let point = p.triangles[i].point(b.b1, b.b2);
                let ng = info.normal;
                let ns = if info.shading == NO_SHADING {
                    ng
                } else {
                    let n = &p.shading[info.shading as usize];
                    let b0 = T::ONE - b.b1 - b.b2;
                    let s =
                        ((&n[0]).scale(b0) + (&n[1]).scale(b.b1) + (&n[2]).scale(b.b2)).normalize();
                    // normalize() gives a unit vector, zero, or NaN.
                    let d = s.dot(&ng);
                    let usable = s.length_squared() > <T as Real>::from_f64(0.5) && !d.is_nan();
                    if !usable {
                        ng
                    } else if d < T::ZERO {
                        (-&s).eval()
                    } else {
                        s
                    }
                };
                (point, ng, ns, info.prim_id, info.material)
            }
            CONE => {
                let info = &p.cone_info[i];
                let n = flip(p.cones[i].normal(rd, b.t), info.inside_visible);
                let point = p.cones[i].point(rd, b.t);
                (point, n, n, info.prim_id, info.material)
            }
            _ => {
                let info = &p.plane_info[i];
                let n = p.planes[i].normal;
                let point = p.planes[i].point(rd, b.t);
                (point, n, n, info.prim_id, info.material)
            }
        };
        Hit {
            t: b.t,
            point,
            geometric_normal: ng,
            shading_normal: ns,
            prim_id: info_id,
            material,
        }
    }
}
