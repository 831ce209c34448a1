#!/usr/bin/env bash
# The scaling study of tiled renders: what one task of an array job spends on reading the
# scene and building its tree against tracing its tile, how evenly the split shares the
# work, and the speed-up that implies for 1 to 64 nodes.
#
# For each scene and image size it renders the full image once in one process, then every
# tile of N = 2, 4, ..., 64 with the cost-balanced split of `tracer render --tile I/N`
# and, for the sizes in EQUAL_SIZES, with bands of equal height (`--pixel-bounds`, rows
# floor(I H/N) to floor((I+1) H/N)). Every task is a process of its own with one thread
# (one node's core); JOBS of them run at a time. Each writes `--stats` JSON: wall ms of
# parse, build, split and trace, CPU ms of the process before the trace (`setup_cpu`) and
# of the trace, rays. The tables use CPU times, which a loaded machine disturbs less than
# wall times. Each split's tiles are merged and the merged image compared with the full
# render byte for byte (the script stops if they differ). Then it prints the tables of
# tracer/RESULTS.md ("Rendering on a cluster: scaling") from the JSON files.
#
# Usage: tracer/scripts/slurm/scaling.sh [SCENE_DIR] [OUT_DIR]
#   SCENE_DIR  holds balls-s6, teapot-s40 and mount-s8 .nff.gz (default ../shared/scenes/spd-large)
#   OUT_DIR    keeps the JSON files (default target/scaling); REPORT_ONLY=1 prints the
#              tables again from it without rendering.
# Environment: TRACER=BIN (default: build and use target/perf/tracer), JOBS=2,
#   SCENES="balls-s6 teapot-s40 mount-s8", SIZES="512x512 3840x2160",
#   EQUAL_SIZES="512x512", COUNTS="2 4 8 16 32 64".
set -euo pipefail
root=$(cd "$(dirname "$0")/../../.." && pwd)
scenes_dir=$(cd "${1:-$root/../shared/scenes/spd-large}" && pwd)
out=${2:-$root/target/scaling}
scenes=${SCENES:-balls-s6 teapot-s40 mount-s8}
sizes=${SIZES:-512x512 3840x2160}
counts=${COUNTS:-2 4 8 16 32 64}
equal_sizes=${EQUAL_SIZES:-512x512}
jobs=${JOBS:-2}
if [[ -z ${TRACER:-} && -z ${REPORT_ONLY:-} ]]; then
  (cd "$root" && cargo build --profile perf -q -p tracer-cli --bin tracer)
fi
T=${TRACER:-$root/target/perf/tracer}

