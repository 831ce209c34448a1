//! Rendering: from a [`Scene`] and [`Settings`] to an [`Image`].
//!
//! [`render_with_stats`] picks the renderer compiled for the scene's effects
//! ([`crate::effects`]; `f32` only, see [`Float`]), starts the threads
//! ([`crate::schedule`]) and runs it: the renderer traces the eye ray of every point of
//! the image grid ([`Grid`]: pixel centres, SPD's pixel corners, or one supersample per
//! pixel and pass) with `eye_radiance`, the one loop over the image, which traces
//! single rays (`eye_sample`, then [`crate::shade`]) or, for `f32` scenes with packets
//! on, blocks of rays ([`crate::packets`]). Supersampling adds the samples pass by pass
//! and SPD mode averages the corners.
//!
//! Every pixel is computed by the same sequential code whatever thread runs it, and ray
//! counts are summed as integers, so the image and the statistics are identical bit for
//! bit for any thread count, any scheduler, with packets on or off, and for the
//! specialised and the general renderer.

use crate::camera::{Camera, Grid, Window};
use crate::effects::{self, has, EffectChoice, EffectFn, EffectSet, EffectsMode, SUPERSAMPLING};
use crate::float::{Family, Float};
use crate::image::Image;
use crate::packets::{block_shape, radiance_tile, MAX_LANES, TILE, TILE_SHAPE};
use crate::schedule::{filled, for_each_mut, for_each_point, page_work, with_threads, Progress};
use crate::settings::TraceLimits;
use crate::shade::trace_fx;
use crate::stats::RayCounts;
use crate::world::Scene;
use rayon::prelude::*;
use std::time::Instant;
use vecexpr::simd::Isa;
use vecexpr::{Expr, Vec3};

pub use crate::settings::{PixelBounds, Schedule, Scheduler, Settings};

/// What a render produced besides the image.
#[derive(Clone, Copy, Debug, Default)]
pub struct RenderStats {
    /// Rays by kind.
    pub rays: RayCounts,
    /// Wall-clock tracing time in milliseconds.
    pub trace_ms: f64,
    /// The effects needed and the renderer that ran.
    pub effects: EffectChoice,
    /// CPU time of all threads while tracing, in milliseconds (0 where unavailable).
    pub trace_cpu_ms: f64,
    /// Tracing time in ticks of [`crate::cycles`] (TSC reference cycles where available).
    pub trace_cycles: u64,
}

/// Renders `scene` with `settings`.
pub fn render<T: Float>(scene: &Scene<T>, settings: &Settings) -> Image {
    render_with_stats(scene, settings).0
}

/// Renders `scene` and reports ray counts and trace time.
///
/// # Panics
/// If a thread pool with the requested number of threads cannot be created.
pub fn render_with_stats<T: Float>(scene: &Scene<T>, settings: &Settings) -> (Image, RenderStats) {
    render_with_progress(scene, settings, &())
}

/// [`render_with_stats`], telling `progress` how far it is.
///
/// # Panics
/// As [`render_with_stats`].
pub fn render_with_progress<T: Float>(
    scene: &Scene<T>,
    settings: &Settings,
    progress: &dyn Progress,
) -> (Image, RenderStats) {
    render_choice(scene, settings, effect_choice(scene, settings), progress)
}

/// The renderer `settings.effects` picks for `scene`: in `auto` mode the specialised one
/// for the effects needed, where `T` has specialised renderers ([`specialised`]).
fn effect_choice<T: Float>(scene: &Scene<T>, settings: &Settings) -> EffectChoice {
    let required = EffectSet::required(scene, settings);
    let mode = if specialised::<T>() {
        settings.effects
    } else {
        EffectsMode::All
    };
    EffectChoice {
        mode: settings.effects,
        ..EffectChoice::new(mode, required)
    }
}

