//! Every scheduler, tile size and thread count gives the same image and ray counts bit
//! for bit, and the four-wide BVH gives the same image as the binary one.

use std::path::Path;
use tracer::geometry::AccelOptions;
use tracer::render::{render_with_stats, Schedule, Scheduler, Settings};
use tracer::Scene;

fn scene(name: &str, accel: &AccelOptions) -> Scene<f32> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name);
    Scene::from_desc(&tracer::scene::load(&path).unwrap(), accel)
}

/// The same image bit for bit: `to_bits` per channel (+0 and -0 differ, a NaN equals
/// itself), which `==` on floats is not.
fn same_bits(a: &tracer::Image, b: &tracer::Image) -> bool {
    (a.width, a.height) == (b.width, b.height)
        && a.pixels
            .iter()
            .flatten()
            .zip(b.pixels.iter().flatten())
            .all(|(x, y)| x.to_bits() == y.to_bits())
}

#[test]
fn schedulers_tiles_and_threads_agree() {
    for name in ["balls-s1.nff", "showcase.nff"] {
        let s = scene(name, &AccelOptions::default());
        for spd in [false, true] {
            let base = Settings {
                width: Some(37),
                height: Some(29),
                spd,
                ..Settings::default()
            };
            let (reference, rc) = render_with_stats(&s, &base);
            for (scheduler, tile) in [
                (Scheduler::Rayon, 16),
                (Scheduler::Static, 16),
                (Scheduler::Tiles, 1),
                (Scheduler::Tiles, 8),
                (Scheduler::Tiles, 64),
            ] {
                for threads in [1, 2, 3] {
                    let settings = Settings {
                        threads: Some(threads),
                        schedule: Schedule { scheduler, tile },
                        ..base.clone()
                    };
                    let (img, st) = render_with_stats(&s, &settings);
                    let what =
                        format!("{name} spd={spd} {scheduler:?} tile {tile}, {threads} threads");
                    assert!(same_bits(&img, &reference), "{what}: image differs");
                    assert_eq!(st.rays, rc.rays, "{what}: ray counts differ");
                }
            }
        }
    }
}

#[test]
fn wide_and_binary_bvh_give_the_same_image() {
    for name in [
        "balls-s1.nff",
        "gears-s1.nff",
        "teapot-s1.nff",
        "showcase.nff",
    ] {
        let wide = scene(name, &AccelOptions::default());
        let binary = scene(
            name,
            &AccelOptions {
                wide: false,
                ..AccelOptions::default()
            },
        );
        let settings = Settings {
            width: Some(48),
            height: Some(48),
            ..Settings::default()
        };
        let (a, ra) = render_with_stats(&wide, &settings);
        let (b, rb) = render_with_stats(&binary, &settings);
        assert!(same_bits(&a, &b), "{name}: images differ");
        assert_eq!(ra.rays, rb.rays, "{name}: ray counts differ");
    }
}
