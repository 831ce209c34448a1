//! The tracer's ray casting against Intel Embree 3, on the same scenes and the same rays.
//!
//! Built only with the `embree` feature (it links `libembree3`); `benches/embree/run.sh`
//! installs Debian's `libembree-dev` and runs it. For every scene, image size and thread
//! count it casts, on both sides:
//! - `eye`: the eye rays of the NFF camera through the pixel centres, closest hit
//!   (Embree `rtcIntersect1`, tracer [`tracer::Scene::cast`]);
//! - `shadow`: from every eye hit of the tracer (offset off the surface as in shading)
//!   toward the first light, any hit before the light (Embree `rtcOccluded1`, tracer
//!   [`tracer::Scene::occluded`]);
//! - `eye16`: the eye rays in packets of 4x4 pixels (Embree `rtcIntersect16`, tracer
//!   [`tracer::Scene::cast_packet_into`] with the widest instruction set, see
//!   [`tracer_packet16`]).
//!
//! Geometry: polygons and patches are cut into triangles by the tracer's own
//! triangulation and given to Embree as one triangle mesh; spheres as one
//! `RTC_GEOMETRY_TYPE_SPHERE_POINT` geometry (Embree's built-in spheres); cones and cylinders as
//! `RTC_GEOMETRY_TYPE_CONE_LINEAR_CURVE` segments, one per NFF cone, with no neighbours.
//! Embree's cone curves have flat end caps where NFF cones are open, so a ray through
//! the open end of a cone is a hit in Embree only; in the SPD scenes (the tree's
//! branches) the ends sit inside other primitives, and the agreement column shows what
//! difference remains. The alternative, user geometry with the tracer's own cone test
//! called back from Embree, would measure a callback per cone rather than Embree.
//!
//! **Embree user spheres.** For a scene with spheres a second Embree scene is built, the
//! same except that its spheres are one `RTC_GEOMETRY_TYPE_USER` geometry: Embree's BVH
//! over the boxes of a bounds callback, and in its leaves intersect and occluded
//! callbacks ([`user_sphere_intersect`], [`user_sphere_occluded`]) running a plain sphere
//! test of the bench's own (`benches/support/user_spheres.rs`, after Haines et al.,
//! *Ray Tracing Gems* chapter 7), not the tracer's. The callbacks take packets of any
//! width `N` through the documented structure-of-arrays layout, so `rtcIntersect16` runs
//! them too, at whatever width Embree's traversal hands over. These rows get a table of
//! their own beside the built-in spheres' (`--no-user-spheres` leaves them out).
//!
//! **Robust mode.** With `--robust` Embree's scenes are built with
//! `RTC_SCENE_FLAG_ROBUST`, which its documentation describes as acceleration
//! structures that allow robust traversal, without the optimisations that reduce
//! arithmetic accuracy, against rays slipping through the edges of neighbouring
//! primitives. That is the closest of Embree's modes to what the tracer always does (a
//! watertight triangle test, Woop et al. 2013, and Ize's conservative box test), though
//! not the same guarantee: Embree's issue tracker reports edge misses in robust mode too
//! (embree/embree#387). Without the option Embree runs its default kernels, which the
//! targets are measured against.
//!
//! **Tree width.** Where the CPU has AVX2 the tracer's single rays walk its eight-wide
//! tree; `--four-wide` keeps them on the four-wide one, for a comparison in one binary.
//!
//! Each measurement is repeated `--runs` times, Embree (then Embree with user spheres,
//! where measured) and the tracer interleaved round by round, and the median wall time is
//! reported as Mrays/s, with Mrays per CPU second of all threads in parentheses (steadier
//! on a shared machine); the ratio is tracer / Embree throughput. Both sides run their
//! ray-casting query and keep its result: Embree fills its `RTCHit` (distance,
//! barycentrics, unnormalised geometric normal, primitive and geometry ids), the tracer
//! its [`tracer::geometry::Intersection`] (distance, barycentrics, primitive). Neither
//! builds what shading needs next (the hit point, unit normals, an interpolated shading
//! normal, the material: the tracer's [`tracer::Scene::hit`], which the renderer calls
//! and this bench does not time). The
//! agreement is the share of rays where both report the same hit or miss. Build times
//! (from the parsed scene description, conversion included, on all cores; Embree's
//! without creating the device) are printed too: medians of `--runs` builds of each
//! side, in alternation. The environment variable
//! `EMBREE_CONFIG` is passed to `rtcNewDevice`.

mod ffi;

use benches::user_spheres::{self, HIT_FIELDS, RAY_FIELDS};
use ffi::*;
use rayon::prelude::*;
use std::ffi::c_void;
use std::path::PathBuf;
use std::time::Instant;
use tracer::geometry::{offset_ray, polygon::triangulate, AccelOptions};
use tracer::packets::MAX_LANES;
use tracer::scene::desc::{SceneDesc, Shape};
use tracer::stats::process_cpu_ms;
use tracer::{Hit, Ray, Scene};
use vecexpr::simd::Isa;
use vecexpr::Expr;

/// Rays per parallel task (tasks of packets: this many rays in packets of 16).
const CHUNK: usize = 1024;

/// How a scene's spheres are given to Embree.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Spheres {
    /// `RTC_GEOMETRY_TYPE_SPHERE_POINT`, Embree's own sphere primitive.
    BuiltIn,
    /// `RTC_GEOMETRY_TYPE_USER` with the bench's callbacks.
    User,
}

