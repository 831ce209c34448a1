//! Eye rays traced in SIMD packets, one packet per block of pixels.
//!
//! With packets on, the renderer works through the image a block of `W` pixels at a time
//! ([`block_shape`]: 2x2 for SSE2's four lanes, 4x2 for AVX2's eight, 4x4 for AVX-512's
//! sixteen): the block's eye rays are traced as one packet through the BVH
//! ([`crate::geometry::Geometry::intersect_packet`]) by the kernel compiled for the
//! chosen instruction set ([`vecexpr::simd::Isa::dispatch`]), then each pixel is shaded
//! from its hit by the single-ray shading code; secondary rays stay single. Hits are
//! bit-identical to the single-ray ones, so the image is the same with packets on or
//! off and for every instruction set.
//!
//! Packets serve the `f32` renderers of one ray per pixel (and the SPD corner rays);
//! `f64` scenes and supersampling trace single rays. Off x86-64 there are no packets.

use crate::camera::Camera;
use crate::geometry::Geometry;
use crate::ray::{Hit, Ray};
use crate::render::Settings;
use crate::world::Scene;
use core::any::{Any, TypeId};
use vecexpr::simd::{Isa, Kernel, SimdF32};
use vecexpr::Real;

/// How eye rays are traced.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Packets {
    /// One ray at a time.
    Off,
    /// In packets of the instruction set's width.
    On(Isa),
}

impl Default for Packets {
    /// [`Packets::auto`].
    fn default() -> Self {
        Self::auto()
    }
}

impl Packets {
    /// Packets of the widest instruction set of the running CPU when that is AVX2 or
    /// AVX-512; off on a CPU with SSE2 only (where packets of four rays execute 0.84 to
    /// 1.10 times the instructions of single rays, so no clear gain) and off x86-64.
    pub fn auto() -> Self {
        match Isa::detect() {
            Some(isa) if isa >= Isa::Avx2 => Self::On(isa),
            _ => Self::Off,
        }
    }

    /// The instruction set, when on.
    pub fn isa(self) -> Option<Isa> {
        match self {
            Self::Off => None,
            Self::On(isa) => Some(isa),
        }
    }

    /// `off` or the instruction set's name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Off => "off",
            Self::On(isa) => isa.name(),
        }
    }

    /// From the command line's `--packets auto|on|off` and `--isa auto|sse2|avx2|avx512`:
    /// `auto` packets are [`Packets::auto`] unless an instruction set is named.
    ///
    /// # Errors
    /// A message naming the instruction sets available when the CPU lacks the one asked
    /// for, or when the words are not among those above.
    pub fn from_args(packets: &str, isa_name: &str) -> Result<Self, String> {
        let isa = match isa_name {
            "auto" => Isa::detect(),
            name => {
                let Some(isa) = Isa::from_name(name) else {
                    return Err(format!("--isa {name}: expected auto, sse2, avx2 or avx512"));
                };
                if !isa.is_available() {
                    let have: Vec<&str> = Isa::available().iter().map(|i| i.name()).collect();
                    return Err(format!(
                        "--isa {name}: this CPU does not support {name} (available: {})",
                        if have.is_empty() {
                            "none".to_string()
                        } else {
                            have.join(", ")
                        }
                    ));
                }
                Some(isa)
            }
        };
        match (packets, isa) {
            ("off", _) => Ok(Self::Off),
            ("auto", Some(named)) if isa_name != "auto" => Ok(Self::On(named)),
            ("auto", _) => Ok(Self::auto()),
            ("on", Some(isa)) => Ok(Self::On(isa)),
            ("on", None) => Err("--packets on: no SIMD instruction set on this CPU".into()),
            (other, _) => Err(format!("--packets {other}: expected auto, on or off")),
        }
    }
}

