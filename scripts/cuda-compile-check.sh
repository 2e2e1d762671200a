#!/usr/bin/env bash
# Compiles every translation unit of softflow with nvcc for a GPU, on a
# machine without one: objects only, nothing linked or run. It catches what
# the CPU builds cannot (nvcc's rules for device lambdas: no KOKKOS_LAMBDA in
# gtest's private TestBody, no function-local type in a device lambda's
# captures, ...) before a GPU is lent.
#
#   scripts/gpu-prepare.sh /work/.mirror/kokkos+kokkos/repo   # once: gpu-kit/
#   scripts/cuda-compile-check.sh                              # -> "N of N compiled"
#
# Needs nvcc (CUDA >= 12) and the kit of scripts/gpu-prepare.sh (its Kokkos
# source is configured for CUDA, not built: a minute instead of twenty; its
# library prefix gives MPI, HDF5, FFTW, toml++, GoogleTest headers).
# Environment: KIT (default gpu-kit), WORK (default /tmp/softflow-cuda-compile),
# ARCH and SM (the Kokkos architecture and nvcc's, default HOPPER90 and
# sm_90), JOBS (default all cores), UNITS (the units to compile, default
# all: e.g. UNITS="src/solid_phase.cpp tests/test_mthinc.cpp" after a change).
# Exits 1 when a unit fails; its messages are in WORK/obj/<unit>.log.
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$PWD
kit=$(realpath -m "${KIT:-gpu-kit}")
work=$(realpath -m "${WORK:-/tmp/softflow-cuda-compile}")
arch=${ARCH:-HOPPER90}
sm=${SM:-sm_90}
jobs=${JOBS:-$(nproc)}
export PATH=$PATH:/usr/local/cuda/bin
command -v nvcc >/dev/null || { echo "cuda-compile-check: no nvcc on PATH" >&2; exit 2; }
ls "$kit"/kokkos-*.tar.gz "$kit"/prefix.tar.gz >/dev/null 2>&1 ||
  { echo "cuda-compile-check: no kit in $kit: run scripts/gpu-prepare.sh first" >&2; exit 2; }

# Kokkos, configured for CUDA (its generated config headers are all a
# compile needs), and the kit's library prefix
rm -rf "$work" && mkdir -p "$work/kokkos" "$work/prefix" "$work/obj"
tar -xzf "$(ls "$kit"/kokkos-*.tar.gz | head -1)" -C "$work/kokkos" --strip-components=1
tar -xzf "$kit/prefix.tar.gz" -C "$work/prefix"
K=$work/kokkos B=$work/kokkos-build P=$work/prefix/usr
cmake -S "$K" -B "$B" -DKokkos_ENABLE_CUDA=ON "-DKokkos_ARCH_$arch=ON" -DCMAKE_CXX_COMPILER="$K/bin/nvcc_wrapper" \
  -DCMAKE_CXX_STANDARD=20 -DCMAKE_CXX_EXTENSIONS=OFF -DBUILD_TESTING=OFF -DCMAKE_BUILD_TYPE=Release \
  > "$work/kokkos-configure.log" 2>&1 || { tail -30 "$work/kokkos-configure.log"; exit 2; }
inc=(-I"$K/core/src" -I"$B" -I"$B/core/src" -I"$K/containers/src" -I"$K/algorithms/src" -I"$K/simd/src"
     -I"$B/simd/src" -I"$K/tpls/desul/include" -I"$B/tpls/desul/include" -I"$K/tpls/mdspan/include"
     -I"$P/lib/x86_64-linux-gnu/openmpi/include" -I"$P/include/hdf5/openmpi" -I"$P/include"
     -I"$repo/src" -I"$repo/tests" -I"$repo/perf")
flags=(-std=c++20 -O1 "-arch=$sm" --extended-lambda --expt-relaxed-constexpr
       "-DSOFTFLOW_SOURCE_DIR=\"$repo\"")
# config.cpp and the FFTW back end are host-only in the CUDA build (CMakeLists.txt)
units=${UNITS:-$(ls src/*.cpp tests/*.cpp perf/*.cpp | grep -v -e '^src/config.cpp$' -e '^src/fft_fftw.cpp$')}
export K_NVCC="$K/bin/nvcc_wrapper" WORKOBJ="$work/obj"
printf '%s\n' $units | xargs -P "$jobs" -I{} bash -c '
  u={}; o=$WORKOBJ/$(echo "$u" | tr / _)
  if "$K_NVCC" "$@" -c "$u" -o "$o.o" > "$o.log" 2>&1; then echo "ok   $u"; else echo "FAIL $u ($o.log)"; fi
' _ "${flags[@]}" "${inc[@]}" | sort | tee "$work/summary.txt"
n=$(wc -l < "$work/summary.txt")
bad=$(grep -c '^FAIL' "$work/summary.txt" || true)
echo "cuda-compile-check: $((n - bad)) of $n compiled (nvcc $(nvcc --version | grep -o 'release [0-9.]*' | cut -d' ' -f2), $sm)"
[ "$bad" = 0 ]