/// An Embree device and scene, released on drop.
struct Embree {
    device: RTCDevice,
    scene: RTCScene,
    /// The user geometry's spheres (centre, radius), read by its callbacks through the
    /// geometry's user pointer; dropped after the scene is released (empty with
    /// [`Spheres::BuiltIn`]).
    #[expect(dead_code, reason = "owns the buffer Embree reads through a pointer")]
    user_spheres: Vec<[f32; 4]>,
}

// SAFETY: a committed Embree scene may be queried from any number of threads at once
// (Embree API docs, rtcIntersect1: "thread-safe"); nothing mutates it after commit.
unsafe impl Sync for Embree {}

impl Drop for Embree {
    fn drop(&mut self) {
        // SAFETY: both handles were created by `Embree::build` and are released once.
        unsafe {
            rtcReleaseScene(self.scene);
            rtcReleaseDevice(self.device);
        }
    }
}

/// Writes `items` into a new geometry buffer of `geom`.
///
/// # Safety
/// `geom` is a live geometry that accepts a buffer of `format` made of `T`s.
unsafe fn fill_buffer<T: Copy>(geom: RTCGeometry, kind: i32, format: i32, items: &[T]) {
    // SAFETY: the caller guarantees `geom`; Embree returns a buffer of `items.len()`
    // elements of `size_of::<T>()` bytes (with the tail padding its 16-byte loads need,
    // which only shared buffers must provide themselves), checked for null.
    unsafe {
        let p =
            rtcSetNewGeometryBuffer(geom, kind, 0, format, std::mem::size_of::<T>(), items.len())
                as *mut T;
        assert!(!p.is_null(), "Embree could not allocate a buffer");
        std::ptr::copy_nonoverlapping(items.as_ptr(), p, items.len());
    }
}

/// The sphere `prim_id` of a user geometry whose user pointer is `user_ptr`.
///
/// # Safety
/// `user_ptr` is the first of the live spheres of [`Embree::user_spheres`], and
/// `prim_id` is below their count (Embree passes the ids `0..count` given to
/// `rtcSetGeometryUserPrimitiveCount`).
#[inline(always)]
unsafe fn user_sphere(user_ptr: *mut c_void, prim_id: u32) -> [f32; 4] {
    // SAFETY: in bounds of the live, unchanged buffer by the caller's guarantee.
    unsafe { *(user_ptr as *const [f32; 4]).add(prim_id as usize) }
}

/// The bounds callback of the user spheres.
///
/// # Safety
/// Called by Embree during the build with valid arguments for the user geometry made
/// in [`Embree::build`].
unsafe extern "C" fn user_sphere_bounds(args: *const RTCBoundsFunctionArguments) {
    // SAFETY: Embree passes a valid argument structure whose `bounds_o` is writable; the
    // user pointer (given both as user data and as the bounds payload) and the primitive
    // id satisfy `user_sphere`'s contract.
    unsafe {
        let a = &*args;
        let (lo, hi) = user_spheres::sphere_bounds(user_sphere(a.geometry_user_ptr, a.prim_id));
        *a.bounds_o = RTCBounds {
            lower_x: lo[0],
            lower_y: lo[1],
            lower_z: lo[2],
            align0: 0.0,
            upper_x: hi[0],
            upper_y: hi[1],
            upper_z: hi[2],
            align1: 0.0,
        };
    }
}

/// The intersect callback of the user spheres: the closest hits of `N` rays against one
/// sphere ([`user_spheres::intersect_lanes`]).
///
/// # Safety
/// Called by Embree during a closest-hit query with valid arguments for the user
/// geometry made in [`Embree::build`].
unsafe extern "C" fn user_sphere_intersect(args: *const RTCIntersectFunctionNArguments) {
    // SAFETY: Embree passes `N` entries in `valid`, the query's live context, and in
    // `rayhit` `N` rays and hits as a structure of arrays (`rtcore_ray.h`, `RTCRayHitN`:
    // 12 ray then 8 hit fields of `N` 32-bit words with RTC_MAX_INSTANCE_LEVEL_COUNT 1),
    // which no one else touches during the call; the user pointer and primitive id
    // satisfy `user_sphere`'s contract.
    unsafe {
        let a = &*args;
        let n = a.n as usize;
        let valid = std::slice::from_raw_parts(a.valid, n);
        let rayhit =
            std::slice::from_raw_parts_mut(a.rayhit as *mut u32, (RAY_FIELDS + HIT_FIELDS) * n);
        user_spheres::intersect_lanes(
            valid,
            user_sphere(a.geometry_user_ptr, a.prim_id),
            a.prim_id,
            a.geom_id,
            (*a.context).inst_id[0],
            rayhit,
        );
    }
}