/// The pixel block of one packet: `(width, height)`, `width * height` = lanes.
pub fn block_shape(isa: Isa) -> (usize, usize) {
    match isa.lanes() {
        4 => (2, 2),
        8 => (4, 2),
        _ => (4, 4),
    }
}

/// Lanes of the widest packet (AVX-512's sixteen).
pub const MAX_LANES: usize = crate::geometry::packet::MAX_LANES;

/// One packet's hits, lane `j * width + i` for pixel `(i, j)` of the block.
type Block<T> = [Option<Hit<T>>; MAX_LANES];

/// Where the eye ray of grid point `(x, y)` crosses the image plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum EyeGrid {
    /// The pixel centre `(x + 1/2, y + 1/2)`.
    Centers,
    /// The pixel corner `(x, y)` (SPD mode).
    Corners,
}

impl EyeGrid {
    /// The image-plane point, computed exactly as the single-ray renderer does.
    #[inline]
    pub(crate) fn point<T: Real>(self, x: usize, y: usize) -> (T, T) {
        match self {
            Self::Centers => {
                let half = T::from_f64(0.5);
                (T::from_f64(x as f64) + half, T::from_f64(y as f64) + half)
            }
            Self::Corners => (T::from_f64(x as f64), T::from_f64(y as f64)),
        }
    }
}

/// The closest hit of the eye ray of every point of a grid, stored by packet.
pub(crate) struct EyeHits<T: Real> {
    blocks: Vec<Block<T>>,
    bw: usize,
    bh: usize,
    nbx: usize,
}

impl<T: Real> EyeHits<T> {
    /// The hit of the eye ray of grid point `(x, y)`.
    #[inline]
    pub(crate) fn get(&self, x: usize, y: usize) -> Option<&Hit<T>> {
        let b = &self.blocks[(y / self.bh) * self.nbx + x / self.bw];
        b[(y % self.bh) * self.bw + x % self.bw].as_ref()
    }
}

/// Runs [`Geometry::intersect_packet`] on one packet.
struct EyeKernel<'a> {
    geometry: &'a Geometry<f32>,
    rays: &'a [Option<Ray<f32>>; MAX_LANES],
    out: &'a mut Block<f32>,
}

impl Kernel for EyeKernel<'_> {
    type Output = ();
    #[inline(always)]
    fn run<S: SimdF32>(self) {
        self.geometry.intersect_packet::<S>(self.rays, self.out);
    }
}

/// The eye rays of block `(bx, by)` of a `w` x `h` grid (`None` outside the grid).
#[inline]
fn block_rays(
    cam: &Camera<f32>,
    grid: EyeGrid,
    (bw, bh): (usize, usize),
    (w, h): (usize, usize),
    (bx, by): (usize, usize),
) -> [Option<Ray<f32>>; MAX_LANES] {
    let mut rays = [None; MAX_LANES];
    for j in 0..bh {
        for i in 0..bw {
            let (x, y) = (bx * bw + i, by * bh + j);
            if x < w && y < h {
                let (px, py) = grid.point::<f32>(x, y);
                rays[j * bw + i] = Some(Ray::new(cam.position, cam.direction(px, py)));
            }
        }
    }
    rays
}

/// Traces one packet of eye rays with `isa` into `out`: the hits of [`block_rays`].
/// (An out-parameter: the kilobyte of hit records is written once, where it is kept.)
#[inline]
fn trace_block(
    geometry: &Geometry<f32>,
    isa: Isa,
    rays: &[Option<Ray<f32>>; MAX_LANES],
    out: &mut Block<f32>,
) {
    dispatch(
        isa,
        EyeKernel {
            geometry,
            rays,
            out,
        },
    );
}

/// Runs [`Geometry::occluded_packet`] on one packet.
struct ShadowKernel<'a> {
    geometry: &'a Geometry<f32>,
    rays: &'a [Option<Ray<f32>>; MAX_LANES],
    out: &'a mut [bool; MAX_LANES],
}

