#!/usr/bin/env bash
# sward's tests on a fresh machine: set up (Vulkan loader, lavapipe, validation layer), then run
# every test of the workspace (examples and doc examples included), build the API docs of the
# crates without Bevy, failing on any rustdoc warning, and package the physics crate as it would
# be published (a dry run). GPU tests run on whatever Vulkan device is present (lavapipe on a
# machine without a GPU) with the validation layer on, and fail if there is none.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh --xvfb
[[ -f "$HOME/.cargo/env" ]] && source "$HOME/.cargo/env"
# Avian's colliders too (its feature's tests and example).
cargo test --workspace --locked --features sward-bevy/avian "$@"
# The API docs of the crates without Bevy: their dependencies checked with the features the app
# alone has (as `cargo check -p sward --bins` checks them), not all of Bevy checked again for
# sward-bevy's (its doc example is compiled with the tests).
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --locked -p sward-core -p sward-gpu -p sward-wgpu -p sward --lib --bins
# --allow-dirty: a checkout may carry build products git does not ignore; nothing is uploaded.
cargo package -p sward-core --locked --allow-dirty
