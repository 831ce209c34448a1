//! The measurement loops shared by every group, so all implementations of a kernel are
//! timed by the same code: inputs `black_box`ed, outputs kept alive.

use crate::config::id;
use criterion::measurement::WallTime;
use criterion::BenchmarkGroup;
use std::hint::black_box;

/// Latency of one call `f(a, b)` on single values (one 3- or 4-vector).
pub fn single<T, O>(
    g: &mut BenchmarkGroup<'_, WallTime>,
    implementation: &str,
    size: &str,
    a: T,
    b: T,
    f: impl Fn(&T, &T) -> O,
) {
    g.bench_function(id(implementation, size), |bch| {
        bch.iter(|| f(black_box(&a), black_box(&b)))
    });
}

/// Throughput of `out[k] = f(a[k], b[k])` over a whole batch (AoS vectors or SoA
/// packets).
pub fn batch<T, O: Clone>(
    g: &mut BenchmarkGroup<'_, WallTime>,
    implementation: &str,
    size: &str,
    a: &[T],
    b: &[T],
    f: impl Fn(&T, &T) -> O,
) {
    let mut out = vec![f(&a[0], &b[0]); a.len()];
    g.bench_function(id(implementation, size), |bch| {
        bch.iter(|| {
            let (a, b) = (black_box(a), black_box(b));
            for ((o, x), y) in out.iter_mut().zip(a).zip(b) {
                *o = f(x, y);
            }
            black_box(&mut out);
        })
    });
}

/// Throughput of `out[k] = f(a[k], b[k], c[k], d[k], e[k])` over a batch.
pub fn batch5<T, O: Clone>(
    g: &mut BenchmarkGroup<'_, WallTime>,
    implementation: &str,
    size: &str,
    v: &[Vec<T>; 5],
    f: impl Fn(&T, &T, &T, &T, &T) -> O,
) {
    let mut out = vec![f(&v[0][0], &v[1][0], &v[2][0], &v[3][0], &v[4][0]); v[0].len()];
    g.bench_function(id(implementation, size), |bch| {
        bch.iter(|| {
            let [a, b, c, d, e] = black_box(v);
            let inputs = a.iter().zip(b).zip(c).zip(d).zip(e);
            for (o, ((((a, b), c), d), e)) in out.iter_mut().zip(inputs) {
                *o = f(a, b, c, d, e);
            }
            black_box(&mut out);
        })
    });
}

/// Throughput of `out[k] = f(a[k], b[k])` over a batch stored as hand-managed SoA
/// arrays (the hand-written packet code: the compiler vectorises across vectors).
pub fn soa(
    g: &mut BenchmarkGroup<'_, WallTime>,
    implementation: &str,
    size: &str,
    a: &crate::data::Soa,
    b: &crate::data::Soa,
    f: impl Fn([f32; 3], [f32; 3]) -> [f32; 3],
) {
    let mut out = a.clone();
    g.bench_function(id(implementation, size), |bch| {
        bch.iter(|| {
            let (a, b) = (black_box(a), black_box(b));
            let n = out.x.len();
            let (ax, ay, az) = (&a.x[..n], &a.y[..n], &a.z[..n]);
            let (bx, by, bz) = (&b.x[..n], &b.y[..n], &b.z[..n]);
            let (ox, oy, oz) = (&mut out.x[..n], &mut out.y[..n], &mut out.z[..n]);
            for i in 0..n {
                let r = f([ax[i], ay[i], az[i]], [bx[i], by[i], bz[i]]);
                ox[i] = r[0];
                oy[i] = r[1];
                oz[i] = r[2];
            }
            black_box(&mut out);
        })
    });
}
