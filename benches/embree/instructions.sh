#!/usr/bin/env bash
# Instructions per ray (valgrind callgrind, one thread, 256x256) of Embree's single-ray
# queries next to the tracer's, on the same eye and shadow rays:
# - Embree: rtcIntersect1 and rtcOccluded1, inclusive, in the Embree bench
#   (benches/embree/main.rs) run once with --runs 1, which calls each twice per ray (an
#   untimed round, then the timed one). Under valgrind Embree sees no AVX-512 and picks
#   its AVX2 kernels.
# - tracer: the closest hit with its hit record (`cast_single` of
#   tracer/examples/packet_walk.rs) and the any hit of the shadow rays (`cast_shadow` of
#   tracer/examples/shadow_walk.rs, the bench's shadow rays).
# Usage: benches/embree/instructions.sh SCENE.nff...
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
cargo build -q --profile perf -p tracer --example packet_walk --example shadow_walk
bench=$(cargo bench -q -p benches --features embree --bench embree --no-run \
  --message-format=json | python3 -c '
import json, sys
for line in sys.stdin:
    m = json.loads(line)
    if m.get("executable") and m.get("target", {}).get("name") == "embree":
        print(m["executable"])')
ir() { valgrind --tool=callgrind --callgrind-out-file="$1" "${@:2}" 2>/dev/null; }
incl() { callgrind_annotate --inclusive=yes "$1" 2>/dev/null | awk -v f="$2" '$0 ~ f && !done {gsub(",", "", $1); print $1; done = 1}'; }
tmp=$(mktemp -d)
echo "| scene | Embree eye | tracer eye | tracer / Embree | Embree shadow | tracer shadow | tracer / Embree |"
echo "|---|---:|---:|---:|---:|---:|---:|"
for s in "$@"; do
  out=$(ir "$tmp/e" --toggle-collect=rtcIntersect1 --toggle-collect=rtcOccluded1 "$bench" \
    --runs 1 --threads 1 --sizes 256x256 --no-user-spheres "$s")
  eye=65536
  shadow=$(awk -F'|' '/shadow \(rtcOccluded1\)/ && !done {gsub(/ /, "", $5); print $5; done = 1}' <<<"$out")
  e1=$(incl "$tmp/e" 'rtcIntersect1')
  e2=$(incl "$tmp/e" 'rtcOccluded1')
  t1=$(valgrind --tool=callgrind --callgrind-out-file=/dev/null --toggle-collect='*cast_single*' \
    target/perf/examples/packet_walk --only single --runs 1 --threads 1 --size 256x256 "$s" 2>&1 |
    awk '/Collected/ {print $4}')
  t2=$(valgrind --tool=callgrind --callgrind-out-file=/dev/null --toggle-collect='*cast_shadow*' \
    target/perf/examples/shadow_walk --runs 1 --size 256x256 "$s" 2>&1 | awk '/Collected/ {print $4}')
  python3 -c "
import sys
n, e1, e2, t1, t2, eye, sh = sys.argv[1], *map(int, sys.argv[2:])
a, b = e1 / (2 * eye), t1 / eye
c, d = e2 / (2 * sh), t2 / sh
print(f'| {n} | {a:.0f} | {b:.0f} | {b / a:.2f} | {c:.0f} | {d:.0f} | {d / c:.2f} |')" \
    "$(basename "$s" .nff)" "$e1" "$e2" "$t1" "$t2" "$eye" "$shadow"
done
rm -rf "$tmp"