/// Does precision `T` have the specialised renderers of [`effects::INSTANCES`]? Only
/// `f32` ([`Float::AS_F32`]), the default: `f64`, the reference precision, always runs
/// the general renderer, which halves the number of renderers compiled.
pub fn specialised<T: Float>() -> bool {
    T::AS_F32.is_some()
}

/// Renders `scene` with the renderer compiled for `renderer`: the instance of
/// [`effects::INSTANCES`] chosen for it in `auto` mode, or the general one if it is not
/// in the table or `T` has no specialised renderers ([`specialised`]).
///
/// # Panics
/// If `renderer` lacks an effect the scene and settings need
/// ([`EffectSet::required`]), or as [`render_with_stats`].
pub fn render_with_effects<T: Float>(
    scene: &Scene<T>,
    settings: &Settings,
    renderer: EffectSet,
) -> (Image, RenderStats) {
    let required = EffectSet::required(scene, settings);
    assert!(
        renderer.contains(required),
        "the renderer for {:?} cannot render a scene that needs {:?}",
        renderer.names(),
        required.names()
    );
    let renderer = if specialised::<T>() && effects::INSTANCES.contains(&renderer.bits()) {
        renderer
    } else {
        EffectSet::ALL
    };
    let choice = EffectChoice {
        mode: settings.effects,
        required,
        renderer,
        general: renderer.is_general(),
    };
    render_choice(scene, settings, choice, &())
}

/// One monomorphised renderer, called through [`effects::dispatch`].
struct Renderer<'a, T: Float> {
    scene: &'a Scene<T>,
    settings: &'a Settings,
    progress: &'a dyn Progress,
}

impl<T: Float> EffectFn<(Image, RayCounts)> for Renderer<'_, T> {
    fn call<const FX: u32>(self) -> (Image, RayCounts) {
        if self.settings.spd {
            render_corners::<T, FX>(self.scene, self.settings, self.progress)
        } else {
            render_grid::<T, FX>(self.scene, self.settings, self.progress)
        }
    }
}

/// The `f32` renderers, dispatched on `set`. Not generic, so compiled once, in this
/// crate.
#[inline(never)]
fn render_f32(
    scene: &Scene<f32>,
    settings: &Settings,
    set: EffectSet,
    progress: &dyn Progress,
) -> (Image, RayCounts) {
    let renderer = Renderer {
        scene,
        settings,
        progress,
    };
    effects::dispatch(set, renderer)
}

fn render_choice<T: Float>(
    scene: &Scene<T>,
    settings: &Settings,
    choice: EffectChoice,
    progress: &dyn Progress,
) -> (Image, RenderStats) {
    let run = || {
        let cpu = crate::stats::process_cpu_ms();
        let start = Instant::now();
        let start_cycles = crate::cycles::start();
        let (image, rays) = match T::AS_F32 {
            Some(p) => {
                let scene = T::to_f32::<SceneOf>(p, scene);
                render_f32(scene, settings, choice.renderer, progress)
            }
            None => Renderer {
                scene,
                settings,
                progress,
            }
            .call::<{ effects::ALL }>(),
        };
        let trace_cycles = crate::cycles::since(start_cycles);
        let trace_ms = start.elapsed().as_secs_f64() * 1e3;
        let trace_cpu_ms = match (cpu, crate::stats::process_cpu_ms()) {
            (Some(a), Some(b)) => b - a,
            _ => 0.0,
        };
        (
            image,
            RenderStats {
                rays,
                trace_ms,
                effects: choice,
                trace_cpu_ms,
                trace_cycles,
            },
        )
    };
    with_threads(settings.threads, run)
}

/// How [`eye_radiance`] runs: scheduler, threads, progress, and the packets'
/// instruction set when they are on (with the proof that `T` is `f32`).
struct Run<'a, T: Float> {
    schedule: Schedule,
    threads: Option<usize>,
    progress: &'a dyn Progress,
    packets: Option<(T::F32, Isa)>,
}