/// The occluded callback of the user spheres: `tfar = -inf` for each of the `N` rays
/// that the sphere blocks ([`user_spheres::occluded_lanes`]).
///
/// # Safety
/// Called by Embree during an any-hit query with valid arguments for the user geometry
/// made in [`Embree::build`].
unsafe extern "C" fn user_sphere_occluded(args: *const RTCOccludedFunctionNArguments) {
    // SAFETY: Embree passes `N` entries in `valid` and in `ray` `N` rays as a structure
    // of arrays (`RTCRayN`: 12 fields of `N` 32-bit words), which no one else touches
    // during the call; the user pointer and primitive id satisfy `user_sphere`'s
    // contract.
    unsafe {
        let a = &*args;
        let n = a.n as usize;
        let valid = std::slice::from_raw_parts(a.valid, n);
        let ray = std::slice::from_raw_parts_mut(a.ray as *mut u32, RAY_FIELDS * n);
        user_spheres::occluded_lanes(valid, user_sphere(a.geometry_user_ptr, a.prim_id), ray);
    }
}

impl Embree {
    /// Builds the Embree scene of `desc` (see the module docs for the mapping), with its
    /// spheres as `spheres` says, and the seconds it took, not counting the creation of
    /// the device.
    fn build(desc: &SceneDesc, spheres_as: Spheres, robust: bool) -> (Self, f64) {
        // EMBREE_CONFIG is passed to the device (for example `verbose=1` prints the ISA
        // and build settings Embree chose).
        let config = std::env::var("EMBREE_CONFIG")
            .ok()
            .and_then(|c| std::ffi::CString::new(c).ok());
        // SAFETY: `config` outlives the call; a null device is checked below.
        let device =
            unsafe { rtcNewDevice(config.as_ref().map_or(std::ptr::null(), |c| c.as_ptr())) };
        assert!(!device.is_null(), "rtcNewDevice failed");
        let start = Instant::now();
        let (mut verts, mut tris) = (Vec::<[f32; 3]>::new(), Vec::<[u32; 3]>::new());
        let (mut spheres, mut cones) = (Vec::<[f32; 4]>::new(), Vec::<[f32; 4]>::new());
        let f = |p: &[f64; 3]| p.map(|x| x as f32);
        for s in &desc.shapes {
            match &s.shape {
                Shape::Sphere { center, radius, .. } => {
                    let c = f(center);
                    spheres.push([c[0], c[1], c[2], *radius as f32]);
                }
                Shape::Cone {
                    base,
                    base_radius,
                    apex,
                    apex_radius,
                    ..
                } => {
                    let (b, a) = (f(base), f(apex));
                    cones.push([b[0], b[1], b[2], *base_radius as f32]);
                    cones.push([a[0], a[1], a[2], *apex_radius as f32]);
                }
                Shape::Polygon { vertices } | Shape::Patch { vertices, .. } => {
                    if let Some(t) = triangulate(vertices) {
                        let base = verts.len() as u32;
                        verts.extend(vertices.iter().map(f));
                        tris.extend(t.triangles.iter().map(|t| t.map(|i| base + i)));
                    }
                }
            }
        }
        let user_spheres = match spheres_as {
            Spheres::User => std::mem::take(&mut spheres),
            Spheres::BuiltIn => Vec::new(),
        };
        // SAFETY: the device is live; every geometry comes from it; the buffers are
        // filled with items of the size given for their format; the user geometry's
        // pointer is the first of `user_spheres`, whose heap buffer the returned value
        // keeps alive and unchanged until after the scene is released, and its primitive
        // count is their number, as the callbacks require.
        unsafe {
            let scene = rtcNewScene(device);
            if robust {
                rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
            }
            let attach = |geom: RTCGeometry| {
                rtcCommitGeometry(geom);
                rtcAttachGeometry(scene, geom);
                rtcReleaseGeometry(geom);
            };
            if !tris.is_empty() {
                let g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
                fill_buffer(g, RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT3, &verts);
                fill_buffer(g, RTC_BUFFER_TYPE_INDEX, RTC_FORMAT_UINT3, &tris);
                attach(g);
            }
            if !spheres.is_empty() {
                let g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
                fill_buffer(g, RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT4, &spheres);
                attach(g);
            }
            if !user_spheres.is_empty() {
                let g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
                let ptr = user_spheres.as_ptr() as *mut c_void;
                rtcSetGeometryUserPrimitiveCount(g, user_spheres.len() as u32);
                rtcSetGeometryUserData(g, ptr);
                rtcSetGeometryBoundsFunction(g, Some(user_sphere_bounds), ptr);
                rtcSetGeometryIntersectFunction(g, Some(user_sphere_intersect));
                rtcSetGeometryOccludedFunction(g, Some(user_sphere_occluded));
                attach(g);
            }
            if !cones.is_empty() {
                let g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_CONE_LINEAR_CURVE);
                fill_buffer(g, RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT4, &cones);
                // Segment k runs from vertex 2k to 2k + 1: no two segments are neighbours.
                let idx: Vec<u32> = (0..cones.len() as u32 / 2).map(|k| 2 * k).collect();
                fill_buffer(g, RTC_BUFFER_TYPE_INDEX, RTC_FORMAT_UINT, &idx);
                attach(g);
            }
            rtcCommitScene(scene);
            let err = rtcGetDeviceError(device);
            assert_eq!(err, RTC_ERROR_NONE, "Embree error {err}");
            let built = Self {
                device,
                scene,
                user_spheres,
            };
            (built, start.elapsed().as_secs_f64())
        }
    }

    /// Closest hit distance (`None`: miss).
    #[inline]
    fn intersect1(&self, r: &Ray<f32>) -> Option<f32> {
        let mut ctx = RTCIntersectContext::new(RTC_INTERSECT_CONTEXT_FLAG_COHERENT);
        let mut rh = RTCRayHit {
            ray: rtc_ray(r, r.t_max),
            hit: RTCHit {
                geom_id: RTC_INVALID_GEOMETRY_ID,
                inst_id: [RTC_INVALID_GEOMETRY_ID],
                ..RTCHit::default()
            },
        };
        // SAFETY: the scene is committed; `ctx` and `rh` are valid for the call.
        unsafe { rtcIntersect1(self.scene, &mut ctx, &mut rh) };
        (rh.hit.geom_id != RTC_INVALID_GEOMETRY_ID).then_some(rh.ray.tfar)
    }

    /// Is anything hit before `t_max`?
    #[inline]
    fn occluded1(&self, r: &Ray<f32>, t_max: f32) -> bool {
        let mut ctx = RTCIntersectContext::new(RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT);
        let mut ray = rtc_ray(r, t_max);
        // SAFETY: the scene is committed; `ctx` and `ray` are valid for the call.
        unsafe { rtcOccluded1(self.scene, &mut ctx, &mut ray) };
        ray.tfar == f32::NEG_INFINITY
    }

    /// Closest hits of 16 rays; `out[k]` for `rays[k]`.
    #[inline]
    fn intersect16(&self, rays: [&Ray<f32>; 16], out: &mut [Option<f32>]) {
        let mut ctx = RTCIntersectContext::new(RTC_INTERSECT_CONTEXT_FLAG_COHERENT);
        let mut rh = RTCRayHit16::default();
        for (k, r) in rays.iter().enumerate() {
            let q = &mut rh.ray;
            (q.org_x[k], q.org_y[k], q.org_z[k]) = (r.origin[0], r.origin[1], r.origin[2]);
            (q.dir_x[k], q.dir_y[k], q.dir_z[k]) = (r.dir[0], r.dir[1], r.dir[2]);
            (q.tnear[k], q.tfar[k], q.mask[k]) = (r.t_min, r.t_max, u32::MAX);
            rh.hit.geom_id[k] = RTC_INVALID_GEOMETRY_ID;
            rh.hit.inst_id[0][k] = RTC_INVALID_GEOMETRY_ID;
        }
        let valid = [-1i32; 16];
        // SAFETY: the scene is committed; `valid` has 16 entries; `rh` is 64-byte
        // aligned as the API requires.
        unsafe { rtcIntersect16(valid.as_ptr(), self.scene, &mut ctx, &mut rh) };
        for (k, o) in out.iter_mut().enumerate() {
            *o = (rh.hit.geom_id[k] != RTC_INVALID_GEOMETRY_ID).then_some(rh.ray.tfar[k]);
        }
    }
}

