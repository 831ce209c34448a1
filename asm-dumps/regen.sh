#!/bin/sh
# Regenerates every dump under asm-dumps/dumps/ with the toolchain at hand, for every
# kernel and target listed in asm-dumps/bounds.txt, and checks the rules while doing so.
# The dumps are written even when a rule fails, so the failing assembly can be read.
set -eu
cd "$(dirname "$0")/.."
ASM_DUMPS_UPDATE=1 cargo test -p asm-dumps --test integration asm_check:: -- --nocapture
