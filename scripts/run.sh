#!/usr/bin/env bash
# sward's main job on a fresh machine: set up, build, and render the default meadow to meadow.png.
# Arguments are passed to sward (e.g. `scripts/run.sh render --width 1920 --height 1080`).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
[[ -f "$HOME/.cargo/env" ]] && source "$HOME/.cargo/env"
cargo build --release --locked -p sward
exec target/release/sward "$@"
