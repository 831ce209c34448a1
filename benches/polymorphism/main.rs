//! The cost of polymorphism (the thesis' section 5.5): the same rays intersected, closest
//! hit over the whole array, with the same mixed primitives (spheres, triangles, planes
//! in random order) stored three ways:
//!
//! - `dyn`: `Vec<Box<dyn Primitive>>`, one heap object per primitive and an indirect
//!   call per test;
//! - `enum`: `Vec<Prim>`, one tagged value per primitive (as large as the largest kind)
//!   and a `match` per test;
//! - `arrays`: one array per kind, each scanned by its own loop (the tracer's layout,
//!   `tracer/src/geometry/storage.rs`).
//!
//! Two controls separate branch prediction from memory layout: `dyn_sorted` and
//! `enum_sorted` are the first two with the primitives sorted by kind, so their
//! dispatch is as predictable as the arrays' while their footprint stays the same.
//!
//! The intersection kernels are written once, as the [`Primitive`] implementations on the
//! tracer's own primitive types, in vecexpr, and inlined into all three, so only the
//! dispatch and the memory layout differ. Sizes 1 to 4^10 (1,048,576) primitives; each
//! iteration casts enough rays for at least 2^18 ray-primitive tests. Group
//! `polymorphism` is timed in process CPU time ([`benches::cpu::CpuTime`], steady on a
//! shared machine), `polymorphism_cycles` (sizes up to 4^6) by the cycle counter
//! ([`benches::cycles::Cycles`], which like the wall clock also counts time spent
//! waiting for a core). `benches/polymorphism.sh` runs both
//! and prints the table of `benches/RESULTS.md`.

use benches::cpu::CpuTime;
use benches::cycles::Cycles;
use benches::data::Pcg32;
use criterion::measurement::Measurement;
use criterion::{BenchmarkGroup, Criterion, SamplingMode, Throughput};
use std::hint::black_box;
use std::time::Duration;
use tracer::geometry::{Plane, Sphere, Triangle};
use vecexpr::{vec3, Expr, Vec3};

/// A ray with a unit direction.
#[derive(Clone, Copy, Debug)]
struct Ray {
    origin: Vec3<f32>,
    dir: Vec3<f32>,
}

/// One intersection kernel: the nearest `t` in `(0, t_max)`.
trait Primitive {
    fn hit(&self, r: &Ray, t_max: f32) -> Option<f32>;
}

impl Primitive for Sphere<f32> {
    /// The geometric test for a unit direction: $b = f \cdot d$, $c = f \cdot f - r^2$,
    /// roots $-b \pm \sqrt{b^2 - c}$.
    #[inline(always)]
    fn hit(&self, r: &Ray, t_max: f32) -> Option<f32> {
        let f = (r.origin - self.center).eval();
        let b = f.dot(&r.dir);
        let c = f.length_squared() - self.radius * self.radius;
        let disc = b * b - c;
        if disc < 0.0 {
            return None;
        }
        let s = disc.sqrt();
        let t = if -b - s > 0.0 { -b - s } else { -b + s };
        (t > 0.0 && t < t_max).then_some(t)
    }
}

impl Primitive for Triangle<f32> {
    /// Möller–Trumbore (T. Möller, B. Trumbore, "Fast, Minimum Storage Ray/Triangle
    /// Intersection", Journal of Graphics Tools 2(1), 1997), two-sided.
    #[inline(always)]
    fn hit(&self, r: &Ray, t_max: f32) -> Option<f32> {
        let e1 = (self.v[1] - self.v[0]).eval();
        let e2 = (self.v[2] - self.v[0]).eval();
        let p = r.dir.cross(&e2);
        let det = e1.dot(&p);
        if det == 0.0 {
            return None;
        }
        let inv = det.recip();
        let s = (r.origin - self.v[0]).eval();
        let u = s.dot(&p) * inv;
        if !(0.0..=1.0).contains(&u) {
            return None;
        }
        let q = s.cross(&e1);
        let v = r.dir.dot(&q) * inv;
        if !(v >= 0.0 && u + v <= 1.0) {
            return None;
        }
        let t = e2.dot(&q) * inv;
        (t > 0.0 && t < t_max).then_some(t)
    }
}

impl Primitive for Plane<f32> {
    #[inline(always)]
    fn hit(&self, r: &Ray, t_max: f32) -> Option<f32> {
        let denom = r.dir.dot(&self.normal);
        if denom == 0.0 {
            return None;
        }
        let t = (self.point - r.origin).dot(self.normal) / denom;
        (t > 0.0 && t < t_max).then_some(t)
    }
}

