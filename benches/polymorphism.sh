#!/usr/bin/env bash
# The polymorphism-cost bench (benches/polymorphism/main.rs) and its tables: CPU ns per
# ray-primitive test (process CPU time) and TSC ticks per test (cycle counter) for the
# storages, and the ratios to per-type arrays. Criterion medians.
# Usage: benches/polymorphism.sh [criterion filter]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
export CRITERION_HOME=${CRITERION_HOME:-${CARGO_TARGET_DIR:-$root/target}/criterion}
cargo bench -q -p benches --manifest-path "$root/Cargo.toml" --bench polymorphism -- "$@" >&2
python3 - "$CRITERION_HOME" <<'PY'
import json, math, os, sys
home = sys.argv[1]

def median(group, impl, n):
    p = os.path.join(home, group, impl, str(n), "new", "estimates.json")
    if not os.path.exists(p):
        return None
    return json.load(open(p))["median"]["point_estimate"]

for group, unit in (("polymorphism", "CPU ns"), ("polymorphism_cycles", "TSC ticks")):
    print(f"\n{group}: {unit} per ray-primitive test (criterion median), ratios to arrays\n")
    print(f"| primitives | dyn | enum | arrays | dyn sorted | enum sorted "
          "| dyn / arrays | enum / arrays | dyn sorted / arrays | enum sorted / arrays |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for e in range(11):
        n = 4 ** e
        tests = math.ceil(2 ** 18 / n) * n
        v = [median(group, i, n) for i in ("dyn", "enum", "arrays", "dyn_sorted", "enum_sorted")]
        if None in v:
            continue
        d, en, a, ds, es = (x / tests for x in v)
        print(f"| {n} | {d:.2f} | {en:.2f} | {a:.2f} | {ds:.2f} | {es:.2f} "
              f"| {d / a:.2f} | {en / a:.2f} | {ds / a:.2f} | {es / a:.2f} |")
PY
