#!/usr/bin/env bash
# Installs what Firn builds and runs with on Debian 12 (bookworm), from Debian's own packages.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri   # EGL + OpenGL; Mesa's llvmpipe where there is no GPU
  libglew-dev libglfw3-dev libglm-dev libassimp-dev nlohmann-json3-dev libcli11-dev libstb-dev
  libimgui-dev          # the scene editor's panel (firn view --edit), with its GLFW and OpenGL 3 backends
  fonts-dejavu-core     # the panel's font, with the characters Firn's messages use (√, ≤, –)
  zlib1g-dev            # the checkpoints' CRC-32
  libopenmpi-dev openmpi-bin  # runs over several processes (mpirun -np N firn run)
  libgtest-dev libbenchmark-dev
  assimp-testmodels     # the tests voxelize its hostile meshes (AMF/test9.amf: thin parts across a large box)
  glslang-tools         # the tests compile every shader with Khronos' reference front end, glslangValidator
  mesa-vulkan-drivers   # lavapipe, under Mesa's Zink: the GL tests' second GL implementation
  libopenvdb-dev libboost-iostreams-dev  # the VDB caches; Debian's FindOpenVDB.cmake needs Boost.Iostreams too
  xvfb xauth      # a display for the viewer's tests (xvfb-run)
  ffmpeg          # optional at run time: `firn run --mp4`
  gnuplot-nox     # optional at run time: `firn bench`'s plots
  blender python3-numpy  # the add-on and its tests (docs/blender.md); Debian's Blender 3.4 leaves out numpy
)

missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all packages present"
  exit 0
fi

sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
echo "setup: installing ${missing[*]}"
$sudo apt-get update
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y --no-install-recommends "${missing[@]}"