impl Kernel for ShadowKernel<'_> {
    type Output = ();
    #[inline(always)]
    fn run<S: SimdF32>(self) {
        self.geometry.occluded_packet::<S>(self.rays, self.out);
    }
}

/// Is each ray of one packet blocked, traced with `isa`.
#[inline]
fn shadow_packet(
    geometry: &Geometry<f32>,
    isa: Isa,
    rays: &[Option<Ray<f32>>; MAX_LANES],
) -> [bool; MAX_LANES] {
    let mut out = [false; MAX_LANES];
    dispatch(
        isa,
        ShadowKernel {
            geometry,
            rays,
            out: &mut out,
        },
    );
    out
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

/// The instruction set of the packets `settings` asks for, when the renderer's precision
/// `T` is `f32` (packets are `f32` lanes); `None`: trace single rays.
pub(crate) fn packet_isa<T: Real>(settings: &Settings) -> Option<Isa> {
    if TypeId::of::<T>() == TypeId::of::<f32>() {
        settings.packets.isa()
    } else {
        None
    }
}

/// `a` as the type `B` when `A` and `B` are the same type.
fn same_type<A: 'static, B: 'static>(a: A) -> Option<B> {
    let mut a = Some(a);
    (&mut a as &mut dyn Any)
        .downcast_mut::<Option<B>>()
        .and_then(Option::take)
}

/// The eye rays of block `(bx, by)` of a `w` x `h` grid (`None` outside it), lane
/// `j * width + i` for pixel `(i, j)` of the block, and their closest hits, traced as one
/// packet of `isa`.
///
/// # Panics
/// If `T` is not `f32` (see [`packet_isa`]) or the CPU lacks `isa`.
#[allow(clippy::type_complexity)]
pub(crate) fn eye_block<T: Real>(
    scene: &Scene<T>,
    cam: &Camera<T>,
    isa: Isa,
    grid: EyeGrid,
    size: (usize, usize),
    block: (usize, usize),
) -> ([Option<Ray<T>>; MAX_LANES], [Option<Hit<T>>; MAX_LANES]) {
    const F32: &str = "packets trace f32 scenes only";
    let scene = (scene as &dyn Any).downcast_ref::<Scene<f32>>().expect(F32);
    let cam = (cam as &dyn Any).downcast_ref::<Camera<f32>>().expect(F32);
    let rays = block_rays(cam, grid, block_shape(isa), size, block);
    let mut hits = [None; MAX_LANES];
    trace_block(&scene.geometry, isa, &rays, &mut hits);
    (same_type(rays).expect(F32), same_type(hits).expect(F32))
}

/// Are the shadow rays of eye hits traced in packets ([`shadow_block`]) for `scene`?
/// When it has no cones: the packet kernels test spheres and triangles, while each ray
/// of a packet meets a cone alone, by its single-ray test and without the shadow cache
/// of single rays, which measured slower on rings-s7 (4,200 cylinders; see
/// `tracer/RESULTS.md`, "Packets on triangle scenes and shadow packets").
pub(crate) fn shadow_packets<T: Real>(scene: &Scene<T>) -> bool {
    scene.geometry.kinds() & crate::geometry::kinds::CONES == 0
}

/// Lights whose shadow rays of eye hits are traced in packets ([`shadow_block`]); the
/// shadow rays toward further lights stay single.
pub(crate) const PACKET_LIGHTS: usize = 64;

/// For each lane of a block of eye rays and their hits (as [`eye_block`] returns them),
/// the lights whose shadow ray from the hit is blocked, bit `li` for light `li` (the
/// first [`PACKET_LIGHTS`] lights): the shadow rays of the block toward one light, as
/// shading builds them ([`crate::shade::shadow_rays`]), are traced as one any-hit packet
/// of `isa`. Bits of lights a lane casts no shadow ray to are clear.
///
/// # Panics
/// If `T` is not `f32` (see [`packet_isa`]) or the CPU lacks `isa`.
pub(crate) fn shadow_block<T: Real>(
    scene: &Scene<T>,
    isa: Isa,
    limits: &crate::shade::TraceLimits<T>,
    rays: &[Option<Ray<T>>; MAX_LANES],
    hits: &[Option<Hit<T>>; MAX_LANES],
) -> [u64; MAX_LANES] {
    const F32: &str = "packets trace f32 scenes only";
    let mut blocked = [0u64; MAX_LANES];
    let lights = scene.lights.len().min(PACKET_LIGHTS);
    if lights == 0 {
        return blocked;
    }
    let geometry = &(scene as &dyn Any)
        .downcast_ref::<Scene<f32>>()
        .expect(F32)
        .geometry;
    let starts: [Option<_>; MAX_LANES] = core::array::from_fn(|l| match (&rays[l], &hits[l]) {
        (Some(ray), Some(hit)) => Some((hit, crate::shade::shadow_start(ray, hit))),
        _ => None,
    });
    for (li, light) in scene.lights.iter().enumerate().take(lights) {
        let mut packet = [None; MAX_LANES];
        let mut any = false;
        for (p, s) in packet.iter_mut().zip(&starts) {
            if let Some((hit, start)) = s {
                if let Some(r) = crate::shade::shadow_ray(light, hit, start, limits) {
                    let r = (&r as &dyn Any).downcast_ref::<Ray<f32>>().expect(F32);
                    *p = Some(*r);
                    any = true;
                }
            }
        }
        if !any {
            continue;
        }
        let b = shadow_packet(geometry, isa, &packet);
        for (m, &b) in blocked.iter_mut().zip(&b) {
            *m |= u64::from(b) << li;
        }
    }
    blocked
}

impl Scene<f32> {
    /// Whether each of the first [`Isa::lanes`] rays of `rays` is blocked (`None` lanes
    /// are `false`), traced together as one any-hit packet by the kernel of `isa`; the
    /// rest of the result is `false`. Lane `i` is what [`crate::geometry::Geometry::occluded`]
    /// returns for `rays[i]`. Pays off for coherent rays, such as the shadow rays of
    /// neighbouring eye hits toward one light.
    ///
    /// # Panics
    /// If the CPU lacks `isa` ([`Isa::is_available`]) or off x86-64.
    pub fn occluded_packet(
        &self,
        isa: Isa,
        rays: &[Option<Ray<f32>>; MAX_LANES],
    ) -> [bool; MAX_LANES] {
        shadow_packet(&self.geometry, isa, rays)
    }

    /// The closest hits of the first [`Isa::lanes`] rays of `rays` (`None` lanes are
    /// skipped), traced together as one packet by the kernel of `isa`; the rest of the
    /// result is `None`. Lane `i` is bit for bit what [`Scene::intersect`] returns for
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
        trace_block(&self.geometry, isa, rays, &mut hits);
        hits
    }
}

/// The eye rays through the pixel centres of an image, gathered into packets once, and
/// their closest hits, for measuring packet tracing (`tracer bench`) and comparing it
/// with single rays.
pub struct EyePackets {
    isa: Isa,
    rays: Vec<[Option<Ray<f32>>; MAX_LANES]>,
    hits: EyeHits<f32>,
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
            .map(|k| block_rays(cam, EyeGrid::Centers, (bw, bh), (w, h), (k % nbx, k / nbx)))
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
        use rayon::prelude::*;
        let isa = self.isa;
        self.hits
            .blocks
            .par_iter_mut()
            .zip(self.rays.par_iter())
            .with_min_len(16)
            .for_each(|(b, rays)| trace_block(&scene.geometry, isa, rays, b));
    }

    /// The hit of the eye ray of pixel `(x, y)` from the last [`EyePackets::cast`].
    pub fn get(&self, x: usize, y: usize) -> Option<&Hit<f32>> {
        self.hits.get(x, y)
    }
}
