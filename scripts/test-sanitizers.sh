#!/usr/bin/env bash
# The unit, physics and CLI tests under AddressSanitizer + UndefinedBehaviorSanitizer
# (build-asan/, RelWithDebInfo). Any report fails the run. CI runs it after
# scripts/test.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
source scripts/compiler-cache.sh
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DACPCA_SANITIZE=ON "${compiler_cache_flags[@]}" \
  -DACPCA_BUILD_TESTS=ON -DACPCA_WERROR="${ACPCA_WERROR:-0}" >/dev/null
cmake --build build-asan -j "$(nproc)"
cd build-asan
# The h5py check runs Debian's Python, which is not instrumented.
# libhdf5's own leaks when it refuses a corrupt file are suppressed.
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
  LSAN_OPTIONS="suppressions=$(pwd)/../scripts/lsan-suppressions.txt" \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --output-on-failure -j "$(nproc)" --timeout 1800 -E h5py
