#!/usr/bin/env bash
# sward's tests on a fresh machine: set up (Vulkan loader, lavapipe, validation layer, the pinned
# Rust), then run every test of the workspace (examples and doc examples included; the Bevy
# plugin's web example built for a browser and run in one), build the API docs of the crates
# without Bevy, failing on any rustdoc warning, and package the library crates as they would be
# published (a dry run). GPU tests run on whatever Vulkan device is present (lavapipe on a
# machine without a GPU) with the validation layer on, and fail if there is none.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh --xvfb
[[ -f "$HOME/.cargo/env" ]] && source "$HOME/.cargo/env"
# Avian's colliders too (its feature's tests and example), and the Bevy plugin's Vulkan route.
cargo test --workspace --locked --features sward-bevy/avian,sward-bevy/vulkan "$@"
# The Bevy plugin in a browser (built for wasm32 and run in headless Chromium by the tests' web
# example): its dependency graph there holds no Vulkan (ash, gpu-allocator, wgpu-hal), no C++
# (glslang), no blocking wait (pollster) and none of sward's Vulkan crates.
not_for_a_browser=$(cargo tree --locked -p sward-bevy --target wasm32-unknown-unknown -e normal --prefix none |
  awk '{print $1}' | sort -u |
  grep -xE 'ash|gpu-allocator|wgpu-hal|glslang|glslang-sys|pollster|sward-gpu|sward-wgpu' || true)
if [[ -n $not_for_a_browser ]]; then
  echo "sward-bevy's browser build depends on $(echo $not_for_a_browser)" >&2
  exit 1
fi
# The grass core (its Rust and its WGSL) holds no GPU API, and the two renderers stand beside
# each other on it: the Vulkan renderer depends on neither wgpu nor the portable renderer.
depends_on() {
  cargo tree --locked -p "$1" -e normal --prefix none | awk '{print $1}' | sort -u | grep -xE "$2" || true
}
for crate_and_not in 'sward-core:ash|gpu-allocator|glslang|wgpu|wgpu-core|wgpu-hal|naga|sward-gpu|sward-portable' \
  'sward-gpu:wgpu|wgpu-core|wgpu-hal|sward-portable'; do
  crate=${crate_and_not%%:*}
  wrong=$(depends_on "$crate" "${crate_and_not#*:}")
  if [[ -n $wrong ]]; then
    echo "$crate depends on $(echo $wrong)" >&2
    exit 1
  fi
done
# The API docs of the crates without Bevy: their dependencies checked with the features the app
# alone has (as `cargo check -p sward --bins` checks them), not all of Bevy checked again for
# sward-bevy's (its doc example is compiled with the tests).
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --locked -p sward-core -p sward-portable -p sward-gpu -p sward-wgpu -p sward --lib --bins
# --allow-dirty: a checkout may carry build products git does not ignore; nothing is uploaded.
# The core and the portable renderer are packaged and built from their packages (the portable
# one against the core's package); the Vulkan crates and the Bevy plugin are packaged without
# that build, which would build glslang's C++ and Bevy a second time. Cargo finds an unpublished
# dependency only among the packages of the same command, so the second names them all.
# A package's verifying build takes sward-core from a temporary registry of these packages,
# which cargo unpacks into its home once per version and never again: an earlier run's copy of the
# core (other code, same 0.1.0) would stand in for this one's, so those copies go first.
rm -rf "${CARGO_HOME:-$HOME/.cargo}"/registry/src/-*/sward-*
# Cargo also keeps its build of a registry crate for good (a published version never changes),
# so the verifying build would link an earlier run's core all the same: those builds go too.
target_dir=${CARGO_TARGET_DIR:-target}
for info in "$target_dir"/debug/deps/sward_*.d; do
    if grep -qs "registry/src/-" "$info"; then
        build=$(basename "$info" .d)
        rm -rf "$target_dir/debug/.fingerprint/${build//_/-}" "$info"
    fi
done
# A package's build has no workspace profile: cargo's default one would build every dependency
# with full debug information: 121 s and 1.7 GB from nothing here, against 72 s and 0.7 GB.
CARGO_PROFILE_DEV_DEBUG=false cargo package --locked --allow-dirty -p sward-core -p sward-portable
cargo package --locked --allow-dirty --no-verify -p sward-core -p sward-portable -p sward-gpu -p sward-wgpu -p sward-bevy
