#!/usr/bin/env bash
# Installs the packages, then configures and builds the release preset into build/release.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake --preset release
cmake --build --preset release --parallel "$(nproc)"
