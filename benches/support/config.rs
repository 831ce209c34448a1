//! Benchmark sizes and criterion settings shared by all groups.

use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, BenchmarkId, Criterion, SamplingMode};
use std::time::Duration;

/// Number of 3-vectors in a batch.
pub const BATCH: usize = 4096;

/// Size label of a batch of 4096 vectors in array-of-structures form.
pub const AOS: &str = "aos4096";
/// Size label of 4096 vectors as 512 SoA packets of 8 lanes.
pub const SOA8: &str = "soa8x4096";
/// Size label of 4096 vectors as 256 SoA packets of 16 lanes.
pub const SOA16: &str = "soa16x4096";

/// The long-vector lengths and their labels.
pub const LONG: [(usize, &str); 4] = [
    (1 << 10, "1K"),
    (1 << 16, "64K"),
    (1 << 20, "1M"),
    (1 << 24, "16M"),
];

/// Elements of each array of the bandwidth measurement (128 MiB per array, so copy and
/// triad touch 256 and 384 MiB, several times the last-level cache).
pub const STREAM_LEN: usize = 1 << 25;

/// A benchmark group with the settings for small kernels (single vectors and batches):
/// short warm-up and measurement, ten samples, so the whole suite stays within minutes.
pub fn group<'a>(c: &'a mut Criterion, name: &str) -> BenchmarkGroup<'a, WallTime> {
    let mut g = c.benchmark_group(name);
    g.warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_millis(500))
        .sample_size(10)
        .nresamples(2000);
    g
}

/// Switches `g` to settings for a long vector of `n` elements: flat sampling (each
/// sample the same iteration count) and a longer measurement for the memory-bound sizes.
pub fn long_settings(g: &mut BenchmarkGroup<'_, WallTime>, n: usize) {
    if n >= 1 << 20 {
        g.sampling_mode(SamplingMode::Flat)
            .warm_up_time(Duration::from_millis(300))
            .measurement_time(Duration::from_millis(1500));
    } else {
        g.sampling_mode(SamplingMode::Auto)
            .warm_up_time(Duration::from_millis(200))
            .measurement_time(Duration::from_millis(500));
    }
}

/// The id `implementation/size`.
pub fn id(implementation: &str, size: &str) -> BenchmarkId {
    BenchmarkId::new(implementation, size)
}
