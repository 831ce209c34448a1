//! How fast vecexpr runs in an unoptimised build: 10^6 normalize + reflect of `f32`
//! 3-vectors, timed with the wall clock. Expression templates lean on inlining, so the
//! profile the *user's* crate compiles vecexpr with matters; `vecexpr/README.md` has the
//! measurements with opt-level 0, 1 and 3 for vecexpr and the command that took them.
//!
//! Run with `cargo run -p vecexpr --example debug_build` (add `--release` for the
//! optimised baseline).

use std::hint::black_box;
use std::time::Instant;
use vecexpr::{vec3, Expr, Vec3};

const N: usize = 1_000_000;
const RUNS: usize = 5;

fn main() {
    // Deterministic inputs (a linear congruential generator), never normalised before.
    let mut state = 0x2545_f491u32;
    let mut next = || {
        state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (state >> 8) as f32 / (1u32 << 24) as f32 - 0.5
    };
    let dirs: Vec<Vec3<f32>> = (0..N).map(|_| vec3(next(), next(), next())).collect();
    let n = vec3(0.0f32, 1.0, 0.0);

    let mut times = Vec::with_capacity(RUNS);
    let mut check = 0.0f32;
    for _ in 0..RUNS {
        let t0 = Instant::now();
        let mut acc = Vec3::<f32>::zero();
        for d in black_box(&dirs) {
            let r = d.normalize().reflect(black_box(&n));
            acc += &r;
        }
        times.push(t0.elapsed().as_secs_f64());
        check = black_box(acc).sum();
    }
    times.sort_by(f64::total_cmp);
    println!(
        "10^6 normalize + reflect: median {:.1} ms (min {:.1} ms) over {RUNS} runs; checksum {check}",
        times[RUNS / 2] * 1e3,
        times[0] * 1e3,
    );
}
