#!/usr/bin/env bash
# sward-web's page built for a browser into OUT_DIR: the crate built for wasm32-unknown-unknown
# (with sward-bevy's web example, scripts/browser-build.sh; --release: alone, optimised, as the
# browser bench times it), bound by wasm-bindgen (installed at the version Cargo.lock builds with
# where it is missing), and the page beside it. What the page does is read from plan.json in the
# same folder (crates/sward-web/page/page.mjs); crates/sward-wgpu/tests/browser/run.mjs serves
# and runs it.
#
#   scripts/web-page.sh OUT_DIR [--release]
set -euo pipefail
out=$(realpath -m "$1")
cd "$(dirname "$0")/.."
[[ -f "$HOME/.cargo/env" ]] && source "$HOME/.cargo/env"
source scripts/browser-build.sh
built=$(build_page "${2:-}" -p sward-web)
rm -rf "$out" && mkdir -p "$out"
wasm-bindgen --target web --no-typescript --out-dir "$out" "$built/sward_web.wasm"
cp crates/sward-web/page/page.html crates/sward-web/page/page.mjs "$out/"
