#!/usr/bin/env bash
# Sets up, builds and runs the whole test suite (unit, physics and CLI tests).
set -euo pipefail
cd "$(dirname "$0")/.."
# ACPCA_WERROR=1 (CI) turns compiler warnings into errors.
bash scripts/build.sh -DACPCA_BUILD_TESTS=ON -DACPCA_WERROR="${ACPCA_WERROR:-0}"
cd build
ctest --output-on-failure -j "$(nproc)" --timeout 900
