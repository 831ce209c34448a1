#!/usr/bin/env bash
# Load imbalance of a tile split in instructions, which unlike times do not depend on the
# machine's load: every tile of an N-tile split of SCENE, with the cost-balanced split of
# `tracer render --tile I/N` and with bands of equal height (`--pixel-bounds`), run under
# valgrind's callgrind with collection on only inside `tracer::render::render_f32`
# (the trace; parsing, the build and the split's probe are left out). Prints max / mean of
# the tiles' instructions for both splits and checks that each split's tiles add up to
# the one-process render's instructions within 1 %. JOBS (default 2) callgrind runs at a time.
# Usage: tracer/scripts/slurm/scaling-instructions.sh SCENE_FILE [N] [WxH]
#   (defaults N=16 and 512x512; TRACER=BIN, default target/perf/tracer)
set -euo pipefail
root=$(cd "$(dirname "$0")/../../.." && pwd)
scene=$1 n=${2:-16} size=${3:-512x512}
w=${size%x*} h=${size#*x}
T=${TRACER:-$root/target/perf/tracer}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
jobs=("full --width $w --height $h")
for ((i = 0; i < n; i++)); do
  jobs+=("cost-$i --width $w --height $h --tile $i/$n")
  jobs+=("equal-$i --width $w --height $h --pixel-bounds 0,$w,$((i * h / n)),$(((i + 1) * h / n))")
done
run() {
  local name=$1
  shift
  valgrind --tool=callgrind --callgrind-out-file=/dev/null \
    --toggle-collect='tracer::render::render_f32' \
    "$T" render "$scene" --threads 1 -o "$out/$name.exr" "$@" 2>&1 >/dev/null |
    awk -v n="$name" '/Collected/{print n, $4}'
}
export -f run
export T scene out
printf '%s\n' "${jobs[@]}" | xargs -P "${JOBS:-2}" -I{} bash -c 'run {}' >"$out/ir.txt"
python3 - "$out/ir.txt" "$(basename "$scene")" "$n" "$size" <<'EOF'
import sys
ir = {}
for line in open(sys.argv[1]):
    name, v = line.split()
    ir[name] = int(v)
full = ir.pop("full")
assert full > 0, "nothing collected: is render_f32 inlined?"
print(f"| scene | size | N | split | max Ir | mean Ir | max / mean | sum / full |")
print("|---|---|---:|---|---:|---:|---:|---:|")
for split in ("cost", "equal"):
    v = [x for k, x in ir.items() if k.startswith(split + "-")]
    mean = sum(v) / len(v)
    s = sum(v) / full
    assert abs(s - 1) < 0.01, f"{split}: tiles add up to {s:.4f} of the full render"
    print(f"| {sys.argv[2]} | {sys.argv[4]} | {sys.argv[3]} | {split} | {max(v):,} | {mean:,.0f} | {max(v) / mean:.3f} | {s:.4f} |")
EOF
