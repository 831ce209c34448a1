//! Cost of invalid rays against valid ones (Embree's `verify` criterion: at most 2.5x).
//!
//! ```sh
//! cargo run --release -p tracer --example invalid_rays [SCENE.nff] [ROUNDS]
//! ```
//!
//! Valid rays are eye rays through random image points; the invalid set is the same rays
//! with a NaN or infinite origin component, an infinite or zero direction, or a NaN
//! `t_max`, in turn. Each round times both sets with `intersect` and with `occluded`,
//! alternating which goes first; the medians over the rounds and their ratios are printed.

use std::hint::black_box;
use std::time::Instant;
use tracer::geometry::AccelOptions;
use tracer::{Ray, Scene};
use vecexpr::vec3;

fn main() {
    let mut args = std::env::args().skip(1);
    let path = args.next().unwrap_or_else(|| {
        concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/teapot-s1.nff").to_string()
    });
    let rounds: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(21);
    let desc = match tracer::scene::load(std::path::Path::new(&path)) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let scene = Scene::<f32>::from_desc(&desc, &AccelOptions::default());
    let cam = scene.camera_for(512, 512);
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut rnd = move || {
        state ^= state >> 12;
        state ^= state << 25;
        state ^= state >> 27;
        (state.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 40) as f32 / (1u32 << 24) as f32
    };
    let n = 200_000;
    let valid: Vec<Ray<f32>> = (0..n)
        .map(|_| Ray::new(cam.position, cam.direction(rnd() * 512.0, rnd() * 512.0)))
        .collect();
    let invalid: Vec<Ray<f32>> = valid
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let mut r = *r;
            match i % 5 {
                0 => r.origin[i % 3] = f32::NAN,
                1 => r.origin[i % 3] = f32::INFINITY,
                2 => r.dir[i % 3] = f32::NEG_INFINITY,
                3 => r.dir = vec3(0.0, 0.0, 0.0),
                _ => r.t_max = f32::NAN,
            }
            r
        })
        .collect();
    let hits = valid
        .iter()
        .filter(|r| scene.intersect(r).is_some())
        .count();
    let closest = |rays: &[Ray<f32>]| {
        let t = Instant::now();
        let mut k = 0usize;
        for r in rays {
            k += black_box(scene.intersect(black_box(r))).is_some() as usize;
        }
        black_box(k);
        t.elapsed().as_secs_f64() * 1e9 / rays.len() as f64
    };
    let any = |rays: &[Ray<f32>]| {
        let t = Instant::now();
        let mut k = 0usize;
        for r in rays {
            k += black_box(scene.geometry.occluded(black_box(r))) as usize;
        }
        black_box(k);
        t.elapsed().as_secs_f64() * 1e9 / rays.len() as f64
    };
    let mut m: [Vec<f64>; 4] = Default::default();
    for round in 0..rounds {
        let order: [usize; 4] = if round % 2 == 0 {
            [0, 1, 2, 3]
        } else {
            [3, 2, 1, 0]
        };
        for k in order {
            let ns = match k {
                0 => closest(&valid),
                1 => closest(&invalid),
                2 => any(&valid),
                _ => any(&invalid),
            };
            m[k].push(ns);
        }
    }
    let med = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let [a, b, c, d] = m.each_mut().map(med);
    println!(
        "{path}: {n} rays ({hits} valid ones hit), {rounds} rounds, median ns/ray\n\
         intersect: valid {a:.1}, invalid {b:.1}, invalid/valid {:.3}\n\
         occluded:  valid {c:.1}, invalid {d:.1}, invalid/valid {:.3}",
        b / a,
        d / c
    );
}
