#!/usr/bin/env bash
# The SoA packet kernels of the kernels bench side by side: vecexpr's plain-array packets
# (`vecexpr`), vecexpr on the explicit lane types of vecexpr::simd run through
# `Isa::dispatch` (`vecexpr_f32x8` = AVX2 + FMA, `vecexpr_f32x16` = AVX-512F, whatever the
# build target), ultraviolet's `Vec3x8` and the hand-written SoA loop (benches/RESULTS.md,
# "Explicit SIMD lanes against ultraviolet").
#
#   benches/lanes.sh [TARGET...]       # default: x86-64 x86-64-v3
#       builds the bench once per target (x86-64 = the default build, in target/; others
#       with RUSTFLAGS="-C target-cpu=TARGET" in target/bench-targets/TARGET, which
#       changes ultraviolet: its f32x8 is two SSE registers unless AVX is enabled at
#       compile time), runs the SoA geometry benchmarks (every implementation side by side
#       in one criterion run per target; LANES_ROUNDS rounds, default 3, the targets
#       alternating) and prints a table of the medians over the rounds of criterion's
#       medians.
#   benches/lanes.sh ab BIN_A BIN_B [ROUNDS]
#       runs two bench executables alternately (ROUNDS times each, default 3) on the
#       explicit-lane benchmarks and prints, per benchmark, the median over the rounds of
#       criterion's medians and the ratio B / A.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
filter='^(normalize|cross|reflect|refract|reflect_normalize|normalize_zero_lane)/[a-z0-9_]+/soa'

# The executable `cargo bench --no-run` built (the last "Executable" line).
build() {
    cargo bench -p benches --bench kernels --no-run 2>&1 |
        sed -n 's/.*Executable .*(\(.*\))$/\1/p' | tail -n 1
}

table() {
    python3 - "$@" <<'PY'
import json, os, statistics, sys
homes = sys.argv[1:]
def median(home, g, i, s):
    # The median over the rounds (directories HOME-1, HOME-2, ...) of criterion's medians.
    ms = []
    r = 1
    while os.path.isdir(f"{home}-{r}"):
        p = os.path.join(f"{home}-{r}", g, i, s, "new", "estimates.json")
        if os.path.exists(p):
            ms.append(json.load(open(p))["median"]["point_estimate"])
        r += 1
    return statistics.median(ms) if ms else None
def fmt(ns):
    return "" if ns is None else (f"{ns / 1000:.2f} µs" if ns >= 1000 else f"{ns:.0f} ns")
groups = ["normalize", "cross", "reflect", "refract", "reflect_normalize", "normalize_zero_lane"]
cols = [("vecexpr", "soa8x4096", "vecexpr P8 (arrays)"),
        ("vecexpr_f32x8", "soa8x4096", "vecexpr F32x8"),
        ("vecexpr", "soa16x4096", "vecexpr P16 (arrays)"),
        ("vecexpr_f32x16", "soa16x4096", "vecexpr F32x16"),
        ("ultraviolet", "soa8x4096", "ultraviolet Vec3x8"),
        ("hand", "soa8x4096", "hand SoA")]
print("| kernel | build | " + " | ".join(c[2] for c in cols) +
      " | ultraviolet / F32x8 | ultraviolet / F32x16 |")
print("|---|---|" + "---:|" * (len(cols) + 2))
for g in groups:
    for spec in homes:
        target, home = spec.split("=", 1)
        v = [median(home, g, i, s) for i, s, _ in cols]
        if all(x is None for x in v):
            continue
        uv, x8, x16 = v[4], v[1], v[3]
        r8 = f"{uv / x8:.2f}" if uv and x8 else ""
        r16 = f"{uv / x16:.2f}" if uv and x16 else ""
        print(f"| {g} | {target} | " + " | ".join(fmt(x) for x in v) + f" | {r8} | {r16} |")
PY
}

if [[ ${1:-} == ab ]]; then
    a=$2 b=$3 rounds=${4:-3}
    base=$root/target/bench-targets/lanes-ab
    rm -rf "$base"
    abfilter='^(reflect_normalize|normalize|normalize_zero_lane)/vecexpr_f32x(8|16)/'
    for r in $(seq "$rounds"); do
        for side in a b; do
            bin=$a
            [[ $side == b ]] && bin=$b
            CRITERION_HOME=$base/$side-$r "$bin" --bench "$abfilter" >/dev/null 2>&1
        done
    done
    python3 - "$base" "$rounds" <<'PY'
import json, os, statistics, sys
base, rounds = sys.argv[1], int(sys.argv[2])
rows = {}
for side in "ab":
    for r in range(1, rounds + 1):
        home = os.path.join(base, f"{side}-{r}")
        for dp, _, files in os.walk(home):
            if dp.endswith("/new") and "estimates.json" in files:
                key = os.path.relpath(os.path.dirname(dp), home)
                m = json.load(open(os.path.join(dp, "estimates.json")))["median"]["point_estimate"]
                rows.setdefault(key, {"a": [], "b": []})[side].append(m)
print(f"| benchmark | A (median of {rounds}) | B (median of {rounds}) | B / A |")
print("|---|---:|---:|---:|")
for key in sorted(rows):
    a, b = (statistics.median(rows[key][s]) for s in "ab")
    print(f"| {key} | {a / 1000:.2f} µs | {b / 1000:.2f} µs | {b / a:.2f} |")
PY
    exit 0
fi

targets=("$@")
[[ ${#targets[@]} -gt 0 ]] || targets=(x86-64 x86-64-v3)
bins=()
# Build everything first, so compiling one target does not disturb measuring another.
for t in "${targets[@]}"; do
    if [[ $t == x86-64 ]]; then
        bins+=("$(build)")
    else
        bins+=("$(RUSTFLAGS="-C target-cpu=$t" CARGO_TARGET_DIR=$root/target/bench-targets/$t build)")
    fi
done
rounds=${LANES_ROUNDS:-3}
homes=()
for k in "${!targets[@]}"; do
    home=$root/target/bench-targets/lanes-${targets[$k]}
    rm -rf "$home" "$home"-*
    homes+=("${targets[$k]}=$home")
done
# The targets alternate, round after round, so a change in the machine's load touches all.
for r in $(seq "$rounds"); do
    for k in "${!targets[@]}"; do
        echo "== round $r, ${targets[$k]}: ${bins[$k]}" >&2
        CRITERION_HOME=$root/target/bench-targets/lanes-${targets[$k]}-$r \
            "${bins[$k]}" --bench "$filter" >&2
    done
done
table "${homes[@]}"
