//! Image error against a reference, and the Pareto front of error against time.

use tracer::image::Image;

/// The error of an image against a reference, on values clamped to [0, 1].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Metrics {
    /// Root-mean-square error over all channels of all pixels.
    pub rmse: f64,
    /// Peak signal-to-noise ratio in dB, peak 1 ($+\infty$ for identical images).
    pub psnr: f64,
    /// Largest absolute difference of a channel.
    pub max_abs: f64,
    /// Share of pixels (0 to 1) where some channel differs by more than 1/255.
    pub over_1_255: f64,
}

/// Compares `image` with `reference`, channel values clamped to [0, 1].
///
/// # Panics
/// If the sizes differ.
pub fn compare(image: &Image, reference: &Image) -> Metrics {
    assert_eq!(
        (image.width, image.height),
        (reference.width, reference.height),
        "images of different sizes"
    );
    let (mut sq, mut max_abs, mut over) = (0.0f64, 0.0f64, 0usize);
    for (a, b) in image.pixels.iter().zip(&reference.pixels) {
        let mut pixel_max = 0.0f64;
        for c in 0..3 {
            let d = (f64::from(a[c].clamp(0.0, 1.0)) - f64::from(b[c].clamp(0.0, 1.0))).abs();
            sq += d * d;
            pixel_max = pixel_max.max(d);
        }
        max_abs = max_abs.max(pixel_max);
        if pixel_max > 1.0 / 255.0 {
            over += 1;
        }
    }
    let n = image.pixels.len().max(1) as f64;
    let mse = sq / (3.0 * n);
    Metrics {
        rmse: mse.sqrt(),
        psnr: if mse > 0.0 {
            -10.0 * mse.log10()
        } else {
            f64::INFINITY
        },
        max_abs,
        over_1_255: over as f64 / n,
    }
}

/// The points of `(time, error)` on the Pareto front: no other point is at least as fast
/// and at least as accurate while strictly better in one of the two.
pub fn pareto(points: &[(f64, f64)]) -> Vec<bool> {
    points
        .iter()
        .map(|&(t, e)| {
            !points
                .iter()
                .any(|&(t2, e2)| t2 <= t && e2 <= e && (t2 < t || e2 < e))
        })
        .collect()
}
