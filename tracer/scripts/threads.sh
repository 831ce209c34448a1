#!/usr/bin/env bash
# Thread speedup by scheduler: renders each scene (512x512, depth 5) with every scheduler
# (rayon, static, tiles of several sizes) on 1..N threads, all configurations interleaved
# round by round, and prints the median trace time, the median CPU time and the speedup
# over the same scheduler on one thread.
# Usage: tracer/scripts/threads.sh [ROUNDS] [MAX_THREADS] [SCENE...]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
rounds=${1:-3}
maxt=${2:-$(nproc)}
shift $(( $# < 2 ? $# : 2 ))
scenes=("$@")
[[ ${#scenes[@]} -eq 0 ]] && scenes=("$root/../shared/scenes/spd/balls-s4.nff" "$root/../shared/scenes/spd/teapot-s12.nff")
out=$(mktemp -d)
cargo build --profile perf -q -p tracer-cli --manifest-path "$root/Cargo.toml"
bin=${TRACER_BIN:-${CARGO_TARGET_DIR:-$root/target}/perf/tracer}
configs=("rayon 16" "static 16" "tiles 4" "tiles 16" "tiles 64")
for r in $(seq 1 "$rounds"); do
  for s in "${scenes[@]}"; do
    for c in "${configs[@]}"; do
      set -- $c
      for t in $(seq 1 "$maxt"); do
        n=$(basename "$s" .nff)
        # --tile only with the tile scheduler (the others refuse it); 16 names the
        # default in the file names of the others.
        tile=()
        [ "$1" = tiles ] && tile=(--tile-size "$2")
        "$bin" render "$s" -o "$out/i.png" --width 512 --height 512 --depth 5 --threads "$t" \
          --scheduler "$1" "${tile[@]}" --stats "$out/$n-$1-$2-$t-$r.json"
      done
    done
  done
done
python3 - "$out" "$rounds" "$maxt" "${scenes[@]}" <<'PY'
import glob, json, os, statistics, sys
out, rounds, maxt, scenes = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4:]
print(f"rounds: {rounds}; medians; speedup = 1-thread wall / t-thread wall of the same round")
print("| scene | scheduler | tile | threads | trace ms | CPU ms | speedup |")
print("|---|---|---:|---:|---:|---:|---:|")
for s in scenes:
    n = os.path.basename(s)[:-4]
    for cfg in ["rayon-16", "static-16", "tiles-4", "tiles-16", "tiles-64"]:
        one = [json.load(open(f"{out}/{n}-{cfg}-1-{r}.json"))["times_ms"] for r in range(1, rounds + 1)]
        for t in range(1, maxt + 1):
            d = [json.load(open(f"{out}/{n}-{cfg}-{t}-{r}.json"))["times_ms"] for r in range(1, rounds + 1)]
            w = statistics.median(x["trace"] for x in d)
            c = statistics.median(x["trace_cpu"] for x in d)
            sp = statistics.median(a["trace"] / b["trace"] for a, b in zip(one, d))
            sched, tile = cfg.split("-")
            print(f"| {n} | {sched} | {tile if sched == 'tiles' else '-'} | {t} | {w:.0f} | {c:.0f} | {sp:.2f} |")
PY
