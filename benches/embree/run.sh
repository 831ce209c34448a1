#!/usr/bin/env bash
# The tracer against Intel Embree 3 on the same scenes and rays (benches/embree/main.rs):
# installs Debian's libembree-dev if its header is missing (needs root or sudo), builds
# the bench with the `embree` feature and runs it on the seven classic SPD scenes, eye
# rays at 512x512 and 1920x1080, 1 and 2 threads; for scenes with spheres also Embree with
# the spheres as user geometry (not with --no-user-spheres); --robust builds Embree's
# scenes in its robust mode (RTC_SCENE_FLAG_ROBUST); --four-wide keeps the tracer's single
# rays on its four-wide tree where the CPU has AVX2. Prints Markdown tables.
# Usage: benches/embree/run.sh [--runs N] [--threads 1,2] [--sizes WxH,...] [--robust]
#                              [--no-user-spheres] [--four-wide] [SCENE.nff...]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
if [ ! -f /usr/include/embree3/rtcore.h ]; then
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo=sudo
  $sudo apt-get install -y libembree-dev
fi
opts=() scenes=()
while [ $# -gt 0 ]; do
  case $1 in
    --runs|--threads|--sizes) opts+=("$1" "$2"); shift 2 ;;
    --no-user-spheres|--robust|--four-wide) opts+=("$1"); shift ;;
    *) scenes+=("$1"); shift ;;
  esac
done
if [ ${#scenes[@]} -eq 0 ]; then
  spd=$root/../shared/scenes/spd
  scenes=("$spd"/balls-s4.nff "$spd"/gears-s4.nff "$spd"/mount-s6.nff "$spd"/rings-s7.nff
          "$spd"/teapot-s12.nff "$spd"/tetra-s6.nff "$spd"/tree-s11.nff)
fi
cargo bench -q -p benches --features embree --bench embree --manifest-path "$root/Cargo.toml" \
  -- "${opts[@]}" "${scenes[@]}"
