#!/usr/bin/env python3
"""Fixed and per-node cost of a ray kernel, from a callgrind profile by instruction.

Counts, in a callgrind output written with `--dump-instr=yes`, the instructions whose
execution count is exactly N (the rays or packets of the run): those run once per ray,
whatever the tree. Prints the kernel's instructions per ray, those run once per ray, and
the source lines that hold most of the latter (from `objdump -l` of BINARY).

Usage: tracer/scripts/once-per-ray.py CALLGRIND_OUT BINARY N [LINES]
  e.g. valgrind --tool=callgrind --dump-instr=yes --callgrind-out-file=cg.out \\
         --toggle-collect='*closest_best_avx2*' target/perf/examples/packet_walk \\
         --only single --size 256x256 --runs 1 --threads 1 ../shared/scenes/spd/teapot-s12.nff
       tracer/scripts/once-per-ray.py cg.out target/perf/examples/packet_walk 65536
"""
import collections
import re
import subprocess
import sys


def counts(path):
    """Execution count per instruction address (calls' inclusive costs left out)."""
    out = collections.Counter()
    addr, skip = 0, False
    pos = re.compile(r"^(0x[0-9a-f]+|[+-]\d+|\*)\s+(?:[+-]?\d+|\*)\s+(\d+)")
    for line in open(path):
        if line.startswith("calls="):
            skip = True  # the next position line is the call's inclusive cost
            continue
        m = pos.match(line)
        if not m:
            continue
        a = m.group(1)
        if a.startswith("0x"):
            addr = int(a, 16)
        elif a[0] in "+-":
            addr += int(a)
        if skip:
            skip = False
            continue
        out[addr] += int(m.group(2))
    return out


def main():
    path, binary, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
    top = int(sys.argv[4]) if len(sys.argv) > 4 else 15
    cnt = counts(path)
    if not cnt:
        sys.exit(f"{path}: no instruction counts (was it written with --dump-instr=yes?)")
    lo, hi = min(cnt), max(cnt) + 16
    dis = subprocess.run(
        ["objdump", "-d", "-l", "--no-show-raw-insn", binary,
         f"--start-address={lo:#x}", f"--stop-address={hi:#x}"],
        capture_output=True, text=True, check=True).stdout
    src, by_line = "?", collections.Counter()
    for line in dis.splitlines():
        m = re.match(r"\s+([0-9a-f]+):", line)
        if m:
            if cnt.get(int(m.group(1), 16)) == n:
                by_line[src] += 1
        elif line.startswith("/"):
            src = line.rsplit("/", 1)[-1]
    total = sum(cnt.values()) / n
    once = sum(c for c in cnt.values() if c == n) / n
    print(f"instructions per ray: {total:.1f}; run exactly once per ray: {once:.1f}")
    for s, c in by_line.most_common(top):
        print(f"{c:6d}  {s}")


if __name__ == "__main__":
    main()