#[inline]
fn rtc_ray(r: &Ray<f32>, t_max: f32) -> RTCRay {
    RTCRay {
        org_x: r.origin[0],
        org_y: r.origin[1],
        org_z: r.origin[2],
        tnear: r.t_min,
        dir_x: r.dir[0],
        dir_y: r.dir[1],
        dir_z: r.dir[2],
        time: 0.0,
        tfar: t_max,
        mask: u32::MAX,
        id: 0,
        flags: 0,
    }
}

/// The tracer's closest hits of one 4x4 packet: one packet of sixteen with AVX-512, two
/// of eight with AVX2 ([`Scene::cast_packet_into`]), single rays on other CPUs.
#[inline]
fn tracer_packet16(
    scene: &Scene<f32>,
    isa: Option<Isa>,
    rays: [&Ray<f32>; 16],
    out: &mut [Option<f32>],
) {
    match isa {
        Some(isa) if isa >= Isa::Avx2 => {
            let n = isa.lanes();
            let mut hits = [None; MAX_LANES];
            for (o, r) in out.chunks_mut(n).zip(rays.chunks(n)) {
                let mut lanes = [None; MAX_LANES];
                for (l, r) in lanes.iter_mut().zip(r) {
                    *l = Some(**r);
                }
                scene.cast_packet_into(isa, &lanes, &mut hits);
                for (o, h) in o.iter_mut().zip(&hits) {
                    *o = h.as_ref().map(|h| h.t());
                }
            }
        }
        _ => {
            for (o, r) in out.iter_mut().zip(rays) {
                *o = scene.cast(r).map(|h| h.t());
            }
        }
    }
}

/// Median of `v`.
fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        0.0
    } else if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Median wall-clock and process CPU seconds of one call.
#[derive(Clone, Copy, Debug, Default)]
struct Timing {
    wall: f64,
    cpu: f64,
}

/// Wall and CPU seconds of `f`.
fn timed(f: &mut impl FnMut()) -> (f64, f64) {
    let c = process_cpu_ms();
    let s = Instant::now();
    f();
    let wall = s.elapsed().as_secs_f64();
    let cpu = match (c, process_cpu_ms()) {
        (Some(a), Some(b)) => (b - a) * 1e-3,
        _ => 0.0,
    };
    (wall, cpu)
}

/// Median times of each of `fs`, run one after the other, round by round, `runs` times.
fn interleaved(runs: usize, fs: &mut [&mut dyn FnMut()]) -> Vec<Timing> {
    // One untimed round of each first (page faults, caches, thread start).
    for f in fs.iter_mut() {
        f();
    }
    let mut times = vec![(Vec::new(), Vec::new()); fs.len()];
    for _ in 0..runs {
        for (f, (w, c)) in fs.iter_mut().zip(&mut times) {
            let (wall, cpu) = timed(f);
            w.push(wall);
            c.push(cpu);
        }
    }
    times
        .into_iter()
        .map(|(w, c)| Timing {
            wall: median(w),
            cpu: median(c),
        })
        .collect()
}

