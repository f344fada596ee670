#!/usr/bin/env bash
# The quick suites (unit and physics tests, and every reader of outside
# input: transport, model, scene, mesh, environment and lights files) under
# AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/, at -O1 -g1, the
# optimisation AddressSanitizer's documentation suggests, with line tables:
# reports still name the file and line, and a cold build takes about half the
# time -O2 -g takes).
# Any report fails the run. The slow end-to-end suites run in the main build
# only (scripts/test.sh). CI runs it after scripts/test.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
source scripts/compiler-cache.sh
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DACPCA_SANITIZE=ON "${compiler_cache_flags[@]}" \
  -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
  -DACPCA_BUILD_TESTS=ON -DACPCA_WERROR="${ACPCA_WERROR:-0}" >/dev/null
cmake --build build-asan -j "$(nproc)" --target quick_suites
cd build-asan
# libhdf5's own leaks when it refuses a corrupt file are suppressed.
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
  LSAN_OPTIONS="suppressions=$(pwd)/../scripts/lsan-suppressions.txt" \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --output-on-failure -j "$(nproc)" --timeout 1800 -L quick
