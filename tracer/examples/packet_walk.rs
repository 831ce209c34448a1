//! Eye rays three ways on the same scenes, interleaved run by run: single rays over the
//! four-wide BVH, packets over the binary BVH and packets over the four-wide BVH (with
//! hand-over to single rays where few rays of a packet are left).
//!
//! ```sh
//! cargo run --profile perf -p tracer --example packet_walk -- [--runs N] [--threads N] \
//!     [--isa sse2|avx2|avx512] [--size WxH] [--only single|binary|wide] \
//!     [--traversal-cost C] [--max-leaf N] [--tile N] [--four-wide] [--no-avx512] SCENE...
//! ```
//!
//! Prints one Markdown row per scene: median Mrays per second of each way over `--runs`
//! rounds (the three alternate within a round), and the ratios. Each way writes every
//! ray's hit record into a buffer, as a renderer keeps them (and as `tracer bench`
//! times both). Every packet hit is
//! checked against the single-ray hit of its pixel once, before timing. With
//! `--only single|binary|wide` only that way is run, once per round and unchecked (for
//! an instruction count under callgrind). Single rays are cast in row order, or with
//! `--tile N` tile by tile (N x N pixels, tiles in row order). `--four-wide` keeps single
//! rays on the four-wide tree, `--no-avx512` on the AVX2 compilation of the eight-wide
//! walk where the CPU has AVX-512 ([`AccelOptions::avx512`]).

use rayon::prelude::*;
use std::process::ExitCode;
use std::time::Instant;
use tracer::geometry::AccelOptions;
use tracer::packets::EyePackets;
use tracer::stats::median;
use tracer::{Hit, Ray, Scene};
use vecexpr::simd::Isa;

struct Options {
    runs: usize,
    threads: usize,
    isa: Isa,
    size: (u32, u32),
    only: Option<usize>,
    tile: usize,
    accel: AccelOptions,
    scenes: Vec<String>,
}

fn parse_args() -> Result<Options, String> {
    let mut o = Options {
        runs: 5,
        threads: 1,
        isa: Isa::detect().ok_or("no SIMD instruction set")?,
        size: (512, 512),
        only: None,
        tile: 0,
        accel: AccelOptions::default(),
        scenes: Vec::new(),
    };
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = |name: &str| args.next().ok_or(format!("{name}: missing value"));
        match a.as_str() {
            "--runs" => {
                o.runs = value("--runs")?
                    .parse()
                    .map_err(|e| format!("--runs: {e}"))?
            }
            "--tile" => {
                o.tile = value("--tile")?
                    .parse()
                    .map_err(|e| format!("--tile: {e}"))?
            }
            "--threads" => {
                o.threads = value("--threads")?
                    .parse()
                    .map_err(|e| format!("--threads: {e}"))?
            }
            "--isa" => {
                let v = value("--isa")?;
                o.isa = Isa::from_name(&v)
                    .filter(|i| i.is_available())
                    .ok_or(format!("--isa {v}: not available"))?;
            }
            "--size" => {
                let v = value("--size")?;
                let (w, h) = v
                    .split_once('x')
                    .ok_or(format!("--size {v}: expected WxH"))?;
                o.size = (
                    w.parse().map_err(|e| format!("--size: {e}"))?,
                    h.parse().map_err(|e| format!("--size: {e}"))?,
                );
            }
            "--traversal-cost" => {
                let v = value("--traversal-cost")?;
                o.accel.traversal_cost = v.parse().map_err(|e| format!("--traversal-cost: {e}"))?;
            }
            "--four-wide" => o.accel.eight_wide = false,
            "--no-avx512" => o.accel.avx512 = false,
            "--max-leaf" => {
                let v = value("--max-leaf")?;
                o.accel.max_leaf_size = v.parse().map_err(|e| format!("--max-leaf: {e}"))?;
            }
            "--only" => {
                let v = value("--only")?;
                let k = ["single", "binary", "wide"].iter().position(|w| *w == v);
                o.only = Some(k.ok_or(format!("--only {v}: expected single, binary or wide"))?);
            }
            s if s.starts_with("--") => return Err(format!("unknown option {s}")),
            s => o.scenes.push(s.to_string()),
        }
    }
    if o.scenes.is_empty() {
        return Err(
            "usage: packet_walk [--runs N] [--threads N] [--isa ISA] [--size WxH] SCENE...".into(),
        );
    }
    Ok(o)
}