/// The tagged storage.
#[derive(Clone, Copy, Debug)]
enum Prim {
    Sphere(Sphere<f32>),
    Triangle(Triangle<f32>),
    Plane(Plane<f32>),
}

impl Prim {
    #[inline(always)]
    fn hit(&self, r: &Ray, t_max: f32) -> Option<f32> {
        match self {
            Prim::Sphere(s) => s.hit(r, t_max),
            Prim::Triangle(t) => t.hit(r, t_max),
            Prim::Plane(p) => p.hit(r, t_max),
        }
    }
}

/// The tracer's layout: one array per kind.
#[derive(Default)]
struct Arrays {
    spheres: Vec<Sphere<f32>>,
    triangles: Vec<Triangle<f32>>,
    planes: Vec<Plane<f32>>,
}

/// The closest hit: `(t, index)`; the index counts from 0 through the storage order
/// (for [`Arrays`]: spheres, then triangles, then planes); `usize::MAX` for none.
#[inline(always)]
fn closest_in<P: Primitive>(prims: &[P], r: &Ray, base: usize, best: &mut (f32, usize)) {
    for (i, p) in prims.iter().enumerate() {
        if let Some(t) = p.hit(r, best.0) {
            *best = (t, base + i);
        }
    }
}

#[inline(never)]
fn closest_dyn(prims: &[Box<dyn Primitive>], r: &Ray) -> (f32, usize) {
    let mut best = (f32::INFINITY, usize::MAX);
    for (i, p) in prims.iter().enumerate() {
        if let Some(t) = p.hit(r, best.0) {
            best = (t, i);
        }
    }
    best
}

#[inline(never)]
fn closest_enum(prims: &[Prim], r: &Ray) -> (f32, usize) {
    let mut best = (f32::INFINITY, usize::MAX);
    for (i, p) in prims.iter().enumerate() {
        if let Some(t) = p.hit(r, best.0) {
            best = (t, i);
        }
    }
    best
}

#[inline(never)]
fn closest_arrays(a: &Arrays, r: &Ray) -> (f32, usize) {
    let mut best = (f32::INFINITY, usize::MAX);
    closest_in(&a.spheres, r, 0, &mut best);
    closest_in(&a.triangles, r, a.spheres.len(), &mut best);
    closest_in(&a.planes, r, a.spheres.len() + a.triangles.len(), &mut best);
    best
}

/// `n` primitives, a third of each kind in random order, inside $[-1, 1]^3$, sized so
/// that a ray crosses a few of them whatever `n`, and `rays` rays from outside the cube
/// through it.
fn scene(n: usize, rays: usize, seed: u64) -> (Vec<Prim>, Vec<Ray>) {
    let mut rng = Pcg32::new(seed);
    let size = 0.5 / (n as f32).cbrt();
    let p3 = |rng: &mut Pcg32| {
        vec3(
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        )
    };
    let prims = (0..n)
        .map(|_| {
            let c = p3(&mut rng);
            match rng.next_u32() % 3 {
                0 => Prim::Sphere(Sphere {
                    center: c,
                    radius: size * rng.range(0.3, 1.0),
                }),
                1 => {
                    let corner = |rng: &mut Pcg32| {
                        let u = Vec3::<f32>::from(rng.unit3());
                        (c + u.scale(size * 1.5)).eval()
                    };
                    Prim::Triangle(Triangle {
                        v: [corner(&mut rng), corner(&mut rng), corner(&mut rng)],
                    })
                }
                _ => Prim::Plane(
                    Plane::new(c, Vec3::from(rng.unit3())).expect("unit normal is valid"),
                ),
            }
        })
        .collect();
    let rays = (0..rays)
        .map(|_| {
            let origin = Vec3::<f32>::from(rng.unit3()).scale(3.0).eval();
            let dir = (p3(&mut rng).scale(0.5) - origin).normalize();
            Ray { origin, dir }
        })
        .collect();
    (prims, rays)
}

/// The three storages of the same primitives, and the first two once more with the
/// primitives sorted by kind (same footprint, predictable dispatch).
struct Storages {
    dyns: Vec<Box<dyn Primitive>>,
    enums: Vec<Prim>,
    dyns_sorted: Vec<Box<dyn Primitive>>,
    enums_sorted: Vec<Prim>,
    arrays: Arrays,
    rays: Vec<Ray>,
}

