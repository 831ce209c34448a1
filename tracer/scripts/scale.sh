#!/usr/bin/env bash
# Build and scale: every scene of ../shared/scenes/spd-large next to its classic-size
# counterpart. Prints one Markdown table with, per scene: primitives, the geometry build
# of `tracer bench` (conversion + BVH, median wall ms), the BVH's share of it in wall and
# CPU ms and the SAH cost (the bvh_build example), binary and wide nodes, bytes per
# primitive, peak memory of a 512x512 render (/usr/bin/time -v, maximum resident set),
# eye and shadow ray throughput (Mrays per wall second, per CPU second in parentheses),
# the frame time (wall and CPU ms), and for the large scenes the ratio of their eye and
# shadow throughput (per CPU second) to the small counterpart's.
# Usage: tracer/scripts/scale.sh [RUNS] [THREADS]   (defaults 3 and all cores)
# TRACER=BIN BVH_BUILD=BIN measure other builds of the two programs (e.g. an older
# commit's) instead of building the current tree.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
runs=${1:-3}
threads=${2:-$(nproc)}
cd "$root"
if [[ -z ${TRACER:-} || -z ${BVH_BUILD:-} ]]; then
  cargo build --profile perf -q -p tracer-cli --bin tracer --example bvh_build
fi
T=${TRACER:-$root/target/perf/tracer}
B=${BVH_BUILD:-$root/target/perf/examples/bvh_build}
S=$root/../shared/scenes/spd
L=$root/../shared/scenes/spd-large
small=(balls-s4 tetra-s6 mount-s6 teapot-s12)
large=(balls-s5 balls-s6 tetra-s8 mount-s8 teapot-s40)
files=()
for s in "${small[@]}"; do files+=("$S/$s.nff"); done
for s in "${large[@]}"; do files+=("$L/$s.nff.gz"); done
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$T" bench "${files[@]}" --runs "$runs" --threads "$threads" >"$out/bench.md"
"$B" --runs "$runs" --threads "$threads" "${files[@]}" >"$out/build.md"
for f in "${files[@]}"; do
  n=$(basename "$f"); n=${n%%.*}
  /usr/bin/time -v "$T" render "$f" -o "$out/img.png" --width 512 --height 512 \
    --threads "$threads" 2>&1 >/dev/null | awk -v n="$n" '/Maximum resident/{print n, $6}'
done >"$out/peak.txt"
python3 - "$out" <<'EOF'
import sys
d = sys.argv[1]
def rows(path):
    out = {}
    for line in open(path):
        c = [x.strip() for x in line.strip().strip('|').split('|')]
        # The first table of a file (`tracer bench` prints a packet table after it).
        if len(c) > 3 and c[0] != 'scene' and not c[0].startswith('---') and c[0] not in out:
            out[c[0]] = c
    return out
bench, build = rows(f'{d}/bench.md'), rows(f'{d}/build.md')
peak = dict(l.split() for l in open(f'{d}/peak.txt'))
pair = {'balls-s5': 'balls-s4', 'balls-s6': 'balls-s4', 'tetra-s8': 'tetra-s6',
        'mount-s8': 'mount-s6', 'teapot-s40': 'teapot-s12'}
cpu = lambda s: float(s.split('(')[1].rstrip(')'))
print('| scene | prims | build ms | BVH ms | BVH CPU ms | SAH cost | nodes | wide nodes '
      '| B/prim | peak MB | eye Mrays/s | shadow Mrays/s | frame ms | frame CPU ms '
      '| eye / small | shadow / small |')
print('|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|')
for name in ['balls-s4', 'balls-s5', 'balls-s6', 'tetra-s6', 'tetra-s8', 'mount-s6',
             'mount-s8', 'teapot-s12', 'teapot-s40']:
    b, g = bench[name], build[name]
    ratio = ['-', '-']
    if name in pair:
        s = bench[pair[name]]
        ratio = [f'{cpu(b[i]) / cpu(s[i]):.2f}' for i in (5, 6)]
    mb = int(peak[name]) / 1024
    print(f'| {name} | {b[1]} | {b[2]} | {g[4]} | {g[5]} | {g[10]} | {b[3]} | {g[7]} '
          f'| {b[4]} | {mb:.0f} | {b[5]} | {b[6]} | {b[8]} | {b[9]} | {ratio[0]} | {ratio[1]} |')
EOF
