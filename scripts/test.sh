#!/usr/bin/env bash
# Sets up, builds and runs the whole test suite (unit, physics and CLI tests).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh -DACPCA_BUILD_TESTS=ON
cd build
ctest --output-on-failure -j "$(nproc)" --timeout 900
