//! The measurement loops shared by every group, so all implementations of a kernel are
//! timed by the same code: inputs `black_box`ed, outputs kept alive.

use crate::config::id;
use crate::data::Aligned;
use criterion::measurement::WallTime;
use criterion::BenchmarkGroup;
use std::hint::black_box;
use vecexpr::simd::{Isa, SimdF32};
use vecexpr::typenum::U3;
use vecexpr::{vec3, Vector};

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

/// Throughput of a kernel on explicit SIMD lanes (`vecexpr::simd`) over a batch in the
/// flat packet layout of [`crate::data::aosoa`], run through [`Isa::dispatch`]: `run`
/// is called with the instruction set and the input and output buffers, and is expected
/// to dispatch a [`vecexpr::simd::Kernel`] that loops over all packets, so the whole loop
/// is compiled for that instruction set. The buffers are copied to 64-byte aligned
/// memory first. Skipped (with a note) where the CPU lacks it.
pub fn lanes(
    g: &mut BenchmarkGroup<'_, WallTime>,
    implementation: &str,
    size: &str,
    isa: Isa,
    a: &[f32],
    b: &[f32],
    run: impl Fn(Isa, &[f32], &[f32], &mut [f32]),
) {
    if !isa.is_available() {
        eprintln!("{implementation}/{size}: skipped, this CPU has no {isa}");
        return;
    }
    // Inputs and output 64-byte aligned, as the lane types and ultraviolet's are.
    let (a, b) = (Aligned::new(a), Aligned::new(b));
    let (a, b) = (a.as_slice(), b.as_slice());
    let mut out = Aligned::new(a);
    g.bench_function(id(implementation, size), |bch| {
        bch.iter(|| {
            run(isa, black_box(a), black_box(b), out.as_mut_slice());
            black_box(&mut out);
        })
    });
}

/// Loads packet `c` (`x`, `y`, `z` lanes one after the other, as [`crate::data::aosoa`]
/// lays them out) as an SoA 3-vector.
///
/// # Panics
/// If `c` is shorter than three registers.
#[inline(always)]
pub fn load3<S: SimdF32>(c: &[f32]) -> Vector<S, U3> {
    let n = S::LANES;
    vec3(
        S::load(&c[..n]),
        S::load(&c[n..2 * n]),
        S::load(&c[2 * n..3 * n]),
    )
}

/// Stores an SoA 3-vector into packet `c`, the inverse of [`load3`].
///
/// # Panics
/// If `c` is shorter than three registers.
#[inline(always)]
pub fn store3<S: SimdF32>(v: Vector<S, U3>, c: &mut [f32]) {
    let n = S::LANES;
    v[0].store(&mut c[..n]);
    v[1].store(&mut c[n..2 * n]);
    v[2].store(&mut c[2 * n..3 * n]);
}
