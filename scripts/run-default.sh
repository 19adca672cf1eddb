#!/usr/bin/env bash
# Sets up, builds, and runs the built-in default scene headless into firn-out/ (stats.csv, frame_NNNN.ply).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
build/release/firn run --out firn-out "$@"
