#!/usr/bin/env bash
# Packaging: every published crate packages with its sources, README and
# licence files, and a user's crate builds and runs against the packages.
#
# 1. `cargo package` the published crates together (cargo packages
#    workspace crates that depend on each other in one call, before any is
#    on crates.io), without its verification build: the user's crate below
#    builds the packages instead, with optimized dependencies.
# 2. Check each .crate: Cargo.toml, README.md, LICENSE-MIT, LICENSE-APACHE
#    and src/lib.rs are regular, non-empty files, and each adapter's src/
#    is the shared source (crates/rapier-adapter/src), file for file.
# 3. Unpack them under target/packaged/crates, and build and test
#    tests/packaged (its own workspace and lock file, target under
#    target/packaged/target): it depends on kimpact, kimpact2d, kimpact3d
#    and kimpact-reference by version, patched to the unpacked packages, and
#    runs the README's drop-in (Newton's cradle, 2D and 3D).
#
# Needs crates.io reachable (the index, for the lock files cargo package
# writes). Run from anywhere; CI calls it from .ci/run.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
export CARGO_TERM_COLOR="${CARGO_TERM_COLOR:-never}"

published=(kimpact kimpact2d kimpact3d kimpact2d-f64 kimpact3d-f64 kimpact-reference)
adapters=(kimpact2d kimpact3d kimpact2d-f64 kimpact3d-f64)
# `cargo pkgid` ends in `#0.1.0` (or `#kimpact@0.1.0`).
version=$(cargo pkgid -p kimpact | sed 's/.*[#@]//')
case "${CARGO_TARGET_DIR:-}" in
    "") target_dir="$root/target" ;;
    /*) target_dir="$CARGO_TARGET_DIR" ;;
    *) target_dir="$root/$CARGO_TARGET_DIR" ;;
esac
# tests/packaged/Cargo.toml patches the crates to these directories.
unpacked="$root/target/packaged/crates"

echo "-- cargo package (${published[*]}, $version)"
# --allow-dirty: a developer's uncommitted edits are what they want checked
# (CI runs on a clean clone).
args=()
for p in "${published[@]}"; do args+=(-p "$p"); done
cargo package --locked --no-verify --allow-dirty "${args[@]}"

echo "-- package contents"
rm -rf "$unpacked"
mkdir -p "$unpacked"
fail=0
for p in "${published[@]}"; do
    crate="$target_dir/package/$p-$version.crate"
    dir="$unpacked/$p"
    mkdir -p "$dir"
    tar -xzf "$crate" -C "$dir" --strip-components=1
    # Fresh mtimes: tar keeps the archive's, which can be older than a
    # previous run's build of the same path, and cargo would reuse it.
    find "$dir" -type f -exec touch {} +
    for f in Cargo.toml README.md LICENSE-MIT LICENSE-APACHE src/lib.rs; do
        if [ -L "$dir/$f" ] || [ ! -f "$dir/$f" ] || [ ! -s "$dir/$f" ]; then
            echo "error: $p-$version.crate has no regular, non-empty $f" >&2
            fail=1
        fi
    done
    cmp -s "$dir/LICENSE-MIT" LICENSE-MIT || { echo "error: $p: LICENSE-MIT differs from the root's" >&2; fail=1; }
    cmp -s "$dir/LICENSE-APACHE" LICENSE-APACHE || { echo "error: $p: LICENSE-APACHE differs from the root's" >&2; fail=1; }
    echo "$p-$version.crate: $(tar -tzf "$crate" | wc -l) files"
done
for p in "${adapters[@]}"; do
    if ! diff -r crates/rapier-adapter/src "$unpacked/$p/src" > /dev/null; then
        echo "error: $p-$version.crate's src/ is not crates/rapier-adapter/src:" >&2
        diff -rq crates/rapier-adapter/src "$unpacked/$p/src" >&2 || true
        fail=1
    fi
done
[ "$fail" = 0 ] || exit 1

echo "-- a user's crate against the packages (tests/packaged)"
export CARGO_TARGET_DIR="$root/target/packaged/target"
cd "$root/tests/packaged"
cargo fmt --check
# --locked: the lock file is committed; after a dependency change, run
# `cargo update -w` here (with the packages unpacked by this script).
cargo test --locked
cargo run --locked
