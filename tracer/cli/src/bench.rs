//! `tracer bench`: build time, ray-casting throughput by ray kind and frame time of a
//! scene, as medians over repeated runs.
//!
//! The rays are those of a frame: eye rays through the pixel centres of the NFF camera,
//! shadow rays from every eye hit toward the first light (offset off the surface as in
//! shading), and mirror-reflection rays from every eye hit. Each kind is generated once,
//! then cast `runs` times on the rayon pool in chunks of [`CHUNK`] rays; eye and
//! reflection rays ask for the closest hit, shadow rays for any hit before the light.
//! The frame is a full render (Whitted shading at the given depth) with the given
//! scheduler. Nothing here asserts on time: it only reports.

use crate::args::{load_scene, whole, PacketArgs, Precision, ScheduleArgs};
use rayon::prelude::*;
use std::path::PathBuf;
use std::time::Instant;
use tracer::geometry::offset_ray;
use tracer::geometry::AccelOptions;
use tracer::packets::{EyePackets, Packets};
use tracer::ray::Ray;
use tracer::render::{render_with_stats, Schedule, Settings};
use tracer::scene::desc::SceneDesc;
use tracer::stats::{median, process_cpu_ms};
use tracer::world::Scene;
use vecexpr::Expr;

#[derive(clap::Args, Debug)]
/// Options of `tracer bench`.
pub struct BenchArgs {
    /// Scene files (.nff, .nff.gz, .obj).
    #[arg(required = true)]
    pub scenes: Vec<PathBuf>,
    /// Image width.
    #[arg(long, default_value_t = 512, value_parser = whole(1, 65536), allow_negative_numbers = true)]
    pub width: u32,
    /// Image height.
    #[arg(long, default_value_t = 512, value_parser = whole(1, 65536), allow_negative_numbers = true)]
    pub height: u32,
    /// Maximum ray depth of the frame.
    #[arg(long, default_value_t = 5, value_parser = whole(1, 64), allow_negative_numbers = true)]
    pub depth: u32,
    /// Runs per measurement (medians are printed).
    #[arg(long, default_value_t = 5, value_parser = whole(1, 1000), allow_negative_numbers = true)]
    pub runs: u32,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = whole(1, 1024), allow_negative_numbers = true)]
    pub threads: Option<u32>,
    /// Arithmetic precision.
    #[arg(long, value_enum, default_value_t = Precision::F32)]
    pub precision: Precision,
    /// Trace without the BVH (brute force).
    #[arg(long)]
    pub no_bvh: bool,
    /// Traverse the binary BVH instead of the four-wide one (not with --no-bvh).
    #[arg(long, conflicts_with = "no_bvh")]
    pub binary_bvh: bool,
    /// Output of povray-times, for the ratio column.
    #[arg(long, value_name = "FILE")]
    pub peer: Option<PathBuf>,
    /// Parallel scheduler and tile size.
    #[command(flatten)]
    pub schedule: ScheduleArgs,
    /// Eye-ray packets and their instruction set.
    #[command(flatten)]
    pub packets: PacketArgs,
}

/// Runs `tracer bench`: [`prepare`], then measures every scene and prints the tables.
///
/// # Errors
/// One line `FILE:LINE: message` or `FILE: message` for bad input.
pub fn run(args: &BenchArgs) -> Result<(), String> {
    let Prepared {
        peer,
        options: opts,
        scenes,
    } = prepare(args)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.threads.unwrap_or(0))
        .build()
        .map_err(|e| format!("cannot create the thread pool: {e}"))?;
    let mut rows = Vec::new();
    for (name, desc) in &scenes {
        let row = pool.install(|| match args.precision {
            Precision::F32 => bench_scene::<f32>(name, desc, &opts),
            Precision::F64 => bench_scene::<f64>(name, desc, &opts),
        });
        rows.push(row);
    }
    print!("{}", table(&rows, &peer));
    println!("\n{LEGEND}");
    let packets = packet_table(&rows);
    if !packets.is_empty() {
        print!("\n{packets}");
        println!("\n{PACKET_LEGEND}");
    }
    Ok(())
}

/// A benchmark checked and ready to measure.
pub struct Prepared {
    /// The peer's times (`--peer`).
    pub peer: Vec<(String, f64)>,
    /// What to measure.
    pub options: BenchOptions,
    /// Each scene's short name and description, in the order given.
    pub scenes: Vec<(String, SceneDesc)>,
}

