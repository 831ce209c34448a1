#!/usr/bin/env bash
# Eye packets of two builds of `packet_walk` (tracer/examples/packet_walk.rs) side by
# side on a noisy host: for each scene, ROUNDS alternations of one-run, one-thread
# measurements of the packets over the four-wide tree (512x512), then the median rate of
# each build and the median of the per-pair ratios new / old.
# Usage: tracer/scripts/packet-ab.sh OLD_BIN NEW_BIN ROUNDS SCENE...
#   SCENE is a name in ../shared/scenes/spd without .nff, e.g. teapot-s12, or a path
#   (with a '/'), e.g. ../shared/scenes/spd-large/balls-s6.nff.gz
#   ONLY=single measures single eye rays over the four-wide tree instead of packets.
#   SIZE=WxH sets the image size (512x512 by default).
#   e.g. git worktree add /tmp/old COMMIT && cargo build --profile perf -p tracer
#   --example packet_walk --manifest-path /tmp/old/Cargo.toml --target-dir /tmp/old-t &&
#   cargo build --profile perf -p tracer --example packet_walk &&
#   tracer/scripts/packet-ab.sh /tmp/old-t/perf/examples/packet_walk
#   target/perf/examples/packet_walk 15 teapot-s12 balls-s4
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
old=$1 new=$2 rounds=$3
shift 3
S=$root/../shared/scenes/spd
only=${ONLY:-wide}
size=${SIZE:-512x512}
case $only in
  wide) col=5 ;;
  single) col=3 ;;
  *) echo "ONLY=$only: expected wide or single" >&2; exit 2 ;;
esac
scene() { case $1 in */*) echo "$1" ;; *) echo "$S/$1.nff" ;; esac; }
rate() { "$1" --runs 1 --threads 1 --only "$only" --size "$size" "$(scene "$2")" | awk -F'|' -v c=$col '/nff/ {print $c}'; }
echo "| scene | old Mrays/s | new Mrays/s | new / old |"
echo "|---|---:|---:|---:|"
for s in "$@"; do
  name=$(basename "$s")
  name=${name%%.*}
  pairs=""
  for _ in $(seq "$rounds"); do
    pairs+="$(rate "$old" "$s") $(rate "$new" "$s")"$'\n'
  done
  python3 -c '
import statistics, sys
p = [tuple(map(float, l.split())) for l in sys.argv[2].splitlines() if l.strip()]
a = statistics.median(x for x, _ in p)
b = statistics.median(y for _, y in p)
r = statistics.median(y / x for x, y in p)
print(f"| {sys.argv[1]} | {a:.2f} | {b:.2f} | {r:.3f} |")' "$name" "$pairs"
done
