#!/usr/bin/env bash
# The cost of one step of a scene, counted by cachegrind rather than timed:
# deterministic, so an A/B of two builds is not lost in this shared host's
# noise (timings of one binary vary from run to run here).
#
#   crates/kimpact-bench/cachegrind-step.sh BIN SCENE MODE BALLS [PRECISION]
#
# BIN is a `kimpact-bench` binary (`cargo build --release -p kimpact-bench`,
# copied out of target/ to compare two builds). Runs the scene alone
# (`--solo`) twice under cachegrind, WARMUP then 0 and STEPS measured steps
# (environment, default 20 and 40), and prints per step, from the
# difference: instructions, L1 misses, L2 misses, and an estimate in cycles,
# Ir + 10 L1 + 100 L2 (cachegrind's usual weights). The last level is modelled
# as a 4 MB L2, not the host's large L3 (which holds every scene, so would
# show no misses). A model: no prefetcher, no out-of-order overlap.
# Use it to compare builds, not as a ratio to native.
set -euo pipefail
if [ $# -lt 4 ]; then
    sed -n '2,16p' "$0"
    exit 2
fi
bin=$1 scene=$2 mode=$3 balls=$4 precision=${5:-f32}
warmup=${WARMUP:-20} steps=${STEPS:-40}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cost() { # steps -> "Ir L1 L2"
    valgrind --tool=cachegrind --cache-sim=yes --LL=4194304,16,64 \
        --cachegrind-out-file="$dir/out" "$bin" --solo --scene "$scene" \
        --balls "$balls" --mode "$mode" --precision "$precision" \
        --steps "$1" --warmup "$warmup" ${EXTRA:-} >/dev/null 2>&1
    awk '/^events:/ { for (i = 2; i <= NF; i++) e[i] = $i }
         /^summary:/ { for (i = 2; i <= NF; i++) v[e[i]] = $i
             print v["Ir"], v["I1mr"] + v["D1mr"] + v["D1mw"], v["ILmr"] + v["DLmr"] + v["DLmw"] }' "$dir/out"
}
read -r i0 l10 l20 <<<"$(cost 0)"
read -r i1 l11 l21 <<<"$(cost "$steps")"
awk -v s="$steps" -v i="$((i1 - i0))" -v a="$((l11 - l10))" -v b="$((l21 - l20))" \
    -v name="$scene $balls $mode $precision" 'BEGIN {
    printf "%s per step: %.1f M instructions, %.0f k L1 misses, %.0f k L2 misses, %.1f M cycles (estimate)\n",
        name, i / s / 1e6, a / s / 1e3, b / s / 1e3, (i + 10 * a + 100 * b) / s / 1e6 }'