/// One side's result of one row: median times and agreement with the tracer.
#[derive(Clone, Copy, Debug)]
struct Side {
    time: Timing,
    agree: f64,
}

/// One row of the report.
struct Row {
    scene: String,
    size: (u32, u32),
    threads: usize,
    kind: &'static str,
    rays: usize,
    /// Embree with its built-in sphere primitive.
    embree: Side,
    /// Embree with the spheres as user geometry (scenes with spheres only).
    user: Option<Side>,
    tracer: Timing,
}

/// Indices of the eye rays in packet order: 4x4 tiles, row by row inside a tile.
fn tile_order(w: u32, h: u32) -> Vec<usize> {
    let mut v = Vec::with_capacity((w * h) as usize);
    for ty in (0..h).step_by(4) {
        for tx in (0..w).step_by(4) {
            for dy in 0..4 {
                for dx in 0..4 {
                    v.push(((ty + dy) * w + tx + dx) as usize);
                }
            }
        }
    }
    v
}

fn agreement(a: impl Iterator<Item = bool>, b: impl Iterator<Item = bool>) -> f64 {
    let (mut same, mut n) = (0usize, 0usize);
    for (x, y) in a.zip(b) {
        same += usize::from(x == y);
        n += 1;
    }
    if n == 0 {
        1.0
    } else {
        same as f64 / n as f64
    }
}

/// `out[i] = f(&items[i])` for all `i`, in parallel tasks of [`CHUNK`] items.
#[inline]
fn par_map<I: Sync, O: Send>(out: &mut [O], items: &[I], f: impl Fn(&I) -> O + Sync) {
    out.par_chunks_mut(CHUNK)
        .zip(items.par_chunks(CHUNK))
        .for_each(|(os, is)| {
            for (o, i) in os.iter_mut().zip(is) {
                *o = f(i);
            }
        });
}

/// `f(packet, out)` for the packets of sixteen rays in `order` (indices into `eye`) and
/// the matching sixteen entries of `out`, in parallel tasks of [`CHUNK`] rays.
#[inline]
fn par_packets(
    out: &mut [Option<f32>],
    order: &[usize],
    eye: &[Ray<f32>],
    f: impl Fn([&Ray<f32>; 16], &mut [Option<f32>]) + Sync,
) {
    out.par_chunks_mut(CHUNK)
        .zip(order.par_chunks(CHUNK))
        .for_each(|(hs, idx)| {
            for (h, i) in hs.chunks_exact_mut(16).zip(idx.chunks_exact(16)) {
                f(std::array::from_fn(|k| &eye[i[k]]), h);
            }
        });
}

/// Runs the sides of one row interleaved: Embree, Embree with user spheres when `user`
/// is given, and the tracer, each writing its own results (Embree's `E`, the tracer's
/// `T`); then the row's times, each Embree side's agreement with the tracer
/// (`same(embree results, tracer results)`), and the tracer's results.
fn race<E: Clone + Send, T: Clone + Send>(
    runs: usize,
    n: usize,
    (e_init, t_init): (E, T),
    embree: impl Fn(&mut [E]),
    user: Option<impl Fn(&mut [E])>,
    tracer: impl Fn(&mut [T]),
    same: impl Fn(&[E], &[T]) -> f64,
) -> ((Side, Option<Side>, Timing), Vec<T>) {
    let mut e = vec![e_init.clone(); n];
    let mut u = if user.is_some() {
        vec![e_init; n]
    } else {
        Vec::new()
    };
    let mut t = vec![t_init; n];
    let mut fe = || embree(&mut e);
    let mut fu = || {
        if let Some(user) = &user {
            user(&mut u)
        }
    };
    let mut ft = || tracer(&mut t);
    let times = if user.is_some() {
        interleaved(runs, &mut [&mut fe, &mut fu, &mut ft])
    } else {
        interleaved(runs, &mut [&mut fe, &mut ft])
    };
    let embree = Side {
        time: times[0],
        agree: same(&e, &t),
    };
    let user = user.is_some().then(|| Side {
        time: times[1],
        agree: same(&u, &t),
    });
    ((embree, user, times[times.len() - 1]), t)
}

/// The share of entries where both hit or both miss.
fn same_hits<T>(a: &[Option<f32>], b: &[Option<T>]) -> f64 {
    agreement(a.iter().map(Option::is_some), b.iter().map(Option::is_some))
}

/// The share of entries where both are blocked or both are not.
fn same_blocked(a: &[bool], b: &[bool]) -> f64 {
    agreement(a.iter().copied(), b.iter().copied())
}