/// Every check of `tracer bench` before the first measurement: the peer's times, the
/// options, and every scene read.
///
/// # Errors
/// As [`run`].
pub fn prepare(args: &BenchArgs) -> Result<Prepared, String> {
    let peer = match &args.peer {
        Some(p) => parse_peer_times(
            &std::fs::read_to_string(p).map_err(|e| format!("{}: {e}", p.display()))?,
        ),
        None => Vec::new(),
    };
    let options = BenchOptions {
        width: args.width,
        height: args.height,
        depth: args.depth,
        runs: args.runs as usize,
        threads: args.threads.map(|t| t as usize),
        schedule: args.schedule.schedule()?,
        accel: AccelOptions {
            use_bvh: !args.no_bvh,
            wide: !args.binary_bvh,
            ..AccelOptions::default()
        },
        packets: {
            args.packets.check_applies(args.precision)?;
            args.packets.packets()?
        },
    };
    let mut scenes = Vec::new();
    for path in &args.scenes {
        let desc = load_scene(path, &Default::default(), args.precision)?;
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let name = name.split('.').next().unwrap_or_default().to_string();
        scenes.push((name, desc));
    }
    Ok(Prepared {
        peer,
        options,
        scenes,
    })
}

/// Rays per parallel task when casting.
pub const CHUNK: usize = 1024;

/// What to measure.
#[derive(Clone, Debug)]
pub struct BenchOptions {
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Maximum ray depth of the frame.
    pub depth: u32,
    /// Repetitions of each measurement; medians are reported.
    pub runs: usize,
    /// Worker threads (`None`: all cores).
    pub threads: Option<usize>,
    /// Frame scheduler.
    pub schedule: Schedule,
    /// Acceleration structure options.
    pub accel: AccelOptions,
    /// Eye-ray packets: of the frame, and the extra packet eye-ray measurement.
    pub packets: Packets,
}

impl Default for BenchOptions {
    /// 512x512, depth 5, 5 runs, all cores, default scheduler and BVH.
    fn default() -> Self {
        Self {
            width: 512,
            height: 512,
            depth: 5,
            runs: 5,
            threads: None,
            schedule: Schedule::default(),
            accel: AccelOptions::default(),
            packets: Packets::default(),
        }
    }
}

/// One scene's results (times in milliseconds, medians).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BenchRow {
    /// Scene name.
    pub scene: String,
    /// Primitives in the BVH.
    pub primitives: usize,
    /// Geometry build (conversion, BVH, reordering).
    pub build_ms: f64,
    /// BVH nodes.
    pub nodes: usize,
    /// BVH and primitive bytes per primitive.
    pub bytes_per_prim: f64,
    /// Eye rays cast per run.
    pub eye_rays: usize,
    /// Eye rays: median time per run.
    pub eye: Timing,
    /// Shadow rays cast per run.
    pub shadow_rays: usize,
    /// Shadow rays: median time per run.
    pub shadow: Timing,
    /// Reflection rays cast per run.
    pub reflect_rays: usize,
    /// Reflection rays: median time per run.
    pub reflect: Timing,
    /// Full frame.
    pub frame: Timing,
    /// Rays of all kinds in one frame.
    pub frame_rays: u64,
    /// The packets of the frame and of `eye_packet`.
    pub packets: Packets,
    /// Eye rays in packets (the same rays as `eye`, interleaved with it run by run):
    /// median time per run; zero when packets are off or the precision is not `f32`.
    pub eye_packet: Timing,
}

/// Median wall time and median process CPU time in ms of `runs` calls of `f`.
fn time_median(runs: usize, mut f: impl FnMut()) -> Timing {
    let (mut wall, mut cpu) = (Vec::new(), Vec::new());
    for _ in 0..runs.max(1) {
        let c = process_cpu_ms();
        let s = Instant::now();
        f();
        wall.push(s.elapsed().as_secs_f64() * 1e3);
        if let (Some(a), Some(b)) = (c, process_cpu_ms()) {
            cpu.push(b - a);
        }
    }
    Timing {
        wall: median(&wall),
        cpu: median(&cpu),
    }
}

/// A median wall-clock and CPU time, in ms.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timing {
    /// Wall-clock time.
    pub wall: f64,
    /// CPU time of all threads (0 where unavailable).
    pub cpu: f64,
}

fn mrays(n: usize, ms: f64) -> f64 {
    if ms > 0.0 {
        n as f64 / ms / 1e3
    } else {
        0.0
    }
}

