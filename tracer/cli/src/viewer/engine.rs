//! Progressive rendering without a window: the part of the viewer that traces.
//!
//! An [`Engine`] holds the scene (built in each precision when first needed), a thread
//! pool of the requested size and one running sum per pixel. [`Engine::set_view`] sets
//! the camera and knobs; a change restarts the accumulation. Each [`Engine::step`] adds one
//! supersample per pixel with [`render::accumulate_pass`], until the `aa` x `aa` grid is
//! complete; the image is then exactly [`render::render`]'s for the same camera.

use super::knobs::Knobs;
use crate::Precision;
use std::time::Instant;
use tracer::geometry::AccelOptions;
use tracer::image::Image;
use tracer::render::{self, Settings};
use tracer::scene::desc::{CameraDesc, SceneDesc};
use tracer::stats::RayCounts;
use tracer::world::Scene;
use vecexpr::{vec3, Expr, Real, Vec3};

/// What one pass cost.
#[derive(Clone, Copy, Debug, Default)]
pub struct PassStats {
    /// Rays traced in the pass, by kind.
    pub rays: RayCounts,
    /// Tracing time in milliseconds.
    pub trace_ms: f64,
    /// Time to build a scene in a precision first used by this pass (else 0).
    pub build_ms: f64,
}

impl PassStats {
    /// Millions of rays (of every kind) per second of tracing.
    pub fn mrays_per_s(&self) -> f64 {
        self.rays.total() as f64 / (self.trace_ms.max(1e-9) * 1e3)
    }
}

/// Running sums in the precision being rendered.
enum Sums {
    F32(Vec<Vec3<f32>>),
    F64(Vec<Vec3<f64>>),
}

/// The progressive renderer behind the window.
pub struct Engine {
    desc: SceneDesc,
    accel: AccelOptions,
    scene32: Option<Scene<f32>>,
    scene64: Option<Scene<f64>>,
    pool: rayon::ThreadPool,
    pool_threads: usize,
    width: u32,
    height: u32,
    camera: CameraDesc,
    knobs: Knobs,
    sums: Sums,
    passes: u32,
}

fn zeros<T: Real>(n: usize) -> Vec<Vec3<T>> {
    vec![vec3(T::ZERO, T::ZERO, T::ZERO); n]
}

fn pool(threads: usize) -> Result<rayon::ThreadPool, String> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads.max(1))
        .build()
        .map_err(|e| format!("cannot start {threads} rendering threads: {e}"))
}

impl Engine {
    /// An engine for `desc` rendering `width` x `height` images, starting at the scene's
    /// camera with `knobs`.
    ///
    /// # Errors
    /// If the thread pool cannot be started.
    pub fn new(
        desc: SceneDesc,
        accel: AccelOptions,
        width: u32,
        height: u32,
        knobs: Knobs,
    ) -> Result<Self, String> {
        let n = width as usize * height as usize;
        Ok(Self {
            camera: desc.camera.clone(),
            desc,
            accel,
            scene32: None,
            scene64: None,
            pool: pool(knobs.threads)?,
            pool_threads: knobs.threads,
            width,
            height,
            knobs,
            sums: match knobs.precision {
                Precision::F32 => Sums::F32(zeros(n)),
                Precision::F64 => Sums::F64(zeros(n)),
            },
            passes: 0,
        })
    }

    /// Image width and height.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The current knobs.
    pub fn knobs(&self) -> &Knobs {
        &self.knobs
    }

    /// Sets the camera and knobs; any change restarts the accumulation at one sample per
    /// pixel.
    ///
    /// # Errors
    /// If a thread pool of the new size cannot be started (the old one is kept).
    pub fn set_view(&mut self, camera: &CameraDesc, knobs: &Knobs) -> Result<(), String> {
        if *camera == self.camera && *knobs == self.knobs {
            return Ok(());
        }
        if knobs.threads != self.pool_threads {
            self.pool = pool(knobs.threads)?;
            self.pool_threads = knobs.threads;
        }
        self.camera = camera.clone();
        self.knobs = *knobs;
        self.restart();
        Ok(())
    }

    /// Drops the accumulated samples.
    pub fn restart(&mut self) {
        let n = self.width as usize * self.height as usize;
        match (&mut self.sums, self.knobs.precision) {
            (Sums::F32(s), Precision::F32) => s.fill(vec3(0.0, 0.0, 0.0)),
            (Sums::F64(s), Precision::F64) => s.fill(vec3(0.0, 0.0, 0.0)),
            (_, Precision::F32) => self.sums = Sums::F32(zeros(n)),
            (_, Precision::F64) => self.sums = Sums::F64(zeros(n)),
        }
        self.passes = 0;
    }

