#!/usr/bin/env bash
# sward-bevy's web example (crates/sward-bevy/examples/web.rs) built for a browser into OUT_DIR:
# built for wasm32-unknown-unknown (with sward-web's page, scripts/browser-build.sh), bound by
# wasm-bindgen (installed at the version Cargo.lock builds with where it is missing), with its
# index.html beside it. Serve OUT_DIR (`python3 -m http.server -d OUT_DIR`) and open index.html
# in a browser with WebGPU. --release builds the example alone, optimised.
#
#   scripts/web-example.sh OUT_DIR [--release]
set -euo pipefail
out=$(realpath -m "$1")
cd "$(dirname "$0")/.."
[[ -f "$HOME/.cargo/env" ]] && source "$HOME/.cargo/env"
source scripts/browser-build.sh
built=$(build_page "${2:-}" -p sward-bevy --example web)
rm -rf "$out" && mkdir -p "$out"
wasm-bindgen --target web --no-typescript --out-dir "$out" --out-name web "$built/examples/web.wasm"
cp crates/sward-bevy/examples/web/index.html "$out/"
