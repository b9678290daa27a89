#!/usr/bin/env bash
# The Bevy plugins (CI step): formatting, lints, tests, the headless examples
# and docs of bevy_kimpact2d and bevy_kimpact3d, in their own workspace.
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
echo "bevy plugins: passed"
