#!/usr/bin/env bash
# Installs what adaptive-cpca needs from Debian 12's packages, when missing:
# everything, or with `build` only what building the CLI needs (the demo).
# Idempotent and non-interactive; needs root (or sudo) only if something is missing.
set -euo pipefail

# What building the CLI and its libraries needs (the demo's set; Debian's
# OpenImageIO CMake config refers to the binaries of openimageio-tools; ccache
# lets a later build, or CI's clone, reuse what was compiled)...
packages=(
  build-essential cmake pkg-config ccache
  libembree-dev libtbb-dev libeigen3-dev
  libopenimageio-dev openimageio-tools libopencv-dev
  libhdf5-dev libcli11-dev nlohmann-json3-dev libassimp-dev libssl-dev libarchive-dev
  libopenexr-dev libdeflate-dev libisal-dev
  libopenblas-dev liblapacke-dev
  openmpi-bin libopenmpi-dev
  libgtest-dev
  python3 python3-dev python3-numpy pybind11-dev
)
# ...and what the test suites, the fuzzers and CI add: image tools, the
# format check, Python's test tools, PyTorch (adaptive_cpca.torch; it reads
# EXR maps through OpenImageIO's binding) and the wheel's build tools, an X
# server for the viewer, clang for the fuzzers, and the real assets the tests
# check against, Debian's Chromium for the web page's tests (headless) and
# OpenEXR's exrheader for the frames' headers.
if [ "${1:-}" != build ]; then
  packages+=(
    clang-format
    python3-venv python3-h5py python3-matplotlib python3-pytest python3-torch
    python3-openimageio
    python3-build python3-wheel python3-setuptools
    xvfb xauth
    clang libclang-rt-14-dev
    blender-data assimp-testmodels
    chromium openexr
  )
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "setup: installing ${missing[*]}" >&2
as_root=()
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  as_root=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${as_root[@]}" apt-get update -qq
"${as_root[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
