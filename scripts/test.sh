#!/usr/bin/env bash
# Builds softflow and runs the whole test suite (ctest: unit, convergence,
# MPI at 1, 2 and 4 ranks, restart, bad input). Works on a fresh Debian 12
# machine: the first call provides the toolchain (scripts/toolchain.sh).
#   scripts/test.sh [ctest arguments...]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/toolchain.sh setup
scripts/toolchain.sh run bash -c '
  set -e
  cmake -S . -B "$SOFTFLOW_BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$SOFTFLOW_BUILD"
  cd "$SOFTFLOW_BUILD" && ctest --output-on-failure -j2 "$@"' bash "$@"
