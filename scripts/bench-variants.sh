#!/usr/bin/env bash
# The performance-pass measurements of docs/benchmarks-history.md: each renderer option against the others on
# the same cases. Usage: scripts/bench-variants.sh SWARD_BINARY OUT_DIR
set -euo pipefail
sward=$1
out=$2
mkdir -p "$out"
compute=(--presets meadow --counts 2^20,2^22,2^24 --modes all --max-seconds 1.5)
run() {
  local name=$1
  shift
  echo "== $name: $*"
  "$sward" bench "$@" --out "$out/$name" | grep -E '^\| 2\^|^renderer|^device|copy bandwidth'
}
run separate-per-blade-atomics "${compute[@]}" --separate --no-subgroup-atomics
run separate "${compute[@]}" --separate
run fused "${compute[@]}"
for wg in 64 128 512 1024; do
  run "fused-wg$wg" "${compute[@]}" --workgroup "$wg"
done
draw=(--presets cis565,meadow --counts 2^20 --modes all --max-seconds 1.5)
run lod-preset "${draw[@]}"
for level in 2 4 16; do
  run "lod-max$level" "${draw[@]}" --lod-max "$level"
done
run cis565-640x480 --presets cis565 --counts 2^16,2^20 --modes none,all --max-seconds 1.5 --width 640 --height 480
