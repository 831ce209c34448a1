//! Parallel, deterministic rendering.
//!
//! Pixels are shaded in parallel by one of three schedulers ([`Scheduler`]): rayon's work
//! stealing over rows (like TBB), a static partition into one contiguous block of rows per
//! thread over `std::thread::scope` (like OpenMP `schedule(static)`), or a dynamic queue of
//! square tiles that threads take from an atomic counter. Every pixel is computed by the
//! same sequential code whatever thread runs it, and ray counts are summed as integers, so
//! the image and the statistics are identical bit for bit for any thread count and any
//! scheduler.

use crate::arith::Arith;
use crate::effects::{self, has, EffectChoice, EffectFn, EffectSet, EffectsMode, SUPERSAMPLING};
use crate::image::Image;
use crate::packet::{
    block_shape, eye_block, packet_isa, shadow_block, shadow_packets, EyeGrid, Packets, MAX_LANES,
};
use crate::ray::Ray;
use crate::shade::{trace_fx, TraceLimits};
use crate::stats::RayCounts;
use crate::world::Scene;
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
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
    /// The renderer specialised for the scene's effects, or the general one (the image
    /// is the same).
    pub effects: EffectsMode,
    /// How pixels are distributed over threads.
    pub schedule: Schedule,
    /// Approximate arithmetic in shading (default: exact).
    pub arith: Arith,
    /// Eye rays in SIMD packets ([`Packets::auto`] by default); the image is the same
    /// either way ([`crate::packet`]).
    pub packets: Packets,
}

/// The parallel scheduler.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Scheduler {
    /// rayon work stealing over rows.
    #[default]
    Rayon,
    /// One contiguous block of rows per thread, fixed in advance.
    Static,
    /// Square tiles taken one at a time from a shared atomic counter.
    Tiles,
}

/// Scheduler and tile size.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Schedule {
    /// Which scheduler.
    pub scheduler: Scheduler,
    /// Tile edge in pixels for [`Scheduler::Tiles`] (at least 1).
    pub tile: u32,
}

impl Default for Schedule {
    /// rayon over rows; 16x16 tiles when tiles are chosen.
    fn default() -> Self {
        Self {
            scheduler: Scheduler::Rayon,
            tile: 16,
        }
    }
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
            effects: EffectsMode::Auto,
            schedule: Schedule::default(),
            arith: Arith::EXACT,
            packets: Packets::default(),
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
    /// The effects needed and the renderer that ran.
    pub effects: EffectChoice,
    /// CPU time of all threads while tracing, in milliseconds (0 where unavailable).
    pub trace_cpu_ms: f64,
    /// Tracing time in ticks of [`crate::cycles`] (TSC reference cycles where available).
    pub trace_cycles: u64,
}

/// Progress of a render, for a front end to show: [`start`](Progress::start) with the
/// number of rows (of pixels, or of packet blocks) to trace, [`advance`](Progress::advance)
/// from the worker threads as rows are done, [`finish`](Progress::finish) at the end.
/// `()` shows nothing.
pub trait Progress: Sync {
    /// A pass over `rows` rows begins.
    fn start(&self, rows: u64);
    /// `rows` more rows are done.
    fn advance(&self, rows: u64);
    /// The pass is done.
    fn finish(&self);
}

impl Progress for () {
    fn start(&self, _: u64) {}
    fn advance(&self, _: u64) {}
    fn finish(&self) {}
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
    render_with_progress(scene, settings, &())
}

/// [`render_with_stats`], telling `progress` how far it is.
///
/// # Panics
/// As [`render_with_stats`].
pub fn render_with_progress<T: Real>(
    scene: &Scene<T>,
    settings: &Settings,
    progress: &dyn Progress,
) -> (Image, RenderStats) {
    render_choice(scene, settings, effect_choice(scene, settings), progress)
}

