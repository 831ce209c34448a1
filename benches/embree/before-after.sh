#!/usr/bin/env bash
# Tracer / Embree throughput ratios of two builds of the Embree bench, run alternately
# round by round on the same scenes (each run already interleaves Embree and the
# tracer), so machine load hits both builds alike. Prints, per scene, thread count and
# ray kind, the median over the rounds of the tracer / Embree ratio per wall second and,
# in parentheses, per CPU second, before and after; then the geometric means per kind
# and thread count. Embree keeps its built-in spheres here (--no-user-spheres).
# Usage: benches/embree/before-after.sh OLD_BENCH NEW_BENCH [ROUNDS] [SCENE.nff...]
#   Build a bench binary with `cargo bench -p benches --features embree --bench embree
#   --no-run` (it prints the executable's path) and copy it away before building the
#   other commit.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
old=$1 new=$2 rounds=${3:-3}
shift $(($# < 3 ? $# : 3))
scenes=("$@")
if [ ${#scenes[@]} -eq 0 ]; then
  spd=$root/../shared/scenes/spd
  scenes=("$spd"/gears-s4.nff "$spd"/mount-s6.nff "$spd"/teapot-s12.nff "$spd"/tetra-s6.nff)
fi
out=$(mktemp)
for r in $(seq 1 "$rounds"); do
  for b in old new; do
    bin=$old
    [ $b = new ] && bin=$new
    echo "== $b" >>"$out"
    # Builds that know --no-user-spheres list it in their usage; older ones measure
    # the built-in spheres only anyway.
    only_builtin=()
    case $("$bin" 2>&1 || true) in *--no-user-spheres*) only_builtin=(--no-user-spheres) ;; esac
    "$bin" --runs 5 --threads 1,2 --sizes 512x512 "${only_builtin[@]}" "${scenes[@]}" 2>/dev/null |
      grep '^| [^ ]* | [0-9]*x[0-9]* |' >>"$out"
  done
done
python3 - "$out" <<'PY'
import collections, math, re, statistics, sys
d = collections.defaultdict(list)
b = None
for l in open(sys.argv[1]):
    if l.startswith("=="):
        b = l.split()[1]
        continue
    c = [x.strip() for x in l.split("|")]
    m = re.match(r"([\d.]+) \(([\d.]+)\)", c[8])
    d[(c[1], c[3], c[5].split()[0], b)].append((float(m.group(1)), float(m.group(2))))
print("| scene | threads | kind | before: tracer / Embree | after: tracer / Embree |")
print("|---|---:|---|---:|---:|")
gm = collections.defaultdict(list)
for k in sorted({k[:3] for k in d}):
    row = []
    for b in ("old", "new"):
        v = d[k + (b,)]
        w, c = statistics.median(x[0] for x in v), statistics.median(x[1] for x in v)
        gm[(k[2], k[1], b)].append((w, c))
        row.append(f"{w:.2f} ({c:.2f})")
    print(f"| {k[0]} | {k[1]} | {k[2]} | {row[0]} | {row[1]} |")
print("\n| kind | threads | before: geometric mean | after: geometric mean |")
print("|---|---:|---:|---:|")
for kind, t in sorted({k[:2] for k in gm}):
    cells = []
    for b in ("old", "new"):
        v = gm[(kind, t, b)]
        g = [math.exp(sum(math.log(x[i]) for x in v) / len(v)) for i in (0, 1)]
        cells.append(f"{g[0]:.2f} ({g[1]:.2f})")
    print(f"| {kind} | {t} | {cells[0]} | {cells[1]} |")
PY
rm -f "$out"
