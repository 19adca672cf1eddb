#!/usr/bin/env bash
# Sets up, builds, and runs every test (unit tests, and GL tests on headless EGL: llvmpipe without a GPU).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
ctest --preset release --parallel "$(nproc)"