/// The renderer `settings.effects` picks for `scene`: in `auto` mode the specialised one
/// for the effects needed, where `T` has specialised renderers ([`specialised`]).
fn effect_choice<T: Real>(scene: &Scene<T>, settings: &Settings) -> EffectChoice {
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
/// `f32`, the default: `f64`, the reference precision, always runs the general renderer,
/// which halves the number of renderers compiled.
pub fn specialised<T: Real>() -> bool {
    core::any::TypeId::of::<T>() == core::any::TypeId::of::<f32>()
}

/// Renders `scene` with the renderer compiled for `renderer`: the instance of
/// [`effects::INSTANCES`] chosen for it in `auto` mode, or the general one if it is not
/// in the table or `T` has no specialised renderers ([`specialised`]).
///
/// # Panics
/// If `renderer` lacks an effect the scene and settings need
/// ([`EffectSet::required`]), or as [`render_with_stats`].
pub fn render_with_effects<T: Real>(
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
struct Renderer<'a, T: Real> {
    scene: &'a Scene<T>,
    settings: &'a Settings,
    progress: &'a dyn Progress,
}

impl<T: Real> EffectFn<(Image, RayCounts)> for Renderer<'_, T> {
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
    effects::dispatch(
        set,
        Renderer {
            scene,
            settings,
            progress,
        },
    )
}

