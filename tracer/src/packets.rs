//! Eye rays traced in SIMD packets, one packet per block of pixels, and the shadow rays
//! of their hits traced as packets too.
//!
//! # The walk of a packet
//! With packets on, the renderer ([`crate::render`](mod@crate::render)) works through
//! the image a block of pixels at a time ([`block_shape`]: 2x2 for SSE2's four lanes,
//! 4x2 for AVX2's eight, 4x4 for AVX-512's sixteen):
//! 1. `eye_block` makes the block's eye rays ([`crate::camera::Camera::ray`] through
//!    [`Grid::point`], four at a time by `Camera::rays4`) and traces them as one packet
//!    ([`crate::geometry::Geometry::intersect_packet`], run by the kernel compiled for the chosen
//!    instruction set through [`vecexpr::simd::Isa::dispatch`]). The packet walks the
//!    four-wide BVH together ([`crate::bvh::packet_traverse`]); in a leaf, spheres,
//!    triangles and cones are tested against all its rays at once by the lane kernels
//!    that sit beside the single-ray ones ([`crate::geometry::sphere`],
//!    [`crate::geometry::triangle`], [`crate::geometry::cone`]).
//! 2. **Hand-over.** Where at most two rays of a packet, of any width, reach a
//!    subtree, the packet hands them over: each continues alone with the single-ray
//!    traversal of that subtree, keeping its closest hit so far. Rays and primitives the
//!    lane kernels do not cover (planes, rays whose triangle shear axes differ,
//!    edge functions exactly zero) are likewise tested by the single-ray kernels, lane
//!    by lane ([`crate::geometry::packet_query`]).
//! 3. The hits are shaded by the single-ray shading's steps (`shade::Surface`), one
//!    light at a time over the block (`shade_packet`): each hit's shadow ray toward the
//!    light, built by `Surface::light_ray`, joins one any-hit packet (a ray leaves it
//!    at its first blocker), and the hits it leaves unblocked add the light's terms.
//!    Before its walk the packet tests the primitive that last blocked a packet toward
//!    that light on this thread (`SHADOW_HINTS`, the packet form of the single rays'
//!    shadow cache); the rays it blocks do not walk the tree.
//! 4. Each hit then makes its reflection and refraction rays (`Surface::spawn`).
//! 5. **Secondary rays.** `radiance_tile` does steps 1 to 4 for a tile of 4x4 blocks
//!    (`TILE_SHAPE`), then gathers the reflection and refraction rays of all the
//!    tile's hits, sorts them by octant and traces them in full packets, generation
//!    after generation (the shadow rays of these hits stay single, with the shadow
//!    cache). Last, each ray's
//!    radiance is added to its parent's colour, in the order the recursive single-ray
//!    shading adds it.
//!
//! Every lane computes exactly what the single ray computes (same operations in the
//! same order, no fused multiply-add), and every hit is offered to the ray's record in
//! the single-ray way (closer, or as close and earlier in the input). So the image is
//! the same bit for bit with packets on or off, for every instruction set and hand-over
//! threshold (`tests/packets.rs`, and `geometry::packet_query`'s own test of every
//! threshold).
//!
//! Packets are `f32` lanes, so only `f32` scenes have them: the functions here take `f32`
//! types, and generic renderers reach them through the proof [`crate::Float::AS_F32`].
//! `f64` scenes trace single rays. Off x86-64 there are no packets.

use crate::camera::{Camera, Grid, Window};
use crate::effects::{has, REFLECTION, REFRACTION, SHADOWS};
use crate::ray::{Hit, Ray};
use crate::settings::TraceLimits;
use crate::shade::{shade_local, trace_fx, Secondary, Surface, CACHE_LIGHTS};
use crate::stats::RayCounts;
use crate::world::Scene;
use std::cell::Cell;
use vecexpr::simd::Isa;
use vecexpr::Vec3;

pub use crate::geometry::MAX_LANES;
pub use crate::settings::Packets;

/// The pixel block of one packet: `(width, height)`, `width * height` = lanes.
pub fn block_shape(isa: Isa) -> (usize, usize) {
    match isa.lanes() {
        4 => (2, 2),
        8 => (4, 2),
        _ => (4, 4),
    }
}

/// One packet's hits, lane `j * width + i` for pixel `(i, j)` of the block.
type Block = [Option<Hit<f32>>; MAX_LANES];

