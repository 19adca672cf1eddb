#!/usr/bin/env bash
# Sets up, builds, and runs every test (unit tests, and GL tests on headless EGL: llvmpipe without a GPU), then
# checks the installed package with examples/embed (scripts/test-install.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
ctest --preset release --parallel "$(nproc)"
bash scripts/test-install.sh  # the installed package, used by examples/embed from its own build folder
