#!/usr/bin/env bash
# GPU acceptance in one command. On a machine with one NVIDIA GPU, its
# driver, nvcc, a C/C++ compiler, CMake and python3 (no internet, no MPI,
# HDF5 or FFTW; root or not), from the kit that scripts/gpu-prepare.sh made
# on a CPU machine (gpu-kit/):
#   1. unpacks the kit's library prefix (Open MPI, parallel HDF5, FFTW, ...)
#   2. builds Kokkos from the kit's source (CUDA, Hopper90 unless ARCH says)
#   3. builds softflow (library, softflow, softflow_tests, softflow-perf)
#   4. runs the test suite (ctest)
#   5. runs the perf harness on the three perf scenes (64x40x64) and on the
#      dilute and dense reference cases at 8 points per radius (128x80x128)
#      and writes the JSON, report.md and this log to perf/results/<class>/
# printing each step with a timestamp. Meant to fit in 10 minutes on a
# 16-core GPU machine.
#
#   scripts/gpu-check.sh                      # CUDA, class CUDA-<GPU name>, e.g. CUDA-H200
#   BACKEND=openmp scripts/gpu-check.sh       # the same on the CPU with an OpenMP Kokkos (rehearsal)
#
# Environment: BACKEND (cuda | openmp), ARCH (Kokkos architecture for CUDA,
# default HOPPER90), KIT (default gpu-kit), WORK (build folder, default
# /tmp/softflow-gpu-check), JOBS (build and test parallelism, default all
# cores), CLASS (machine class; default CUDA-<GPU> or rehearsal-OpenMP-<threads>),
# PHASES (default "kokkos build test harness"; a phase whose output is in
# WORK from an earlier call may be left out), WARMUP/STEPS/REPS (harness,
# default 3/5/5), GRID (the three scenes, default 64x40x64), GRID8 (the
# 8-ppr runs, default 128x80x128), COPY_TO (also copy the results there;
# default $OUT when that is a folder, as on the workplace's device machine).
set -uo pipefail
cd "$(dirname "$0")/.."
repo=$PWD
backend=${BACKEND:-cuda}
kit=$(realpath -m "${KIT:-$repo/gpu-kit}")
work=$(realpath -m "${WORK:-/tmp/softflow-gpu-check}")
jobs=${JOBS:-$(nproc)}
phases=" ${PHASES:-kokkos build test harness} "
t0=$(date +%s)
mkdir -p "$work"
logfile=$work/gpu-check.log
exec > >(tee "$logfile") 2>&1
log() { printf '[gpu-check %s +%4ds] %s\n' "$(date +%T)" $(( $(date +%s) - t0 )) "$*"; }
die() { log "FAILED: $*"; exit 1; }
declare -A took=()
phase_start() { log "== $1"; ps=$(date +%s); }
phase_end() { took[$1]=$(( $(date +%s) - ps )); log "== $1 done in ${took[$1]} s"; }

case $backend in
  cuda|openmp) ;;
  *) die "BACKEND must be cuda or openmp, not '$backend'" ;;
esac
log "softflow GPU check: backend $backend, kit $kit, work $work, $jobs jobs"
log "repository $repo, commit $(git -C "$repo" describe --always --dirty --tags 2>/dev/null || echo 'unknown (no git)')"

# ------------------------------------------------------------ what the machine has
if [ $backend = cuda ]; then
  command -v nvcc >/dev/null || { [ -x /usr/local/cuda/bin/nvcc ] && export PATH=/usr/local/cuda/bin:$PATH; }
  command -v nvcc >/dev/null || die "no nvcc on PATH or in /usr/local/cuda/bin"
  command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader |
    sed 's/^/  GPU: /'
fi
export PATH=$PATH:/usr/sbin:/sbin  # ldconfig
for t in cmake python3 tar gzip ldconfig; do
  command -v $t >/dev/null || die "no $t on PATH"
