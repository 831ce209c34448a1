//! The tracer's ray casting against Intel Embree 3, on the same scenes and the same rays.
//!
//! Built only with the `embree` feature (it links `libembree3`); `benches/embree/run.sh`
//! installs Debian's `libembree-dev` and runs it. For every scene, image size and thread
//! count it casts, on both sides:
//! - `eye`: the eye rays of the NFF camera through the pixel centres, closest hit
//!   (Embree `rtcIntersect1`, tracer [`tracer::Scene::intersect`]);
//! - `shadow`: from every eye hit of the tracer (offset off the surface as in shading)
//!   toward the first light, any hit before the light (Embree `rtcOccluded1`, tracer
//!   [`tracer::Scene::occluded`]);
//! - `eye16`: the eye rays in packets of 4x4 pixels (Embree `rtcIntersect16`, tracer
//!   [`tracer::Scene::intersect_packet`] with the widest instruction set, see
//!   [`tracer_packet16`]).
//!
//! Geometry: polygons and patches are cut into triangles by the tracer's own
//! triangulation and given to Embree as one triangle mesh; spheres as one
//! `RTC_GEOMETRY_TYPE_SPHERE_POINT` geometry; cones and cylinders as
//! `RTC_GEOMETRY_TYPE_CONE_LINEAR_CURVE` segments, one per NFF cone, with no neighbours.
//! Embree's cone curves have flat end caps where NFF cones are open, so a ray through
//! the open end of a cone is a hit in Embree only; in the SPD scenes (the tree's
//! branches) the ends sit inside other primitives, and the agreement column shows what
//! difference remains. The alternative, user geometry with the tracer's own cone test
//! called back from Embree, would measure a callback per cone rather than Embree.
//!
//! Each measurement is repeated `--runs` times, Embree and tracer interleaved, and the
//! median wall time is reported as Mrays/s, with Mrays per CPU second of all threads in
//! parentheses (steadier on a shared machine); the ratio is tracer / Embree throughput. The
//! agreement is the share of rays where both report the same hit or miss. Build times
//! (from the parsed scene description, conversion included, on all cores; Embree's
//! without creating the device) are printed too. The environment variable `EMBREE_CONFIG` is passed to `rtcNewDevice`.

mod ffi;

use ffi::*;
use rayon::prelude::*;
use std::path::PathBuf;
use std::time::Instant;
use tracer::geometry::{offset_ray, polygon::triangulate, AccelOptions};
use tracer::packets::MAX_LANES;
use tracer::scene::desc::{SceneDesc, Shape};
use tracer::stats::process_cpu_ms;
use tracer::{Ray, Scene};
use vecexpr::simd::Isa;
use vecexpr::Expr;

/// Rays per parallel task (tasks of packets: this many rays in packets of 16).
const CHUNK: usize = 1024;

