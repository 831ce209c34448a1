#!/bin/sh
# Runs the criterion suite once per instruction set: the default target (x86-64),
# -C target-cpu=x86-64-v3 and -C target-cpu=x86-64-v4, each build in its own target
# directory (RUSTFLAGS apply to every crate, glam and ultraviolet included), then writes
# benches/results/tables.md and benches/results/speedup.svg from the medians.
#
#   benches/run-targets.sh            # everything (about 10 minutes per target on 2 cores)
#   benches/run-targets.sh abcde      # only groups/benchmarks matching a criterion filter
#
# BENCH_TARGET_DIR (default target/bench-targets) holds the builds and criterion data;
# BENCH_TARGETS overrides the list. A target whose instructions this CPU lacks (x86-64-v3
# needs AVX2 and FMA, x86-64-v4 AVX-512) is skipped with a note: its kernels are then
# checked by their assembly only (asm-dumps).
set -eu
cd "$(dirname "$0")/.."
base=${BENCH_TARGET_DIR:-target/bench-targets}
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
report_args=""
for t in $targets; do
    echo "== $t"
    RUSTFLAGS="-C target-cpu=$t" CARGO_TARGET_DIR="$base/$t" CRITERION_HOME="$base/criterion-$t" \
        cargo bench -p benches --bench kernels -- "$@"
    report_args="$report_args $t=$base/criterion-$t"
done
# shellcheck disable=SC2086 # word splitting of the TARGET=DIR list is intended
cargo run -p benches --release --example report -- --out benches/results $report_args
