//! The machine's memory bandwidth, measured in the same run as the kernels: STREAM's
//! copy (`c = a`) and triad (`a = b + s c`) on arrays of 32 Mi `f32` (McCalpin, "Memory
//! Bandwidth and Machine Balance in Current High Performance Computers", 1995). Bytes
//! are counted as STREAM does: 8 per element for copy, 12 for triad (write-allocate
//! traffic not counted).

use benches::config::{self, id, STREAM_LEN};
use benches::data::Pcg32;
use criterion::{Criterion, SamplingMode, Throughput};
use std::hint::black_box;
use std::time::Duration;

/// The criterion group `bandwidth`.
pub fn bench(c: &mut Criterion) {
    let mut g = config::group(c, "bandwidth");
    g.sampling_mode(SamplingMode::Flat)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    let n = STREAM_LEN;
    let mut rng = Pcg32::new(10);
    let (b, cc) = (rng.vec(n), rng.vec(n));
    let mut a = vec![0.0f32; n];
    g.throughput(Throughput::Bytes(8 * n as u64));
    g.bench_function(id("copy", "32M"), |bch| {
        bch.iter(|| {
            for (dst, &src) in a.iter_mut().zip(black_box(&b)) {
                *dst = src;
            }
            black_box(&mut a);
        })
    });
    g.throughput(Throughput::Bytes(12 * n as u64));
    g.bench_function(id("triad", "32M"), |bch| {
        bch.iter(|| {
            let s = black_box(3.0f32);
            for ((dst, &x), &y) in a.iter_mut().zip(black_box(&b)).zip(black_box(&cc)) {
                *dst = x + s * y;
            }
            black_box(&mut a);
        })
    });
    g.finish();
}