    /// Samples per pixel accumulated so far.
    pub fn passes(&self) -> u32 {
        self.passes
    }

    /// Samples per pixel at which the image is complete (`aa * aa`).
    pub fn target_passes(&self) -> u32 {
        self.knobs.aa * self.knobs.aa
    }

    /// Whether every supersample has been traced.
    pub fn converged(&self) -> bool {
        self.passes >= self.target_passes()
    }

    /// Traces the next supersample of every pixel (nothing if converged).
    pub fn step(&mut self) -> PassStats {
        if self.converged() {
            return PassStats::default();
        }
        let settings = Settings {
            depth: self.knobs.depth,
            threshold: self.knobs.threshold,
            effects: self.knobs.effects,
            ..Settings::default()
        };
        let (w, h, aa, pass) = (self.width, self.height, self.knobs.aa, self.passes);
        let mut build_ms = 0.0;
        let start = Instant::now();
        let (desc, accel) = (&self.desc, &self.accel);
        let rays = match &mut self.sums {
            Sums::F32(sums) => {
                let scene = built(&mut self.scene32, desc, accel, &mut build_ms);
                pass_in(
                    &self.pool,
                    scene,
                    &self.camera,
                    &settings,
                    w,
                    h,
                    aa,
                    pass,
                    sums,
                )
            }
            Sums::F64(sums) => {
                let scene = built(&mut self.scene64, desc, accel, &mut build_ms);
                pass_in(
                    &self.pool,
                    scene,
                    &self.camera,
                    &settings,
                    w,
                    h,
                    aa,
                    pass,
                    sums,
                )
            }
        };
        self.passes += 1;
        PassStats {
            rays,
            trace_ms: start.elapsed().as_secs_f64() * 1e3 - build_ms,
            build_ms,
        }
    }

    /// The image so far: the mean of the samples accumulated (black before the first).
    pub fn image(&self) -> Image {
        let mut image = Image::new(self.width, self.height);
        if self.passes == 0 {
            return image;
        }
        let k = 1.0 / self.passes as f64;
        match &self.sums {
            Sums::F32(s) => mean_into(s, k, &mut image),
            Sums::F64(s) => mean_into(s, k, &mut image),
        }
        image
    }
}

/// The scene in precision `T`, built from `desc` on first use (adding the build time to
/// `build_ms`).
fn built<'a, T: tracer::Float>(
    slot: &'a mut Option<Scene<T>>,
    desc: &SceneDesc,
    accel: &AccelOptions,
    build_ms: &mut f64,
) -> &'a Scene<T> {
    slot.get_or_insert_with(|| {
        let t = Instant::now();
        let s = Scene::from_desc(desc, accel);
        *build_ms = t.elapsed().as_secs_f64() * 1e3;
        s
    })
}

#[allow(clippy::too_many_arguments)]
fn pass_in<T: tracer::Float>(
    pool: &rayon::ThreadPool,
    scene: &Scene<T>,
    camera: &CameraDesc,
    settings: &Settings,
    w: u32,
    h: u32,
    aa: u32,
    pass: u32,
    sums: &mut [Vec3<T>],
) -> RayCounts {
    let cam = tracer::Camera::new(camera, w, h);
    pool.install(|| render::accumulate_pass(scene, &cam, settings, aa, pass, sums).0)
}

/// `image = sums * k`, converted as [`render::render`] converts its pixels.
fn mean_into<T: Real>(sums: &[Vec3<T>], k: f64, image: &mut Image) {
    let k = T::from_f64(k);
    for (p, s) in image.pixels.iter_mut().zip(sums) {
        let c = s.scale(k).eval();
        *p = [
            c[0].to_f64() as f32,
            c[1].to_f64() as f32,
            c[2].to_f64() as f32,
        ];
    }
}

/// Packs linear RGB as `0x00RRGGBB`, with [`Image::to_rgb8`]'s clamping and rounding.
#[inline]
pub fn pack_rgb(p: [f32; 3]) -> u32 {
    let b = p.map(|c| (c.clamp(0.0, 1.0) * 255.0 + 0.5) as u32);
    (b[0] << 16) | (b[1] << 8) | b[2]
}