fn storages(n: usize) -> Storages {
    let rays_per_iter = (1usize << 18).div_ceil(n);
    let (enums, rays) = scene(n, rays_per_iter, 0x5eed_0000 + n as u64);
    let mut arrays = Arrays::default();
    // Boxes allocated in array order, as a loader would.
    let boxed = |prims: &[Prim]| -> Vec<Box<dyn Primitive>> {
        prims
            .iter()
            .map(|p| -> Box<dyn Primitive> {
                match *p {
                    Prim::Sphere(s) => Box::new(s),
                    Prim::Triangle(t) => Box::new(t),
                    Prim::Plane(p) => Box::new(p),
                }
            })
            .collect()
    };
    let dyns = boxed(&enums);
    let mut enums_sorted = enums.clone();
    enums_sorted.sort_by_key(|p| match p {
        Prim::Sphere(_) => 0,
        Prim::Triangle(_) => 1,
        Prim::Plane(_) => 2,
    });
    let dyns_sorted = boxed(&enums_sorted);
    for p in &enums {
        match *p {
            Prim::Sphere(s) => arrays.spheres.push(s),
            Prim::Triangle(t) => arrays.triangles.push(t),
            Prim::Plane(p) => arrays.planes.push(p),
        }
    }
    Storages {
        dyns,
        enums,
        dyns_sorted,
        enums_sorted,
        arrays,
        rays,
    }
}

/// Sizes: 4^0 … 4^max_exp.
fn sizes(max_exp: u32) -> impl Iterator<Item = usize> {
    (0..=max_exp).map(|e| 4usize.pow(e))
}

/// Casts every ray; the sum of the hit indices keeps the results alive.
#[inline(always)]
fn cast(rays: &[Ray], f: impl Fn(&Ray) -> (f32, usize)) -> usize {
    rays.iter()
        .map(|r| f(black_box(r)).1)
        .fold(0usize, usize::wrapping_add)
}

fn run<M: Measurement>(g: &mut BenchmarkGroup<'_, M>, n: usize) {
    let s = storages(n);
    // All three find the same closest hits (same kernels, same order within a kind).
    for r in s.rays.iter().take(64) {
        let t = [
            closest_dyn(&s.dyns, r).0,
            closest_enum(&s.enums, r).0,
            closest_arrays(&s.arrays, r).0,
            closest_dyn(&s.dyns_sorted, r).0,
            closest_enum(&s.enums_sorted, r).0,
        ];
        assert!(t.iter().all(|&x| x == t[0]), "storages disagree: {t:?}");
    }
    g.throughput(Throughput::Elements((s.rays.len() * n) as u64));
    if n >= 1 << 16 {
        g.sampling_mode(SamplingMode::Flat);
    } else {
        g.sampling_mode(SamplingMode::Auto);
    }
    g.bench_function(criterion::BenchmarkId::new("dyn", n), |b| {
        b.iter(|| cast(&s.rays, |r| closest_dyn(&s.dyns, r)))
    });
    g.bench_function(criterion::BenchmarkId::new("enum", n), |b| {
        b.iter(|| cast(&s.rays, |r| closest_enum(&s.enums, r)))
    });
    g.bench_function(criterion::BenchmarkId::new("arrays", n), |b| {
        b.iter(|| cast(&s.rays, |r| closest_arrays(&s.arrays, r)))
    });
    g.bench_function(criterion::BenchmarkId::new("dyn_sorted", n), |b| {
        b.iter(|| cast(&s.rays, |r| closest_dyn(&s.dyns_sorted, r)))
    });
    g.bench_function(criterion::BenchmarkId::new("enum_sorted", n), |b| {
        b.iter(|| cast(&s.rays, |r| closest_enum(&s.enums_sorted, r)))
    });
}

fn settings<M: Measurement>(g: &mut BenchmarkGroup<'_, M>) {
    g.warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_millis(800))
        .sample_size(15)
        .nresamples(2000);
}

fn cpu(c: &mut Criterion<CpuTime>) {
    let mut g = c.benchmark_group("polymorphism");
    settings(&mut g);
    for n in sizes(10) {
        run(&mut g, n);
    }
    g.finish();
}

fn cycles(c: &mut Criterion<Cycles>) {
    let mut g = c.benchmark_group("polymorphism_cycles");
    settings(&mut g);
    for n in sizes(6) {
        run(&mut g, n);
    }
    g.finish();
}

fn main() {
    eprintln!(
        "bytes: Sphere {}, Triangle {}, Plane {}, Prim (enum) {}, Box<dyn Primitive> {}",
        std::mem::size_of::<Sphere<f32>>(),
        std::mem::size_of::<Triangle<f32>>(),
        std::mem::size_of::<Plane<f32>>(),
        std::mem::size_of::<Prim>(),
        std::mem::size_of::<Box<dyn Primitive>>()
    );
    let mut c = Criterion::default()
        .with_measurement(CpuTime)
        .configure_from_args();
    cpu(&mut c);
    c.final_summary();
    let mut c = Criterion::default()
        .with_measurement(Cycles)
        .configure_from_args();
    cycles(&mut c);
    c.final_summary();
}