/// The closest hit of the eye ray of every point of a grid, stored by packet.
struct EyeHits {
    blocks: Vec<Block>,
    bw: usize,
    bh: usize,
    nbx: usize,
}

impl EyeHits {
    /// The hit of the eye ray of grid point `(x, y)`.
    #[inline]
    fn get(&self, x: usize, y: usize) -> Option<&Hit<f32>> {
        let b = &self.blocks[(y / self.bh) * self.nbx + x / self.bw];
        b[(y % self.bh) * self.bw + x % self.bw].as_ref()
    }
}

/// The eye rays of block `(bx, by)` of a `w` x `h` grid (`None` outside the grid) into
/// the first `bw * bh` lanes of `rays` (the others are left as they are).
#[inline]
fn block_rays(
    cam: &Camera<f32>,
    grid: Grid,
    (bw, bh): (usize, usize),
    win: Window,
    (bx, by): (usize, usize),
    rays: &mut [Option<Ray<f32>>; MAX_LANES],
) {
    let (w, h) = win.size;
    // The image-plane points, and which lanes lie on the grid.
    let (mut px, mut py, mut on) = ([0.0f32; MAX_LANES], [0.0f32; MAX_LANES], 0u32);
    for j in 0..bh {
        for i in 0..bw {
            let (x, y) = (bx * bw + i, by * bh + j);
            if x < w && y < h {
                let k = j * bw + i;
                (px[k], py[k]) = win.point::<f32>(grid, x, y);
                on |= 1 << k;
            }
        }
    }
    #[cfg(target_arch = "x86_64")]
    {
        // Four rays at a time ([`Camera::rays4`]; every block shape has a multiple of
        // four lanes); lanes off the grid are computed for the point (0, 0) and dropped.
        debug_assert!((bw * bh).is_multiple_of(4));
        for k in (0..bw * bh).step_by(4) {
            let four = |v: &[f32; MAX_LANES]| [v[k], v[k + 1], v[k + 2], v[k + 3]];
            for (l, r) in cam.rays4(&four(&px), &four(&py)).into_iter().enumerate() {
                rays[k + l] = (on & (1 << (k + l)) != 0).then_some(r);
            }
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    for k in 0..bw * bh {
        rays[k] = (on & (1 << k) != 0).then(|| cam.ray(px[k], py[k]));
    }
}

/// The eye rays of block `(bx, by)` of a `w` x `h` grid (`None` outside it), lane
/// `j * width + i` for pixel `(i, j)` of the block, and their closest hits, traced as one
/// packet of `isa`, written into the first [`Isa::lanes`] lanes of `rays` and `hits`
/// where the caller keeps them (the lanes beyond stay as they are, `None` in the
/// callers' buffers). Returned by value, the two arrays (1.4 KB, most of it hit
/// records) were zeroed and copied for every block.
///
/// # Panics
/// If the CPU lacks `isa`.
#[inline]
#[allow(clippy::too_many_arguments)] // the block's place and its two output buffers
pub(crate) fn eye_block(
    scene: &Scene<f32>,
    cam: &Camera<f32>,
    isa: Isa,
    grid: Grid,
    win: Window,
    block: (usize, usize),
    rays: &mut [Option<Ray<f32>>; MAX_LANES],
    hits: &mut Block,
) {
    block_rays(cam, grid, block_shape(isa), win, block, rays);
    scene.geometry.intersect_packet_into(isa, rays, hits);
}

/// Shades the hits of a packet: lane `k` holds ray `rays[k]` and its closest hit
/// `hits[k]`, at ray depth `depth[k]` with accumulated weight `weight[k]`; `each(k,
/// color, spawned, counts)` receives, lane by lane in order, the local colour of each
/// hit and the secondary rays it spawns, as [`shade_local`] computes them.
///
/// With `packets`, the lanes are shaded by [`shade_local`]'s steps ([`Surface`]) one
/// light at a time: each lane's shadow ray toward the light
/// ([`Surface::light_ray`]) joins one any-hit packet of `isa`, and each lane the packet
/// leaves unblocked adds the light's terms ([`Surface::add_light`]). Each lane still
/// adds the ambient term, then the lights in order, then spawns its rays, so its
/// values are [`shade_local`]'s bit for bit. Without `packets` (or without shadows),
/// each lane is shaded by [`shade_local`] itself, its shadow rays traced singly with
/// the shadow cache.
///
/// # Panics
/// If the CPU lacks `isa`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn shade_packet<const FX: u32>(
    scene: &Scene<f32>,
    isa: Isa,
    limits: &TraceLimits<f32>,
    packets: bool,
    (rays, hits): (&[Option<Ray<f32>>; MAX_LANES], &Block),
    (depth, weight): (&[u32; MAX_LANES], &[f32; MAX_LANES]),
    counts: &mut RayCounts,
    mut each: impl FnMut(usize, Vec3<f32>, [Option<Secondary<f32>>; 2], &mut RayCounts),
) {
    if !(packets && has(FX, SHADOWS)) {
        for (k, (ray, hit)) in rays.iter().zip(hits).enumerate() {
            if let (Some(ray), Some(hit)) = (ray, hit) {
                let (color, spawned) =
                    shade_local::<f32, FX>(scene, ray, hit, depth[k], weight[k], limits, counts);
                each(k, color, spawned, counts);
            }
        }
        return;
    }
    // The surface of each lane's hit and its colour so far, filled in place
    // (`core::array::from_fn` was compiled out of line here and copied the array out).
    let mut lanes: [Option<(Surface<'_, f32>, Vec3<f32>)>; MAX_LANES] = [const { None }; MAX_LANES];
    for ((lane, ray), hit) in lanes.iter_mut().zip(rays).zip(hits) {
        if let (Some(ray), Some(hit)) = (ray, hit) {
            let s = Surface::new(scene, ray, hit);
            let color = s.ambient();
            *lane = Some((s, color));
        }
    }
    let ar = &limits.arith;
    for (li, light) in scene.lights.iter().enumerate() {
        let mut packet = [None; MAX_LANES];
        let mut dirs = [Vec3::zero(); MAX_LANES];
        let mut any = false;
        for (k, (lane, hit)) in lanes.iter().zip(hits).enumerate() {
            if let (Some((s, _)), Some(hit)) = (lane, hit) {
                if let Some((shadow, l)) = s.light_ray(light, hit, ar) {
                    counts.shadow += 1;
                    packet[k] = Some(shadow);
                    dirs[k] = l;
                    any = true;
                }
            }
        }
        if !any {
            continue;
        }
        // Lights beyond the cache's start from no entry and keep none.
        let was = SHADOW_HINTS.with(|h| h.get(li).map(Cell::get));
        let mut hint = was.unwrap_or(crate::geometry::NO_HINT);
        let blocked = scene.geometry.occluded_packet_hint(isa, &packet, &mut hint);
        if was.is_some_and(|was| was != hint) {
            SHADOW_HINTS.with(|h| h[li].set(hint));
        }
        for (k, lane) in lanes.iter_mut().enumerate() {
            if let (Some(_), false, Some((s, color))) = (&packet[k], blocked[k], lane) {
                s.add_light::<FX>(color, light, &dirs[k], ar);
            }
        }
    }
    for (k, lane) in lanes.iter().enumerate() {
        if let (Some((s, color)), Some(ray), Some(hit)) = (lane, &rays[k], &hits[k]) {
            let spawned = s.spawn::<FX>(ray, hit, depth[k], weight[k], limits, counts);
            each(k, *color, spawned, counts);
        }
    }
}

/// One ray of the ray trees of a tile ([`radiance_tile`]).
struct Node {
    depth: u32,
    /// The local colour of its hit, then, once its own secondary rays are added, its
    /// radiance.
    color: Vec3<f32>,
    /// The ray, its weight and how its radiance joins the colour of the hit that
    /// spawned it; `None` for an eye ray (weight 1, its ray in the tile's eye packets).
    join: Option<Secondary<f32>>,
    /// The nodes of the secondary rays its hit spawned, in the order it spawned them.
    children: core::ops::Range<usize>,
    /// Was its radiance traced at once, by the single-ray recursion, when the tile had
    /// [`NODE_LIMIT`] nodes already?
    traced: bool,
}

/// The most nodes a tile of [`radiance_tile`] holds; the ray trees beyond are traced by
/// the single-ray recursion, depth first. (A tile holds all of its ray trees at once,
/// and with deep refraction they grow without bound: mount-s6 at `--depth 40` spawns
/// 57,000 rays per pixel.)
const NODE_LIMIT: usize = 4096;

/// Blocks of eye rays per tile of [`radiance_tile`]: [`TILE_SHAPE`] blocks across and
/// down.
pub(crate) const TILE: usize = TILE_SHAPE.0 * TILE_SHAPE.1;
/// See [`TILE`]. Four by four blocks (16x8 pixels with AVX2) gather more secondary rays
/// of one octant into a packet than two by two did: the viewer's balls-s4 frames took
/// 0.96 of the time (`tracer/RESULTS.md`, "Viewer frame rate"); eight by four and four
/// by eight measured the same as four by four.
pub(crate) const TILE_SHAPE: (usize, usize) = (4, 4);

/// Block `b` of tile `tile`: `(TILE_SHAPE.0 * tile.0 + i, TILE_SHAPE.1 * tile.1 + j)`
/// for `b = j * TILE_SHAPE.0 + i`.
#[inline]
fn tile_block(tile: (usize, usize), b: usize) -> (usize, usize) {
    (
        TILE_SHAPE.0 * tile.0 + b % TILE_SHAPE.0,
        TILE_SHAPE.1 * tile.1 + b / TILE_SHAPE.0,
    )
}

/// The radiance of each eye ray, `[block][lane]`, of tile `tile` of window `win`, block
/// `b` being [`tile_block`]`(tile, b)` (see [`eye_block`]; lanes without a ray stay
/// zero).
///
/// Every ray of the tile's ray trees is traced in packets of `isa`, generation by
/// generation: the eye rays block by block, with the shadow rays of their hits as one
/// any-hit packet per light ([`shade_packet`]); then the reflection and refraction rays
/// the hits spawn, gathered over the whole tile in the order of their parents into full
/// packets, and so on down the generations. (The shadow rays of secondary hits stay
/// single, where the shadow cache of [`crate::shade`] serves them: as packets they took
/// 1.14 times the instructions of balls-s4's frame.) Each hit is shaded by the steps
/// of the single-ray code ([`shade_local`]), and once the deepest generation is done
/// each ray's
/// radiance is added to its parent's colour, children before parents and the children
/// of one hit in the order it spawned them, which is the order in which the recursive
/// single-ray shading adds them. So the values and the ray counts are those of
/// [`crate::shade::trace_fx`], bit for bit.
///
/// # Panics
/// If the CPU lacks `isa`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn radiance_tile<const FX: u32>(
    scene: &Scene<f32>,
    cam: &Camera<f32>,
    isa: Isa,
    grid: Grid,
    win: Window,
    tile: (usize, usize),
    limits: &TraceLimits<f32>,
    counts: &mut RayCounts,
) -> [[Vec3<f32>; MAX_LANES]; TILE] {
    let mut out = [[Vec3::zero(); MAX_LANES]; TILE];
    if !has(FX, REFLECTION | REFRACTION) {
        // Eye rays only: each hit shaded as its packet is done.
        let (mut rays, mut hits) = ([None; MAX_LANES], [None; MAX_LANES]);
        for (b, out) in out.iter_mut().enumerate() {
            let block = tile_block(tile, b);
            eye_block(scene, cam, isa, grid, win, block, &mut rays, &mut hits);
            for (o, ray) in out.iter_mut().zip(&rays) {
                if ray.is_some() {
                    counts.eye += 1;
                    *o = scene.background;
                }
            }
            let at = (&[1; MAX_LANES], &[1.0; MAX_LANES]);
            shade_packet::<FX>(
                scene,
                isa,
                limits,
                true,
                (&rays, &hits),
                at,
                counts,
                |k, color, _, _| out[k] = color,
            );
        }
        return out;
    }
    let mut nodes = NODES.take();
    nodes.clear();
    let mut eye = [[usize::MAX; MAX_LANES]; TILE];
    let mut packets = [([None; MAX_LANES], [None; MAX_LANES]); TILE];
    for (b, (index, packet)) in eye.iter_mut().zip(&mut packets).enumerate() {
        let (rays, hits) = packet;
        eye_block(scene, cam, isa, grid, win, tile_block(tile, b), rays, hits);
        for (e, ray) in index.iter_mut().zip(rays.iter()) {
            if ray.is_some() {
                counts.eye += 1;
                *e = nodes.len();
                nodes.push(Node {
                    depth: 1,
                    color: scene.background,
                    join: None,
                    children: 0..0,
                    traced: false,
                });
            }
        }
    }
    // The first node of the generation after the eye rays'.
    let mut start = nodes.len();
    for (index, (rays, hits)) in eye.iter().zip(&packets) {
        shade_generation::<FX, false>(
            scene, isa, limits, true, rays, hits, index, &mut nodes, counts,
        );
    }
    let mut order = ORDER.take();
    while start < nodes.len() {
        let end = nodes.len();
        by_octant(&nodes[start..end], start, &mut order);
        for chunk in order.chunks(isa.lanes()) {
            let mut rays = [None; MAX_LANES];
            let mut index = [usize::MAX; MAX_LANES];
            for (k, &i) in chunk.iter().enumerate() {
                rays[k] = nodes[i].join.map(|s| s.ray);
                index[k] = i;
            }
            let mut hits = [None; MAX_LANES];
            scene.geometry.intersect_packet_into(isa, &rays, &mut hits);
            // Room for every ray the packet's hits may spawn, or else they are traced at
            // once by the single-ray recursion.
            if nodes.len() + 2 * MAX_LANES <= NODE_LIMIT {
                shade_generation::<FX, false>(
                    scene, isa, limits, false, &rays, &hits, &index, &mut nodes, counts,
                );
            } else {
                shade_generation::<FX, true>(
                    scene, isa, limits, false, &rays, &hits, &index, &mut nodes, counts,
                );
            }
        }
        start = end;
    }
    ORDER.set(order);
    // Children come after their parents, so backwards every child's radiance is
    // complete before it is added to its parent's colour.
    let ar = &limits.arith;
    for i in (0..nodes.len()).rev() {
        for c in nodes[i].children.clone() {
            let (color, join) = (nodes[c].color, nodes[c].join);
            if let Some(s) = join {
                s.add_to(&mut nodes[i].color, &color, ar);
            }
        }
    }
    for (o, index) in out.iter_mut().zip(&eye) {
        for (o, &e) in o.iter_mut().zip(index) {
            if e != usize::MAX {
                *o = nodes[e].color;
            }
        }
    }
    NODES.set(nodes);
    out
}

thread_local! {
    /// The last occluder of a shadow packet toward each light on this thread, tested
    /// against the next packet's rays before its walk (the packet form of the shadow
    /// cache of [`crate::shade`]). Like that cache it only decides how soon occluders
    /// are found, never whether they are, so images do not depend on it.
    static SHADOW_HINTS: [Cell<u32>; CACHE_LIGHTS] =
        const { [const { Cell::new(crate::geometry::NO_HINT) }; CACHE_LIGHTS] };
    /// The nodes of [`radiance_tile`], kept from tile to tile on each thread.
    static NODES: Cell<Vec<Node>> = const { Cell::new(Vec::new()) };
    /// The order of a generation's nodes in its packets ([`by_octant`]).
    static ORDER: Cell<Vec<usize>> = const { Cell::new(Vec::new()) };
}

/// Into `order`, the indices `first..first + nodes.len()` of the nodes of `nodes` still
/// to trace, sorted (stably) by the octant of their rays' directions: a packet walks the
/// tree once per octant among its rays ([`crate::bvh::Bvh::traverse4_packet`]), so rays
/// of one octant fill the packets of a generation together.
fn by_octant(nodes: &[Node], first: usize, order: &mut Vec<usize>) {
    // Octants 0 to 7, and 8 for a node already traced.
    let key = |n: &Node| match &n.join {
        Some(s) if !n.traced => {
            let d = &s.ray.dir;
            usize::from(d[0] < 0.0) | usize::from(d[1] < 0.0) << 1 | usize::from(d[2] < 0.0) << 2
        }
        _ => 8,
    };
    let mut starts = [0usize; 10];
    for n in nodes {
        starts[key(n) + 1] += 1;
    }
    for o in 1..10 {
        starts[o] += starts[o - 1];
    }
    let to_trace = starts[8];
    order.clear();
    order.resize(nodes.len(), 0);
    for (i, n) in nodes.iter().enumerate() {
        let o = key(n);
        order[starts[o]] = first + i;
        starts[o] += 1;
    }
    order.truncate(to_trace);
}

/// Shades the hits of one packet of a generation of [`radiance_tile`]: lane `k` holds
/// ray `rays[k]` of node `index[k]` and its closest hit `hits[k]`; the node's colour
/// becomes the local colour of its hit, or the background, and the secondary rays the
/// hit spawns are appended to `nodes`: to be traced with the next generation, or with
/// `BEYOND` (no room left under [`NODE_LIMIT`]) traced at once by the single-ray
/// recursion, their radiance in the node. With `shadows` (the eye rays' generation)
/// the hits' shadow rays go in packets ([`shade_packet`]); the later generations trace
/// theirs singly, with the shadow cache, which measured faster on balls-s4.
#[allow(clippy::too_many_arguments)]
#[inline]
fn shade_generation<const FX: u32, const BEYOND: bool>(
    scene: &Scene<f32>,
    isa: Isa,
    limits: &TraceLimits<f32>,
    shadows: bool,
    rays: &[Option<Ray<f32>>; MAX_LANES],
    hits: &Block,
    index: &[usize; MAX_LANES],
    nodes: &mut Vec<Node>,
    counts: &mut RayCounts,
) {
    let mut depth = [0; MAX_LANES];
    let mut weight = [0.0; MAX_LANES];
    for (k, &i) in index.iter().enumerate() {
        if let Some(n) = nodes.get(i) {
            depth[k] = n.depth;
            weight[k] = n.join.map_or(1.0, |s| s.weight);
        }
    }
    let at = (&depth, &weight);
    let each = |k: usize, color, spawned: [Option<Secondary<f32>>; 2], counts: &mut _| {
        let (i, depth) = (index[k], depth[k]);
        nodes[i].color = color;
        let first = nodes.len();
        for s in spawned.into_iter().flatten() {
            let color = if BEYOND {
                trace_fx::<f32, FX>(scene, &s.ray, depth + 1, s.weight, limits, counts)
            } else {
                scene.background
            };
            nodes.push(Node {
                depth: depth + 1,
                color,
                join: Some(s),
                children: 0..0,
                traced: BEYOND,
            });
        }
        nodes[i].children = first..nodes.len();
    };
    shade_packet::<FX>(scene, isa, limits, shadows, (rays, hits), at, counts, each);
}

/// The eye rays through the pixel centres of an image, gathered into packets once, and
/// their closest hits, for measuring packet tracing (`tracer bench`) and comparing it
/// with single rays.
pub struct EyePackets {
    isa: Isa,
    rays: Vec<[Option<Ray<f32>>; MAX_LANES]>,
    hits: EyeHits,
}

impl EyePackets {
    /// The packets of `isa` for the image of `cam` (no hits yet).
    ///
    /// # Panics
    /// If the CPU lacks `isa` (checked when casting).
    pub fn new(cam: &Camera<f32>, isa: Isa) -> Self {
        let (w, h) = (cam.width as usize, cam.height as usize);
        let (bw, bh) = block_shape(isa);
        let (nbx, nby) = (w.div_ceil(bw), h.div_ceil(bh));
        let rays = (0..nbx * nby)
            .map(|k| {
                let mut rays = [None; MAX_LANES];
                let block = (k % nbx, k / nbx);
                let win = Window::full((w, h));
                block_rays(cam, Grid::Centers, (bw, bh), win, block, &mut rays);
                rays
            })
            .collect();
        Self {
            isa,
            rays,
            hits: EyeHits {
                blocks: vec![[None; MAX_LANES]; nbx * nby],
                bw,
                bh,
                nbx,
            },
        }
    }

    /// Number of rays (pixels).
    pub fn len(&self) -> usize {
        self.rays.iter().flatten().flatten().count()
    }

    /// Are there no rays?
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Traces every packet against `scene` on the current rayon pool.
    pub fn cast(&mut self, scene: &Scene<f32>) {
        let (isa, rays, geometry) = (self.isa, &self.rays, &scene.geometry);
        crate::schedule::for_each_mut(&mut self.hits.blocks, 16, |k, b| {
            geometry.intersect_packet_into(isa, &rays[k], b);
        });
    }

    /// The hit of the eye ray of pixel `(x, y)` from the last [`EyePackets::cast`].
    pub fn get(&self, x: usize, y: usize) -> Option<&Hit<f32>> {
        self.hits.get(x, y)
    }
}
