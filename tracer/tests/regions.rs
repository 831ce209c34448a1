//! Rendering part of the image (`Settings::region`): every pixel of a region is bit for
//! bit the pixel of the full render, for random regions and for regions that tile the
//! image, in f32 and f64, with and without packets, supersampling and SPD corners.

use proptest::prelude::*;
use std::path::Path;
use tracer::geometry::AccelOptions;
use tracer::packets::Packets;
use tracer::render::{render_with_stats, PixelBounds, Settings};
use tracer::{Float, Image, Scene};

fn scene<T: Float>(name: &str) -> Scene<T> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name);
    Scene::from_desc(&tracer::scene::load(&path).unwrap(), &AccelOptions::default())
}

/// Does `part` hold, bit for bit (`to_bits`), the pixels `b` of `full`?
fn same_pixels(full: &Image, part: &Image, b: PixelBounds) -> bool {
    (part.width, part.height) == (b.width(), b.height())
        && (b.y0..b.y1).all(|y| {
            (b.x0..b.x1).all(|x| {
                let (p, q) = (full.get(x, y), part.get(x - b.x0, y - b.y0));
                p.iter().zip(&q).all(|(a, c)| a.to_bits() == c.to_bits())
            })
        })
}

const W: u32 = 29;
const H: u32 = 23;

fn settings(aa: u32, spd: bool, packets: Packets) -> Settings {
    Settings {
        width: Some(W),
        height: Some(H),
        aa,
        spd,
        packets,
        ..Settings::default()
    }
}

/// Random bounds inside the image, at least one pixel.
fn bounds() -> impl Strategy<Value = PixelBounds> {
    (0..W, 1..=W, 0..H, 1..=H).prop_map(|(a, b, c, d)| PixelBounds {
        x0: a.min(b - 1),
        x1: b.max(a + 1),
        y0: c.min(d - 1),
        y1: d.max(c + 1),
    })
}

fn check_regions<T: Float>(name: &str, cases: &[PixelBounds]) {
    let s = scene::<T>(name);
    for (aa, spd) in [(1, false), (2, false), (1, true)] {
        for packets in [Packets::Off, Packets::auto()] {
            let base = settings(aa, spd, packets);
            let (full, _) = render_with_stats(&s, &base);
            for &b in cases {
                let part = render_with_stats(
                    &s,
                    &Settings {
                        region: Some(b),
                        ..base.clone()
                    },
                )
                .0;
                assert!(
                    same_pixels(&full, &part, b),
                    "{name} {b} aa {aa} spd {spd} packets {}",
                    packets.name()
                );
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]

    #[test]
    fn random_regions_are_the_full_render_f32(b in bounds()) {
        check_regions::<f32>("showcase.nff", &[b]);
    }

    #[test]
    fn random_regions_are_the_full_render_f64(b in bounds()) {
        check_regions::<f64>("balls-s1.nff", &[b]);
    }
}

/// Regions that tile the image add up to it: the ray counts of the parts sum to the
/// full render's (SPD corners on a tile's edge are traced by both tiles, so SPD is left
/// out of the sum).
#[test]
fn bands_sum_to_the_full_render() {
    let s = scene::<f32>("tetra-s1.nff");
    let base = settings(1, false, Packets::auto());
    let (full, stats) = render_with_stats(&s, &base);
    let cuts = [0, 5, 6, 17, H];
    let mut rays = tracer::RayCounts::default();
    for w in cuts.windows(2) {
        let b = PixelBounds {
            x0: 0,
            x1: W,
            y0: w[0],
            y1: w[1],
        };
        let (part, st) = render_with_stats(
            &s,
            &Settings {
                region: Some(b),
                ..base.clone()
            },
        );
        assert!(same_pixels(&full, &part, b), "{b}");
        rays += st.rays;
    }
    assert_eq!(rays, stats.rays);
}

#[test]
#[should_panic(expected = "outside")]
fn bounds_outside_the_image_panic() {
    let s = scene::<f32>("balls-s1.nff");
    let region = Some(PixelBounds {
        x0: 0,
        x1: W + 1,
        y0: 0,
        y1: H,
    });
    render_with_stats(
        &s,
        &Settings {
            region,
            ..settings(1, false, Packets::Off)
        },
    );
}