/// Measures one scene in precision `T` on the current rayon pool.
pub fn bench_scene<T: tracer::Float>(
    name: &str,
    desc: &SceneDesc,
    opts: &BenchOptions,
) -> BenchRow {
    let mut builds = Vec::new();
    let mut scene = None;
    for _ in 0..opts.runs.max(1) {
        // Drop the previous scene first so peak memory stays that of one.
        drop(scene.take());
        let s = Instant::now();
        let built = Scene::<T>::from_desc(desc, &opts.accel);
        builds.push(s.elapsed().as_secs_f64() * 1e3);
        scene = Some(built);
    }
    let scene = scene.expect("at least one build");
    let g = scene.geometry.stats();
    let (w, h) = (opts.width, opts.height);
    let cam = scene.camera_for(w, h);

    // Eye rays through pixel centres.
    let eye: Vec<Ray<T>> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| {
            let px = T::from_f64(x as f64 + 0.5);
            let py = T::from_f64(y as f64 + 0.5);
            Ray::new(cam.position, cam.direction(px, py))
        })
        .collect();
    let mut hits = vec![None; eye.len()];
    let cast_eye = |hits: &mut [Option<tracer::ray::Hit<T>>]| {
        hits.par_chunks_mut(CHUNK)
            .zip(eye.par_chunks(CHUNK))
            .for_each(|(hs, rs)| {
                for (h, r) in hs.iter_mut().zip(rs) {
                    *h = scene.intersect(r);
                }
            });
    };
    // Packets of the same eye rays (f32 only), run by run alternating with single rays.
    let scene32 = (&scene as &dyn core::any::Any).downcast_ref::<Scene<f32>>();
    let cam32 = (&cam as &dyn core::any::Any).downcast_ref::<tracer::Camera<f32>>();
    let mut packets = match (opts.packets.isa(), cam32) {
        (Some(isa), Some(cam)) => Some(EyePackets::new(cam, isa)),
        _ => None,
    };
    let (mut eye_t, mut packet_t) = (Vec::new(), Vec::new());
    for _ in 0..opts.runs.max(1) {
        eye_t.push(time_median(1, || cast_eye(&mut hits)));
        if let (Some(p), Some(s)) = (packets.as_mut(), scene32) {
            packet_t.push(time_median(1, || p.cast(s)));
        }
    }
    let median_of = |t: &[Timing]| Timing {
        wall: median(&t.iter().map(|t| t.wall).collect::<Vec<_>>()),
        cpu: median(&t.iter().map(|t| t.cpu).collect::<Vec<_>>()),
    };
    let eye_ms = median_of(&eye_t);
    let eye_packet = median_of(&packet_t);

    // Shadow rays toward the first light and mirror rays, from every eye hit.
    let light = scene.lights.first().map(|l| l.position);
    let mut shadow: Vec<(Ray<T>, T)> = Vec::new();
    let mut reflect: Vec<Ray<T>> = Vec::new();
    for (r, h) in eye.iter().zip(&hits) {
        let Some(h) = h else { continue };
        let ng = if h.geometric_normal.dot(&r.dir) < T::ZERO {
            h.geometric_normal
        } else {
            (-&h.geometric_normal).eval()
        };
        let above = offset_ray(&h.point, &ng, &ng);
        if let Some(lp) = light {
            let to = (&lp - &h.point).eval();
            let dist = to.length();
            if dist > T::ZERO && dist.is_finite() {
                shadow.push((Ray::new(above, (&to).scale(dist.recip()).eval()), dist));
            }
        }
        reflect.push(Ray::new(above, r.dir.reflect(&ng).normalize()));
    }
    let mut occluded = vec![false; shadow.len()];
    let shadow_ms = time_median(opts.runs, || {
        occluded
            .par_chunks_mut(CHUNK)
            .zip(shadow.par_chunks(CHUNK))
            .for_each(|(os, rs)| {
                for (o, (r, d)) in os.iter_mut().zip(rs) {
                    *o = scene.occluded(&Ray { t_max: *d, ..*r });
                }
            });
    });
    let mut rhits = vec![None; reflect.len()];
    let reflect_ms = time_median(opts.runs, || {
        rhits
            .par_chunks_mut(CHUNK)
            .zip(reflect.par_chunks(CHUNK))
            .for_each(|(hs, rs)| {
                for (h, r) in hs.iter_mut().zip(rs) {
                    *h = scene.intersect(r);
                }
            });
    });

    let settings = Settings {
        width: Some(w),
        height: Some(h),
        depth: opts.depth,
        threads: opts.threads,
        schedule: opts.schedule,
        packets: opts.packets,
        ..Settings::default()
    };
    let (mut frames, mut frames_cpu) = (Vec::new(), Vec::new());
    let mut frame_rays = 0;
    for _ in 0..opts.runs.max(1) {
        let (_, st) = render_with_stats(&scene, &settings);
        frames.push(st.trace_ms);
        frames_cpu.push(st.trace_cpu_ms);
        frame_rays = st.rays.total();
    }

    BenchRow {
        scene: name.to_string(),
        primitives: g.spheres + g.triangles + g.cones,
        build_ms: median(&builds),
        nodes: g.bvh_nodes,
        bytes_per_prim: g.bytes_per_primitive(),
        eye_rays: eye.len(),
        eye: eye_ms,
        shadow_rays: shadow.len(),
        shadow: shadow_ms,
        reflect_rays: reflect.len(),
        reflect: reflect_ms,
        frame: Timing {
            wall: median(&frames),
            cpu: median(&frames_cpu),
        },
        frame_rays,
        packets: opts.packets,
        eye_packet,
    }
}

