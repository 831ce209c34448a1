#!/usr/bin/env bash
# Where a render spends its time: samples CPU time with perf (DWARF call graphs, one
# thread, 1024x1024) and sorts every sample by the innermost tracer function on its
# stack, inlined frames included: shadow-ray queries, closest-hit queries, shading, the
# camera and pixel loop, or anything else (parsing, BVH build, image output, kernel).
# Prints a Markdown table per effects mode, then the phase times of the same run from
# its --stats JSON (milliseconds and cycle-counter ticks, see tracer/src/cycles.rs).
# Needs perf and python3.
# Usage: tracer/scripts/profile-phases.sh SCENE.nff [all|auto]...
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
scene=${1:?usage: profile-phases.sh SCENE.nff [all|auto]...}
shift
modes=${*:-all auto}
cargo build --profile perf -q -p tracer-cli --manifest-path "$root/Cargo.toml"
bin=${CARGO_TARGET_DIR:-$root/target}/perf/tracer
out=$(mktemp -d)
for m in $modes; do
  perf record -q -e cpu-clock -F 4000 --call-graph dwarf,16384 -o "$out/perf.data" \
    "$bin" render "$scene" -o "$out/img.png" --threads 1 --width 1024 --height 1024 \
    --effects "$m" --stats "$out/stats.json" 2>/dev/null
  perf script -i "$out/perf.data" --inline 2>/dev/null > "$out/perf.txt"
  echo "$(basename "$scene") --effects $m"
  python3 - "$out/perf.txt" <<'PY'
import collections, re, sys

RULES = [
    (r"occluded_kinds|\bocclude|any<|any_moller", "shadow-ray queries"),
    (r"intersect_kinds|\bintersect<f|closest<|closest_moller|make_hit", "closest-hit queries"),
    (r"trace_fx|shade_fx|\bshade<|\btrace<", "shading"),
    (r"render_grid|render_corners|eye_sample|camera", "camera and pixel loop"),
]
OTHER = "other (parse, build, output, kernel)"

def category(frame):
    for pattern, name in RULES:
        if re.search(pattern, frame):
            return name
    return None

counts = collections.Counter()
for block in open(sys.argv[1]).read().split("\n\n"):
    lines = [l.strip() for l in block.strip().split("\n")]
    if len(lines) < 2 or "cpu-clock" not in lines[0]:
        continue
    frames = lines[1:]
    # perf lists, per address, the containing function and then the inlined frames
    # from the innermost out: move the containing function after them.
    ordered, i = [], 0
    while i < len(frames):
        ip = frames[i].split()[0]
        group = [f for f in frames[i:] if f.split()[0] == ip]
        ordered += [f for f in group if "(inlined)" in f] + [f for f in group if "(inlined)" not in f]
        i += len(group)
    cat = next((c for c in map(category, ordered) if c), OTHER)
    counts[cat] += 1
total = sum(counts.values())
print("| part | samples | share |\n|---|---:|---:|")
for _, name in RULES + [(None, OTHER)]:
    print(f"| {name} | {counts[name]} | {100 * counts[name] / total:.1f}% |")
print(f"| total | {total} | |")
PY
  python3 - "$out/stats.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
ms, cy, clock = s["times_ms"], s["times_cycles"], s["cycle_clock"]
print(f"\n| phase | ms | cycles ({clock['source']}, {clock['ticks_per_second'] / 1e9:.3f} GHz) |\n|---|---:|---:|")
for k in ("parse", "build", "trace", "total"):
    print(f"| {k} | {ms[k]:.1f} | {cy[k]} |")
PY
done
rm -r "$out"
