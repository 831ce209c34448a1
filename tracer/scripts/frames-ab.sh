#!/usr/bin/env bash
# Frame time of two tracer binaries on the seven classic SPD scenes (512x512, depth 5,
# packets auto), interleaved: each round runs `tracer bench` with the old and then the
# new binary. Prints per-scene medians over rounds of the median frame wall ms and frame
# CPU ms (all threads), the ratios old / new, and the eye-packet throughput of both.
# Usage: tracer/scripts/frames-ab.sh OLD_BIN NEW_BIN [ROUNDS] [RUNS] [THREADS]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
old=$1 new=$2 rounds=${3:-3} runs=${4:-3} threads=${5:-$(nproc)}
S=$root/../shared/scenes/spd
scenes=("$S"/{balls-s4,gears-s4,mount-s6,rings-s7,teapot-s12,tetra-s6,tree-s11}.nff)
d=$(mktemp -d)
for r in $(seq 1 "$rounds"); do
  "$old" bench "${scenes[@]}" --runs "$runs" --threads "$threads" > "$d/old-$r.md"
  "$new" bench "${scenes[@]}" --runs "$runs" --threads "$threads" > "$d/new-$r.md"
done
python3 - "$d" "$rounds" <<'PY'
import math, re, statistics, sys
d, R = sys.argv[1], int(sys.argv[2])
def rows(path):
    main, pkt = {}, {}
    for line in open(path):
        c = [x.strip() for x in line.strip().strip("|").split("|")]
        if len(c) == 13 and re.match(r"^[0-9]", c[1]):
            main[c[0]] = (float(c[8]), float(c[9]))          # frame ms, frame CPU ms
        elif len(c) == 6 and re.match(r"^[0-9]", c[2]):
            pkt[c[0]] = float(re.findall(r"\(([0-9.]+)\)", c[3])[0])  # packet Mrays/CPU s
    return main, pkt
o = [rows(f"{d}/old-{r}.md") for r in range(1, R + 1)]
n = [rows(f"{d}/new-{r}.md") for r in range(1, R + 1)]
med = statistics.median
print("| scene | frame ms before | frame ms after | before / after | frame CPU ms before | frame CPU ms after | before / after (CPU) | eye packets Mrays/CPU s before | after |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
gw, gc = [], []
for s in o[0][0]:
    ow = [x[0][s][0] for x in o]; nw = [x[0][s][0] for x in n]
    oc = [x[0][s][1] for x in o]; nc = [x[0][s][1] for x in n]
    rw = med(a / b for a, b in zip(ow, nw)); rc = med(a / b for a, b in zip(oc, nc))
    gw.append(rw); gc.append(rc)
    op = med(x[1].get(s, 0.0) for x in o); np_ = med(x[1].get(s, 0.0) for x in n)
    print(f"| {s} | {med(ow):.1f} | {med(nw):.1f} | {rw:.2f} | {med(oc):.1f} | {med(nc):.1f} | {rc:.2f} | {op:.2f} | {np_:.2f} |")
g = lambda v: math.exp(sum(map(math.log, v)) / len(v))
print(f"| geometric mean | | | {g(gw):.2f} | | | {g(gc):.2f} | | |")
PY