/// An Embree device and scene, released on drop.
struct Embree {
    device: RTCDevice,
    scene: RTCScene,
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

impl Embree {
    /// Builds the Embree scene of `desc` (see the module docs for the mapping), and
    /// the seconds it took, not counting the creation of the device.
    fn build(desc: &SceneDesc) -> (Self, f64) {
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
        // SAFETY: the device is live; every geometry comes from it; the buffers are
        // filled with items of the size given for their format.
        unsafe {
            let scene = rtcNewScene(device);
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
            (Self { device, scene }, start.elapsed().as_secs_f64())
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
/// of eight with AVX2 ([`Scene::intersect_packet`]), single rays on other CPUs.
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
            for (o, r) in out.chunks_mut(n).zip(rays.chunks(n)) {
                let mut lanes = [None; MAX_LANES];
                for (l, r) in lanes.iter_mut().zip(r) {
                    *l = Some(**r);
                }
                let hits = scene.intersect_packet(isa, &lanes);
                for (o, h) in o.iter_mut().zip(&hits) {
                    *o = h.as_ref().map(|h| h.t);
                }
            }
        }
        _ => {
            for (o, r) in out.iter_mut().zip(rays) {
                *o = scene.intersect(r).map(|h| h.t);
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

/// Median times of `a` and of `b`, run alternately `runs` times.
fn interleaved(runs: usize, mut a: impl FnMut(), mut b: impl FnMut()) -> (Timing, Timing) {
    let (mut wa, mut ca, mut wb, mut cb) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    // One untimed round of each first (page faults, caches, thread start).
    a();
    b();
    for _ in 0..runs {
        let (w, c) = timed(&mut a);
        wa.push(w);
        ca.push(c);
        let (w, c) = timed(&mut b);
        wb.push(w);
        cb.push(c);
    }
    let t = |w, c| Timing {
        wall: median(w),
        cpu: median(c),
    };
    (t(wa, ca), t(wb, cb))
}

/// One row of the report.
struct Row {
    scene: String,
    size: (u32, u32),
    threads: usize,
    kind: &'static str,
    rays: usize,
    embree: Timing,
    tracer: Timing,
    agree: f64,
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

/// All measurements of one scene at one size on the current rayon pool.
fn measure(
    name: &str,
    scene: &Scene<f32>,
    embree: &Embree,
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
    let row = |kind, rays, (embree, tracer), agree| Row {
        scene: name.to_string(),
        size: (w, h),
        threads,
        kind,
        rays,
        embree,
        tracer,
        agree,
    };
    let mut rows = Vec::new();

    // Eye rays, one at a time.
    let mut e_hits = vec![None; eye.len()];
    let mut t_hits = vec![None; eye.len()];
    let times = interleaved(
        runs,
        || {
            e_hits
                .par_chunks_mut(CHUNK)
                .zip(eye.par_chunks(CHUNK))
                .for_each(|(hs, rs)| {
                    for (h, r) in hs.iter_mut().zip(rs) {
                        *h = embree.intersect1(r);
                    }
                })
        },
        || {
            t_hits
                .par_chunks_mut(CHUNK)
                .zip(eye.par_chunks(CHUNK))
                .for_each(|(hs, rs)| {
                    for (h, r) in hs.iter_mut().zip(rs) {
                        *h = scene.intersect(r);
                    }
                })
        },
    );
    let agree = agreement(
        e_hits.iter().map(Option::is_some),
        t_hits.iter().map(Option::is_some),
    );
    rows.push(row("eye", eye.len(), times, agree));

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
        let mut e_occ = vec![false; shadow.len()];
        let mut t_occ = vec![false; shadow.len()];
        let times = interleaved(
            runs,
            || {
                e_occ
                    .par_chunks_mut(CHUNK)
                    .zip(shadow.par_chunks(CHUNK))
                    .for_each(|(os, rs)| {
                        for (o, (r, d)) in os.iter_mut().zip(rs) {
                            *o = embree.occluded1(r, *d);
                        }
                    })
            },
            || {
                t_occ
                    .par_chunks_mut(CHUNK)
                    .zip(shadow.par_chunks(CHUNK))
                    .for_each(|(os, rs)| {
                        for (o, (r, d)) in os.iter_mut().zip(rs) {
                            *o = scene.occluded(&Ray { t_max: *d, ..*r });
                        }
                    })
            },
        );
        let agree = agreement(e_occ.iter().copied(), t_occ.iter().copied());
        rows.push(row("shadow", shadow.len(), times, agree));
    }

    // Eye rays in packets of 4x4 pixels.
    let isa = Isa::detect();
    let order = tile_order(w, h);
    let mut e16 = vec![None; eye.len()];
    let mut t16 = vec![None; eye.len()];
    let packet = |idx: &[usize]| -> [&Ray<f32>; 16] { std::array::from_fn(|k| &eye[idx[k]]) };
    let times = interleaved(
        runs,
        || {
            e16.par_chunks_mut(CHUNK)
                .zip(order.par_chunks(CHUNK))
                .for_each(|(hs, idx)| {
                    for (h, i) in hs.chunks_exact_mut(16).zip(idx.chunks_exact(16)) {
                        embree.intersect16(packet(i), h);
                    }
                })
        },
        || {
            t16.par_chunks_mut(CHUNK)
                .zip(order.par_chunks(CHUNK))
                .for_each(|(hs, idx)| {
                    for (h, i) in hs.chunks_exact_mut(16).zip(idx.chunks_exact(16)) {
                        tracer_packet16(scene, isa, packet(i), h);
                    }
                })
        },
    );
    let agree = agreement(
        e16.iter().map(Option::is_some),
        t16.iter().map(Option::is_some),
    );
    rows.push(row("eye16", eye.len(), times, agree));
    rows
}

struct Args {
    scenes: Vec<PathBuf>,
    sizes: Vec<(u32, u32)>,
    threads: Vec<usize>,
    runs: usize,
}

const USAGE: &str =
    "usage: embree [--runs N] [--threads 1,2] [--sizes 512x512,1920x1080] SCENE.nff...";

fn parse_args() -> Result<Args, String> {
    let mut a = Args {
        scenes: Vec::new(),
        sizes: vec![(512, 512), (1920, 1080)],
        threads: vec![1, 2],
        runs: 5,
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
        let (embree, embree_build) = Embree::build(&desc);
        let s = Instant::now();
        let scene = Scene::<f32>::from_desc(&desc, &AccelOptions::default());
        let tracer_build = s.elapsed().as_secs_f64();
        builds.push((name.clone(), embree_build, tracer_build));
        for &t in &args.threads {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .build()
                .expect("cannot start the thread pool");
            for &size in &args.sizes {
                eprintln!("{name} {}x{} {t} thread(s)", size.0, size.1);
                rows.extend(pool.install(|| measure(&name, &scene, &embree, size, args.runs)));
            }
        }
    }
    println!(
        "| scene | size | threads | rays | kind | Embree Mrays/s | tracer Mrays/s \
         | tracer / Embree | agreement |\n|---|---|---:|---:|---|---:|---:|---:|---:|"
    );
    for r in &rows {
        let (e, t) = (mrays(r.rays, r.embree.wall), mrays(r.rays, r.tracer.wall));
        let (ec, tc) = (mrays(r.rays, r.embree.cpu), mrays(r.rays, r.tracer.cpu));
        let ekind = match r.kind {
            "eye" => "eye (rtcIntersect1)",
            "shadow" => "shadow (rtcOccluded1)",
            _ => "eye16 (rtcIntersect16)",
        };
        println!(
            "| {} | {}x{} | {} | {} | {} | {:.2} ({:.2}) | {:.2} ({:.2}) | {:.2} ({:.2}) | {:.3}% |",
            r.scene,
            r.size.0,
            r.size.1,
            r.threads,
            r.rays,
            ekind,
            e,
            ec,
            t,
            tc,
            t / e,
            tc / ec,
            100.0 * r.agree
        );
    }
    // Geometric means of the ratio per kind and thread count.
    println!(
        "\n| kind | threads | geomean tracer / Embree | min | max | geomean per CPU s |\n\
         |---|---:|---:|---:|---:|---:|"
    );
    for kind in ["eye", "shadow", "eye16"] {
        for &t in &args.threads {
            let sel = || rows.iter().filter(|r| r.kind == kind && r.threads == t);
            let v: Vec<f64> = sel().map(|r| r.embree.wall / r.tracer.wall).collect();
            let vc: Vec<f64> = sel().map(|r| r.embree.cpu / r.tracer.cpu).collect();
            if v.is_empty() {
                continue;
            }
            let gm = |v: &[f64]| (v.iter().map(|x| x.ln()).sum::<f64>() / v.len() as f64).exp();
            let (lo, hi) = v
                .iter()
                .fold((f64::MAX, 0f64), |(a, b), &x| (a.min(x), b.max(x)));
            println!(
                "| {kind} | {t} | {:.2} | {lo:.2} | {hi:.2} | {:.2} |",
                gm(&v),
                gm(&vc)
            );
        }
    }
    println!("\n| scene | Embree build ms | tracer build ms |\n|---|---:|---:|");
    for (n, e, t) in builds {
        println!("| {n} | {:.1} | {:.1} |", e * 1e3, t * 1e3);
    }
    std::process::ExitCode::SUCCESS
}
