//! Specialised against general renderer, per scene, interleaved.
//!
//! ```sh
//! cargo run --profile perf -p tracer --example effects -- ../shared/scenes/spd
//! cargo run --profile perf -p tracer --example effects -- --runs 11 --threads 2 DIR_OR_SCENE...
//! ```
//!
//! For each scene (a file, or the SPD scenes at their published sizes found in a
//! directory; missing ones are skipped) the scene is loaded once, both renderers run once
//! to warm up, then `--runs` times each, alternating which goes first. Every run's image
//! and ray counts must equal the general renderer's, else the program stops. Printed: a
//! Markdown table of median trace times (wall clock, and CPU time of all threads, which
//! another process's load on the machine disturbs less) and their ratios.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;
use tracer::effects::{EffectSet, EffectsMode};
use tracer::geometry::AccelOptions;
use tracer::render::{render_with_stats, Settings};
use tracer::stats::median;
use tracer::{Image, RayCounts, Scene};

/// The SPD scenes at their published sizes (size 1 is the default of the last four).
const SPD: [&str; 12] = [
    "balls-s4",
    "gears-s4",
    "mount-s6",
    "rings-s7",
    "teapot-s12",
    "tetra-s6",
    "tree-s11",
    "lattice-s12",
    "shells-s5",
    "jacks-s1",
    "sombrero-s1",
    "nurbtst-s1",
];

struct Options {
    runs: usize,
    threads: usize,
    spd: bool,
    scenes: Vec<PathBuf>,
}

fn parse_args() -> Result<Options, String> {
    let mut o = Options {
        runs: 7,
        threads: 1,
        spd: false,
        scenes: Vec::new(),
    };
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut number = |what: &str| -> Result<usize, String> {
            args.next()
                .and_then(|v| v.parse().ok())
                .filter(|&n| n > 0)
                .ok_or_else(|| format!("{what} needs a positive number"))
        };
        match a.as_str() {
            "--runs" => o.runs = number("--runs")?,
            "--threads" => o.threads = number("--threads")?,
            "--spd" => o.spd = true,
            _ => {
                let p = PathBuf::from(&a);
                if p.is_dir() {
                    o.scenes.extend(
                        SPD.iter()
                            .map(|s| p.join(format!("{s}.nff")))
                            .filter(|f| f.is_file()),
                    );
                } else if p.is_file() {
                    o.scenes.push(p);
                } else {
                    return Err(format!("{a}: no such file or directory"));
                }
            }
        }
    }
    if o.scenes.is_empty() {
        return Err("usage: effects [--runs N] [--threads N] [--spd] DIR_OR_SCENE...".into());
    }
    Ok(o)
}

/// CPU time of all threads of this process so far, in ms (Linux: the run time in
/// `/proc/self/task/*/schedstat`, which has nanosecond resolution); `None` elsewhere.
fn cpu_ms() -> Option<f64> {
    let mut ns = 0u64;
    for task in std::fs::read_dir("/proc/self/task").ok()? {
        let text = std::fs::read_to_string(task.ok()?.path().join("schedstat")).ok()?;
        ns += text.split_whitespace().next()?.parse::<u64>().ok()?;
    }
    Some(ns as f64 * 1e-6)
}

/// Are the images equal bit for bit?
fn same_bits(a: &Image, b: &Image) -> bool {
    (a.width, a.height) == (b.width, b.height)
        && a.pixels
            .iter()
            .flatten()
            .zip(b.pixels.iter().flatten())
            .all(|(x, y)| x.to_bits() == y.to_bits())
}

/// One timed render: image, rays, wall ms, CPU ms.
fn run(pool: &rayon::ThreadPool, scene: &Scene<f32>, s: &Settings) -> (Image, RayCounts, f64, f64) {
    let cpu0 = cpu_ms();
    let t0 = Instant::now();
    let (img, st) = pool.install(|| render_with_stats(scene, s));
    let wall = t0.elapsed().as_secs_f64() * 1e3;
    let cpu = match (cpu0, cpu_ms()) {
        (Some(a), Some(b)) => b - a,
        _ => f64::NAN,
    };
    (img, st.rays, wall, cpu)
}

fn bench(path: &Path, o: &Options) -> Result<String, String> {
    let desc = tracer::scene::load(path).map_err(|e| e.to_string())?;
    let scene = Scene::<f32>::from_desc(&desc, &AccelOptions::default());
    // One pool for all runs, so its threads' CPU time can be read.
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(o.threads)
        .build()
        .map_err(|e| e.to_string())?;
    let base = Settings {
        spd: o.spd,
        ..Settings::default()
    };
    let general = Settings {
        effects: EffectsMode::All,
        ..base.clone()
    };
    let (reference, rays, _, _) = run(&pool, &scene, &general);
    let (_, st) = render_with_stats(&scene, &base);
    let chosen: EffectSet = st.effects.renderer;
    // [general, specialised] wall and CPU times.
    let mut wall = [Vec::new(), Vec::new()];
    let mut cpu = [Vec::new(), Vec::new()];
    for i in 0..o.runs {
        for k in [i % 2, 1 - i % 2] {
            let s = if k == 0 { &general } else { &base };
            let (img, r, w, c) = run(&pool, &scene, s);
            if !same_bits(&img, &reference) || r != rays {
                return Err(format!(
                    "{}: the {} renderer's image or ray counts differ",
                    path.display(),
                    if k == 0 { "general" } else { "specialised" }
                ));
            }
            wall[k].push(w);
            cpu[k].push(c);
        }
    }
    let name = path.file_stem().unwrap_or_default().to_string_lossy();
    let [wg, ws] = wall.map(|v| median(&v));
    let [cg, cs] = cpu.map(|v| median(&v));
    Ok(format!(
        "| {name} | {} | {} | {wg:.1} | {ws:.1} | {:.2} | {cg:.1} | {cs:.1} | {:.2} |",
        chosen.names().join(" "),
        rays.total(),
        wg / ws,
        cg / cs
    ))
}

fn main() -> ExitCode {
    let o = match parse_args() {
        Ok(o) => o,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::from(2);
        }
    };
    println!(
        "{} runs each, interleaved, {} thread(s), {}; medians in ms",
        o.runs,
        o.threads,
        if o.spd {
            "SPD rules"
        } else {
            "default settings"
        }
    );
    println!();
    println!("| scene | specialised for | rays | general wall | specialised wall | ratio | general CPU | specialised CPU | ratio |");
    println!("|---|---|---:|---:|---:|---:|---:|---:|---:|");
    for path in &o.scenes {
        match bench(path, &o) {
            Ok(row) => println!("{row}"),
            Err(e) => {
                eprintln!("{e}");
                return ExitCode::from(2);
            }
        }
    }
    ExitCode::SUCCESS
}