# One line per task: NAME ARGS..., run by xargs, JOBS at a time.
tasks() {
  local scene=$1 size=$2 w=${2%x*} h=${2#*x} split n i
  local file=$scenes_dir/$scene.nff.gz dir=$out/$scene-$size
  local common="$file --width $w --height $h --threads 1"
  echo "$common -o $dir/full.pfm --stats $dir/full.json"
  for n in $counts; do
    for ((i = 0; i < n; i++)); do
      echo "$common --tile $i/$n -o $dir/cost-$n/tile-%d.exr --stats $dir/cost-$n/tile-%d.json"
      if [[ " $equal_sizes " == *" $size "* ]]; then
        echo "$common --pixel-bounds 0,$w,$((i * h / n)),$(((i + 1) * h / n))" \
          "-o $dir/equal-$n/tile-$i.exr --stats $dir/equal-$n/tile-$i.json"
      fi
    done
  done
}

# Merges each split's tiles, times the merge and compares with the full render.
check() {
  local scene=$1 size=$2 dir=$out/$1-$2 n split start end
  for n in $counts; do
    for split in cost equal; do
      [[ -d $dir/$split-$n ]] || continue
      start=$(date +%s%N)
      "$T" merge "$dir/$split-$n"/tile-*.exr -o "$dir/$split-$n/merged.pfm"
      end=$(date +%s%N)
      echo $(((end - start) / 1000000)) >"$dir/$split-$n/merge_ms"
      cmp "$dir/full.pfm" "$dir/$split-$n/merged.pfm" ||
        { echo "$scene $size $split N=$n: merged image differs from the full render" >&2; exit 1; }
      rm "$dir/$split-$n/merged.pfm" "$dir/$split-$n"/tile-*.exr
    done
  done
  echo "$scene $size: every split merged equal to the full render" >&2
}

if [[ -z ${REPORT_ONLY:-} ]]; then
  echo "started $(date -u +%H:%M:%S) UTC on $(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg)" >&2
  for size in $sizes; do
    for scene in $scenes; do
      rm -rf "${out:?}/$scene-$size"
      for n in $counts; do
        mkdir -p "$out/$scene-$size/cost-$n"
        [[ " $equal_sizes " == *" $size "* ]] && mkdir -p "$out/$scene-$size/equal-$n"
      done
      # shellcheck disable=SC2016 # $0 and $@ belong to the inner shell
      tasks "$scene" "$size" | xargs -P "$jobs" -L 1 sh -c '"$0" render "$@" 2>/dev/null' "$T"
      check "$scene" "$size"
    done
  done
  echo "finished $(date -u +%H:%M:%S) UTC, load $(cut -d' ' -f1 /proc/loadavg)" >&2
fi

python3 - "$out" "$counts" "$scenes" "$sizes" <<'EOF'
import json, statistics, sys
from pathlib import Path
out, counts = Path(sys.argv[1]), [int(n) for n in sys.argv[2].split()]
scenes, sizes = sys.argv[3].split(), sys.argv[4].split()
med = statistics.median

def task(j):
    t, r = j["times_ms"], j["rays"]
    return dict(parse=t["parse"], build=t["build"], split=t["split"], trace=t["trace"],
                size=(j["image"]["width"], j["image"]["height"]),
                setup_cpu=t["setup_cpu"], trace_cpu=t["trace_cpu"], rays=sum(r.values()))

def load(d):
    return [task(json.loads(f.read_text())) for f in d.glob("tile-*.json")]

def probe(f, n):
    """The split's probe in CPU ms, modelled: its samples' share of the image's pixels
    times the one-process trace (tiles.rs: min(w, 64) x min(h, max(4N, 64)) eye rays)."""
    w, h = f["size"]
    return f["trace_cpu"] * min(w, 64) * min(h, max(4 * n, 64)) / (w * h)

def imb(ts, key):
    if not ts:
        return float("nan")
    v = [t[key] for t in ts]
    return max(v) / (sum(v) / len(v))

def fmt(x):
    return "-" if x != x else f"{x:.2f}"

for size in sizes:
    runs = {}
    for s in scenes:
        d = out / f"{s}-{size}"
        if not (d / "full.json").exists():
            continue
        sp = {(k, n): d / f"{k}-{n}" for k in ("cost", "equal") for n in counts if (d / f"{k}-{n}").is_dir()}
        runs[s] = dict(full=task(json.loads((d / "full.json").read_text())),
                       tiles={k: load(p) for k, p in sp.items()},
                       merge={k: float((p / "merge_ms").read_text()) for k, p in sp.items()})
    if not runs:
        continue
    print(f"### {size}, one thread per task\n")
    print("Overhead of a task against the trace (CPU ms of the process: `setup` is reading the scene, "
          "building the tree and, for `--tile`, the split's probe). Full: the one-process render. "
          "Tasks: medians over every tile task of the scene; split: median wall ms of the probe "
          "over the N tasks of a split; merge: median wall ms of `tracer merge` over the splits.\n")
    print("| scene | full setup CPU ms | full trace CPU ms | setup / trace | rays | task parse wall ms | task build wall ms | task setup CPU ms | split wall ms N=4 | N=16 | N=64 | merge wall ms |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for s, r in runs.items():
        f = r["full"]
        every = [t for ts in r["tiles"].values() for t in ts]
        split = {n: med(t["split"] for t in r["tiles"][("cost", n)]) for n in (4, 16, 64) if n in counts}
        print(f"| {s} | {f['setup_cpu']:.0f} | {f['trace_cpu']:.0f} | {f['setup_cpu'] / f['trace_cpu']:.2f} | {f['rays']:,} | "
              f"{med(t['parse'] for t in every):.0f} | {med(t['build'] for t in every):.0f} | "
              f"{med(t['setup_cpu'] for t in every):.0f} | " + " | ".join(f"{split.get(n, 0):.1f}" for n in (4, 16, 64)) + f" | {med(r['merge'].values()):.0f} |")
    print()
    print("Load imbalance, max / mean over the tiles of a split: by trace CPU time (one run each), by "
          "rays (the same on every machine) and by trace wall time; `cost`: `--tile I/N`, `equal`: "
          "bands of equal height; last column: the tiles' trace CPU time added up over the "
          "one-process render's.\n")
    print("| scene | N | CPU cost | CPU equal | rays cost | rays equal | wall cost | wall equal | sum / full (cost) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for s, r in runs.items():
        for n in counts:
            c, e = r["tiles"][("cost", n)], r["tiles"].get(("equal", n), [])
            row = [imb(c, "trace_cpu"), imb(e, "trace_cpu"), imb(c, "rays"), imb(e, "rays"),
                   imb(c, "trace"), imb(e, "trace"), sum(t["trace_cpu"] for t in c) / r["full"]["trace_cpu"]]
            print(f"| {s} | {n} | " + " | ".join(map(fmt, row)) + " |")
    print()
    print("Speed-up on N nodes, one tile task a node, modelled from the tasks measured here one after "
          "another (CPU ms): T(1) = the one-process render's setup + trace; T(N) = a task's reading and "
          "building (the median over all tile tasks of the scene) + the probe (modelled, as below) + "
          "the split's largest tile trace (the merge, in the first table, left out); "
          "speed-up = T(1) / T(N). `by rays`: the same with the largest tile's trace taken as its "
          "share of the split's rays times the one-process trace (free of the per-tile timing noise). `overhead`: setup / (setup + largest trace). `shared tree`: the cost split's speed-up if "
          "no task read the scene or built the tree (each still runs the split's probe, counted as its "
          "samples' share of the pixels times the one-process trace), the bound for "
          "a tree built once and loaded by every task at no cost; `limit`: T(1) / a task's reading and "
          "building, the speed-up no N can pass while every task reads the scene and builds the tree.\n")
    print("| scene | N | T(N) ms, cost | speed-up cost | by rays | speed-up equal | by rays | overhead (cost) | shared tree (cost) | limit |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for s, r in runs.items():
        f = r["full"]
        t1 = f["setup_cpu"] + f["trace_cpu"]
        # Reading and building, the same in every task: one median over all the tasks.
        base = med(t["setup_cpu"] - (probe(f, n) if k == "cost" else 0)
                   for (k, n), ts in r["tiles"].items() for t in ts)
        limit = t1 / base
        print(f"| {s} | 1 | {t1:.0f} | 1.00 | 1.00 | 1.00 | 1.00 | {f['setup_cpu'] / t1:.2f} | {t1 / f['trace_cpu']:.2f} | {limit:.1f} |")
        for n in counts:
            res = {}
            res["equal"] = (0, float("nan"), 0, 0, float("nan"))
            for k in ("cost", "equal"):
                if (k, n) not in r["tiles"]:
                    continue
                ts, m = r["tiles"][(k, n)], 0.0
                setup, trace = base + probe(f, n), max(t["trace_cpu"] for t in ts)
                tn = setup + trace + m
                shared = probe(f, n) + trace + m
                by_rays = f["trace_cpu"] * max(t["rays"] for t in ts) / sum(t["rays"] for t in ts)
                res[k] = (tn, t1 / tn, setup / (setup + trace), t1 / shared, t1 / (setup + by_rays + m))
            c, e = res["cost"], res["equal"]
            print(f"| {s} | {n} | {c[0]:.0f} | {c[1]:.2f} | {c[4]:.2f} | {fmt(e[1])} | {fmt(e[4])} | {c[2]:.2f} | {c[3]:.2f} | {limit:.1f} |")
    print()
EOF
