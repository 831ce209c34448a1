#!/usr/bin/env bash
# Headless test of the viewer's window: starts a virtual X server (Xvfb, installed with
# apt-get if missing) and runs the windowed viewer test under it, which then must not
# skip: the viewer plays tracer/cli/tests/data/viewer-path.txt on balls-s1 in a real window,
# lets the last view converge, writes a screenshot, and the test compares it with the
# offline render of the same camera.
# Usage: tracer/scripts/viewer-test.sh   (as root where Xvfb must be installed)
# Outside CI (CI unset), a machine where Xvfb cannot be installed or started skips the
# test with a message; in CI that is a failure.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)

skip() {
  if [ "${CI:-}" = "true" ]; then
    echo "viewer-test: FAILED: $1" >&2
    exit 1
  fi
  echo "viewer-test: SKIPPED: $1"
  exit 0
}

# The X server, and the X client libraries the window loads at run time.
libs=(libx11-6 libx11-xcb1 libxcb1 libxcursor1 libxrandr2 libxi6 libxkbcommon-x11-0)
if ! command -v Xvfb >/dev/null; then
  if [ "$(id -u)" != 0 ] || ! command -v apt-get >/dev/null; then
    skip "Xvfb is not installed and cannot be installed here (needs root and apt-get)"
  fi
  echo "viewer-test: installing Xvfb"
  apt-get update -qq || skip "apt-get update failed"
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
    xvfb "${libs[@]}" >/dev/null || skip "apt-get install xvfb failed"
fi

# Xvfb picks a free display number and writes it to fd 3.
dfile=$(mktemp)
Xvfb -displayfd 3 -screen 0 800x600x24 -nolisten tcp 3>"$dfile" 2>/dev/null &
xvfb_pid=$!
trap 'kill "$xvfb_pid" 2>/dev/null || true; rm -f "$dfile"' EXIT
for _ in $(seq 100); do
  [ -s "$dfile" ] && break
  kill -0 "$xvfb_pid" 2>/dev/null || break
  sleep 0.1
done
[ -s "$dfile" ] || skip "Xvfb did not start"
export DISPLAY=":$(head -n1 "$dfile")"
echo "viewer-test: Xvfb on $DISPLAY"

cd "$root"
# --workspace: the same features as CI's `cargo test --workspace`, so nothing is rebuilt.
TRACER_VIEWER_REQUIRE_DISPLAY=1 cargo test -q --workspace --test cli -- \
  --exact viewer::windowed_script_matches_offline_render --nocapture
