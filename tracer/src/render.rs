//! Parallel, deterministic rendering.
//!
//! Rows are shaded in parallel with rayon; every pixel is computed by the same
//! sequential code whatever thread runs it, and ray counts are summed as integers, so the
//! image and the statistics are identical bit for bit for any thread count.

use crate::arith::Arith;
use crate::image::Image;
use crate::ray::Ray;
use crate::shade::{trace, TraceLimits};
use crate::stats::RayCounts;
use crate::world::Scene;
use rayon::prelude::*;
use std::time::Instant;
use vecexpr::{vec3, Expr, Real, Vec3};

/// Render settings. `None` sizes use the scene's own resolution.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Image width (default: the scene's).
    pub width: Option<u32>,
    /// Image height (default: the scene's).
    pub height: Option<u32>,
    /// Antialiasing: an `aa` x `aa` regular grid of rays per pixel (1 = one ray through
    /// the pixel centre).
    pub aa: u32,
    /// Maximum ray depth (eye rays are depth 1).
    pub depth: u32,
    /// Adaptive termination threshold on a ray's accumulated weight; 0 disables it.
    pub threshold: f64,
    /// Worker threads (`None`: all cores).
    pub threads: Option<usize>,
    /// SPD testing rules: 513x513 corner rays averaged into 512x512 pixels (in general
    /// (w+1) x (h+1) corner rays), depth 5, no adaptive cutoff, transmitters spawn
    /// reflection rays.
    pub spd: bool,
    /// Show a progress bar on a terminal.
    pub progress: bool,
    /// Approximate arithmetic in shading (default: exact).
    pub arith: Arith,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            width: None,
            height: None,
            aa: 1,
            depth: 5,
            threshold: 0.0,
            threads: None,
            spd: false,
            progress: false,
            arith: Arith::EXACT,
        }
    }
}

impl Settings {
    /// The image size these settings give for `scene`.
    pub fn size<T: Real>(&self, scene: &Scene<T>) -> (u32, u32) {
        let (w, h) = scene.camera.resolution;
        (self.width.unwrap_or(w), self.height.unwrap_or(h))
    }

    /// The recursion limits in effect (SPD mode forces depth 5 and no threshold).
    pub fn limits<T: Real>(&self) -> TraceLimits<T> {
        if self.spd {
            TraceLimits {
                max_depth: 5,
                threshold: T::ZERO,
                spd: true,
                arith: self.arith,
            }
        } else {
            TraceLimits {
                max_depth: self.depth.max(1),
                threshold: T::from_f64(self.threshold.max(0.0)),
                spd: false,
                arith: self.arith,
            }
        }
    }
}

/// What a render produced besides the image.
#[derive(Clone, Copy, Debug, Default)]
pub struct RenderStats {
    /// Rays by kind.
    pub rays: RayCounts,
    /// Wall-clock tracing time in milliseconds.
    pub trace_ms: f64,
}

/// Renders `scene` with `settings`.
pub fn render<T: Real>(scene: &Scene<T>, settings: &Settings) -> Image {
    render_with_stats(scene, settings).0
}

/// Renders `scene` and reports ray counts and trace time.
///
/// # Panics
/// If a thread pool with the requested number of threads cannot be created.
pub fn render_with_stats<T: Real>(scene: &Scene<T>, settings: &Settings) -> (Image, RenderStats) {
    let run = || {
        let start = Instant::now();
        let (image, rays) = if settings.spd {
            render_corners(scene, settings)
        } else {
            render_grid(scene, settings)
        };
        let trace_ms = start.elapsed().as_secs_f64() * 1e3;
        (image, RenderStats { rays, trace_ms })
    };
    match settings.threads {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n.max(1))
            .build()
            .expect("cannot create the rendering thread pool")
            .install(run),
        None => run(),
    }
}

