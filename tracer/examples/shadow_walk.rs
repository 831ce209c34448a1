//! Shadow rays alone, as `benches/embree` casts them: from every eye hit through the
//! pixel centres (offset off the surface as in shading) toward the scene's first light,
//! any hit before the light, one ray at a time ([`tracer::Scene::occluded`]).
//!
//! ```sh
//! cargo run --profile perf -p tracer --example shadow_walk -- [--runs N] [--threads N] \
//!     [--size WxH] [--four-wide] [--no-avx512] SCENE...
//! ```
//!
//! Prints one Markdown row per scene: the shadow rays, the share blocked and the median
//! Mrays per second over `--runs` rounds. For an instruction count, run it under
//! callgrind with `--toggle-collect='*cast_shadow*'` and divide by rays x runs.
//! `--four-wide` and `--no-avx512` as for the `packet_walk` example.

use rayon::prelude::*;
use std::process::ExitCode;
use std::time::Instant;
use tracer::geometry::offset_ray;
use tracer::stats::median;
use tracer::{Ray, Scene};
use vecexpr::Expr;

struct Options {
    runs: usize,
    threads: usize,
    size: (u32, u32),
    four_wide: bool,
    no_avx512: bool,
    scenes: Vec<String>,
}

fn parse_args() -> Result<Options, String> {
    let mut o = Options {
        runs: 5,
        threads: 1,
        size: (512, 512),
        four_wide: false,
        no_avx512: false,
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
            "--threads" => {
                o.threads = value("--threads")?
                    .parse()
                    .map_err(|e| format!("--threads: {e}"))?
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
            "--four-wide" => o.four_wide = true,
            "--no-avx512" => o.no_avx512 = true,
            s if s.starts_with("--") => return Err(format!("unknown option {s}")),
            s => o.scenes.push(s.to_string()),
        }
    }
    if o.scenes.is_empty() {
        return Err("usage: shadow_walk [--runs N] [--threads N] [--size WxH] SCENE...".into());
    }
    Ok(o)
}

/// The shadow rays of `benches/embree`: from each eye hit toward `light`, `t_max` at it.
fn shadow_rays(scene: &Scene<f32>, (w, h): (u32, u32)) -> Vec<Ray<f32>> {
    let Some(light) = scene.lights.first().map(|l| l.position) else {
        return Vec::new();
    };
    let cam = scene.camera_for(w, h);
    let mut out = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let r = Ray::new(cam.position, cam.direction(x as f32 + 0.5, y as f32 + 0.5));
            let Some(hit) = scene.intersect(&r) else {
                continue;
            };
            let ng = if hit.geometric_normal.dot(&r.dir) < 0.0 {
                hit.geometric_normal
            } else {
                (-&hit.geometric_normal).eval()
            };
            let above = offset_ray(&hit.point, &ng, &ng);
            let to = (&light - &hit.point).eval();
            let dist = to.length();
            if dist > 0.0 && dist.is_finite() {
                let dir = (&to).scale(dist.recip()).eval();
                out.push(Ray {
                    t_max: dist,
                    ..Ray::new(above, dir)
                });
            }
        }
    }
    out
}

/// Casts every shadow ray alone on the current pool; the number blocked. (A function of
/// its own, so that callgrind can count it alone.)
#[inline(never)]
fn cast_shadow(scene: &Scene<f32>, rays: &[Ray<f32>]) -> usize {
    rays.par_iter()
        .with_min_len(256)
        .filter(|r| scene.occluded(r))
        .count()
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
        "{} thread(s), {}x{}, {} rounds; median Mrays/s",
        o.threads, o.size.0, o.size.1, o.runs
    );
    println!();
    println!("| scene | shadow rays | blocked | Mrays/s |");
    println!("|---|---:|---:|---:|");
    for path in &o.scenes {
        let desc = match tracer::scene::load(std::path::Path::new(path)) {
            Ok(d) => d,
            Err(e) => {
                eprintln!("{e}");
                return ExitCode::from(2);
            }
        };
        let accel = tracer::geometry::AccelOptions {
            eight_wide: !o.four_wide,
            avx512: !o.no_avx512,
            ..Default::default()
        };
        let scene: Scene<f32> = Scene::from_desc(&desc, &accel);
        let rays = shadow_rays(&scene, o.size);
        let n = rays.len() as f64;
        let mut blocked = 0;
        let mut times = Vec::new();
        for _ in 0..o.runs {
            pool.install(|| {
                let s = Instant::now();
                blocked = std::hint::black_box(cast_shadow(&scene, &rays));
                times.push(n / s.elapsed().as_secs_f64() * 1e-6);
            });
        }
        let name = std::path::Path::new(path)
            .file_name()
            .map_or(path.clone(), |f| f.to_string_lossy().into_owned());
        println!(
            "| {name} | {} | {:.1}% | {:.2} |",
            rays.len(),
            100.0 * blocked as f64 / n.max(1.0),
            median(&times)
        );
    }
    ExitCode::SUCCESS
}
