#!/bin/sh
# Runs the criterion suite once per instruction set: the default target (x86-64),
# -C target-cpu=x86-64-v3 and -C target-cpu=x86-64-v4, each build in its own target
# directory (RUSTFLAGS apply to every crate, glam and ultraviolet included), then writes
# benches/results/tables.md and benches/results/speedup.svg from the medians.
#
#   benches/run-targets.sh            # everything (about 10 minutes per target on 2 cores)
#   benches/run-targets.sh abcde      # only groups/benchmarks matching a criterion filter
#
# BENCH_TARGET_DIR (default target/bench-targets) holds the builds and criterion data.
set -eu
cd "$(dirname "$0")/.."
base=${BENCH_TARGET_DIR:-target/bench-targets}
targets="x86-64 x86-64-v3 x86-64-v4"
# Build everything first, so compiling one target does not disturb measuring another.
for t in $targets; do
    RUSTFLAGS="-C target-cpu=$t" CARGO_TARGET_DIR="$base/$t" \
        cargo bench -p benches --bench kernels --no-run
done
report_args=""
for t in $targets; do
    echo "== $t"
    RUSTFLAGS="-C target-cpu=$t" CARGO_TARGET_DIR="$base/$t" CRITERION_HOME="$base/criterion-$t" \
        cargo bench -p benches --bench kernels -- "$@"
    report_args="$report_args $t=$base/criterion-$t"
done
# shellcheck disable=SC2086 # word splitting of the TARGET=DIR list is intended
cargo run -p benches --release --example report -- --out benches/results $report_args
