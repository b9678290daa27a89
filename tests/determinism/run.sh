#!/usr/bin/env bash
# The determinism check (CI step): build tests/determinism in release without
# and with rapier's `parallel` feature (both with `enhanced-determinism`), run
# it sequentially and in parallel with rayon's pool at 1, 2 and 4 threads
# (rapier's passes and kimpact's own), and require identical hashes of every
# body's final position and velocity.
#
#   tests/determinism/run.sh              # all four runs
#   DETERMINISM_PARALLEL_ONLY=1 tests/determinism/run.sh
#                                         # only the parallel build (1, 2, 4 threads)
set -euo pipefail
cd "$(dirname "$0")"
# Under the main workspace's target/ so that CI caches it with the rest.
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$PWD/../../target/determinism}"
bin="$CARGO_TARGET_DIR/release/kimpact-determinism"
out="$CARGO_TARGET_DIR/out"
mkdir -p "$out"
runs=()
# The two builds compile the sources twice: if they change in between (an
# edit in a shared checkout), the hashes would differ for that reason alone.
sources() {
    find ../../crates/kimpact/src ../../crates/rapier-adapter/src ../../tests/cases src \
        Cargo.toml Cargo.lock ../../crates/kimpact3d/Cargo.toml -type f | sort | xargs cat | cksum
}
before=$(sources)

if [ -z "${DETERMINISM_PARALLEL_ONLY:-}" ]; then
    cargo build --release --locked
    "$bin" > "$out/sequential.txt"
    runs+=(sequential)
fi

cargo build --release --locked --features parallel
RAYON_NUM_THREADS=1 "$bin" > "$out/parallel-1.txt"
RAYON_NUM_THREADS=2 "$bin" > "$out/parallel-2.txt"
RAYON_NUM_THREADS=4 "$bin" > "$out/parallel-4.txt"
runs+=(parallel-1 parallel-2 parallel-4)

status=0
if [ "$(sources)" != "$before" ]; then
    echo "determinism: the sources changed during the check; run it again" >&2
    exit 2
fi
for r in "${runs[@]:1}"; do
    if ! diff -u "$out/${runs[0]}.txt" "$out/$r.txt"; then
        echo "determinism: $r differs from ${runs[0]}" >&2
        status=1
    fi
done
cat "$out/${runs[0]}.txt"
if [ "$status" -eq 0 ]; then
    echo "determinism: ${runs[*]} agree bit for bit"
fi
exit "$status"
