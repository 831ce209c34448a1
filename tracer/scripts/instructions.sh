#!/usr/bin/env bash
# Instructions executed per frame (valgrind callgrind, single thread) of two tracer
# configurations on the seven classic SPD scenes: Ir of a 128x128 render minus Ir of a
# 1x1 render of the same scene, so parsing and the BVH build cancel out. Instruction
# counts do not depend on the machine's load, unlike times.
# Usage: tracer/scripts/instructions.sh "OLD_BIN [ARGS]" "NEW_BIN [ARGS]"
#   e.g. tracer/scripts/instructions.sh "target/perf/tracer --binary-bvh" target/perf/tracer
# SCENES="gears-s4 tetra-s6" limits the run to those scenes.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
S=$root/../shared/scenes/spd
out=$(mktemp -d)
ir() { valgrind --tool=callgrind --callgrind-out-file=/dev/null "$@" 2>&1 | awk '/Collected/{print $4}'; }
echo "| scene | A Ir | B Ir | B / A |"
echo "|---|---:|---:|---:|"
for s in ${SCENES:-balls-s4 gears-s4 mount-s6 rings-s7 teapot-s12 tetra-s6 tree-s11}; do
  row=()
  for v in "$1" "$2"; do
    read -r -a cmd <<<"$v"
    b=${cmd[0]}
    a=$(ir "$b" render "$S/$s.nff" -o "$out/i.png" --width 128 --height 128 --threads 1 "${cmd[@]:1}")
    z=$(ir "$b" render "$S/$s.nff" -o "$out/i.png" --width 1 --height 1 --threads 1 "${cmd[@]:1}")
    row+=($((a - z)))
  done
  python3 -c "import sys; a,b=map(int,sys.argv[2:]); print(f'| {sys.argv[1]} | {a:,} | {b:,} | {b/a:.3f} |')" "$s" "${row[@]}"
done
