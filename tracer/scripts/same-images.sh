#!/usr/bin/env bash
# Bit-identical images from two tracer binaries: renders every scene of tracer/scenes
# and of ../shared/scenes/spd at 128x128 with single rays and (in f32, the only precision
# packets trace) with packets, with each scheduler and in both precisions, with both
# binaries, and compares the PFMs (linear floats) byte for byte. The scenes of
# tracer/scenes are also rendered in SPD mode (corner rays) and with 2x2 supersampling
# (with `--packets off` and, in f32, `auto`: builds before 3 December traced
# supersamples one ray at a time and refused `--packets on` with them). Prints each
# difference and the number of comparisons; exits 1 on a difference.
# Usage: tracer/scripts/same-images.sh OLD_BIN NEW_BIN
#   e.g. tracer/scripts/same-images.sh /tmp/old/target/release/tracer target/release/tracer
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
old=$1 new=$2
d=$(mktemp -d)
trap 'rm -rf "$d"' EXIT
n=0 diff=0
compare() { # SCENE ARGS...
  local scene=$1
  shift
  "$old" render "$scene" -o "$d/old.pfm" --width 128 --height 128 "$@" >/dev/null
  "$new" render "$scene" -o "$d/new.pfm" --width 128 --height 128 "$@" >/dev/null
  n=$((n + 1))
  if ! cmp -s "$d/old.pfm" "$d/new.pfm"; then
    echo "differ: $(basename "$scene") $*"
    diff=$((diff + 1))
  fi
}
for scene in "$root"/tracer/scenes/*.nff "$root"/../shared/scenes/spd/*.nff; do
  for precision in f32 f64; do
    for packets in off on; do
      [ "$precision/$packets" = f64/on ] && continue
      for scheduler in rayon static tiles; do
        compare "$scene" --precision "$precision" --packets "$packets" --scheduler "$scheduler"
      done
    done
  done
done
for scene in "$root"/tracer/scenes/*.nff; do
  for precision in f32 f64; do
    for packets in off on; do
      [ "$precision/$packets" = f64/on ] && continue
      compare "$scene" --precision "$precision" --packets "$packets" --spd
    done
    compare "$scene" --precision "$precision" --packets off --aa 2
    [ "$precision" = f32 ] && compare "$scene" --precision f32 --packets auto --aa 2
  done
done
echo "$n comparisons, $diff differences"
[ "$diff" -eq 0 ]