/// All measurements of one scene at one size on the current rayon pool: Embree with
/// built-in spheres (`embree`), with user spheres (`user`, if given), and the tracer.
fn measure(
    name: &str,
    scene: &Scene<f32>,
    embree: &Embree,
    user: Option<&Embree>,
    (w, h): (u32, u32),
    runs: usize,
) -> Vec<Row> {
    assert!(
        w % 4 == 0 && h % 4 == 0,
        "image sizes must be multiples of 4"
    );
    let threads = rayon::current_num_threads();
    let cam = scene.camera_for(w, h);
    let eye: Vec<Ray<f32>> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| Ray::new(cam.position, cam.direction(x as f32 + 0.5, y as f32 + 0.5)))
        .collect();
    let row = |kind, rays, (embree, user, tracer)| Row {
        scene: name.to_string(),
        size: (w, h),
        threads,
        kind,
        rays,
        embree,
        user,
        tracer,
    };
    let mut rows = Vec::new();

    // Eye rays, one at a time.
    let (sides, t_hits) = race(
        runs,
        eye.len(),
        (None, None),
        |out| par_map(out, &eye, |r| embree.intersect1(r)),
        user.map(|u| {
            let eye = &eye;
            move |out: &mut [Option<f32>]| par_map(out, eye, |r| u.intersect1(r))
        }),
        |out| par_map(out, &eye, |r| scene.cast(r)),
        same_hits,
    );
    rows.push(row("eye", eye.len(), sides));
    let t_hits: Vec<Option<Hit<f32>>> = eye
        .iter()
        .zip(&t_hits)
        .map(|(r, c)| c.as_ref().map(|c| scene.hit(r, c)))
        .collect();

    // Shadow rays from the tracer's eye hits toward the first light.
    if let Some(light) = scene.lights.first().map(|l| l.position) {
        let mut shadow: Vec<(Ray<f32>, f32)> = Vec::new();
        for (r, hit) in eye.iter().zip(&t_hits) {
            let Some(hit) = hit else { continue };
            let ng = if hit.geometric_normal.dot(&r.dir) < 0.0 {
                hit.geometric_normal
            } else {
                (-&hit.geometric_normal).eval()
            };
            let above = offset_ray(&hit.point, &ng, &ng);
            let to = (&light - &hit.point).eval();
            let dist = to.length();
            if dist > 0.0 && dist.is_finite() {
                shadow.push((Ray::new(above, (&to).scale(dist.recip()).eval()), dist));
            }
        }
        let (sides, _) = race(
            runs,
            shadow.len(),
            (false, false),
            |out| par_map(out, &shadow, |(r, d)| embree.occluded1(r, *d)),
            user.map(|u| {
                let shadow = &shadow;
                move |out: &mut [bool]| par_map(out, shadow, |(r, d)| u.occluded1(r, *d))
            }),
            |out| {
                par_map(out, &shadow, |(r, d)| {
                    scene.occluded(&Ray { t_max: *d, ..*r })
                })
            },
            same_blocked,
        );
        rows.push(row("shadow", shadow.len(), sides));
    }

    // Eye rays in packets of 4x4 pixels.
    let isa = Isa::detect();
    let order = tile_order(w, h);
    let (sides, _) = race(
        runs,
        eye.len(),
        (None, None),
        |out| par_packets(out, &order, &eye, |p, h| embree.intersect16(p, h)),
        user.map(|u| {
            let (order, eye) = (&order, &eye);
            move |out: &mut [Option<f32>]| par_packets(out, order, eye, |p, h| u.intersect16(p, h))
        }),
        |out| par_packets(out, &order, &eye, |p, h| tracer_packet16(scene, isa, p, h)),
        same_hits,
    );
    rows.push(row("eye16", eye.len(), sides));
    rows
}

struct Args {
    scenes: Vec<PathBuf>,
    sizes: Vec<(u32, u32)>,
    threads: Vec<usize>,
    runs: usize,
    /// Also measure Embree with the spheres as user geometry (scenes with spheres).
    user_spheres: bool,
    /// Build Embree's scenes in its robust mode (`RTC_SCENE_FLAG_ROBUST`).
    robust: bool,
    /// The tracer's single rays walk the four-wide tree even where the CPU has AVX2
    /// (`AccelOptions::eight_wide` off), for a comparison of the two in one run.
    four_wide: bool,
}

const USAGE: &str = "usage: embree [--runs N] [--threads 1,2] [--sizes 512x512,1920x1080] \
                     [--no-user-spheres] [--robust] [--four-wide] SCENE.nff...";

fn parse_args() -> Result<Args, String> {
    let mut a = Args {
        scenes: Vec::new(),
        sizes: vec![(512, 512), (1920, 1080)],
        threads: vec![1, 2],
        runs: 5,
        user_spheres: true,
        robust: false,
        four_wide: false,
    };
    let mut it = std::env::args().skip(1);
    while let Some(arg) = it.next() {
        let mut value = || it.next().ok_or(format!("{arg} needs a value\n{USAGE}"));
        match arg.as_str() {
            "--runs" => a.runs = value()?.parse().map_err(|e| format!("--runs: {e}"))?,
            "--threads" => {
                a.threads = value()?
                    .split(',')
                    .map(|t| t.parse().map_err(|e| format!("--threads: {e}")))
                    .collect::<Result<_, _>>()?
            }
            "--sizes" => {
                a.sizes = value()?
                    .split(',')
                    .map(|s| {
                        let (w, h) = s.split_once('x').ok_or(format!("--sizes: {s}: not WxH"))?;
                        let p =
                            |v: &str| v.parse::<u32>().map_err(|e| format!("--sizes: {s}: {e}"));
                        Ok((p(w)?, p(h)?))
                    })
                    .collect::<Result<_, String>>()?
            }
            "--no-user-spheres" => a.user_spheres = false,
            "--robust" => a.robust = true,
            "--four-wide" => a.four_wide = true,
            // cargo bench passes --bench to bench targets.
            "--bench" => {}
            s if s.starts_with('-') => return Err(format!("unknown option {s}\n{USAGE}")),
            s => a.scenes.push(s.into()),
        }
    }
    if a.scenes.is_empty() {
        return Err(USAGE.into());
    }
    if a.sizes
        .iter()
        .any(|(w, h)| w % 4 != 0 || h % 4 != 0 || *w == 0 || *h == 0)
    {
        return Err("--sizes: width and height must be positive multiples of 4".into());
    }
    Ok(a)
}

