#!/usr/bin/env bash
# Cost follows the particles: the same snowball in a 48³ and in a 192³ domain, timed in one run of this
# script (the machines are shared and noisy, so only the ratio is meaningful). Prints ms per step for each
# and the ratio. Usage: benchmarks/empty_domain.sh [path/to/firn] [frames]
set -euo pipefail
firn=${1:-build/release/firn}
frames=${2:-10}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

for cells in 48 192; do
  cat > "$work/snowball_$cells.json" <<JSON
{
  "name": "snowball in a ${cells}³ domain",
  "grid": { "origin": [0, 0, 0], "cells": [$cells, $cells, $cells], "cell_size": 0.02 },
  "time": { "dt": 2e-4, "frame_rate": 100, "frames": $frames },
  "solver": { "kernel": "quadratic", "transfer": "pic_flip" },
  "materials": { "snow": { "preset": "stomakhin" } },
  "bodies": [ { "shape": "sphere", "center": [0.48, 0.48, 0.48], "radius": 0.1, "material": "snow" } ]
}
JSON
done

# Alternate the two sizes three times and keep each one's median, so drift in machine load hits both.
for round in 1 2 3; do
  for cells in 48 192; do
    "$firn" run "$work/snowball_$cells.json" --out "$work/out_${cells}_$round" --no-ply > /dev/null 2>&1
  done
done
for cells in 48 192; do
  for round in 1 2 3; do
    # Frames 1..N: steps and wall milliseconds (frame 0 is start-up, excluded).
    awk -F, 'NR > 2 { steps += $3; ms += $10 } END { printf "%.4f\n", ms / steps }' "$work/out_${cells}_$round/stats.csv"
  done | sort -n | sed -n 2p > "$work/median_$cells"
  echo "domain ${cells}³: $(cat "$work/median_$cells") ms per step (median of 3)"
done
awk -v small="$(cat "$work/median_48")" -v large="$(cat "$work/median_192")" \
  'BEGIN { printf "192³ / 48³ time per step: %.3f\n", large / small }'
