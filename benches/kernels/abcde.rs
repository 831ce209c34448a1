//! `a*b + c*d - e`, element-wise: the expression-template showcase. Eager code builds
//! three temporaries; vecexpr evaluates the tree in one loop.

use crate::{Batch, V3};
use benches::config::{self, id, AOS, LONG, SOA16, SOA8};
use benches::data::Pcg32;
use benches::eager::{Eager, EagerHeap};
use benches::hand;
use benches::run::batch5;
use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Criterion, Throughput};
use std::hint::black_box;
use vecexpr::typenum::{U1024, U1048576, U16777216, U3, U4, U65536};
use vecexpr::{Expr, Vector};

/// One call on five single values.
fn single5<T>(
    g: &mut BenchmarkGroup<'_, WallTime>,
    implementation: &str,
    size: &str,
    v: [T; 5],
    f: impl Fn(&T, &T, &T, &T, &T) -> T,
) {
    g.bench_function(id(implementation, size), |b| {
        b.iter(|| {
            let [a, b, c, d, e] = black_box(&v);
            f(a, b, c, d, e)
        })
    });
}

/// The criterion group `abcde`.
pub fn bench(c: &mut Criterion) {
    let mut g = config::group(c, "abcde");
    let mut rng = Pcg32::new(1);

    // One 3-vector.
    let a: [[f32; 3]; 5] = core::array::from_fn(|_| rng.vec3s(1)[0]);
    single5(&mut g, "vecexpr", "3", a.map(V3::from), |a, b, c, d, e| {
        (a * b + c * d - e).eval()
    });
    single5(
        &mut g,
        "vecexpr_fma",
        "3",
        a.map(V3::from),
        |a, b, c, d, e| a.mul_add(b, c * d - e).eval(),
    );
    single5(
        &mut g,
        "eager",
        "3",
        a.map(|v| Eager::<f32, U3>::from_fn(|k| v[k])),
        |a, b, c, d, e| &(&(a * b) + &(c * d)) - e,
    );
    single5(&mut g, "hand", "3", a, |a, b, c, d, e| {
        hand::abcde3(*a, *b, *c, *d, *e)
    });
    single5(
        &mut g,
        "glam_vec3",
        "3",
        a.map(glam::Vec3::from),
        |a, b, c, d, e| *a * *b + *c * *d - *e,
    );
    single5(
        &mut g,
        "glam_vec3a",
        "3",
        a.map(glam::Vec3A::from),
        |a, b, c, d, e| *a * *b + *c * *d - *e,
    );
    single5(
        &mut g,
        "nalgebra",
        "3",
        a.map(nalgebra::Vector3::from),
        |a, b, c, d, e| a.component_mul(b) + c.component_mul(d) - e,
    );

    // One 4-vector.
    let a4: [[f32; 4]; 5] = core::array::from_fn(|_| {
        let v = rng.vec(4);
        [v[0], v[1], v[2], v[3]]
    });
    single5(
        &mut g,
        "vecexpr",
        "4",
        a4.map(Vector::<f32, U4>::from),
        |a, b, c, d, e| (a * b + c * d - e).eval(),
    );
    single5(
        &mut g,
        "vecexpr_fma",
        "4",
        a4.map(Vector::<f32, U4>::from),
        |a, b, c, d, e| a.mul_add(b, c * d - e).eval(),
    );
    single5(
        &mut g,
        "eager",
        "4",
        a4.map(|v| Eager::<f32, U4>::from_fn(|k| v[k])),
        |a, b, c, d, e| &(&(a * b) + &(c * d)) - e,
    );
    single5(&mut g, "hand", "4", a4, |a, b, c, d, e| {
        [0, 1, 2, 3].map(|k| a[k] * b[k] + c[k] * d[k] - e[k])
    });
    single5(
        &mut g,
        "glam_vec4",
        "4",
        a4.map(glam::Vec4::from),
        |a, b, c, d, e| *a * *b + *c * *d - *e,
    );
    single5(
        &mut g,
        "nalgebra",
        "4",
        a4.map(nalgebra::Vector4::from),
        |a, b, c, d, e| a.component_mul(b) + c.component_mul(d) - e,
    );

    // 4096 3-vectors, AoS and SoA.
    let bs: [Batch; 5] = core::array::from_fn(|_| Batch::random(&mut rng, config::BATCH));
    g.throughput(Throughput::Elements(config::BATCH as u64));
    batch5(
        &mut g,
        "vecexpr",
        AOS,
        &core::array::from_fn(|k| bs[k].vx.clone()),
        |a, b, c, d, e| (a * b + c * d - e).eval(),
    );
    batch5(
        &mut g,
        "vecexpr_fma",
        AOS,
        &core::array::from_fn(|k| bs[k].vx.clone()),
        |a, b, c, d, e| a.mul_add(b, c * d - e).eval(),
    );
    batch5(
        &mut g,
        "eager",
        AOS,
        &core::array::from_fn(|k| bs[k].eager.clone()),
        |a, b, c, d, e| &(&(a * b) + &(c * d)) - e,
    );
    batch5(
        &mut g,
        "hand",
        AOS,
        &core::array::from_fn(|k| bs[k].arr.clone()),
        |a, b, c, d, e| hand::abcde3(*a, *b, *c, *d, *e),
    );
    batch5(
        &mut g,
        "glam_vec3",
        AOS,
        &core::array::from_fn(|k| bs[k].glam3.clone()),
        |a, b, c, d, e| *a * *b + *c * *d - *e,
    );
    batch5(
        &mut g,
        "glam_vec3a",
        AOS,
        &core::array::from_fn(|k| bs[k].glam3a.clone()),
        |a, b, c, d, e| *a * *b + *c * *d - *e,
    );
    batch5(
        &mut g,
        "nalgebra",
        AOS,
        &core::array::from_fn(|k| bs[k].na.clone()),
        |a, b, c, d, e| a.component_mul(b) + c.component_mul(d) - e,
    );
    batch5(
        &mut g,
        "vecexpr",
        SOA8,
        &core::array::from_fn(|k| bs[k].p8.clone()),
        |a, b, c, d, e| (a * b + c * d - e).eval(),
    );
    batch5(
        &mut g,
        "eager",
        SOA8,
        &core::array::from_fn(|k| bs[k].e8.clone()),
        |a, b, c, d, e| &(&(a * b) + &(c * d)) - e,
    );
    batch5(
        &mut g,
        "ultraviolet",
        SOA8,
        &core::array::from_fn(|k| bs[k].uv.clone()),
        |a, b, c, d, e| *a * *b + *c * *d - *e,
    );
    batch5(
        &mut g,
        "vecexpr",
        SOA16,
        &core::array::from_fn(|k| bs[k].p16.clone()),
        |a, b, c, d, e| (a * b + c * d - e).eval(),
    );
    {
        let s: [benches::data::Soa; 5] = core::array::from_fn(|k| bs[k].soa.clone());
        let mut out = s[0].clone();
        g.bench_function(id("hand", SOA8), |bch| {
            bch.iter(|| {
                let [a, b, c, d, e] = black_box(&s);
                hand::abcde(&a.x, &b.x, &c.x, &d.x, &e.x, &mut out.x);
                hand::abcde(&a.y, &b.y, &c.y, &d.y, &e.y, &mut out.y);
                hand::abcde(&a.z, &b.z, &c.z, &d.z, &e.z, &mut out.z);
                black_box(&mut out);
            })
        });
    }

    // Long vectors.
    long::<U1024>(&mut g, &mut rng, LONG[0].1);
    long::<U65536>(&mut g, &mut rng, LONG[1].1);
    long::<U1048576>(&mut g, &mut rng, LONG[2].1);
    long::<U16777216>(&mut g, &mut rng, LONG[3].1);
    g.finish();
}

