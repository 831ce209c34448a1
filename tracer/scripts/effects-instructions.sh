#!/usr/bin/env bash
# Instructions executed by the f32 renderers (callgrind, collecting only inside
# `render_f32`, so parsing and the BVH build are left out), general (`--effects all`)
# against specialised (`--effects auto`), one thread, default settings. Deterministic,
# unlike times on a shared machine. Prints a Markdown table.
# Usage: tracer/scripts/effects-instructions.sh [SCENE_DIR] SCENE...   (names without .nff)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
scenes=$root/../shared/scenes/spd
if [ -d "${1:-}" ]; then scenes=$1; shift; fi
cargo build --profile perf -q -p tracer-cli --manifest-path "$root/Cargo.toml"
bin=${CARGO_TARGET_DIR:-$root/target}/perf/tracer
out=$(mktemp -d)
ir() { # SCENE MODE
  valgrind --tool=callgrind --callgrind-out-file="$out/cg.out" --toggle-collect='*render_f32*' \
    "$bin" render "$scenes/$1.nff" -o "$out/img.png" --threads 1 --effects "$2" 2>&1 |
    sed -n 's/.*Collected : \([0-9]*\).*/\1/p'
}
printf '| scene | general instructions | specialised instructions | ratio |\n|---|---:|---:|---:|\n'
for s in "$@"; do
  g=$(ir "$s" all)
  a=$(ir "$s" auto)
  python3 -c "import sys; g,a=int(sys.argv[2]),int(sys.argv[3]); print(f'| {sys.argv[1]} | {g:,} | {a:,} | {g/a:.2f} |')" "$s" "$g" "$a"
done
rm -r "$out"
