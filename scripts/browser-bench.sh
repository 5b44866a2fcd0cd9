#!/usr/bin/env bash
# sward's portable renderer in headless Chromium's WebGPU (SwiftShader on the CPU where there is
# no GPU): sward-web built for wasm32-unknown-unknown by wasm-bindgen (installed at the version
# Cargo.lock builds with where it is missing), the shipped scenes timed with the far field
# splatted (a browser's device has no 64-bit atomics: 32-bit cells) and drawn as geometry, each
# case's routes alternated over the repeats. Writes OUT_DIR/summary.csv and prints a table;
# with SHOTS=1 also each case's picture by each route (OUT_DIR/shot-*.png).
#
#   scripts/browser-bench.sh [OUT_DIR]
#
# Settings (environment): CASES (comma-separated, default the lavapipe table's shipped scenes;
# sward-web's case_names() lists them all, meadow·billboard among them), WIDTH, HEIGHT (640×360),
# WARMUP (3), FRAMES (8), REPEATS (2), SHOTS (0).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh --xvfb
[[ -f "$HOME/.cargo/env" ]] && source "$HOME/.cargo/env"

out=${1:-${CARGO_TARGET_DIR:-target}/browser-bench}
cases=${CASES:-meadow,hills,trample,planet,landscape,trail,park,openworld}
width=${WIDTH:-640} height=${HEIGHT:-360}

scripts/web-page.sh "$out" --release

shots=[]
if [[ ${SHOTS:-0} == 1 ]]; then
  shots=$(tr ',' '\n' <<< "$cases" |
    awk '{ printf "%s{\"name\":\"%s\",\"route\":\"splatted\"},{\"name\":\"%s\",\"route\":\"drawn\"}", (NR > 1 ? "," : ""), $1, $1 }')
  shots="[$shots]"
fi
cat > "$out/plan.json" <<JSON
{ "cases": $(tr ',' '\n' <<< "$cases" | awk '{ printf "%s\"%s\"", (NR > 1 ? "," : "["), $1 } END { print "]" }'),
  "routes": ["drawn", "splatted"], "width": $width, "height": $height,
  "warmup": ${WARMUP:-3}, "frames": ${FRAMES:-8}, "repeats": ${REPEATS:-2},
  "shots": $shots, "shot_steps": 30 }
JSON
chromium=$(command -v chromium || command -v chromium-browser)
SWARD_PAGE_TIMEOUT_S=${SWARD_PAGE_TIMEOUT_S:-3600} node crates/sward-wgpu/tests/browser/run.mjs "$out" "$chromium"
node crates/sward-web/page/summary.mjs "$out"
if [[ ${SHOTS:-0} == 1 ]] && command -v convert >/dev/null; then
  for rgba in "$out"/out-shot-*.rgba; do
    convert -size "${width}x${height}" -depth 8 "rgba:$rgba" "$out/$(basename "${rgba#*out-}" .rgba).png"
  done
fi
