#!/usr/bin/env bash
# sward-web's page built for a browser into OUT_DIR: the crate built for wasm32-unknown-unknown
# (release, in its own target folder, so a test can build it while cargo holds the workspace's),
# bound by wasm-bindgen (installed at the version Cargo.lock builds with where it is missing),
# and the page beside it. What the page does is read from plan.json in the same folder
# (crates/sward-web/page/page.mjs); crates/sward-wgpu/tests/browser/run.mjs serves and runs it.
#
#   scripts/web-page.sh OUT_DIR
set -euo pipefail
out=$(realpath -m "$1")
cd "$(dirname "$0")/.."
[[ -f "$HOME/.cargo/env" ]] && source "$HOME/.cargo/env"

bindgen=$(awk '/^name = "wasm-bindgen"$/ { getline; gsub(/"/, "", $3); print $3 }' Cargo.lock)
if [[ "$(wasm-bindgen --version 2>/dev/null)" != "wasm-bindgen $bindgen" ]]; then
  echo "sward: installing wasm-bindgen-cli $bindgen (the version Cargo.lock builds sward-web with)" >&2
  # Not --locked: its lock file names crates a registry mirror may not have yet. Not linted
  # (CI lints sward's crates through RUSTC_WORKSPACE_WRAPPER, which would lint this one too), and
  # built in a folder of its own (a test runs this while cargo holds the workspace's).
  env -u RUSTC_WORKSPACE_WRAPPER -u CLIPPY_ARGS -u CARGO_TARGET_DIR cargo install --quiet wasm-bindgen-cli --version "$bindgen"
fi
target=${CARGO_TARGET_DIR:-target}/web-page
cargo build --quiet --release --locked -p sward-web --target wasm32-unknown-unknown --target-dir "$target"
rm -rf "$out" && mkdir -p "$out"
wasm-bindgen --target web --no-typescript --out-dir "$out" "$target/wasm32-unknown-unknown/release/sward_web.wasm"
cp crates/sward-web/page/page.html crates/sward-web/page/page.mjs "$out/"
