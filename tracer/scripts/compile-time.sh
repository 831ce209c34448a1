#!/usr/bin/env bash
# Compile time of the `tracer` program (library and command line, release profile) at a
# base commit and in the working tree, interleaved: each round touches
# `tracer/src/lib.rs` in one tree, rebuilds, then the other. The base tree is a `git archive` of BASE in
# target/compile-base with its own target directory (so dependencies are built once
# there first). Prints one line per build: tree, wall, user and system seconds.
# Usage: tracer/scripts/compile-time.sh BASE [ROUNDS]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
base=${1:?usage: compile-time.sh BASE [ROUNDS]}
rounds=${2:-3}
tree=$root/target/compile-base
mkdir -p "$tree"
git -C "$root" archive "$base" | tar -x -C "$tree"
build() { # DIR TARGET_DIR LABEL
  touch "$1/tracer/src/lib.rs"
  (cd "$1" && CARGO_TARGET_DIR=$2 /usr/bin/time -f "$3 %e wall %U user %S sys" \
    cargo build --release -q --bin tracer 2>&1 | tail -1)
}
# `--bin tracer`, no package: the binary's package, before or after the command line
# moved out of the library into tracer/cli.
(cd "$tree" && CARGO_TARGET_DIR=$tree/target cargo build --release -q --bin tracer)
(cd "$root" && cargo build --release -q --bin tracer)
for _ in $(seq "$rounds"); do
  build "$tree" "$tree/target" base
  build "$root" "${CARGO_TARGET_DIR:-$root/target}" head
done