/// `a*b + c*d - e` over `N` elements; throughput counts the 5 loads and 1 store.
fn long<N: vecexpr::generic_array::ArrayLength>(
    g: &mut BenchmarkGroup<'_, WallTime>,
    rng: &mut Pcg32,
    label: &str,
) {
    let n = N::USIZE;
    config::long_settings(g, n);
    g.throughput(Throughput::Bytes(6 * 4 * n as u64));
    let data: [Vec<f32>; 5] = core::array::from_fn(|_| rng.vec(n));
    {
        let v: [Box<Vector<f32, N>>; 5] =
            core::array::from_fn(|k| Vector::boxed_from_fn(|i| data[k][i]));
        let mut out = Vector::<f32, N>::boxed_splat(0.0);
        g.bench_function(id("vecexpr", label), |bch| {
            bch.iter(|| {
                let [a, b, c, d, e] = black_box(&v);
                out.assign(&**a * &**b + &**c * &**d - &**e);
                black_box(&mut out);
            })
        });
        g.bench_function(id("vecexpr_fma", label), |bch| {
            bch.iter(|| {
                let [a, b, c, d, e] = black_box(&v);
                out.assign((&**a).mul_add(&**b, &**c * &**d - &**e));
                black_box(&mut out);
            })
        });
    }
    {
        let v: [EagerHeap<f32>; 5] = core::array::from_fn(|k| EagerHeap(data[k].clone()));
        g.bench_function(id("eager", label), |bch| {
            bch.iter(|| {
                let [a, b, c, d, e] = black_box(&v);
                &(&(a * b) + &(c * d)) - e
            })
        });
    }
    {
        let mut out = vec![0.0f32; n];
        g.bench_function(id("hand", label), |bch| {
            bch.iter(|| {
                let [a, b, c, d, e] = black_box(&data);
                hand::abcde(a, b, c, d, e, &mut out);
                black_box(&mut out);
            })
        });
    }
    {
        let v: [nalgebra::DVector<f32>; 5] =
            core::array::from_fn(|k| nalgebra::DVector::from_vec(data[k].clone()));
        g.bench_function(id("nalgebra", label), |bch| {
            bch.iter(|| {
                let [a, b, c, d, e] = black_box(&v);
                a.component_mul(b) + c.component_mul(d) - e
            })
        });
    }
}
