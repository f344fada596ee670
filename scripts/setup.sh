#!/usr/bin/env bash
# Installs what adaptive-cpca needs from Debian 12's packages, when missing.
# Idempotent and non-interactive; needs root (or sudo) only if something is missing.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libembree-dev libtbb-dev libeigen3-dev
  libopenimageio-dev openimageio-tools libopencv-dev
  libhdf5-dev libcli11-dev nlohmann-json3-dev libassimp-dev
  libopenblas-dev liblapacke-dev
  openmpi-bin libopenmpi-dev
  libgtest-dev clang-format
  python3 python3-dev python3-venv python3-h5py python3-numpy python3-matplotlib python3-pytest pybind11-dev
  xvfb xauth
  clang libclang-rt-14-dev
  blender-data assimp-testmodels
)

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
