#!/usr/bin/env bash
# Instructions per eye ray (valgrind callgrind, one thread) of two builds of
# `tracer/examples/packet_walk`, on the seven classic SPD scenes at 256x256 (65,536 eye
# rays): single rays (the instructions of `cast_single`, per ray) and AVX2 packets of
# eight (the inclusive instructions of the packet kernel `entry_avx2`, per ray; callgrind
# reports no AVX-512 to the program, so packets are AVX2 under it). Instruction counts
# do not depend on the machine's load, unlike times.
# Usage: tracer/scripts/eye-instructions.sh OLD_PACKET_WALK NEW_PACKET_WALK
#   build each with: cargo build --profile perf -p tracer --example packet_walk
#   (target/perf/examples/packet_walk; copy the old one aside before rebuilding)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
S=$root/../shared/scenes/spd
ir() { # COLLECT BIN ARGS...
  valgrind --tool=callgrind --callgrind-out-file=/dev/null --toggle-collect="$1" "${@:2}" 2>&1 |
    awk '/Collected/{print $4}'
}
echo "| scene | single A | single B | B / A | packets A | packets B | B / A |"
echo "|---|---:|---:|---:|---:|---:|---:|"
for s in balls-s4 gears-s4 mount-s6 rings-s7 teapot-s12 tetra-s6 tree-s11; do
  row=()
  for mode in single wide; do
    collect='*cast_single*'
    [[ $mode == wide ]] && collect='*entry_avx2*'
    for b in "$1" "$2"; do
      row+=("$(ir "$collect" "$b" --only "$mode" --size 256x256 --runs 1 --threads 1 "$S/$s.nff")")
    done
  done
  python3 -c "
import sys
a, b, c, d = (int(x) / 65536 for x in sys.argv[2:])
print(f'| {sys.argv[1]} | {a:.1f} | {b:.1f} | {b / a:.3f} | {c:.1f} | {d:.1f} | {d / c:.3f} |')" "$s" "${row[@]}"
done