done
cxx=$(command -v g++ || command -v c++) || die "no C++ compiler (g++ or c++) on PATH"
command -v gcc >/dev/null || command -v cc >/dev/null || die "no C compiler (gcc or cc) on PATH"
gen=(-G Ninja)
command -v ninja >/dev/null || { command -v make >/dev/null && gen=(-G "Unix Makefiles"); } || die "neither ninja nor make"
glibc=$(ldd --version 2>/dev/null | head -1 | grep -o '[0-9]*\.[0-9]*$')
log "cmake $(cmake --version | head -1 | cut -d' ' -f3), $("$cxx" --version | head -1), glibc $glibc, generator ${gen[1]}$([ $backend = cuda ] && echo ", nvcc $(nvcc --version | grep -o 'release [0-9.]*' | cut -d' ' -f2)")"
[ "$(printf '%s\n' 2.36 "$glibc" | sort -V | head -1)" = 2.36 ] || die "the kit's Debian 12 libraries need glibc >= 2.36 (have $glibc)"
ls "$kit"/kokkos-*.tar.gz "$kit"/prefix.tar.gz >/dev/null 2>&1 || die "no kit in $kit: run scripts/gpu-prepare.sh on a CPU machine first"

# ------------------------------------------------------------ the library prefix
pfx=$work/prefix
stamp=$(sha256sum "$kit/prefix.tar.gz" | cut -c1-16)
if [ "$(cat "$pfx/.stamp" 2>/dev/null)" != "$stamp" ]; then
  log "unpacking the library prefix into $pfx"
  rm -rf "$pfx" && mkdir -p "$pfx" && tar -xzf "$kit/prefix.tar.gz" -C "$pfx" || die "unpacking prefix.tar.gz"
  grep -rlI --null '@SOFTFLOW_KIT@' "$pfx" | xargs -0 -r sed -i "s|@SOFTFLOW_KIT@|$pfx|g"
  # general-purpose libraries the machine already has (zlib, OpenSSL, curl,
  # libgomp...) are taken from the machine, so that its own programs (cmake,
  # python3) never load the kit's older copies through LD_LIBRARY_PATH
  lib=$pfx/usr/lib/x86_64-linux-gnu
  sys=$(ldconfig -p | awk '{print $1}' | sort -u)
  for f in "$lib"/lib*.so.*; do
    so=$(basename "$f" | sed 's/\(\.so\.[0-9]*\).*/\1/')
    case $so in libmpi*|libopen-*|libompi*|libmca_*|libpmix*|libhwloc*|libevent*|libhdf5*|libfftw3*|libtomlplusplus*|libsz*|libaec*|libmunge*|libpkgconf*) continue ;; esac
    grep -qxF "$so" <<<"$sys" && rm -f "$f"
  done
  echo "$stamp" > "$pfx/.stamp"
