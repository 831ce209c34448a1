//! The BLAS-1 kernels: `y += a x` (axpy) and the dot product, on single vectors,
//! batches and long vectors.

use crate::{Batch, V3};
use benches::config::{self, id, AOS, LONG, SOA16, SOA8};
use benches::data::Pcg32;
use benches::eager::{Eager, EagerHeap};
use benches::hand;
use benches::run::{batch, single};
use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Criterion, Throughput};
use std::hint::black_box;
use vecexpr::generic_array::ArrayLength;
use vecexpr::typenum::{U1024, U1048576, U16777216, U3, U65536};
use vecexpr::{Expr, Vector};

/// The scale of axpy: small, so repeated accumulation stays finite and normal.
const A: f32 = 1e-3;

/// The criterion group `axpy`.
pub fn axpy(c: &mut Criterion) {
    let mut g = config::group(c, "axpy");
    let mut rng = Pcg32::new(2);
    let (x, y) = (rng.vec3s(1)[0], rng.vec3s(1)[0]);
    single(&mut g, "vecexpr", "3", V3::from(x), V3::from(y), |x, y| {
        (y + x * A).eval()
    });
    single(
        &mut g,
        "vecexpr_fma",
        "3",
        V3::from(x),
        V3::from(y),
        |x, y| x.mul_add(A, y).eval(),
    );
    single(
        &mut g,
        "eager",
        "3",
        Eager::<f32, U3>::from_fn(|k| x[k]),
        Eager::from_fn(|k| y[k]),
        |x, y| y + &x.scale(A),
    );
    single(&mut g, "hand", "3", x, y, |x, y| {
        [0, 1, 2].map(|k| y[k] + A * x[k])
    });
    single(
        &mut g,
        "glam_vec3",
        "3",
        glam::Vec3::from(x),
        glam::Vec3::from(y),
        |x, y| *y + *x * A,
    );
    single(
        &mut g,
        "glam_vec3a",
        "3",
        glam::Vec3A::from(x),
        glam::Vec3A::from(y),
        |x, y| *y + *x * A,
    );
    single(
        &mut g,
        "nalgebra",
        "3",
        nalgebra::Vector3::from(x),
        nalgebra::Vector3::from(y),
        |x, y| y + x * A,
    );

    let (bx, by) = (
        Batch::random(&mut rng, config::BATCH),
        Batch::random(&mut rng, config::BATCH),
    );
    g.throughput(Throughput::Elements(config::BATCH as u64));
    batch(&mut g, "vecexpr", AOS, &bx.vx, &by.vx, |x, y| {
        (y + x * A).eval()
    });
    batch(&mut g, "vecexpr_fma", AOS, &bx.vx, &by.vx, |x, y| {
        x.mul_add(A, y).eval()
    });
    batch(&mut g, "eager", AOS, &bx.eager, &by.eager, |x, y| {
        y + &x.scale(A)
    });
    batch(&mut g, "hand", AOS, &bx.arr, &by.arr, |x, y| {
        [0, 1, 2].map(|k| y[k] + A * x[k])
    });
    batch(&mut g, "glam_vec3", AOS, &bx.glam3, &by.glam3, |x, y| {
        *y + *x * A
    });
    batch(&mut g, "glam_vec3a", AOS, &bx.glam3a, &by.glam3a, |x, y| {
        *y + *x * A
    });
    batch(&mut g, "nalgebra", AOS, &bx.na, &by.na, |x, y| y + x * A);

    long_axpy::<U1024>(&mut g, &mut rng, LONG[0].1);
    long_axpy::<U65536>(&mut g, &mut rng, LONG[1].1);
    long_axpy::<U1048576>(&mut g, &mut rng, LONG[2].1);
    long_axpy::<U16777216>(&mut g, &mut rng, LONG[3].1);
    g.finish();
}

/// `y += a x` over `N` elements, in place; throughput counts 2 loads and 1 store.
fn long_axpy<N: ArrayLength>(g: &mut BenchmarkGroup<'_, WallTime>, rng: &mut Pcg32, label: &str) {
    let n = N::USIZE;
    config::long_settings(g, n);
    g.throughput(Throughput::Bytes(3 * 4 * n as u64));
    let (x, y) = (rng.vec(n), rng.vec(n));
    {
        let vx: Box<Vector<f32, N>> = Vector::boxed_from_fn(|i| x[i]);
        let mut vy: Box<Vector<f32, N>> = Vector::boxed_from_fn(|i| y[i]);
        g.bench_function(id("vecexpr", label), |b| {
            b.iter(|| {
                *vy += &**black_box(&vx) * black_box(A);
                black_box(&mut vy);
            })
        });
        g.bench_function(id("vecexpr_fma", label), |b| {
            b.iter(|| {
                let vx = black_box(&vx);
                vy.update(&**vx, |y, x| x.mul_add(black_box(A), y));
                black_box(&mut vy);
            })
        });
    }
    {
        let ex = EagerHeap(x.clone());
        let mut ey = EagerHeap(y.clone());
        g.bench_function(id("eager", label), |b| {
            b.iter(|| {
                ey = &ey + &black_box(&ex).scale(black_box(A));
                black_box(&mut ey);
            })
        });
    }
    {
        let mut hy = y.clone();
        g.bench_function(id("hand", label), |b| {
            b.iter(|| {
                hand::axpy(black_box(A), black_box(&x), &mut hy);
                black_box(&mut hy);
            })
        });
    }
    {
        let nx = nalgebra::DVector::from_vec(x.clone());
        let mut ny = nalgebra::DVector::from_vec(y.clone());
        g.bench_function(id("nalgebra", label), |b| {
            b.iter(|| {
                ny.axpy(black_box(A), black_box(&nx), 1.0);
                black_box(&mut ny);
            })
        });
    }
}