/// Reads the table printed by `povray-times` (`scene trace_s cpu_s rays shadow_rays`)
/// into `(scene, trace ms)` pairs; lines that do not parse are skipped.
pub fn parse_peer_times(text: &str) -> Vec<(String, f64)> {
    text.lines()
        .filter_map(|l| {
            let mut f = l.split_whitespace();
            let name = f.next()?;
            let s: f64 = f.next()?.parse().ok()?;
            Some((name.to_string(), s * 1e3))
        })
        .collect()
}

/// What the columns of [`table`] mean, printed below it.
pub const LEGEND: &str = "Columns: prims = primitives; build ms = geometry build \
(conversion, BVH, reordering); nodes = BVH nodes; B/prim = bytes of BVH and primitives per \
primitive; eye, shadow, reflect Mrays/s = millions of rays of that kind per wall-clock \
second (per CPU second of all threads in parentheses); frame ms = wall time of one whole \
render; frame CPU ms = its CPU time, all threads; frame Mrays/s = its rays of every kind per \
second; POV-Ray ms = the --peer frame time; POV-Ray / tracer = that over frame ms (- without \
--peer). Times are medians of --runs.";

/// What the columns of [`packet_table`] mean, printed below it.
pub const PACKET_LEGEND: &str = "Columns: packets = the instruction set of the packets; eye \
single and eye packet Mrays/s = eye rays traced one at a time and in packets, millions per \
wall-clock second (per CPU second in parentheses); packet / single = the speed-up; frame ms \
= one whole render.";

/// The Markdown table of `rows`, with the ratio peer frame time / tracer frame time
/// where `peer` has the scene. Throughputs are rays per wall-clock second and, in
/// parentheses, per CPU second of all threads together.
pub fn table(rows: &[BenchRow], peer: &[(String, f64)]) -> String {
    let mut s = String::from(
        "| scene | prims | build ms | nodes | B/prim | eye Mrays/s | shadow Mrays/s \
         | reflect Mrays/s | frame ms | frame CPU ms | frame Mrays/s | POV-Ray ms \
         | POV-Ray / tracer |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    let rate = |n: usize, t: &Timing| format!("{:.2} ({:.2})", mrays(n, t.wall), mrays(n, t.cpu));
    for r in rows {
        let p = peer.iter().find(|(n, _)| *n == r.scene).map(|p| p.1);
        let (pm, ratio) = match p {
            Some(ms) if r.frame.wall > 0.0 => {
                (format!("{ms:.0}"), format!("{:.2}", ms / r.frame.wall))
            }
            _ => ("-".into(), "-".into()),
        };
        s += &format!(
            "| {} | {} | {:.1} | {} | {:.1} | {} | {} | {} | {:.1} | {:.1} | {} | {} | {} |\n",
            r.scene,
            r.primitives,
            r.build_ms,
            r.nodes,
            r.bytes_per_prim,
            rate(r.eye_rays, &r.eye),
            rate(r.shadow_rays, &r.shadow),
            rate(r.reflect_rays, &r.reflect),
            r.frame.wall,
            r.frame.cpu,
            rate(r.frame_rays as usize, &r.frame),
            pm,
            ratio
        );
    }
    s
}

/// The Markdown table of eye-ray throughput with single rays and with packets (rows
/// without a packet measurement are left out; empty when there are none). Rays per
/// wall-clock second and, in parentheses, per CPU second.
pub fn packet_table(rows: &[BenchRow]) -> String {
    let rows: Vec<&BenchRow> = rows.iter().filter(|r| r.eye_packet.wall > 0.0).collect();
    if rows.is_empty() {
        return String::new();
    }
    let mut s = String::from(
        "| scene | packets | eye single Mrays/s | eye packet Mrays/s | packet / single | frame ms |\n\
         |---|---|---:|---:|---:|---:|\n",
    );
    let rate = |n: usize, t: &Timing| format!("{:.2} ({:.2})", mrays(n, t.wall), mrays(n, t.cpu));
    for r in rows {
        s += &format!(
            "| {} | {} | {} | {} | {:.2} | {:.1} |\n",
            r.scene,
            r.packets.name(),
            rate(r.eye_rays, &r.eye),
            rate(r.eye_rays, &r.eye_packet),
            r.eye.wall / r.eye_packet.wall,
            r.frame.wall,
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peer_table_parses() {
        let t = "scene trace_s cpu_s rays shadow_rays\nballs-s4 0.49 0.9 448962 950670\nbad\n";
        assert_eq!(parse_peer_times(t), vec![("balls-s4".to_string(), 490.0)]);
    }
}