fn mrays(n: usize, s: f64) -> f64 {
    n as f64 / s / 1e6
}

/// Geometric mean (1 for none).
fn geomean(v: &[f64]) -> f64 {
    if v.is_empty() {
        1.0
    } else {
        (v.iter().map(|x| x.ln()).sum::<f64>() / v.len() as f64).exp()
    }
}

/// Tracer / Embree throughput, per wall second and per CPU second.
fn ratios(s: &Side, tracer: &Timing) -> (f64, f64) {
    (s.time.wall / tracer.wall, s.time.cpu / tracer.cpu)
}

const KINDS: [&str; 3] = ["eye", "shadow", "eye16"];

/// The Embree query of a kind, for the table.
fn embree_query(kind: &str) -> &'static str {
    match kind {
        "eye" => "eye (rtcIntersect1)",
        "shadow" => "shadow (rtcOccluded1)",
        _ => "eye16 (rtcIntersect16)",
    }
}

/// Prints the tables: the rows, the user spheres' rows, the ratios per scene, the
/// geometric means and the build times.
fn print_report(rows: &[Row], threads: &[usize], builds: &[(String, f64, Option<f64>, f64)]) {
    println!("Embree with its built-in spheres (RTC_GEOMETRY_TYPE_SPHERE_POINT):\n");
    println!(
        "| scene | size | threads | rays | kind | Embree Mrays/s | tracer Mrays/s \
         | tracer / Embree | agreement |\n|---|---|---:|---:|---|---:|---:|---:|---:|"
    );
    for r in rows {
        let (e, t) = (
            mrays(r.rays, r.embree.time.wall),
            mrays(r.rays, r.tracer.wall),
        );
        let (ec, tc) = (
            mrays(r.rays, r.embree.time.cpu),
            mrays(r.rays, r.tracer.cpu),
        );
        println!(
            "| {} | {}x{} | {} | {} | {} | {e:.2} ({ec:.2}) | {t:.2} ({tc:.2}) | {:.2} ({:.2}) | {:.3}% |",
            r.scene,
            r.size.0,
            r.size.1,
            r.threads,
            r.rays,
            embree_query(r.kind),
            t / e,
            tc / ec,
            100.0 * r.embree.agree
        );
    }
    let with_user: Vec<&Row> = rows.iter().filter(|r| r.user.is_some()).collect();
    if !with_user.is_empty() {
        println!(
            "\nScenes with spheres: Embree with its built-in spheres and with the spheres as \
             user geometry (RTC_GEOMETRY_TYPE_USER, callbacks of benches/support/user_spheres.rs); \
             Mrays/s per wall second, ratios per wall (CPU) second:\n"
        );
        println!(
            "| scene | kind | size | threads | Embree Mrays/s | Embree user Mrays/s \
             | tracer Mrays/s | tracer / Embree | tracer / Embree user | agreement \
             | agreement user |\n|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|"
        );
        for r in &with_user {
            let u = r.user.expect("filtered");
            let (b, bc) = ratios(&r.embree, &r.tracer);
            let (x, xc) = ratios(&u, &r.tracer);
            println!(
                "| {} | {} | {}x{} | {} | {:.2} | {:.2} | {:.2} | {b:.2} ({bc:.2}) \
                 | {x:.2} ({xc:.2}) | {:.3}% | {:.3}% |",
                r.scene,
                r.kind,
                r.size.0,
                r.size.1,
                r.threads,
                mrays(r.rays, r.embree.time.wall),
                mrays(r.rays, u.time.wall),
                mrays(r.rays, r.tracer.wall),
                100.0 * r.embree.agree,
                100.0 * u.agree
            );
        }
    }

    // Per scene: geometric means over the sizes and thread counts.
    println!(
        "\nTracer / Embree per scene, geometric mean over the sizes and thread counts \
         (wall seconds):\n"
    );
    println!(
        "| scene | eye | shadow | eye16 | eye, user spheres | shadow, user spheres \
         | eye16, user spheres |\n|---|---:|---:|---:|---:|---:|---:|"
    );
    let mut names: Vec<&str> = Vec::new();
    for r in rows {
        if !names.contains(&r.scene.as_str()) {
            names.push(&r.scene);
        }
    }
    for name in names {
        let cell = |kind: &str, user: bool| {
            let v: Vec<f64> = rows
                .iter()
                .filter(|r| r.scene == name && r.kind == kind)
                .filter_map(|r| {
                    let side = if user { r.user? } else { r.embree };
                    Some(ratios(&side, &r.tracer).0)
                })
                .collect();
            if v.is_empty() {
                "–".to_string()
            } else {
                format!("{:.2}", geomean(&v))
            }
        };
        let builtin: Vec<String> = KINDS.iter().map(|k| cell(k, false)).collect();
        let user: Vec<String> = KINDS.iter().map(|k| cell(k, true)).collect();
        println!(
            "| {name} | {} | {} |",
            builtin.join(" | "),
            user.join(" | ")
        );
    }

    // Geometric means of the ratio per kind and thread count.
    println!("\nAll scenes, Embree with its built-in spheres:\n");
    println!(
        "| kind | threads | geomean tracer / Embree | min | max | geomean per CPU s |\n\
         |---|---:|---:|---:|---:|---:|"
    );
    let summary = |sel: &dyn Fn(&Row) -> Option<Side>| {
        for kind in KINDS {
            for &t in threads {
                let v: Vec<(f64, f64)> = rows
                    .iter()
                    .filter(|r| r.kind == kind && r.threads == t)
                    .filter_map(|r| sel(r).map(|s| ratios(&s, &r.tracer)))
                    .collect();
                if v.is_empty() {
                    continue;
                }
                let wall: Vec<f64> = v.iter().map(|x| x.0).collect();
                let cpu: Vec<f64> = v.iter().map(|x| x.1).collect();
                let (lo, hi) = wall
                    .iter()
                    .fold((f64::MAX, 0f64), |(a, b), &x| (a.min(x), b.max(x)));
                println!(
                    "| {kind} | {t} | {:.2} | {lo:.2} | {hi:.2} | {:.2} |",
                    geomean(&wall),
                    geomean(&cpu)
                );
            }
        }
    };
    summary(&|r| Some(r.embree));
    if !with_user.is_empty() {
        println!("\nScenes with spheres only, Embree with its built-in spheres:\n");
        println!(
            "| kind | threads | geomean tracer / Embree | min | max | geomean per CPU s |\n\
             |---|---:|---:|---:|---:|---:|"
        );
        summary(&|r| r.user.map(|_| r.embree));
        println!("\nScenes with spheres only, Embree with user spheres:\n");
        println!(
            "| kind | threads | geomean tracer / Embree user | min | max | geomean per CPU s |\n\
             |---|---:|---:|---:|---:|---:|"
        );
        summary(&|r| r.user);
    }

    println!(
        "\n| scene | Embree build ms | Embree user spheres build ms | tracer build ms |\n\
         |---|---:|---:|---:|"
    );
    for (n, e, u, t) in builds {
        let u = u.map_or("–".to_string(), |u| format!("{:.1}", u * 1e3));
        println!("| {n} | {:.1} | {u} | {:.1} |", e * 1e3, t * 1e3);
    }
}

