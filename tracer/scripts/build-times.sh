#!/usr/bin/env bash
# Build time of the README's two commands on a fresh copy of a commit: the first picture
# (`cargo build --release -p tracer-cli`, what `cargo run --release -p tracer-cli` compiles) and
# the tests (`cargo test --workspace --no-run`, then the run itself, which also builds
# the assembly checks' own targets), each in an empty target directory. Prints wall and
# CPU (user + system) seconds per step, and the critical path of each build: the longest
# chain of units in cargo's --timings data, each unit starting when the unit that
# released it finished (or wrote its metadata, for pipelined builds). Wall and unit times
# grow with other load on the machine; CPU seconds do not, so on an otherwise idle machine
# with C cores a build takes about max(CPU / C, critical path) once both are measured
# there. Needs git, python3 and /usr/bin/time.
# Usage: tracer/scripts/build-times.sh [COMMIT] [DIR]
#   COMMIT defaults to HEAD; DIR (default: a new temporary directory) receives the copy,
#   the target directories and cargo's timing reports.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
commit=${1:-HEAD}
dir=${2:-$(mktemp -d)}
mkdir -p "$dir/tree"
git -C "$root" archive "$commit" | tar -x -C "$dir/tree"
# Crates are fetched before timing so the network does not count.
cargo fetch -q --manifest-path "$dir/tree/Cargo.toml"

critical_path() { # the newest cargo-timing*.html of target directory $1
  python3 - "$(ls -t "$1"/cargo-timings/cargo-timing-*.html | head -1)" <<'EOF'
import json, re, sys
html = open(sys.argv[1]).read()
units = json.loads(re.search(r"const UNIT_DATA = (\[.*?\]);\n", html, re.S).group(1))
by = {u["i"]: u for u in units}
# Who released each unit: a unit listed in i's unblocked_units waited for i to finish,
# one in unblocked_rmeta_units for i's metadata (written when the front end is done).
# Older cargo versions call the lists unlocked_*.
def rmeta(u):
    if "rmeta_time" in u:
        return u["rmeta_time"]
    for name, span in u.get("sections") or []:
        if name == "frontend":
            return span["end"]
    return u["duration"]
waits = {u["i"]: [] for u in units}
for u in units:
    for key, meta in (("unblocked_units", False), ("unblocked_rmeta_units", True),
                      ("unlocked_units", False), ("unlocked_rmeta_units", True)):
        for j in u.get(key) or []:
            waits[j].append((u["i"], meta))
finish, chain = {}, {}
for u in sorted(units, key=lambda u: u["start"]):
    start, prev = 0.0, None
    for i, meta in waits[u["i"]]:
        t = finish[i] - by[i]["duration"] + rmeta(by[i]) if meta else finish[i]
        if t > start:
            start, prev = t, i
    finish[u["i"]] = start + u["duration"]
    chain[u["i"]] = (chain[prev] if prev is not None else []) + [u["i"]]
last = max(finish, key=finish.get)
path = chain[last]
print(f"  critical path {finish[last]:.1f} s over {len(path)} units; longest units on it:")
for i in sorted(path, key=lambda i: -by[i]["duration"])[:5]:
    u = by[i]
    print(f"    {u['duration']:7.1f} s  {u['name']} {u['target'].strip()}")
EOF
}

step() { # LABEL TARGET_DIR CARGO_ARGS...
  local label=$1 target=$2
  shift 2
  (cd "$dir/tree" && CARGO_TARGET_DIR=$target /usr/bin/time -o "$dir/time" \
    -f "%e %U %S" cargo "$@" >"$dir/$label.log" 2>&1) || {
    tail -20 "$dir/$label.log"
    exit 1
  }
  read -r wall user sys <"$dir/time"
  python3 -c "import sys; w,u,s=map(float,sys.argv[2:]); print(f'{sys.argv[1]}: {w:.0f} s wall, {u+s:.0f} s CPU')" \
    "$label" "$wall" "$user" "$sys"
}

step first-picture "$dir/target-release" build --release -p tracer-cli --timings
critical_path "$dir/target-release"
step test-build "$dir/target-test" test --workspace --no-run --timings
critical_path "$dir/target-test"
step test-run "$dir/target-test" test --workspace
