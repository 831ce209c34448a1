#!/usr/bin/env bash
# Trace times of the tracer against POV-Ray 3.7 on the seven classic SPD scenes, side by
# side: 512x512, one ray per pixel, no antialiasing, depth 5, all cores. Each round runs
# ../shared/peers/povray-times (which installs POV-Ray with apt if needed) over the seven
# scenes, then the tracer over the same seven; the table gives per-scene medians over the
# rounds, the median over rounds of the ratio POV-Ray / tracer (how many times faster
# the tracer is) and the geometric mean of the ratios, for wall-clock trace time and for
# CPU time of all threads while tracing (steadier on a loaded machine).
# Set TRACER_BIN to measure another tracer binary.
# Usage: tracer/scripts/vs-povray.sh [ROUNDS] [OUT_DIR] [-- extra tracer render options]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
rounds=${1:-3}
out=${2:-$(mktemp -d)}
shift $(( $# < 2 ? $# : 2 ))
[[ ${1:-} == "--" ]] && shift
extra=("$@")
scenes=$root/../shared/scenes/spd
peer=$root/../shared/peers/povray-times
mkdir -p "$out"
cargo build --profile perf -q -p tracer-cli --manifest-path "$root/Cargo.toml"
bin=${TRACER_BIN:-${CARGO_TARGET_DIR:-$root/target}/perf/tracer}
list=(balls-s4 gears-s4 mount-s6 rings-s7 teapot-s12 tetra-s6 tree-s11)
for r in $(seq 1 "$rounds"); do
  "$peer" "$out/pov-$r" >"$out/pov-$r.txt"
  for s in "${list[@]}"; do
    "$bin" render "$scenes/$s.nff" -o "$out/$s-$r.png" --width 512 --height 512 --aa 1 \
      --depth 5 --stats "$out/$s-$r.json" "${extra[@]}"
  done
done
python3 - "$out" "$rounds" "${list[@]}" <<'PY'
import json, math, statistics, sys
out, rounds, names = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
pov = {n: [] for n in names}
pov_cpu = {n: [] for n in names}
for r in range(1, rounds + 1):
    for line in open(f"{out}/pov-{r}.txt"):
        f = line.split()
        if f and f[0] in pov:
            pov[f[0]].append(float(f[1]) * 1e3)
            pov_cpu[f[0]].append(float(f[2]) * 1e3)
print(f"rounds: {rounds}, medians in ms; ratios are medians of the per-round ratios")
print("| scene | POV-Ray trace ms | tracer trace ms | POV-Ray / tracer | POV-Ray CPU ms | tracer CPU ms | CPU ratio |")
print("|---|---:|---:|---:|---:|---:|---:|")
ratios, cpu_ratios = [], []
for n in names:
    d = [json.load(open(f"{out}/{n}-{r}.json"))["times_ms"] for r in range(1, rounds + 1)]
    t = [x["trace"] for x in d]
    c = [x.get("trace_cpu", 0.0) for x in d]
    # The ratio of each round (POV-Ray and tracer run back to back), then the median.
    q = statistics.median(a / b for a, b in zip(pov[n], t))
    qc = statistics.median(a / b for a, b in zip(pov_cpu[n], c)) if min(c) > 0 else float("nan")
    ratios.append(q)
    cpu_ratios.append(qc)
    print(f"| {n} | {statistics.median(pov[n]):.0f} | {statistics.median(t):.1f} | {q:.2f} "
          f"| {statistics.median(pov_cpu[n]):.0f} | {statistics.median(c):.1f} | {qc:.2f} |")
geo = lambda v: math.exp(sum(map(math.log, v)) / len(v))
print(f"| geometric mean | | | {geo(ratios):.2f} | | | {geo(cpu_ratios):.2f} |")
PY
