#!/usr/bin/env bash
# Renders the seven classic SPD scenes in SPD mode (--spd: 513x513 corner rays averaged
# into 512x512 pixels, depth 5, no adaptive cutoff) and prints the rays by kind as a
# Markdown table. Usage: tracer/scripts/spd-counts.sh [SCENE_DIR] [OUT_DIR]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
scenes=${1:-$root/../shared/scenes/spd}
out=${2:-$(mktemp -d)}
mkdir -p "$out"
cargo build --profile perf -q -p tracer-cli --manifest-path "$root/Cargo.toml"
bin=${CARGO_TARGET_DIR:-$root/target}/perf/tracer
printf '| scene | eye | reflection | refraction | shadow | total | trace ms |\n|---|---:|---:|---:|---:|---:|---:|\n'
for s in balls-s4 gears-s4 mount-s6 rings-s7 teapot-s12 tetra-s6 tree-s11; do
  "$bin" render "$scenes/$s.nff" -o "$out/$s.png" --spd --stats "$out/$s.json" 2>/dev/null
  python3 - "$out/$s.json" "$s" <<'PY'
import json, sys
d = json.load(open(sys.argv[1])); r = d["rays"]
tot = r["eye"] + r["reflection"] + r["refraction"] + r["shadow"]
print(f'| {sys.argv[2]} | {r["eye"]:,} | {r["reflection"]:,} | {r["refraction"]:,} | {r["shadow"]:,} | {tot:,} | {d["times_ms"]["trace"]:.0f} |')
PY
done
