# Sourced by the scripts that build a page for a browser (web-page.sh, web-example.sh):
# wasm-bindgen at the version Cargo.lock builds with, installed where it is missing or another
# version, `build_for_the_browser PROFILE`, which builds both pages' wasm in one cargo run, and
# `build_page`, which builds one page's wasm for its script.
bindgen=$(awk '/^name = "wasm-bindgen"$/ { getline; gsub(/"/, "", $3); print $3 }' Cargo.lock)
if [[ "$(wasm-bindgen --version 2>/dev/null)" != "wasm-bindgen $bindgen" ]]; then
  echo "sward: installing wasm-bindgen-cli $bindgen (the version Cargo.lock builds with)" >&2
  # Not --locked: its lock file names crates a registry mirror may not have yet. Not linted
  # (CI lints sward's crates through RUSTC_WORKSPACE_WRAPPER, which would lint this one too), and
  # built in a folder of its own (a test runs this while cargo holds the workspace's).
  env -u RUSTC_WORKSPACE_WRAPPER -u CLIPPY_ARGS -u CARGO_TARGET_DIR cargo install --quiet wasm-bindgen-cli --version "$bindgen"
fi

# The browser's builds, in a target folder of their own: a test builds them while cargo holds
# the workspace's.
browser_target=${CARGO_TARGET_DIR:-target}/browser

# sward-web's page and sward-bevy's web example for wasm32 in one cargo run, so what they share
# (wgpu, naga, the WESL compiler, sward's core and portable renderer, the proc macros) is built
# once with one set of features; each test that needs a page runs this, and the second finds it
# built. The wasm files land in $browser_target/wasm32-unknown-unknown/<profile's folder>/.
build_for_the_browser() {
  cargo build --quiet --locked --profile "$1" --target wasm32-unknown-unknown --target-dir "$browser_target" \
    -p sward-web --lib -p sward-bevy --example web
}

# A page's wasm, built as its script was asked (`$1`): with --release only the page's own
# package or example (the cargo arguments after it), optimised; else both pages' in one dev
# run. Prints the folder the wasm files land in.
build_page() {
  if [[ $1 == --release ]]; then
    shift
    cargo build --quiet --locked --release --target wasm32-unknown-unknown --target-dir "$browser_target" "$@"
    echo "$browser_target/wasm32-unknown-unknown/release"
  else
    [[ -z $1 ]] || { echo "sward: the only flag after OUT_DIR is --release, not $1" >&2; exit 2; }
    build_for_the_browser dev
    echo "$browser_target/wasm32-unknown-unknown/debug"
  fi
}
