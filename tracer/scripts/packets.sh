#!/usr/bin/env bash
# Packets and instruction sets: eye-ray throughput with single rays and with packets of
# every instruction set the CPU has (sse2, avx2, avx512, all in one binary), and the frame
# time with packets off and on, on the seven classic SPD scenes at 512x512, depth 5.
# Each round runs `tracer bench` once per configuration (packets off, then each ISA);
# within one bench, single-ray and packet eye casts alternate run by run. Prints medians
# over rounds and runs: Mrays/s per wall-clock second and, in parentheses, per CPU second
# of all threads.
# Usage: tracer/scripts/packets.sh [ROUNDS] [RUNS] [THREADS] [SCENE...]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
rounds=${1:-2}
runs=${2:-3}
threads=${3:-$(nproc)}
shift $(( $# < 3 ? $# : 3 ))
scenes=("$@")
spd="$root/../shared/scenes/spd"
[[ ${#scenes[@]} -eq 0 ]] && scenes=("$spd"/{balls-s4,gears-s4,mount-s6,rings-s7,teapot-s12,tetra-s6,tree-s11}.nff)
out=$(mktemp -d)
cargo build --profile perf -q -p tracer-cli --manifest-path "$root/Cargo.toml"
bin=${TRACER_BIN:-${CARGO_TARGET_DIR:-$root/target}/perf/tracer}
isas=()
for isa in sse2 avx2 avx512; do
  if "$bin" bench "${scenes[0]}" --width 8 --height 8 --runs 1 --isa "$isa" >/dev/null 2>&1; then
    isas+=("$isa")
  fi
done
for r in $(seq 1 "$rounds"); do
  "$bin" bench "${scenes[@]}" --runs "$runs" --threads "$threads" --packets off > "$out/off-$r.md"
  for isa in "${isas[@]}"; do
    "$bin" bench "${scenes[@]}" --runs "$runs" --threads "$threads" --isa "$isa" > "$out/$isa-$r.md"
  done
done
python3 - "$out" "$rounds" "$threads" "${isas[@]}" <<'PY'
import re, statistics, sys
out, rounds, threads, isas = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4:]
num = lambda s: [float(x) for x in re.findall(r"[0-9.]+", s)]
main, pkt = {}, {}   # (config, scene) -> list of rows
for cfg in ["off"] + isas:
    for r in range(1, rounds + 1):
        for line in open(f"{out}/{cfg}-{r}.md"):
            c = [x.strip() for x in line.strip().strip("|").split("|")]
            if len(c) == 13 and c[0] not in ("scene",) and not c[0].startswith("-"):
                main.setdefault((cfg, c[0]), []).append(c)
            elif len(c) == 6 and c[1] in isas:
                pkt.setdefault((cfg, c[0]), []).append(c)
scenes = [s for (cfg, s) in main if cfg == "off"]
med = lambda xs: statistics.median(xs)
def rate(rows, col):
    w = med([num(x[col])[0] for x in rows]); c = med([num(x[col])[1] for x in rows])
    return w, c
print(f"{threads} threads, 512x512, {rounds} rounds; medians; Mrays/s wall (per CPU second)\n")
print("| scene | eye single | " + " | ".join(f"eye {i} packets" for i in isas) + " | " + " | ".join(f"{i} / single" for i in isas) + " |")
print("|---|---:|" + "---:|" * (2 * len(isas)))
for s in scenes:
    single = [x for cfg in ["off"] + isas for x in main.get((cfg, s), [])]
    sw, sc = rate(single, 5)
    cells, ratios = [], []
    for i in isas:
        pw, pc = rate(pkt[(i, s)], 3)
        cells.append(f"{pw:.2f} ({pc:.2f})")
        ratios.append(f"{pc / sc:.2f}")
    print(f"| {s} | {sw:.2f} ({sc:.2f}) | " + " | ".join(cells) + " | " + " | ".join(ratios) + " |")
print("\n(ratios: packet / single eye-ray throughput per CPU second)\n")
print("| scene | frame ms, packets off | " + " | ".join(f"frame ms, {i}" for i in isas) + " | frame CPU ms off | " + " | ".join(f"frame CPU ms {i}" for i in isas) + " |")
print("|---|---:|" + "---:|" * len(isas) + "---:|" + "---:|" * len(isas))
for s in scenes:
    fw = [med([float(x[8]) for x in main[(cfg, s)]]) for cfg in ["off"] + isas]
    fc = [med([float(x[9]) for x in main[(cfg, s)]]) for cfg in ["off"] + isas]
    print(f"| {s} | " + " | ".join(f"{v:.1f}" for v in fw) + " | " + " | ".join(f"{v:.1f}" for v in fc) + " |")
PY
rm -rf "$out"