/// The packets `settings` asks for, when `T` has them ([`Float::AS_F32`]).
fn packets_for<T: Float>(settings: &Settings) -> Option<(T::F32, Isa)> {
    T::AS_F32.zip(settings.packets.isa())
}

/// Radiance of the eye ray through image-plane point `(px, py)`.
#[inline]
fn eye_sample<T: Float, const FX: u32>(
    scene: &Scene<T>,
    cam: &Camera<T>,
    px: T,
    py: T,
    limits: &TraceLimits<T>,
    counts: &mut RayCounts,
) -> Vec3<T> {
    counts.eye += 1;
    trace_fx::<T, FX>(scene, &cam.ray(px, py), 1, T::ONE, limits, counts)
}

/// The radiance of the eye ray through every point of window `win` of the grid of
/// `grid`'s points, row-major, and the rays traced: the one loop over the image. Single
/// rays are traced point by point ([`eye_sample`]); packets ([`crate::packets`]) a tile
/// of blocks at a time ([`radiance_tile`]). The values are the same either way, bit for
/// bit.
fn eye_radiance<T: Float, const FX: u32>(
    scene: &Scene<T>,
    cam: &Camera<T>,
    grid: Grid,
    win: Window,
    limits: &TraceLimits<T>,
    run: &Run<'_, T>,
) -> (Vec<Vec3<T>>, RayCounts) {
    let size = win.size;
    if let Some((p, isa)) = run.packets {
        let (bw, bh) = block_shape(isa);
        let (tw, th) = (bw * TILE_SHAPE.0, bh * TILE_SHAPE.1);
        let tiles = (size.0.div_ceil(tw), size.1.div_ceil(th));
        let scene = T::to_f32::<SceneOf>(p, scene);
        let cam = T::to_f32::<CameraOf>(p, cam);
        let limits = T::to_f32::<LimitsOf>(p, limits);
        run.progress.add_rows(tiles.1 as u64);
        let (tiles, counts) = for_each_point(
            tiles,
            run.schedule,
            run.threads,
            run.progress,
            |tx, ty, counts| {
                radiance_tile::<FX>(scene, cam, isa, grid, win, (tx, ty), limits, counts)
            },
        );
        let values = scatter(&tiles, (bw, bh), size);
        return (T::from_f32::<PointsOf>(p, values), counts);
    }
    run.progress.add_rows(size.1 as u64);
    for_each_point(
        size,
        run.schedule,
        run.threads,
        run.progress,
        |x, y, counts| {
            let (px, py) = win.point::<T>(grid, x, y);
            eye_sample::<T, FX>(scene, cam, px, py, limits, counts)
        },
    )
}

/// The per-tile values of a `w` x `h` grid, in tiles of [`TILE_SHAPE`] blocks of shape
/// `(bw, bh)` (as [`radiance_tile`] returns them), in row-major order. One task per row
/// of tiles, on the current thread pool: done serially, this copy and the first touch
/// of its pages took 2.5 ms of tetra-s6's 17 ms render (512², two threads).
fn scatter<V: Copy + Default + Send + Sync>(
    tiles: &[[[V; MAX_LANES]; TILE]],
    (bw, bh): (usize, usize),
    (w, h): (usize, usize),
) -> Vec<V> {
    let (tw, th) = (bw * TILE_SHAPE.0, bh * TILE_SHAPE.1);
    let ntx = w.div_ceil(tw);
    let mut out: Vec<V> = filled(w * h);
    if w == 0 {
        return out;
    }
    out.par_chunks_mut(th * w)
        .zip(tiles.par_chunks(ntx))
        .for_each(|(rows, row_tiles)| {
            let rows_here = rows.len() / w;
            for (tx, tile) in row_tiles.iter().enumerate() {
                for (b, block) in tile.iter().enumerate() {
                    let bx = tx * tw + (b % TILE_SHAPE.0) * bw;
                    let by = (b / TILE_SHAPE.0) * bh;
                    for j in 0..bh {
                        for i in 0..bw {
                            let (x, y) = (bx + i, by + j);
                            if x < w && y < rows_here {
                                rows[y * w + x] = block[j * bw + i];
                            }
                        }
                    }
                }
            }
        });
    out
}

