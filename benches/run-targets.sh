#!/bin/sh
# Runs the criterion suite for each instruction set: the default target (x86-64),
# -C target-cpu=x86-64-v3 and -C target-cpu=x86-64-v4, each build in its own target
# directory (RUSTFLAGS apply to every crate, glam and ultraviolet included), ROUNDS
# rounds (default 3) with the targets alternating inside each round, then writes
# benches/results/tables.md and benches/results/speedup.svg from the medians (per
# benchmark the median of the rounds' criterion medians).
#
#   benches/run-targets.sh            # everything (about 4 minutes per target and round)
#   ROUNDS=1 benches/run-targets.sh abcde   # one round of the benchmarks matching a filter
#
# BENCH_TARGET_DIR (default target/bench-targets) holds the builds and criterion data;
# BENCH_TARGETS overrides the list. A target whose instructions this CPU lacks (x86-64-v3
# needs AVX2 and FMA, x86-64-v4 AVX-512) is skipped with a note: its kernels are then
# checked by their assembly only (asm-dumps).
set -eu
cd "$(dirname "$0")/.."
base=${BENCH_TARGET_DIR:-target/bench-targets}
# Absolute: criterion resolves CRITERION_HOME from the bench's own directory (benches/).
case $base in /*) ;; *) base=$(pwd)/$base ;; esac
flags=$(grep -m1 '^flags' /proc/cpuinfo 2>/dev/null || true)
has() { case " $flags " in *" $1 "*) return 0 ;; *) return 1 ;; esac; }
targets=${BENCH_TARGETS:-}
if [ -z "$targets" ]; then
    targets="x86-64"
    if has avx2 && has fma; then targets="$targets x86-64-v3"; else echo "skipping x86-64-v3: no AVX2/FMA on this CPU" >&2; fi
    if has avx512f && has avx512bw && has avx512vl; then targets="$targets x86-64-v4"; else echo "skipping x86-64-v4: no AVX-512 on this CPU (asm-dumps checks its kernels)" >&2; fi
fi
# Build everything first, so compiling one target does not disturb measuring another.
for t in $targets; do
    RUSTFLAGS="-C target-cpu=$t" CARGO_TARGET_DIR="$base/$t" \
        cargo bench -p benches --bench kernels --no-run
done
rounds=${ROUNDS:-3}
r=1
while [ "$r" -le "$rounds" ]; do
    for t in $targets; do
        echo "== round $r of $rounds, $t, $(date -u +%H:%M) UTC, load $(cut -d' ' -f1-3 /proc/loadavg)"
        RUSTFLAGS="-C target-cpu=$t" CARGO_TARGET_DIR="$base/$t" CRITERION_HOME="$base/criterion-$t-r$r" \
            cargo bench -p benches --bench kernels -- "$@"
    done
    r=$((r + 1))
done
report_args=""
for t in $targets; do
    dirs="$base/criterion-$t-r1"
    r=2
    while [ "$r" -le "$rounds" ]; do dirs="$dirs,$base/criterion-$t-r$r"; r=$((r + 1)); done
    report_args="$report_args $t=$dirs"
done
# shellcheck disable=SC2086 # word splitting of the TARGET=DIR list is intended
cargo run -p benches --release --example report -- --out benches/results $report_args