fn main() -> std::process::ExitCode {
    let args = match parse_args() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("{e}");
            return std::process::ExitCode::from(2);
        }
    };
    let mut rows = Vec::new();
    let mut builds = Vec::new();
    for path in &args.scenes {
        let desc = match tracer::scene::load(path) {
            Ok(d) => d,
            Err(e) => {
                eprintln!("{e}");
                return std::process::ExitCode::from(2);
            }
        };
        let name = path
            .file_name()
            .and_then(|n| n.to_str())
            .map(|n| n.trim_end_matches(".gz").trim_end_matches(".nff"))
            .unwrap_or("?")
            .to_string();
        let has_spheres = desc
            .shapes
            .iter()
            .any(|s| matches!(s.shape, Shape::Sphere { .. }));
        let accel = AccelOptions {
            eight_wide: !args.four_wide,
            ..AccelOptions::default()
        };
        // Both sides build `runs` times in alternation (the previous build released
        // first), and the medians are reported; the last builds are the ones traced.
        let (mut times_e, mut times_u, mut times_t) = (Vec::new(), Vec::new(), Vec::new());
        let (mut embree, mut user, mut scene) = (None, None, None);
        for _ in 0..args.runs.max(1) {
            drop(embree.take());
            let (e, te) = Embree::build(&desc, Spheres::BuiltIn, args.robust);
            embree = Some(e);
            times_e.push(te);
            if args.user_spheres && has_spheres {
                drop(user.take());
                let (u, tu) = Embree::build(&desc, Spheres::User, args.robust);
                user = Some(u);
                times_u.push(tu);
            }
            drop(scene.take());
            let s = Instant::now();
            scene = Some(Scene::<f32>::from_desc(&desc, &accel));
            times_t.push(s.elapsed().as_secs_f64());
        }
        let (Some(embree), Some(scene)) = (embree, scene) else {
            unreachable!("at least one build runs");
        };
        builds.push((
            name.clone(),
            median(times_e),
            (!times_u.is_empty()).then(|| median(times_u)),
            median(times_t),
        ));
        let user = user.as_ref();
        for &t in &args.threads {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .build()
                .expect("cannot start the thread pool");
            for &size in &args.sizes {
                eprintln!("{name} {}x{} {t} thread(s)", size.0, size.1);
                rows.extend(
                    pool.install(|| measure(&name, &scene, &embree, user, size, args.runs)),
                );
            }
        }
    }
    if args.robust {
        println!(
            "Embree in its robust mode (RTC_SCENE_FLAG_ROBUST: robust traversal, no \
             accuracy-reducing optimisations)\n"
        );
    }
    print_report(&rows, &args.threads, &builds);
    std::process::ExitCode::SUCCESS
}