/// The criterion group `dot`.
pub fn dot(c: &mut Criterion) {
    let mut g = config::group(c, "dot");
    let mut rng = Pcg32::new(3);
    let (x, y) = (rng.vec3s(1)[0], rng.vec3s(1)[0]);
    single(&mut g, "vecexpr", "3", V3::from(x), V3::from(y), |x, y| {
        x.dot(y)
    });
    single(
        &mut g,
        "eager",
        "3",
        Eager::<f32, U3>::from_fn(|k| x[k]),
        Eager::from_fn(|k| y[k]),
        |x, y| x.dot(y),
    );
    single(&mut g, "hand", "3", x, y, |x, y| hand::dot3(*x, *y));
    single(
        &mut g,
        "glam_vec3",
        "3",
        glam::Vec3::from(x),
        glam::Vec3::from(y),
        |x, y| x.dot(*y),
    );
    single(
        &mut g,
        "glam_vec3a",
        "3",
        glam::Vec3A::from(x),
        glam::Vec3A::from(y),
        |x, y| x.dot(*y),
    );
    single(
        &mut g,
        "nalgebra",
        "3",
        nalgebra::Vector3::from(x),
        nalgebra::Vector3::from(y),
        |x, y| x.dot(y),
    );

    let (bx, by) = (
        Batch::random(&mut rng, config::BATCH),
        Batch::random(&mut rng, config::BATCH),
    );
    g.throughput(Throughput::Elements(config::BATCH as u64));
    batch(&mut g, "vecexpr", AOS, &bx.vx, &by.vx, |x, y| x.dot(y));
    batch(&mut g, "eager", AOS, &bx.eager, &by.eager, |x, y| x.dot(y));
    batch(&mut g, "hand", AOS, &bx.arr, &by.arr, |x, y| {
        hand::dot3(*x, *y)
    });
    batch(&mut g, "glam_vec3", AOS, &bx.glam3, &by.glam3, |x, y| {
        x.dot(*y)
    });
    batch(&mut g, "glam_vec3a", AOS, &bx.glam3a, &by.glam3a, |x, y| {
        x.dot(*y)
    });
    batch(&mut g, "nalgebra", AOS, &bx.na, &by.na, |x, y| x.dot(y));
    batch(&mut g, "vecexpr", SOA8, &bx.p8, &by.p8, |x, y| x.dot(y));
    batch(&mut g, "eager", SOA8, &bx.e8, &by.e8, |x, y| x.dot(y));
    batch(&mut g, "ultraviolet", SOA8, &bx.uv, &by.uv, |x, y| {
        x.dot(*y)
    });
    batch(&mut g, "vecexpr", SOA16, &bx.p16, &by.p16, |x, y| x.dot(y));

    long_dot::<U1024>(&mut g, &mut rng, LONG[0].1);
    long_dot::<U65536>(&mut g, &mut rng, LONG[1].1);
    long_dot::<U1048576>(&mut g, &mut rng, LONG[2].1);
    long_dot::<U16777216>(&mut g, &mut rng, LONG[3].1);
    g.finish();
}

/// $x \cdot y$ over `N` elements; throughput counts 2 loads.
fn long_dot<N: ArrayLength>(g: &mut BenchmarkGroup<'_, WallTime>, rng: &mut Pcg32, label: &str) {
    let n = N::USIZE;
    config::long_settings(g, n);
    g.throughput(Throughput::Bytes(2 * 4 * n as u64));
    let (x, y) = (rng.vec(n), rng.vec(n));
    {
        let vx: Box<Vector<f32, N>> = Vector::boxed_from_fn(|i| x[i]);
        let vy: Box<Vector<f32, N>> = Vector::boxed_from_fn(|i| y[i]);
        g.bench_function(id("vecexpr", label), |b| {
            b.iter(|| black_box(&*vx).dot(black_box(&*vy)))
        });
    }
    {
        let (ex, ey) = (EagerHeap(x.clone()), EagerHeap(y.clone()));
        g.bench_function(id("eager", label), |b| {
            b.iter(|| black_box(&ex).dot(black_box(&ey)))
        });
    }
    g.bench_function(id("hand", label), |b| {
        b.iter(|| hand::dot(black_box(&x), black_box(&y)))
    });
    {
        let (nx, ny) = (
            nalgebra::DVector::from_vec(x.clone()),
            nalgebra::DVector::from_vec(y.clone()),
        );
        g.bench_function(id("nalgebra", label), |b| {
            b.iter(|| black_box(&nx).dot(black_box(&ny)))
        });
    }
}
