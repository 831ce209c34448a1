#!/usr/bin/env bash
# The viewer's frame rate on balls-s4, teapot-s12 and tetra-s6 at 512x512 (one sample
# per pixel, depth 5, all cores), without a window: ROUNDS rounds, the scenes interleaved
# in each, FRAMES frames a run; prints each run's median frame time, then a Markdown table
# of the median over the rounds.
# Usage: tracer/scripts/viewer-bench.sh [SCENE_DIR] [ROUNDS] [FRAMES] [extra view options]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
scenes=${1:-$root/../shared/scenes/spd}
rounds=${2:-3}
frames=${3:-10}
shift $(( $# < 3 ? $# : 3 ))
cargo build --profile perf -q -p tracer-cli --manifest-path "$root/Cargo.toml"
bin=${CARGO_TARGET_DIR:-$root/target}/perf/tracer
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for r in $(seq "$rounds"); do
  for s in balls-s4 teapot-s12 tetra-s6; do
    "$bin" view "$scenes/$s.nff" --width 512 --height 512 --frames "$frames" --no-window "$@" \
      > "$out/$s.$r.txt"
    echo "round $r: $(sed -n 2p "$out/$s.$r.txt" | sed 's/;.*//') [$s]"
  done
done
python3 - "$out" "$rounds" <<'PY'
import re, statistics, sys
out, rounds = sys.argv[1], int(sys.argv[2])
print("\n| scene | median frame ms | fps | median trace ms | other ms | rays/frame (eye, refl, shadow) | Mrays/s |")
print("|---|---:|---:|---:|---:|---|---:|")
for s in ["balls-s4", "teapot-s12", "tetra-s6"]:
    runs = [open(f"{out}/{s}.{r}.txt").read() for r in range(1, rounds + 1)]
    num = lambda pat: statistics.median(float(re.search(pat, t).group(1)) for t in runs)
    frame, trace = num(r"median frame ([\d.]+) ms"), num(r"median trace ([\d.]+) ms")
    m = re.search(r"eye (\d+) reflection (\d+) refraction (\d+) shadow (\d+) total (\d+)", runs[0])
    eye, refl, _, shadow, total = map(int, m.groups())
    print(f"| {s} | {frame:.1f} | {1e3/frame:.1f} | {trace:.1f} | {frame-trace:.1f} | "
          f"{eye:,}, {refl:,}, {shadow:,} | {total/trace/1e3:.2f} |")
PY