fn render_choice<T: Real>(
    scene: &Scene<T>,
    settings: &Settings,
    choice: EffectChoice,
    progress: &dyn Progress,
) -> (Image, RenderStats) {
    let run = || {
        let cpu = crate::stats::process_cpu_ms();
        let start = Instant::now();
        let start_cycles = crate::cycles::start();
        let any: &dyn core::any::Any = scene;
        let (image, rays) = match any.downcast_ref::<Scene<f32>>() {
            Some(scene) => render_f32(scene, settings, choice.renderer, progress),
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
    match settings.threads {
        // The other schedulers start their own threads.
        Some(n) if settings.schedule.scheduler == Scheduler::Rayon => {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n.max(1))
                .build()
                .expect("cannot create the rendering thread pool")
                .install(run)
        }
        _ => run(),
    }
}

/// Radiance of the eye ray through image-plane point `(px, py)`.
#[inline]
fn eye_sample<T: Real, const FX: u32>(
    scene: &Scene<T>,
    cam: &crate::Camera<T>,
    px: T,
    py: T,
    limits: &TraceLimits<T>,
    counts: &mut RayCounts,
) -> Vec3<T> {
    counts.eye += 1;
    let ray = Ray::new(cam.position, cam.direction(px, py));
    trace_fx::<T, FX>(scene, &ray, 1, T::ONE, limits, counts)
}

/// The radiance of each eye ray of one packet of block `(bx, by)` of a `w` x `h` grid,
/// traced together ([`eye_block`]), with the shadow rays of their hits traced as one
/// packet per light ([`shadow_block`]), and shaded one by one as [`eye_sample`] shades
/// them; `put(lane, radiance)` for each lane with a ray.
#[allow(clippy::too_many_arguments)]
#[inline]
fn eye_packet<T: Real, const FX: u32>(
    scene: &Scene<T>,
    cam: &crate::Camera<T>,
    isa: vecexpr::simd::Isa,
    grid: EyeGrid,
    size: (usize, usize),
    block: (usize, usize),
    limits: &TraceLimits<T>,
    counts: &mut RayCounts,
    mut put: impl FnMut(usize, Vec3<T>),
) {
    let (rays, hits) = eye_block(scene, cam, isa, grid, size, block);
    // The shadow rays of the eye hits, toward one light at a time, as packets too.
    let blocked = if crate::effects::has(FX, crate::effects::SHADOWS) && shadow_packets(scene) {
        Some(shadow_block(scene, isa, limits, &rays, &hits))
    } else {
        None
    };
    for (l, (ray, hit)) in rays.iter().zip(&hits).enumerate() {
        let Some(ray) = ray else { continue };
        counts.eye += 1;
        let c = match (hit, &blocked) {
            (Some(hit), Some(b)) => {
                crate::shade::shade_eye_lit::<T, FX>(scene, ray, hit, limits, counts, b[l])
            }
            (Some(hit), None) => {
                crate::shade::shade_fx::<T, FX>(scene, ray, hit, 1, T::ONE, limits, counts)
            }
            (None, _) => scene.background,
        };
        put(l, c);
    }
}

/// Writes the per-block values of a `w` x `h` grid of blocks of `isa`'s shape into
/// `out`, row-major.
fn scatter<V: Copy>(
    blocks: &[[V; MAX_LANES]],
    isa: vecexpr::simd::Isa,
    (w, h): (usize, usize),
    out: &mut [V],
) {
    let (bw, bh) = block_shape(isa);
    let nbx = w.div_ceil(bw);
    for (k, b) in blocks.iter().enumerate() {
        let (bx, by) = (k % nbx, k / nbx);
        for j in 0..bh {
            for i in 0..bw {
                let (x, y) = (bx * bw + i, by * bh + j);
                if x < w && y < h {
                    out[y * w + x] = b[j * bw + i];
                }
            }
        }
    }
}

fn to_rgb<T: Real>(c: &Vec3<T>) -> [f32; 3] {
    [
        c[0].to_f64() as f32,
        c[1].to_f64() as f32,
        c[2].to_f64() as f32,
    ]
}

/// The tiles one thread rendered (index, values in row-major order) and its ray counts.
type TilesDone<V> = (Vec<(usize, Vec<V>)>, RayCounts);

/// Computes `f(x, y, counts)` for every point of a `w` x `h` grid with the chosen
/// scheduler, returning the values in row-major order and the summed ray counts. The
/// value of a point does not depend on the scheduler or the thread that computes it.
fn for_each_point<V, F>(
    w: usize,
    h: usize,
    settings: &Settings,
    progress: &dyn Progress,
    f: F,
) -> (Vec<V>, RayCounts)
where
    V: Copy + Default + Send,
    F: Fn(usize, usize, &mut RayCounts) -> V + Sync,
{
    let mut out = vec![V::default(); w * h];
    if w == 0 || h == 0 {
        return (out, RayCounts::default());
    }
    let threads = settings
        .threads
        .unwrap_or_else(rayon::current_num_threads)
        .max(1);
    let counts = match settings.schedule.scheduler {
        Scheduler::Rayon => out
            .par_chunks_mut(w)
            .enumerate()
            .map(|(y, row)| {
                let mut counts = RayCounts::default();
                for (x, v) in row.iter_mut().enumerate() {
                    *v = f(x, y, &mut counts);
                }
                progress.advance(1);
                counts
            })
            .reduce(RayCounts::default, |a, b| a + b),
        Scheduler::Static => {
            let rows_per = h.div_ceil(threads);
            std::thread::scope(|s| {
                let handles: Vec<_> = out
                    .chunks_mut(rows_per * w)
                    .enumerate()
                    .map(|(k, block)| {
                        let f = &f;
                        s.spawn(move || {
                            let mut counts = RayCounts::default();
                            for (r, row) in block.chunks_mut(w).enumerate() {
                                let y = k * rows_per + r;
                                for (x, v) in row.iter_mut().enumerate() {
                                    *v = f(x, y, &mut counts);
                                }
                                progress.advance(1);
                            }
                            counts
                        })
                    })
                    .collect();
                handles
                    .into_iter()
                    .map(|t| t.join().expect("a render thread panicked"))
                    .fold(RayCounts::default(), |a, b| a + b)
            })
        }
        Scheduler::Tiles => {
            let t = settings.schedule.tile.max(1) as usize;
            let (tx, ty) = (w.div_ceil(t), h.div_ceil(t));
            let next = AtomicUsize::new(0);
            // Each thread keeps the tiles it rendered; they are copied into place after
            // the join, so no two threads ever write the same buffer.
            let done: Vec<TilesDone<V>> = std::thread::scope(|s| {
                let handles: Vec<_> = (0..threads)
                    .map(|_| {
                        let (f, next) = (&f, &next);
                        s.spawn(move || {
                            let mut counts = RayCounts::default();
                            let mut tiles = Vec::new();
                            loop {
                                let k = next.fetch_add(1, Ordering::Relaxed);
                                if k >= tx * ty {
                                    break;
                                }
                                let (x0, y0) = ((k % tx) * t, (k / tx) * t);
                                let (x1, y1) = ((x0 + t).min(w), (y0 + t).min(h));
                                let mut vals = Vec::with_capacity((x1 - x0) * (y1 - y0));
                                for y in y0..y1 {
                                    for x in x0..x1 {
                                        vals.push(f(x, y, &mut counts));
                                    }
                                }
                                tiles.push((k, vals));
                            }
                            (tiles, counts)
                        })
                    })
                    .collect();
                handles
                    .into_iter()
                    .map(|t| t.join().expect("a render thread panicked"))
                    .collect()
            });
            let mut counts = RayCounts::default();
            for (tiles, c) in done {
                counts += c;
                for (k, vals) in tiles {
                    let (x0, y0) = ((k % tx) * t, (k / tx) * t);
                    let tw = (x0 + t).min(w) - x0;
                    for (r, row) in vals.chunks(tw).enumerate() {
                        let at = (y0 + r) * w + x0;
                        out[at..at + tw].copy_from_slice(row);
                    }
                }
            }
            progress.advance(h as u64);
            counts
        }
    };
    (out, counts)
}

/// An `aa` x `aa` grid of rays per pixel, averaged.
fn render_grid<T: Real, const FX: u32>(
    scene: &Scene<T>,
    settings: &Settings,
    progress: &dyn Progress,
) -> (Image, RayCounts) {
    let (w, h) = settings.size(scene);
    let cam = scene.camera_for(w, h);
    let limits = settings.limits::<T>();
    let a = settings.aa.max(1);
    let inv_a = T::from_f64(1.0 / a as f64);
    let norm = T::from_f64(1.0 / (a as f64 * a as f64));
    let mut image = Image::new(w, h);
    // Packets trace the one ray per pixel through the centre: for a = 1 the grid point
    // below is x + (0 + 1/2) * 1 = x + 1/2 exactly, and the pixel the same sum.
    if let Some(isa) = packet_isa::<T>(settings).filter(|_| a == 1) {
        let size = (w as usize, h as usize);
        let (bw, bh) = block_shape(isa);
        let (nbx, nby) = (size.0.div_ceil(bw), size.1.div_ceil(bh));
        progress.start(nby as u64);
        let (blocks, counts) = for_each_point(nbx, nby, settings, progress, |bx, by, counts| {
            let mut out = [[0.0f32; 3]; MAX_LANES];
            let grid = EyeGrid::Centers;
            eye_packet::<T, FX>(
                scene,
                &cam,
                isa,
                grid,
                size,
                (bx, by),
                &limits,
                counts,
                |l, c| {
                    let mut sum = vec3(T::ZERO, T::ZERO, T::ZERO);
                    sum += c;
                    out[l] = if has(FX, SUPERSAMPLING) {
                        to_rgb(&sum.scale(norm).eval())
                    } else {
                        to_rgb(&sum)
                    };
                },
            );
            out
        });
        progress.finish();
        scatter(&blocks, isa, size, &mut image.pixels);
        return (image, counts);
    }
    progress.start(h as u64);
    let (pixels, counts) = for_each_point(
        w as usize,
        h as usize,
        settings,
        progress,
        |x, y, counts| {
            let mut sum = vec3(T::ZERO, T::ZERO, T::ZERO);
            if !has(FX, SUPERSAMPLING) {
                // One ray through the centre: the a = 1 case below without its exact
                // multiplications by 1 (adding to zero is kept, as it turns a -0 into +0
                // there).
                let half = T::from_f64(0.5);
                let (sx, sy) = (T::from_f64(x as f64) + half, T::from_f64(y as f64) + half);
                sum += eye_sample::<T, FX>(scene, &cam, sx, sy, &limits, counts);
                return to_rgb(&sum);
            }
            for j in 0..a {
                let sy = T::from_f64(y as f64) + (T::from_f64(j as f64) + T::from_f64(0.5)) * inv_a;
                for i in 0..a {
                    let sx =
                        T::from_f64(x as f64) + (T::from_f64(i as f64) + T::from_f64(0.5)) * inv_a;
                    sum += eye_sample::<T, FX>(scene, &cam, sx, sy, &limits, counts);
                }
            }
            to_rgb(&sum.scale(norm).eval())
        },
    );
    progress.finish();
    image.pixels = pixels;
    (image, counts)
}

/// SPD mode: one ray through every pixel corner, each pixel the mean of its four.
fn render_corners<T: Real, const FX: u32>(
    scene: &Scene<T>,
    settings: &Settings,
    progress: &dyn Progress,
) -> (Image, RayCounts) {
    let (w, h) = settings.size(scene);
    let cam = scene.camera_for(w, h);
    let limits = settings.limits::<T>();
    let (cw, ch) = (w as usize + 1, h as usize + 1);
    let (corners, counts) = match packet_isa::<T>(settings) {
        Some(isa) => {
            let (bw, bh) = block_shape(isa);
            let (nbx, nby) = (cw.div_ceil(bw), ch.div_ceil(bh));
            progress.start(nby as u64);
            let (blocks, counts) =
                for_each_point(nbx, nby, settings, progress, |bx, by, counts| {
                    let mut out = [Vec3::<T>::zero(); MAX_LANES];
                    let grid = EyeGrid::Corners;
                    let size = (cw, ch);
                    eye_packet::<T, FX>(
                        scene,
                        &cam,
                        isa,
                        grid,
                        size,
                        (bx, by),
                        &limits,
                        counts,
                        |l, c| {
                            out[l] = c;
                        },
                    );
                    out
                });
            progress.finish();
            let mut corners = vec![Vec3::<T>::zero(); cw * ch];
            scatter(&blocks, isa, (cw, ch), &mut corners);
            (corners, counts)
        }
        None => {
            progress.start(ch as u64);
            let done = for_each_point(cw, ch, settings, progress, |x, y, counts| {
                eye_sample::<T, FX>(
                    scene,
                    &cam,
                    T::from_f64(x as f64),
                    T::from_f64(y as f64),
                    &limits,
                    counts,
                )
            });
            progress.finish();
            done
        }
    };
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
pub fn accumulate_pass<T: Real>(
    scene: &Scene<T>,
    cam: &crate::Camera<T>,
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
    let pass = Pass {
        scene,
        cam,
        limits: one.limits::<T>(),
        aa,
        pass,
        // One sample per pixel is the pixel centre, which the packets trace.
        packets: packet_isa::<T>(&one).filter(|_| aa <= 1),
        sums,
    };
    let any: &dyn core::any::Any = scene;
    let counts = match any.downcast_ref::<Scene<f32>>() {
        Some(_) => effects::dispatch(choice.renderer, pass),
        None => pass.call::<{ effects::ALL }>(),
    };
    (counts, choice)
}

/// One pass of [`accumulate_pass`], monomorphised per effect set.
struct Pass<'a, T: Real> {
    scene: &'a Scene<T>,
    cam: &'a crate::Camera<T>,
    limits: TraceLimits<T>,
    aa: u32,
    pass: u32,
    /// Trace the eye rays in packets of this instruction set (only when `aa <= 1`).
    packets: Option<vecexpr::simd::Isa>,
    sums: &'a mut [Vec3<T>],
}

impl<T: Real> EffectFn<RayCounts> for Pass<'_, T> {
    fn call<const FX: u32>(self) -> RayCounts {
        let Pass {
            scene,
            cam,
            limits,
            aa,
            pass,
            packets,
            sums,
        } = self;
        let w = cam.width as usize;
        if let Some(isa) = packets {
            // Pixel centres, as below with a = 1: x + (0 + 1/2) * 1 = x + 1/2 exactly.
            let h = cam.height as usize;
            let (bw, bh) = block_shape(isa);
            return sums
                .par_chunks_mut((w * bh).max(1))
                .enumerate()
                .map(|(by, rows)| {
                    let mut counts = RayCounts::default();
                    for bx in 0..w.div_ceil(bw) {
                        eye_packet::<T, FX>(
                            scene,
                            cam,
                            isa,
                            EyeGrid::Centers,
                            (w, h),
                            (bx, by),
                            &limits,
                            &mut counts,
                            |l, c| rows[(l / bw) * w + bx * bw + l % bw] += c,
                        );
                    }
                    counts
                })
                .reduce(RayCounts::default, |a, b| a + b);
        }
        let a = aa.max(1);
        let (i, j) = (pass % a, (pass / a) % a);
        let inv_a = T::from_f64(1.0 / a as f64);
        let ox = (T::from_f64(i as f64) + T::from_f64(0.5)) * inv_a;
        let oy = (T::from_f64(j as f64) + T::from_f64(0.5)) * inv_a;
        sums.par_chunks_mut(w.max(1))
            .enumerate()
            .map(|(y, row)| {
                let mut counts = RayCounts::default();
                let sy = T::from_f64(y as f64) + oy;
                for (x, sum) in row.iter_mut().enumerate() {
                    let sx = T::from_f64(x as f64) + ox;
                    *sum += eye_sample::<T, FX>(scene, cam, sx, sy, &limits, &mut counts);
                }
                counts
            })
            .reduce(RayCounts::default, |a, b| a + b)
    }
}
