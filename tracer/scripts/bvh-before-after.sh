#!/usr/bin/env bash
# Before/after geometry build time of two `bvh_build` binaries (tracer/examples/
# bvh_build.rs) on one scene, all cores, interleaved: each round runs the old and the new
# binary back to back, once with `--runs 5` (the median of five builds in one process:
# warm, the allocator reusing freed memory) and once with `--runs 1` (the first build
# of a process, on fresh memory, as `tracer render` builds). Prints the medians over the
# rounds of the build (conversion, BVH, reordering) and of its BVH part in wall and
# process CPU ms, and their ratios old / new.
# Usage: tracer/scripts/bvh-before-after.sh OLD_BIN NEW_BIN SCENE [ROUNDS]
#   e.g. git worktree add /tmp/old COMMIT && cargo build --profile perf -p tracer
#   --example bvh_build --manifest-path /tmp/old/Cargo.toml &&
#   tracer/scripts/bvh-before-after.sh /tmp/old/target/perf/examples/bvh_build
#   target/perf/examples/bvh_build ../shared/scenes/spd-large/balls-s6.nff.gz 5
set -euo pipefail
old=$1 new=$2 scene=$3 rounds=${4:-5}
d=$(mktemp -d)
trap 'rm -rf "$d"' EXIT
for r in $(seq 1 "$rounds"); do
  for runs in 5 1; do
    for side in old new; do
      bin=$old
      [ "$side" = new ] && bin=$new
      # The table row: | scene | prims | build ms | without BVH ms | BVH ms | BVH CPU ms | ...
      "$bin" --runs "$runs" "$scene" | grep -v -e '^| scene' -e '^|---' >> "$d/$side-$runs"
    done
  done
done
python3 - "$d" <<'PY'
import statistics, sys
d = sys.argv[1]
def cols(side, runs):
    rows = [l.split("|") for l in open(f"{d}/{side}-{runs}")]
    return [[float(r[i]) for r in rows] for i in (3, 5, 6)]
print("| builds | measure | before ms | after ms | before / after |\n|---|---|---:|---:|---:|")
for runs, what in ((5, "median of five in one process"), (1, "first of a process")):
    o, n = cols("old", runs), cols("new", runs)
    for k, name in enumerate(("build", "BVH", "BVH CPU")):
        a, b = statistics.median(o[k]), statistics.median(n[k])
        print(f"| {what} | {name} | {a:.1f} | {b:.1f} | {a / b:.2f} |")
PY