fi
P=$pfx/usr
L=$P/lib/x86_64-linux-gnu
export PATH=$P/bin:$PATH
export LD_LIBRARY_PATH=$L:$L/openmpi/lib:$L/hdf5/openmpi${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
export PKG_CONFIG=$P/bin/pkgconf
export PKG_CONFIG_LIBDIR=$L/pkgconfig:$P/share/pkgconfig:$L/openmpi/lib/pkgconfig
# Open MPI and PMIx from a moved prefix; one node: shared memory only;
# root allowed; no ssh (everything runs locally); more ranks than cores
export OPAL_PREFIX=$P PMIX_INSTALL_PREFIX=$L/pmix2
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_plm_rsh_agent= OMPI_MCA_btl=self,vader OMPI_MCA_pml=ob1 OMPI_MCA_mtl='^ofi,psm,psm2'
export OMPI_MCA_btl_vader_single_copy_mechanism=none OMPI_MCA_rmaps_base_oversubscribe=1
export OMPI_MCA_orte_tmpdir_base=/tmp OMP_PROC_BIND=false
mpiexec --version 2>&1 | head -1 | sed 's/^/  /' || die "the kit's mpiexec does not run"

# ------------------------------------------------------------ Kokkos
kroot=$work/kokkos-$backend
if [[ $phases == *" kokkos "* ]]; then
  phase_start kokkos
  tarball=$(ls "$kit"/kokkos-*.tar.gz | head -1)
  rm -rf "$work/kokkos-src" "$work/kokkos-build-$backend" "$kroot"
  mkdir -p "$work/kokkos-src" && tar -xzf "$tarball" -C "$work/kokkos-src" --strip-components=1 || die "unpacking $tarball"
  kopts=(-DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX="$kroot" -DCMAKE_CXX_STANDARD=20
         -DCMAKE_CXX_EXTENSIONS=OFF -DBUILD_TESTING=OFF)
  if [ $backend = cuda ]; then
    kopts+=(-DKokkos_ENABLE_CUDA=ON "-DKokkos_ARCH_${ARCH:-HOPPER90}=ON"
            -DCMAKE_CXX_COMPILER="$work/kokkos-src/bin/nvcc_wrapper")
  else
    kopts+=(-DKokkos_ENABLE_OPENMP=ON -DCMAKE_CXX_COMPILER="$cxx")
  fi
  log "Kokkos $(basename "$tarball" .tar.gz): cmake ${kopts[*]}"
  cmake -S "$work/kokkos-src" -B "$work/kokkos-build-$backend" "${gen[@]}" "${kopts[@]}" > "$work/kokkos-configure.log" 2>&1 ||
    { tail -40 "$work/kokkos-configure.log"; die "configuring Kokkos ($work/kokkos-configure.log)"; }
  cmake --build "$work/kokkos-build-$backend" -j "$jobs" > "$work/kokkos-build.log" 2>&1 ||
    { grep -m 20 -B2 -A8 'error' "$work/kokkos-build.log"; die "building Kokkos ($work/kokkos-build.log)"; }
  cmake --install "$work/kokkos-build-$backend" > /dev/null || die "installing Kokkos"
  phase_end kokkos
fi
[ -f "$kroot/lib/cmake/Kokkos/KokkosConfig.cmake" ] || [ -f "$kroot/lib64/cmake/Kokkos/KokkosConfig.cmake" ] ||
  die "no Kokkos in $kroot (the kokkos phase makes it)"

# ------------------------------------------------------------ softflow
build=$work/build-$backend
if [[ $phases == *" build "* ]]; then
  phase_start build
  sopts=(-DCMAKE_BUILD_TYPE=Release -DKokkos_ROOT="$kroot" "-DCMAKE_PREFIX_PATH=$P;$L/cmake"
         -DMPI_C_COMPILER="$P/bin/mpicc" -DMPIEXEC_EXECUTABLE="$P/bin/mpiexec"
         -DHDF5_C_COMPILER_EXECUTABLE="$P/bin/h5pcc")
  # (Open MPI 4's C++ bindings, which the kit leaves out, are kept out of the
  # build by softflow's CMakeLists: OMPI_SKIP_MPICXX)
  [ $backend = cuda ] && sopts+=(-DCMAKE_CXX_COMPILER="$kroot/bin/nvcc_wrapper")
  log "softflow: cmake ${sopts[*]}"
  rm -f "$build/CMakeCache.txt"  # configure afresh (objects already built stay valid)
  cmake -S "$repo" -B "$build" "${gen[@]}" "${sopts[@]}" > "$work/softflow-configure.log" 2>&1 ||
    { tail -40 "$work/softflow-configure.log"; die "configuring softflow ($work/softflow-configure.log)"; }
  grep -E 'Kokkos [0-9]|Found (MPI|HDF5|GTest|CUDAToolkit)|FFTW|fftw3' "$work/softflow-configure.log" | sed 's/^/  /'
  cmake --build "$build" -j "$jobs" --target softflow softflow_tests softflow-perf > "$work/softflow-build.log" 2>&1 ||
    { grep -m 20 -B2 -A8 'error' "$work/softflow-build.log"; die "building softflow ($work/softflow-build.log)"; }
  nwarn=$(grep -c 'warning' "$work/softflow-build.log")
  log "built softflow, softflow_tests, softflow-perf ($nwarn lines with 'warning' in $work/softflow-build.log)"
  phase_end build
fi
[ -x "$build/perf/softflow-perf" ] || die "no $build/perf/softflow-perf (the build phase makes it)"

# ------------------------------------------------------------ tests
status=0
if [[ $phases == *" test "* ]]; then
  phase_start test
  (cd "$build" && ctest --output-on-failure -j "$jobs" --timeout 900) > "$work/ctest.log" 2>&1
  rc=$?
  grep -E '^ *[0-9]+/[0-9]+ Test|tests passed|tests failed|\(Failed\)|\(Timeout\)' "$work/ctest.log" | tail -n 60
  phase_end test
  if [ $rc != 0 ]; then
    sed -n '/The following tests FAILED/,$p' "$work/ctest.log"
    log "TESTS FAILED ($work/ctest.log); the harness runs all the same"
    status=1
  fi
fi

# ------------------------------------------------------------ harness
if [[ $phases == *" harness "* ]]; then
  phase_start harness
  if [ -n "${CLASS:-}" ]; then
    class=$CLASS
  elif [ $backend = cuda ]; then
    gpu=$(nvidia-smi --query-gpu=name --format=csv,noheader 2>/dev/null | head -1 | sed 's/^NVIDIA //; s/ .*//')
    class=CUDA-${gpu:-GPU}
  else
    class=rehearsal-OpenMP-$(nproc)
  fi
  out=$repo/perf/results/$class
  mkdir -p "$out"
  [ $backend = openmp ] && export OMP_NUM_THREADS=${OMP_NUM_THREADS:-$(nproc)}
  IFS=x read -r nx ny nz <<< "${GRID:-64x40x64}"
  IFS=x read -r mx my mz <<< "${GRID8:-128x80x128}"
  runs=("single cases/couette.toml $nx $ny $nz"            # fluid only, explicit (as CaNS)
        "particle cases/phi0016_ca02.toml $nx $ny $nz"     # one sphere, Ca = 0.2, implicit
        "dense cases/phi011_ca02.toml $nx $ny $nz"         # Phi = 0.11, Ca = 0.2, implicit
        "dilute-8ppr cases/phi0016_ca02.toml $mx $my $mz"  # the dilute reference case at 8 ppr
        "dense-8ppr cases/phi011_ca02.toml $mx $my $mz")   # the dense reference case at 8 ppr
  for r in "${runs[@]}"; do
    read -r name case gx gy gz <<< "$r"
    log "harness: $name ($case, ${gx}x${gy}x${gz})"
    # the dense scenes keep the CPU baselines' placement (independent draws, min_gap alone)
    pin=()
    case $name in dense*) pin=(--set 'particles.placement="random"' --set particles.min_gap_cells=0) ;; esac
    "$build/perf/softflow-perf" "$case" "${pin[@]}" --set grid.nx="$gx" --set grid.ny="$gy" --set grid.nz="$gz" \
      --warmup "${WARMUP:-3}" --steps "${STEPS:-5}" --reps "${REPS:-5}" --machine-class "$class" \
      --json "$out/$name.json" > "$work/harness-$name.log" 2>&1 ||
      { tail -20 "$work/harness-$name.log"; log "harness $name FAILED ($work/harness-$name.log)"; status=1; continue; }
    python3 - "$out/$name.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