fn to_rgb<T: Float>(c: &Vec3<T>) -> [f32; 3] {
    [
        c[0].to_f64() as f32,
        c[1].to_f64() as f32,
        c[2].to_f64() as f32,
    ]
}

/// An `aa` x `aa` grid of rays per pixel, averaged: one pass of [`eye_radiance`] per
/// sample position, added in the order [`accumulate_pass`] adds them.
fn render_grid<T: Float, const FX: u32>(
    scene: &Scene<T>,
    settings: &Settings,
    progress: &dyn Progress,
) -> (Image, RayCounts) {
    let (w, h) = settings.size(scene.camera.resolution);
    let cam = scene.camera_for(w, h);
    let region = region(settings, (w, h));
    let win = Window {
        origin: (region.x0 as usize, region.y0 as usize),
        size: (region.width() as usize, region.height() as usize),
    };
    let size = win.size;
    let limits = settings.limits::<T>();
    let a = settings.aa.max(1);
    let mut image = Image::new(region.width(), region.height());
    let run = Run {
        schedule: settings.schedule,
        threads: settings.threads,
        progress,
        packets: packets_for::<T>(settings),
    };
    if a == 1 || !has(FX, SUPERSAMPLING) {
        // One ray through the centre; adding it to zero, as the sum of samples below
        // does, turns a -0 into +0.
        let (values, counts) =
            eye_radiance::<T, FX>(scene, &cam, Grid::Centers, win, &limits, &run);
        progress.finish();
        let zero = Vec3::<T>::zero();
        for_each_mut(&mut image.pixels, page_work::<[f32; 3]>(), |i, p| {
            *p = to_rgb(&(&zero + &values[i]).eval());
        });
        return (image, counts);
    }
    let norm = T::from_f64(1.0 / (a as f64 * a as f64));
    let mut sums = vec![Vec3::<T>::zero(); size.0 * size.1];
    let mut counts = RayCounts::default();
    for k in 0..a * a {
        let grid = Grid::Sample {
            i: k % a,
            j: k / a,
            a,
        };
        let (values, c) = eye_radiance::<T, FX>(scene, &cam, grid, win, &limits, &run);
        counts += c;
        for (s, v) in sums.iter_mut().zip(&values) {
            *s += v;
        }
    }
    progress.finish();
    for (p, s) in image.pixels.iter_mut().zip(&sums) {
        *p = to_rgb(&s.scale(norm).eval());
    }
    (image, counts)
}

/// The pixels `settings` asks for in a `w` x `h` image.
///
/// # Panics
/// If the region is empty or does not lie inside the image.
fn region(settings: &Settings, (w, h): (u32, u32)) -> PixelBounds {
    let b = settings.region.unwrap_or(PixelBounds::full(w, h));
    assert!(
        b.fits(w, h) && !b.is_empty(),
        "pixel bounds {b} are empty or outside the {w} x {h} image"
    );
    b
}

