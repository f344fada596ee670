#!/usr/bin/env bash
# Configures and builds adaptive-cpca (Release) into build/; extra arguments go to CMake.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
source scripts/compiler-cache.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "${compiler_cache_flags[@]}" "$@" >/dev/null
cmake --build build -j "$(nproc)"