s = j["step"]
print(f"  {j['backend']} x {j['concurrency']}: step {s['seconds']['median'] * 1e3:.2f} ms median, "
      f"{s['cell_steps_per_second']['median'] / 1e6:.1f} M cell-steps/s, "
      f"triad {j['stream']['triad_bytes_per_second_per_rank']['median'] / 1e9:.0f} GB/s, "
      f"host-device copies per step {j['cross_space_copies_per_step']}")
PY
  done
  ls "$out"/*.json >/dev/null 2>&1 && python3 perf/report.py "$out"/*.json > "$out/report.md"
  phase_end harness
fi

# ------------------------------------------------------------ summary
total=$(( $(date +%s) - t0 ))
summary="phases (s):"
for p in kokkos build test harness; do [ -n "${took[$p]:-}" ] && summary+=" $p ${took[$p]}"; done
log "$summary; total $total s$([ $backend = cuda ] && [ $total -gt 600 ] && echo ' (OVER the 10-minute budget)')"
copy=${COPY_TO:-${OUT:-}}
[ -n "${out:-}" ] || copy=
[ -n "$copy" ] && { [ ! -d "$copy" ] || [ "$(realpath "$copy")" = "$(realpath "$out")" ]; } && copy=
[ -n "${out:-}" ] && log "results and this log in ${out#"$repo"/}${copy:+, copied to $copy}"
[ $status = 0 ] && log "PASSED" || log "FAILED (see above)"
if [ -n "${out:-}" ]; then
  sleep 1  # let tee write the last lines
  cp "$logfile" "$out/gpu-check.log"
  # the workplace's device machine returns at most 8 files from $OUT
  [ -n "$copy" ] && cp "$out"/*.json "$out"/report.md "$out"/gpu-check.log "$work"/ctest.log "$copy"/ 2>/dev/null
fi
exit $status
