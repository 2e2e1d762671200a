#!/usr/bin/env bash
# The GPUs' loop path on the CPU: builds softflow with SOFTFLOW_HOST_MDRANGE=ON
# (par_for/par_reduce and the transposes through Kokkos' MDRange, as on GPUs)
# into build-mdrange/, runs the test suite there, then runs one short
# suspension case (particles, implicit viscosity, K = 10: every kernel family)
# with both builds and compares their outputs (tests/compare_outputs.py).
#   scripts/test-mdrange.sh [ctest arguments...]
# Needs build/softflow (scripts/test.sh) for the comparison.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/toolchain.sh setup
SOFTFLOW_BUILD=build-mdrange scripts/toolchain.sh run bash -c '
  set -e
  cmake -S . -B "$SOFTFLOW_BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSOFTFLOW_HOST_MDRANGE=ON \
    -DSOFTFLOW_PERF=OFF >/dev/null
  cmake --build "$SOFTFLOW_BUILD"
  (cd "$SOFTFLOW_BUILD" && ctest --output-on-failure -j2 "$@")
  out=$(mktemp -d)
  trap "rm -rf $out" EXIT
  for b in build build-mdrange; do
    OMP_NUM_THREADS=2 "$b/softflow" cases/hard/phi011_ca02_k10.toml --set time.viscous=\"implicit\" \
      --set time.max_steps=40 --set output.series_every=5 --set output.progress_every=0 \
      --set output.checkpoint_minutes=0 --set "output.dir=\"$out/$b\"" >/dev/null
  done
  python3 tests/compare_outputs.py "$out/build" "$out/build-mdrange" 1e-10' bash "$@"