/// Casts every ray alone on the current pool, its hit record into `out` (as the packets
/// write theirs, and as `tracer bench` times single rays). (A function of its own, so
/// that callgrind can count it alone: `--toggle-collect='*cast_single*'`.)
#[inline(never)]
fn cast_single(scene: &Scene<f32>, rays: &[Ray<f32>], out: &mut [Option<Hit<f32>>]) {
    out.par_iter_mut()
        .zip(rays.par_iter())
        .with_min_len(256)
        .for_each(|(h, r)| *h = scene.intersect(r));
}

fn main() -> ExitCode {
    let o = match parse_args() {
        Ok(o) => o,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::from(2);
        }
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(o.threads)
        .build()
        .expect("thread pool");
    println!(
        "{} thread(s), {}x{}, {} packets, {} rounds; median Mrays/s",
        o.threads, o.size.0, o.size.1, o.isa, o.runs
    );
    println!();
    println!("| scene | single, wide | packets, binary | packets, wide | wide / binary packets | wide packets / single |");
    println!("|---|---:|---:|---:|---:|---:|");
    for path in &o.scenes {
        let desc = match tracer::scene::load(std::path::Path::new(path)) {
            Ok(d) => d,
            Err(e) => {
                eprintln!("{e}");
                return ExitCode::from(2);
            }
        };
        let wide: Scene<f32> = Scene::from_desc(&desc, &o.accel);
        let binary: Scene<f32> = Scene::from_desc(
            &desc,
            &AccelOptions {
                wide: false,
                ..o.accel
            },
        );
        let cam = wide.camera_for(o.size.0, o.size.1);
        let (w, h) = (o.size.0 as usize, o.size.1 as usize);
        let pixels: Vec<(usize, usize)> = if o.tile == 0 {
            (0..w * h).map(|k| (k % w, k / w)).collect()
        } else {
            let t = o.tile;
            let mut v = Vec::with_capacity(w * h);
            for ty in (0..h).step_by(t) {
                for tx in (0..w).step_by(t) {
                    for y in ty..(ty + t).min(h) {
                        for x in tx..(tx + t).min(w) {
                            v.push((x, y));
                        }
                    }
                }
            }
            v
        };
        let rays: Vec<Ray<f32>> = pixels
            .iter()
            .map(|&(x, y)| Ray::new(cam.position, cam.direction(x as f32 + 0.5, y as f32 + 0.5)))
            .collect();
        let mut single_hits = vec![None; rays.len()];
        let mut pw = EyePackets::new(&cam, o.isa);
        let mut pb = EyePackets::new(&cam, o.isa);
        if o.only.is_none() {
            pool.install(|| {
                pw.cast(&wide);
                pb.cast(&binary);
            });
            for (r, &(x, y)) in rays.iter().zip(&pixels) {
                let single = wide.intersect(r).map(|h| h.t.to_bits());
                assert_eq!(
                    pw.get(x, y).map(|h| h.t.to_bits()),
                    single,
                    "{path} ({x}, {y})"
                );
                assert_eq!(
                    pb.get(x, y).map(|h| h.t.to_bits()),
                    single,
                    "{path} ({x}, {y})"
                );
            }
        }
        let mut times = [Vec::new(), Vec::new(), Vec::new()];
        let n = rays.len() as f64;
        for _ in 0..o.runs {
            pool.install(|| {
                let run = |k: usize| o.only.is_none_or(|only| only == k);
                if run(0) {
                    let s = Instant::now();
                    cast_single(&wide, &rays, &mut single_hits);
                    std::hint::black_box(&single_hits);
                    times[0].push(n / s.elapsed().as_secs_f64() * 1e-6);
                }
                if run(1) {
                    let s = Instant::now();
                    pb.cast(&binary);
                    times[1].push(n / s.elapsed().as_secs_f64() * 1e-6);
                }
                if run(2) {
                    let s = Instant::now();
                    pw.cast(&wide);
                    times[2].push(n / s.elapsed().as_secs_f64() * 1e-6);
                }
            });
        }
        let [single, bin, wid] = times.map(|v| median(&v));
        let name = std::path::Path::new(path)
            .file_name()
            .map_or(path.clone(), |f| f.to_string_lossy().into_owned());
        println!(
            "| {name} | {single:.2} | {bin:.2} | {wid:.2} | {:.2} | {:.2} |",
            wid / bin,
            wid / single
        );
    }
    ExitCode::SUCCESS
}
