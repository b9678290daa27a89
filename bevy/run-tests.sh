#!/usr/bin/env bash
# The Bevy plugins (CI step): formatting, lints, tests, the headless examples,
# docs and packages of bevy_kimpact2d and bevy_kimpact3d, in their own
# workspace. The windowed examples (feature `windowed`) are not built here:
# bevy's renderer and winit take longer to build than all of this (see
# README.md).
#
# bevy 0.20 asks for rustc 1.97.1, newer than the main workspace's stable
# toolchain: this runs the nightly toolchain with --ignore-rust-version
# (users on a stable rustc >= 1.97.1 need neither). Without a nightly
# toolchain it skips, except under CI (CI=true), where it fails.
set -euo pipefail
cd "$(dirname "$0")"
# Under the main workspace's target/ (as bevy/.cargo/config.toml says), so
# that CI caches it with the rest.
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$PWD/../target/bevy}"
export CARGO_TERM_COLOR="${CARGO_TERM_COLOR:-never}"

if ! cargo +nightly --version >/dev/null 2>&1; then
    if [ "${CI:-}" = "true" ]; then
        echo "bevy plugins: no nightly toolchain (rustup toolchain install nightly)" >&2
        exit 1
    fi
    echo "bevy plugins: skipped (no nightly toolchain)"
    exit 0
fi
cargo +nightly --version

# No --locked: Cargo.lock pins bevy and bevy_rapier, and the adapters are
# path dependencies whose own dependencies may change with the main
# workspace (cargo then adds them to the lock).
nightly=(cargo +nightly)
"${nightly[@]}" fmt --all --check
"${nightly[@]}" clippy --all-targets --ignore-rust-version -- -D warnings
"${nightly[@]}" test --ignore-rust-version
for example in cradle2d cradle3d; do
    "${nightly[@]}" run --quiet --ignore-rust-version --example "$example"
done
RUSTDOCFLAGS="-D warnings" "${nightly[@]}" doc --no-deps --ignore-rust-version

# Packaging, as .ci/package-check.sh checks the main crates: each .crate
# has its Cargo.toml, README.md, licence files and sources as regular,
# non-empty files, its src/, tests/ and examples/ are the shared ones
# (bevy/src, bevy/tests, bevy/examples) file for file, and it depends on
# kimpact2d/kimpact3d by version. --exclude-lockfile: cargo package would
# resolve a lock file against crates.io, where kimpact2d and kimpact3d are
# not yet (a library's lock file is not used by its dependents; publishing
# needs them published first). --no-verify: the tests above built them.
published=(bevy_kimpact2d bevy_kimpact3d)
version=$("${nightly[@]}" pkgid -p bevy_kimpact3d | sed 's/.*[#@]//')
args=()
for p in "${published[@]}"; do args+=(-p "$p"); done
"${nightly[@]}" package --no-verify --allow-dirty --exclude-lockfile "${args[@]}"
unpacked="$CARGO_TARGET_DIR/packaged"
rm -rf "$unpacked"
fail=0
for p in "${published[@]}"; do
    crate="$CARGO_TARGET_DIR/package/$p-$version.crate"
    dir="$unpacked/$p"
    mkdir -p "$dir"
    tar -xzf "$crate" -C "$dir" --strip-components=1
    for f in Cargo.toml README.md LICENSE-MIT LICENSE-APACHE src/lib.rs tests/plugin.rs examples/cradle.rs; do
        if [ -L "$dir/$f" ] || [ ! -f "$dir/$f" ] || [ ! -s "$dir/$f" ]; then
            echo "error: $p-$version.crate has no regular, non-empty $f" >&2
            fail=1
        fi
    done
    for f in LICENSE-MIT LICENSE-APACHE; do
        cmp -s "$dir/$f" "../$f" || { echo "error: $p: $f differs from the root's" >&2; fail=1; }
    done
    for d in src tests examples; do
        if ! diff -r "$d" "$dir/$d" > /dev/null; then
            echo "error: $p-$version.crate's $d/ is not bevy/$d:" >&2
            diff -rq "$d" "$dir/$d" >&2 || true
            fail=1
        fi
    done
    adapter="kimpact${p#bevy_kimpact}"
    if ! grep -A2 "^\[dependencies\.$adapter\]" "$dir/Cargo.toml" | grep -q '^version = "'; then
        echo "error: $p-$version.crate does not depend on $adapter by version" >&2
        fail=1
    fi
    if ! grep -A3 '^\[lib\]' "$dir/Cargo.toml" | grep -q '^path = "src/lib.rs"'; then
        echo "error: $p-$version.crate's Cargo.toml has no library at src/lib.rs" >&2
        fail=1
    fi
    if grep -q '^path = "\.\./' "$dir/Cargo.toml"; then
        echo "error: $p-$version.crate's Cargo.toml points outside the package" >&2
        fail=1
    fi
    echo "$p-$version.crate: $(tar -tzf "$crate" | wc -l) files"
done
[ "$fail" = 0 ] || exit 1
echo "bevy plugins: passed"
