#!/usr/bin/env bash
# Builds the test suite with AddressSanitizer and UndefinedBehaviorSanitizer
# (Kokkos' OpenMP backend, the toolchain's compiler) in its own build folder
# and runs it. Any sanitizer report fails the test that triggered it.
#   scripts/sanitize.sh [ctest arguments...]      e.g. scripts/sanitize.sh -R restart
# Environment: SANITIZE_BUILD (default build-asan). Run it after every change
# to the kernels; it takes about 4 times as long as scripts/test.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/toolchain.sh setup
SOFTFLOW_BUILD=${SANITIZE_BUILD:-build-asan} scripts/toolchain.sh run bash -c '
  set -e
  flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -g"
  cmake -S . -B "$SOFTFLOW_BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSOFTFLOW_PERF=OFF \
    -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_C_FLAGS="$flags" \
    -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
  cmake --build "$SOFTFLOW_BUILD"
  # detect_leaks=0: LeakSanitizer reports the allocations Open MPI, PMIx and
  # hwloc keep until exit (hundreds of blocks in their own libraries, none
  # reachable from softflow); it would flag every test. Heap errors (overflow,
  # use after free, double free) are still reported by AddressSanitizer.
  # abort_on_error / halt_on_error: the first report ends the test as failed.
  export ASAN_OPTIONS=detect_leaks=0:abort_on_error=1:halt_on_error=1
  export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
  cd "$SOFTFLOW_BUILD" && ctest --output-on-failure -j2 "$@"' bash "$@"
