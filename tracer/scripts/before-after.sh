#!/usr/bin/env bash
# Before/after trace time of two tracer binaries on the seven classic SPD scenes
# (512x512, depth 5, all cores), interleaved: each round renders every scene with the
# old and the new binary back to back and checks that the two images are identical.
# Prints per-scene medians and the median of the per-round ratios old / new.
# Usage: tracer/scripts/before-after.sh OLD_BIN NEW_BIN [ROUNDS]
#   e.g. git worktree add /tmp/old COMMIT && cargo build --profile perf --manifest-path
#   /tmp/old/Cargo.toml && tracer/scripts/before-after.sh /tmp/old/target/perf/tracer
#   target/perf/tracer 3
#   (a commit older than the `perf` profile: its `--release` build has the same settings)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
old=$1 new=$2 rounds=${3:-3}
S=$root/../shared/scenes/spd
list=(balls-s4 gears-s4 mount-s6 rings-s7 teapot-s12 tetra-s6 tree-s11)
d=$(mktemp -d)
for r in $(seq 1 "$rounds"); do
  for s in "${list[@]}"; do
    "$old" render "$S/$s.nff" -o "$d/o.png" --width 512 --height 512 --stats "$d/$s-old-$r.json"
    "$new" render "$S/$s.nff" -o "$d/n.png" --width 512 --height 512 --stats "$d/$s-new-$r.json"
    cmp -s "$d/o.png" "$d/n.png" || echo "$s: images differ"
  done
done
python3 - "$d" "$rounds" "${list[@]}" <<'PY'
import json, math, statistics, sys
d, R, names = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
print("| scene | before ms | after ms | before / after |\n|---|---:|---:|---:|")
q = []
for s in names:
    o = [json.load(open(f"{d}/{s}-old-{r}.json"))["times_ms"]["trace"] for r in range(1, R + 1)]
    n = [json.load(open(f"{d}/{s}-new-{r}.json"))["times_ms"]["trace"] for r in range(1, R + 1)]
    x = statistics.median(a / b for a, b in zip(o, n))
    q.append(x)
    print(f"| {s} | {statistics.median(o):.0f} | {statistics.median(n):.0f} | {x:.2f} |")
print(f"| geometric mean | | | {math.exp(sum(map(math.log, q)) / len(q)):.2f} |")
PY
