#!/usr/bin/env bash
# The tiles and frames of a render as Slurm array jobs on a real one-node cluster,
# checked against the one-process render byte for byte; then a lost task: one tile task
# cancelled, `tracer merge` refusing with its index, that index alone resubmitted, and
# the merge again. Installs slurm-wlm and munge with apt-get when missing (needs root),
# starts the cluster (cluster.sh) and stops its daemons by PID at the end. Fails with
# the reason when the cluster cannot start.
# Usage: tracer/scripts/slurm/ci-test.sh   (TRACER: the binary; default: build it)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
  echo "slurm: installing slurm-wlm and munge"
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq slurm-wlm munge >/dev/null
fi
if [ -z "${TRACER:-}" ]; then
  cargo build -q -p tracer-cli --manifest-path "$root/Cargo.toml"
  TRACER=${CARGO_TARGET_DIR:-$root/target}/debug/tracer
fi
TRACER=$(realpath "$TRACER")
work=$(mktemp -d)
chmod 755 "$work"
trap 'bash "$here/cluster.sh" stop "$work/cluster"' EXIT
bash "$here/cluster.sh" start "$work/cluster"
export SLURM_CONF=$work/cluster/slurm.conf
cd "$work"

scene=$root/tracer/scenes/showcase.nff
args="--width 96 --height 72 --aa 2"
fail() { echo "slurm: FAILED: $*" >&2; exit 1; }
# Waits until job $1 has left the queue (at most two minutes).
wait_job() {
  for _ in $(seq 600); do
    [ -z "$(squeue -h -j "$1" 2>/dev/null)" ] && return 0
    sleep 0.2
  done
  squeue >&2; fail "job $1 still queued after two minutes"
}

# shellcheck disable=SC2086
"$TRACER" render "$scene" $args -o ref.png

echo "slurm: 4 tiles and the merge after them"
read -r _ tiles _ merge < <(TRACER=$TRACER bash "$here/submit.sh" "$scene" 4 "$work/run" $args)
wait_job "$tiles"; wait_job "$merge"
[ -f run/image.png ] || { cat slurm-*.out >&2; fail "no merged image (jobs $tiles, $merge)"; }
cmp ref.png run/image.png || fail "merged tiles differ from the one-process render"
echo "slurm: merged image equals the one-process render"

echo "slurm: 3 frames of a camera path"
printf 'move 0.4\nyaw 8\nstrafe -0.2\n' > path.txt
# shellcheck disable=SC2086
"$TRACER" render "$scene" $args --script path.txt --frame 0-2 -o "ref-%04d.png"
sbatch --wait -Q --array=0-2 \
  --export="ALL,TRACER=$TRACER,SCENE=$scene,SCRIPT=$work/path.txt,OUT=$work/frames,ARGS=$args" \
  "$here/frames.sbatch" || { cat slurm-*.out >&2; fail "frames job"; }
for k in 0 1 2; do
  f=$(printf 'frame-%04d.png' "$k")
  cmp "ref-${f#frame-}" "frames/$f" || fail "frame $k differs"
done
echo "slurm: frames equal the one-process renders"

echo "slurm: a lost task"
vars="ALL,TRACER=$TRACER,SCENE=$scene,TILES=4,OUT=$work/lost,ARGS=$args"
job=$(sbatch --parsable --hold --array=0-3 --export="$vars" "$here/tiles.sbatch")
scancel "${job}_3"
scontrol release "$job"
wait_job "$job"
missing=$("$TRACER" merge --missing lost/tile-*.exr)
[ "$missing" = 3 ] || fail "merge --missing printed '$missing', not 3"
if "$TRACER" merge lost/tile-*.exr -o lost.png 2>err.txt; then fail "merge accepted 3 of 4 tiles"; fi
grep -q "tiles 3 of 4 are missing" err.txt || fail "merge said: $(cat err.txt)"
[ ! -e lost.png ] || fail "merge wrote an image from 3 of 4 tiles"
echo "slurm: merge refused: $(cat err.txt)"
sbatch --wait -Q --array="$missing" --export="$vars" "$here/tiles.sbatch" || fail "rerun of tile $missing"
"$TRACER" merge lost/tile-*.exr -o lost.png
cmp ref.png lost.png || fail "merge after the rerun differs"
echo "slurm: after rerunning tile $missing alone the merge equals the one-process render"
