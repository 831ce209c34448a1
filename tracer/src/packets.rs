//! Eye rays traced in SIMD packets, one packet per block of pixels, and the shadow rays
//! of their hits traced as packets too.
//!
//! # The walk of a packet
//! With packets on, the renderer ([`crate::render`](mod@crate::render)) works through
//! the image a block of pixels at a time ([`block_shape`]: 2x2 for SSE2's four lanes,
//! 4x2 for AVX2's eight, 4x4 for AVX-512's sixteen):
//! 1. `eye_block` makes the block's eye rays ([`crate::camera::Camera::ray`] through
//!    [`Grid::point`]) and traces them as one packet
//!    ([`crate::geometry::Geometry::intersect_packet`], run by the kernel compiled for the chosen
//!    instruction set through [`vecexpr::simd::Isa::dispatch`]). The packet walks the
//!    four-wide BVH together ([`crate::bvh::packet_traverse`]); in a leaf, spheres and
//!    triangles are tested against all its rays at once by the lane kernels that sit
//!    beside the single-ray ones ([`crate::geometry::sphere`],
//!    [`crate::geometry::triangle`]).
//! 2. **Hand-over.** Where at most two rays of a packet (four of sixteen) reach a
//!    subtree, the packet hands them over: each continues alone with the single-ray
//!    traversal of that subtree, keeping its closest hit so far. Rays and primitives the
//!    lane kernels do not cover (cones, planes, rays whose triangle shear axes differ,
//!    edge functions exactly zero) are likewise tested by the single-ray kernels, lane
//!    by lane ([`crate::geometry::packet_query`]).
//! 3. `shadow_block` builds the shadow rays of the block's hits toward one light at a
//!    time exactly as shading builds them (`shade::shadow_ray`) and traces
//!    them as one any-hit packet; a ray leaves the packet at its first blocker.
//! 4. Each pixel is then shaded by the single-ray code from its hit and its shadow bits
//!    (`shade::shade_eye_lit`); reflection and refraction rays stay single.
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
//! `f64` scenes and supersampling trace single rays. Off x86-64 there are no packets.

use crate::camera::{Camera, Grid, Window};
use crate::geometry::kinds;
use crate::ray::{Hit, Ray};
use crate::settings::TraceLimits;
use crate::shade::{shadow_ray, shadow_start};
use crate::world::Scene;
use vecexpr::simd::Isa;

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

/// The eye rays of block `(bx, by)` of a `w` x `h` grid (`None` outside the grid).
#[inline]
fn block_rays(
    cam: &Camera<f32>,
    grid: Grid,
    (bw, bh): (usize, usize),
    win: Window,
    (bx, by): (usize, usize),
) -> [Option<Ray<f32>>; MAX_LANES] {
    let mut rays = [None; MAX_LANES];
    let (w, h) = win.size;
    for j in 0..bh {
        for i in 0..bw {
            let (x, y) = (bx * bw + i, by * bh + j);
            if x < w && y < h {
                let (px, py) = win.point::<f32>(grid, x, y);
                rays[j * bw + i] = Some(cam.ray(px, py));
            }
        }
    }
    rays
}

/// The eye rays of block `(bx, by)` of a `w` x `h` grid (`None` outside it), lane
/// `j * width + i` for pixel `(i, j)` of the block, and their closest hits, traced as one
/// packet of `isa`.
///
/// # Panics
/// If the CPU lacks `isa`.
#[inline]
pub(crate) fn eye_block(
    scene: &Scene<f32>,
    cam: &Camera<f32>,
    isa: Isa,
    grid: Grid,
    win: Window,
    block: (usize, usize),
) -> ([Option<Ray<f32>>; MAX_LANES], Block) {
    let rays = block_rays(cam, grid, block_shape(isa), win, block);
    let mut hits = [None; MAX_LANES];
    scene.geometry.intersect_packet_into(isa, &rays, &mut hits);
    (rays, hits)
}

/// Are the shadow rays of eye hits traced in packets ([`shadow_block`]) for `scene`?
/// When it has no cones: the packet kernels test spheres and triangles, while each ray
/// of a packet meets a cone alone, by its single-ray test and without the shadow cache
/// of single rays, which measured slower on rings-s7 (4,200 cylinders; see
/// `tracer/RESULTS.md`, "Packets on triangle scenes and shadow packets").
pub(crate) fn shadow_packets(scene: &Scene<f32>) -> bool {
    scene.geometry.kinds() & kinds::CONES == 0
}

/// Lights whose shadow rays of eye hits are traced in packets ([`shadow_block`]); the
/// shadow rays toward further lights stay single.
pub(crate) const PACKET_LIGHTS: usize = 64;

/// For each lane of a block of eye rays and their hits (as [`eye_block`] returns them),
/// the lights whose shadow ray from the hit is blocked, bit `li` for light `li` (the
/// first [`PACKET_LIGHTS`] lights): the shadow rays of the block toward one light, as
/// shading builds them ([`crate::shade::shadow_ray`]), are traced as one any-hit packet
/// of `isa`. Bits of lights a lane casts no shadow ray to are clear.
///
/// # Panics
/// If the CPU lacks `isa`.
pub(crate) fn shadow_block(
    scene: &Scene<f32>,
    isa: Isa,
    limits: &TraceLimits<f32>,
    rays: &[Option<Ray<f32>>; MAX_LANES],
    hits: &Block,
) -> [u64; MAX_LANES] {
    let mut blocked = [0u64; MAX_LANES];
    let lights = scene.lights.len().min(PACKET_LIGHTS);
    if lights == 0 {
        return blocked;
    }
    let starts: [Option<_>; MAX_LANES] = core::array::from_fn(|l| match (&rays[l], &hits[l]) {
        (Some(ray), Some(hit)) => Some((hit, shadow_start(ray, hit))),
        _ => None,
    });
    for (li, light) in scene.lights.iter().enumerate().take(lights) {
        let mut packet = [None; MAX_LANES];
        let mut any = false;
        for (p, s) in packet.iter_mut().zip(&starts) {
            if let Some((hit, start)) = s {
                if let Some(r) = shadow_ray(light, hit, start, limits) {
                    *p = Some(r);
                    any = true;
                }
            }
        }
        if !any {
            continue;
        }
        let b = scene.geometry.occluded_packet(isa, &packet);
        for (m, &b) in blocked.iter_mut().zip(&b) {
            *m |= u64::from(b) << li;
        }
    }
    blocked
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
                block_rays(
                    cam,
                    Grid::Centers,
                    (bw, bh),
                    Window::full((w, h)),
                    (k % nbx, k / nbx),
                )
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
