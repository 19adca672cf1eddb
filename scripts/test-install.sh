#!/usr/bin/env bash
# Installs build/release into build/install and builds and runs examples/embed against that installed package
# (find_package(Firn)) from its own build folder, build/embed: the check that Firn works as a library.
# Run after scripts/build.sh (scripts/test.sh does both).
set -euo pipefail
cd "$(dirname "$0")/.."
rm -rf build/install build/embed  # fresh each time, so nothing stale can make it pass
cmake --install build/release --prefix build/install
cmake -S examples/embed -B build/embed -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$PWD/build/install"
cmake --build build/embed --parallel "$(nproc)"
build/embed/embed
