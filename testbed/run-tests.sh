#!/usr/bin/env bash
# The testbed app (CI step): formatting, lints, and its tests, which open
# rapier_testbed2d's window under Xvfb and drive a bundled scene through a
# mode switch; in its own workspace and target folder (target/testbed).
#
# Needs Xvfb and a software Vulkan driver for wgpu (Debian's xvfb and
# mesa-vulkan-drivers): installed here under CI when missing.
set -euo pipefail
cd "$(dirname "$0")"
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$PWD/../target/testbed}"
export CARGO_TERM_COLOR="${CARGO_TERM_COLOR:-never}"

if [ "${CI:-}" = "true" ] && ! { command -v xvfb-run >/dev/null 2>&1 \
    && [ -e /usr/share/vulkan/icd.d/lvp_icd.x86_64.json ]; }; then
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq \
        xvfb mesa-vulkan-drivers libvulkan1 libegl1 libegl-mesa0 \
        libxkbcommon-x11-0 libxcursor1 libxrandr2 libxi6 libx11-xcb1 >/dev/null
fi

cargo fmt --check
# Lints and tests in one build: clippy's driver compiles the local crates
# (as `cargo clippy` runs it, with its lints denied), so the testbed's
# dependencies (wgpu, kiss3d, egui) are built once, not a second time in
# `cargo clippy`'s check mode (CLIPPY_ARGS, its arguments joined by
# `__CLIPPY_HACKERY__`, is how `cargo clippy` passes them). `cargo test` builds every target the crate
# has (its binary, its tests and their unit-test builds).
clippy_driver="$(rustc --print sysroot)/bin/clippy-driver"
RUSTC_WORKSPACE_WRAPPER="$clippy_driver" \
    CLIPPY_ARGS="-D__CLIPPY_HACKERY__warnings__CLIPPY_HACKERY__" \
    cargo test
echo "testbed: passed"
