#!/usr/bin/env bash
# Submits a render in N tiles and the merge that follows it, and prints the two job ids.
# Usage: tracer/scripts/slurm/submit.sh SCENE N OUT_DIR [tracer render options...]
#   TRACER (default: target/release/tracer) is the binary every node runs.
# Watch with `squeue`, account with `sacct -j ID`; when a tile task fails, the merge
# waits forever (DependencyNeverSatisfied): cancel it, resubmit the tiles that
# `tracer merge --missing OUT_DIR/tile-*.exr` lists with --array=LIST, then the merge.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
scene=$(realpath "$1"); n=$2; out=$(realpath -m "$3"); shift 3
tracer=$(realpath "${TRACER:-$root/target/release/tracer}")
vars="ALL,TRACER=$tracer,SCENE=$scene,TILES=$n,OUT=$out,ARGS=$*"
tiles=$(sbatch --parsable --array="0-$((n - 1))" --export="$vars" "$here/tiles.sbatch")
merge=$(sbatch --parsable --dependency="afterok:$tiles" --export="ALL,TRACER=$tracer,OUT=$out" \
  "$here/merge.sbatch")
echo "tiles $tiles merge $merge"
