//! BVH build time and tree quality per scene.
//!
//! ```sh
//! cargo run --profile perf -p tracer --example bvh_build -- [--runs N] [--threads N] SCENE...
//! ```
//!
//! For each scene the geometry (`f32`) is built `--runs` times with the BVH and as many
//! times without it, alternating. Printed, as a Markdown table: primitives, the median
//! geometry build with the BVH (conversion, bounds, SAH build, wide collapse, reordering),
//! the median without it (conversion only) and their difference (the BVH's share, in
//! wall-clock and in process CPU time of all threads, which load on the machine
//! disturbs less), the
//! binary and four-wide node counts and depths, the SAH cost of the binary tree
//! ([`tracer::bvh::Bvh::sah_cost`] with the default traversal cost) and the bytes per
//! primitive of BVH plus primitive data.

use std::path::PathBuf;
use std::process::ExitCode;
use tracer::bvh::build::TRAVERSAL_COST;
use tracer::geometry::{AccelOptions, Geometry};
use tracer::stats::{median, process_cpu_ms};

fn main() -> ExitCode {
    let mut runs = 5usize;
    let mut threads = 0usize;
    let mut scenes = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let num = |v: Option<String>| v.and_then(|v| v.parse::<usize>().ok());
        match a.as_str() {
            "--runs" => match num(args.next()) {
                Some(n) if n > 0 => runs = n,
                _ => return usage(),
            },
            "--threads" => match num(args.next()) {
                Some(n) => threads = n,
                None => return usage(),
            },
            _ if a.starts_with("--") => return usage(),
            _ => scenes.push(PathBuf::from(a)),
        }
    }
    if scenes.is_empty() {
        return usage();
    }
    let pool = match rayon::ThreadPoolBuilder::new().num_threads(threads).build() {
        Ok(p) => p,
        Err(e) => {
            eprintln!("cannot create the thread pool: {e}");
            return ExitCode::from(2);
        }
    };
    println!(
        "| scene | prims | build ms | without BVH ms | BVH ms | BVH CPU ms | nodes | wide nodes | depth \
         | wide depth | SAH cost | B/prim |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for path in &scenes {
        let desc = match tracer::scene::load(path) {
            Ok(d) => d,
            Err(e) => {
                eprintln!("{e}");
                return ExitCode::from(2);
            }
        };
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let name = name.split('.').next().unwrap_or_default().to_string();
        let with = AccelOptions::default();
        let without = AccelOptions {
            use_bvh: false,
            ..AccelOptions::default()
        };
        let (mut t_with, mut t_without) = (Vec::new(), Vec::new());
        let (mut c_with, mut c_without) = (Vec::new(), Vec::new());
        let mut last = None;
        pool.install(|| {
            for i in 0..runs {
                // Drop the previous geometry first so that only one is alive at a time.
                drop(last.take());
                let order = if i % 2 == 0 {
                    [true, false]
                } else {
                    [false, true]
                };
                for bvh in order {
                    let c0 = process_cpu_ms().unwrap_or(0.0);
                    let g =
                        Geometry::<f32>::build(&desc.shapes, if bvh { &with } else { &without });
                    let cpu = process_cpu_ms().unwrap_or(0.0) - c0;
                    if bvh {
                        t_with.push(g.stats().build_ms);
                        c_with.push(cpu);
                        last = Some(g);
                    } else {
                        t_without.push(g.stats().build_ms);
                        c_without.push(cpu);
                    }
                }
            }
        });
        let Some(g) = last else { continue };
        let s = g.stats();
        let (a, b) = (median(&t_with), median(&t_without));
        let (ca, cb) = (median(&c_with), median(&c_without));
        let (wide, wide_depth, sah) = g.bvh().map_or((0, 0, 0.0), |b| {
            (
                b.wide_nodes().len(),
                b.wide_depth(),
                b.sah_cost(TRAVERSAL_COST),
            )
        });
        println!(
            "| {name} | {} | {a:.1} | {b:.1} | {:.1} | {:.1} | {} | {wide} | {} | {wide_depth} | {sah:.3} | {:.1} |",
            s.spheres + s.triangles + s.cones,
            a - b,
            ca - cb,
            s.bvh_nodes,
            s.bvh_depth,
            s.bytes_per_primitive()
        );
    }
    ExitCode::SUCCESS
}

fn usage() -> ExitCode {
    eprintln!("usage: bvh_build [--runs N] [--threads N] SCENE...");
    ExitCode::from(2)
}