fn progress_bar(settings: &Settings, rows: u64) -> indicatif::ProgressBar {
    if !settings.progress {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::with_draw_target(
        Some(rows),
        indicatif::ProgressDrawTarget::stderr(),
    );
    if let Ok(style) = indicatif::ProgressStyle::with_template(
        "{bar:40} {pos}/{len} rows, {elapsed} elapsed, ETA {eta}",
    ) {
        bar.set_style(style);
    }
    bar
}

/// Radiance of the eye ray through image-plane point `(px, py)`.
#[inline]
fn eye_sample<T: Real>(
    scene: &Scene<T>,
    cam: &crate::Camera<T>,
    px: T,
    py: T,
    limits: &TraceLimits<T>,
    counts: &mut RayCounts,
) -> Vec3<T> {
    counts.eye += 1;
    let ray = Ray::new(cam.position, cam.direction(px, py));
    trace(scene, &ray, 1, T::ONE, limits, counts)
}

fn to_rgb<T: Real>(c: &Vec3<T>) -> [f32; 3] {
    [
        c[0].to_f64() as f32,
        c[1].to_f64() as f32,
        c[2].to_f64() as f32,
    ]
}

/// An `aa` x `aa` grid of rays per pixel, averaged.
fn render_grid<T: Real>(scene: &Scene<T>, settings: &Settings) -> (Image, RayCounts) {
    let (w, h) = settings.size(scene);
    let cam = scene.camera_for(w, h);
    let limits = settings.limits::<T>();
    let a = settings.aa.max(1);
    let inv_a = T::from_f64(1.0 / a as f64);
    let norm = T::from_f64(1.0 / (a as f64 * a as f64));
    let mut image = Image::new(w, h);
    let bar = progress_bar(settings, h as u64);
    let counts = image
        .pixels
        .par_chunks_mut(w.max(1) as usize)
        .enumerate()
        .map(|(y, row)| {
            let mut counts = RayCounts::default();
            for (x, px) in row.iter_mut().enumerate() {
                let mut sum = vec3(T::ZERO, T::ZERO, T::ZERO);
                for j in 0..a {
                    let sy =
                        T::from_f64(y as f64) + (T::from_f64(j as f64) + T::from_f64(0.5)) * inv_a;
                    for i in 0..a {
                        let sx = T::from_f64(x as f64)
                            + (T::from_f64(i as f64) + T::from_f64(0.5)) * inv_a;
                        sum += eye_sample(scene, &cam, sx, sy, &limits, &mut counts);
                    }
                }
                *px = to_rgb(&sum.scale(norm).eval());
            }
            bar.inc(1);
            counts
        })
        .reduce(RayCounts::default, |a, b| a + b);
    bar.finish_and_clear();
    (image, counts)
}

/// SPD mode: one ray through every pixel corner, each pixel the mean of its four.
fn render_corners<T: Real>(scene: &Scene<T>, settings: &Settings) -> (Image, RayCounts) {
    let (w, h) = settings.size(scene);
    let cam = scene.camera_for(w, h);
    let limits = settings.limits::<T>();
    let (cw, ch) = (w as usize + 1, h as usize + 1);
    let mut corners = vec![vec3(T::ZERO, T::ZERO, T::ZERO); cw * ch];
    let bar = progress_bar(settings, ch as u64);
    let counts = corners
        .par_chunks_mut(cw)
        .enumerate()
        .map(|(y, row)| {
            let mut counts = RayCounts::default();
            for (x, c) in row.iter_mut().enumerate() {
                *c = eye_sample(
                    scene,
                    &cam,
                    T::from_f64(x as f64),
                    T::from_f64(y as f64),
                    &limits,
                    &mut counts,
                );
            }
            bar.inc(1);
            counts
        })
        .reduce(RayCounts::default, |a, b| a + b);
    bar.finish_and_clear();
    let quarter = T::from_f64(0.25);
    let mut image = Image::new(w, h);
    for y in 0..h as usize {
        for x in 0..w as usize {
            let i = y * cw + x;
            let sum = &corners[i] + &corners[i + 1] + &corners[i + cw] + &corners[i + cw + 1];
            image.pixels[y * w as usize + x] = to_rgb(&sum.scale(quarter).eval());
        }
    }
    (image, counts)
}