/// SPD mode: one ray through every pixel corner, each pixel the mean of its four.
fn render_corners<T: Float, const FX: u32>(
    scene: &Scene<T>,
    settings: &Settings,
    progress: &dyn Progress,
) -> (Image, RayCounts) {
    let (w, h) = settings.size(scene.camera.resolution);
    let cam = scene.camera_for(w, h);
    let limits = settings.limits::<T>();
    let region = region(settings, (w, h));
    let (w, h) = (region.width(), region.height());
    // The corners of the region's pixels: one more column and row than pixels.
    let (cw, ch) = (w as usize + 1, h as usize + 1);
    let win = Window {
        origin: (region.x0 as usize, region.y0 as usize),
        size: (cw, ch),
    };
    let run = Run {
        schedule: settings.schedule,
        threads: settings.threads,
        progress,
        packets: packets_for::<T>(settings),
    };
    let (corners, counts) = eye_radiance::<T, FX>(scene, &cam, Grid::Corners, win, &limits, &run);
    progress.finish();
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

/// Adds one supersample per pixel to `sums`, for interactive, progressive rendering.
///
/// `sums` holds `cam.width * cam.height` running sums, row-major from the top left. Pass
/// `k` (for `k` in `0..aa * aa`) traces, for every pixel, the ray at grid position
/// `(k % aa, k / aa)` of the `aa` x `aa` grid that [`render`] uses, through `cam` (which
/// may differ from the scene's own camera), with the depth, threshold and effect mode of
/// `settings` (its size, `aa` and threads are ignored). Running passes `0..aa * aa` in
/// order adds the samples in the order [`render`] adds them, so scaling the sums by
/// `1 / (aa * aa)` gives [`render`]'s image bit for bit (for a scene whose camera is
/// `cam`). Returns the rays traced and the effect set of the renderer that ran (each
/// pass traces one ray per pixel, so supersampling is never among the effects needed).
///
/// Rows run in parallel on the current rayon pool (use `ThreadPool::install` to choose
/// the thread count); the sums do not depend on it.
///
/// # Panics
/// If `sums.len()` is not `cam.width * cam.height`.
pub fn accumulate_pass<T: Float>(
    scene: &Scene<T>,
    cam: &Camera<T>,
    settings: &Settings,
    aa: u32,
    pass: u32,
    sums: &mut [Vec3<T>],
) -> (RayCounts, EffectChoice) {
    let (w, h) = (cam.width as usize, cam.height as usize);
    assert_eq!(sums.len(), w * h, "accumulate_pass: buffer size");
    let one = Settings {
        aa: 1,
        ..settings.clone()
    };
    let choice = effect_choice(scene, &one);
    let a = aa.max(1);
    let pass = Pass {
        scene,
        cam,
        limits: one.limits::<T>(),
        // One sample per pixel is the pixel centre.
        grid: if a == 1 {
            Grid::Centers
        } else {
            Grid::Sample {
                i: pass % a,
                j: (pass / a) % a,
                a,
            }
        },
        packets: packets_for::<T>(&one),
        sums,
    };
    let counts = match T::AS_F32 {
        Some(_) => effects::dispatch(choice.renderer, pass),
        None => pass.call::<{ effects::ALL }>(),
    };
    (counts, choice)
}

/// One pass of [`accumulate_pass`], monomorphised per effect set.
struct Pass<'a, T: Float> {
    scene: &'a Scene<T>,
    cam: &'a Camera<T>,
    limits: TraceLimits<T>,
    grid: Grid,
    packets: Option<(T::F32, Isa)>,
    sums: &'a mut [Vec3<T>],
}

impl<T: Float> EffectFn<RayCounts> for Pass<'_, T> {
    fn call<const FX: u32>(self) -> RayCounts {
        let size = (self.cam.width as usize, self.cam.height as usize);
        // Rows in parallel on the current rayon pool.
        let run = Run {
            schedule: Schedule::default(),
            threads: None,
            progress: &(),
            packets: self.packets,
        };
        let win = Window::full(size);
        let (values, counts) =
            eye_radiance::<T, FX>(self.scene, self.cam, self.grid, win, &self.limits, &run);
        for (s, v) in self.sums.iter_mut().zip(&values) {
            *s += v;
        }
        counts
    }
}

/// [`Family`]s of the types the renderers view as `f32` when packets are on.
struct SceneOf;
impl Family for SceneOf {
    type Of<T: Float> = Scene<T>;
}
struct CameraOf;
impl Family for CameraOf {
    type Of<T: Float> = Camera<T>;
}
struct LimitsOf;
impl Family for LimitsOf {
    type Of<T: Float> = TraceLimits<T>;
}
struct PointsOf;
impl Family for PointsOf {
    type Of<T: Float> = Vec<Vec3<T>>;
}
