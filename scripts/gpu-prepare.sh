#!/usr/bin/env bash
# Prepares, on a CPU machine with Debian 12's package mirror, everything
# scripts/gpu-check.sh needs that is not in this repository, into ONE
# git-ignored folder (gpu-kit/, under 60 MiB), so that a GPU machine with a
# driver, nvcc and a compiler but no internet can build and run softflow:
#
#   gpu-kit/kokkos-<version>.tar.gz   Kokkos source, trimmed (no tests,
#                                     examples, docs, benchmarks), with the
#                                     CUDA-13 fixes below applied
#   gpu-kit/prefix.tar.gz             Open MPI, parallel HDF5, FFTW (+MPI,
#                                     +OpenMP), toml++, nlohmann-json,
#                                     GoogleTest, pkgconf: Debian 12 .deb
#                                     files unpacked (dpkg -x) and trimmed;
#                                     relocated where gpu-check.sh unpacks it
#   gpu-kit/MANIFEST.txt              what is in it (versions, sizes, sha256)
#
# usage: scripts/gpu-prepare.sh KOKKOS_SOURCE      (or KOKKOS_SOURCE=... scripts/gpu-prepare.sh)
#   KOKKOS_SOURCE: a Kokkos git directory (KOKKOS_REF picks the tag, default
#   4.6.01), a source tree, or a .tar.gz of one. No registry serves Kokkos
#   here; a clone of github.com/kokkos/kokkos does, e.g. the git directory
#   the workplace's fetch tool gives (/work/.mirror/kokkos+kokkos/repo).
# Environment: KIT (default gpu-kit), KOKKOS_REF (4.6.01). Needs root-free
# apt-get download, dpkg-deb, tar, gzip, perl, readelf (binutils).
#
# Nothing third-party is committed: gpu-kit/ is in .gitignore.
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$PWD
src=${1:-${KOKKOS_SOURCE:-}}
ref=${KOKKOS_REF:-4.6.01}
kit=${KIT:-$repo/gpu-kit}
[ -n "$src" ] || { sed -n '2,27p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
log() { printf '[gpu-prepare %s] %s\n' "$(date +%T)" "$*"; }
for t in apt-get dpkg-deb tar gzip perl readelf sha256sum; do
  command -v $t >/dev/null || { echo "gpu-prepare: needs $t" >&2; exit 2; }
done

tmp=$(mktemp -d /tmp/gpu-prepare.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$kit"
rm -f "$kit"/kokkos-*.tar.gz "$kit"/prefix.tar.gz "$kit"/MANIFEST.txt

# ---------------------------------------------------------------- Kokkos
log "Kokkos source from $src"
mkdir "$tmp/k"
if [ -d "$src" ] && git -C "$src" rev-parse --git-dir >/dev/null 2>&1 && git -C "$src" rev-parse -q --verify "$ref^{commit}" >/dev/null; then
  git -C "$src" archive --format=tar "$ref" | tar -x -C "$tmp/k"
  kref="$ref ($(git -C "$src" rev-parse "$ref^{commit}"))"
elif [ -f "$src/CMakeLists.txt" ] && [ -d "$src/core/src" ]; then
  cp -a "$src"/. "$tmp/k/"
  rm -rf "$tmp/k/.git"
  kref="source tree $src"
elif [ -f "$src" ]; then
  tar -xzf "$src" -C "$tmp/k"
  # a tarball with one top folder (as GitHub's): step into it
  if [ ! -f "$tmp/k/CMakeLists.txt" ] && [ "$(ls "$tmp/k" | wc -l)" = 1 ]; then
    d=$(ls "$tmp/k"); mv "$tmp/k/$d" "$tmp/k.in"; rmdir "$tmp/k"; mv "$tmp/k.in" "$tmp/k"
  fi
  kref="tarball $(basename "$src")"
else
  echo "gpu-prepare: '$src' is no Kokkos git directory (with $ref), source tree or tarball" >&2; exit 2
fi
K=$tmp/k
[ -f "$K/core/src/Cuda/Kokkos_Cuda_Instance.hpp" ] || { echo "gpu-prepare: not a Kokkos source: $src" >&2; exit 2; }
kv() { sed -n "s/^set(Kokkos_VERSION_$1 \([0-9]*\))/\1/p" "$K/CMakeLists.txt" | head -1; }
kver="$(kv MAJOR).$(kv MINOR).$(printf %02d "$(kv PATCH)")"
kvnum=$(( $(kv MAJOR) * 10000 + $(kv MINOR) * 100 + $(kv PATCH) ))
[ "$kvnum" -ge 40601 ] || { echo "gpu-prepare: Kokkos $kver is older than 4.6.01" >&2; exit 2; }
log "Kokkos $kver: trimming tests, examples, docs, benchmarks"
rm -rf "$K"/.git* "$K"/.jenkins "$K"/benchmarks "$K"/example "$K"/doc "$K"/scripts \
  "$K"/core/unit_test "$K"/core/perf_test "$K"/containers/unit_tests "$K"/containers/performance_tests \
  "$K"/algorithms/unit_tests "$K"/algorithms/perf_test "$K"/simd/unit_tests "$K"/tpls/gtest
# Kokkos' CMake always enters example/ and benchmarks/: empty stand-ins
for d in example benchmarks; do
  mkdir "$K/$d" && echo "# trimmed by softflow's scripts/gpu-prepare.sh" > "$K/$d/CMakeLists.txt"
done

# The CUDA-13 fixes (shared/notes/TOOLCHAIN.md): CUDA 13 changed
# cudaGraphAddDependencies (edge data), cudaMemAdvise and
# cudaMemPrefetchAsync (a cudaMemLocation), removed cudaMemAdvise_v2, and
# dropped sm_70, nvcc_wrapper's default architecture. Each change is guarded
# by CUDART_VERSION >= 13000, so older CUDA builds as before. Kokkos
# releases that already carry the guards are left alone.
fix() {  # fix FILE PERL-SUBSTITUTION WHAT: apply once, fail if it did not match
  local f=$K/$1
  perl -0pi -e "\$n = ($2); END { \$? = \$n ? 0 : 1 }" "$f" || { echo "gpu-prepare: CUDA-13 fix '$3' does not apply to $1" >&2; exit 1; }
}
inst=core/src/Cuda/Kokkos_Cuda_Instance.hpp
if grep -q 'CUDART_VERSION >= 13000' "$K/$inst"; then
  log "Kokkos $kver already has the CUDA-13 guards"
else
  log "applying the CUDA-13 fixes"
  fix $inst 's{\n(\s*)return cudaGraphAddDependencies\(graph, from, to, numDependencies\);}{
#if CUDART_VERSION >= 13000
$1return cudaGraphAddDependencies(graph, from, to, nullptr, numDependencies);
#else
$1return cudaGraphAddDependencies(graph, from, to, numDependencies);
#endif}' cudaGraphAddDependencies
  fix $inst 's{\n(\s*)return cudaMemAdvise\(devPtr, count, advice, device\);}{
#if CUDART_VERSION >= 13000
$1cudaMemLocation loc;
$1loc.id   = device;
$1loc.type = device == cudaCpuDeviceId ? cudaMemLocationTypeHost : cudaMemLocationTypeDevice;
$1return cudaMemAdvise(devPtr, count, advice, loc);
#else
$1return cudaMemAdvise(devPtr, count, advice, device);
#endif}' cudaMemAdvise
  fix $inst 's{\n(\s*)return cudaMemPrefetchAsync\(devPtr, count, dstDevice,\s*get_input_stream\(stream\)\);}{
#if CUDART_VERSION >= 13000
$1cudaMemLocation loc;
$1loc.id   = dstDevice;
$1loc.type = dstDevice == cudaCpuDeviceId ? cudaMemLocationTypeHost : cudaMemLocationTypeDevice;
$1return cudaMemPrefetchAsync(devPtr, count, loc, 0, get_input_stream(stream));
#else
$1return cudaMemPrefetchAsync(devPtr, count, dstDevice, get_input_stream(stream));
#endif}' cudaMemPrefetchAsync
  fix core/src/Cuda/Kokkos_CudaSpace.cpp 's{\n(\s*)KOKKOS_IMPL_CUDA_SAFE_CALL\(cudaMemAdvise_v2\(\s*ptr, arg_alloc_size, cudaMemAdviseSetPreferredLocation, loc\)\);}{
#if CUDART_VERSION >= 13000
$1KOKKOS_IMPL_CUDA_SAFE_CALL(cudaMemAdvise(
$1    ptr, arg_alloc_size, cudaMemAdviseSetPreferredLocation, loc));
#else
$1KOKKOS_IMPL_CUDA_SAFE_CALL(cudaMemAdvise_v2(
$1    ptr, arg_alloc_size, cudaMemAdviseSetPreferredLocation, loc));
#endif}' cudaMemAdvise_v2
fi
if grep -q '^default_arch="sm_70"' "$K/bin/nvcc_wrapper"; then
  fix bin/nvcc_wrapper 's{^default_arch="sm_70"}{default_arch="sm_90"}m' "nvcc_wrapper default_arch"
fi
tar -C "$tmp" --transform "s,^k,kokkos-$kver," -czf "$kit/kokkos-$kver.tar.gz" k

# ---------------------------------------------------------------- Debian prefix
# Hand-picked: the libraries softflow links, their runtime libraries, and
# Open MPI's launcher. Not the Fortran, C++ or high-level HDF5 bindings, not
# Open MPI's InfiniBand/UCX/OFI transports (one node: shared memory only),
# not the compilers (the GPU machine's g++ is the host compiler).
pkgs=(
  openmpi-bin openmpi-common libopenmpi3 libopenmpi-dev
  libevent-core-2.1-7 libevent-pthreads-2.1-7 libhwloc15 libpmix2 libmunge2 libudev1 zlib1g
  libhdf5-openmpi-103-1 libhdf5-openmpi-dev libsz2 libaec0
  libcurl4 libbrotli1 libgssapi-krb5-2 libkrb5-3 libk5crypto3 libkrb5support0 libkeyutils1 libcom-err2
  libidn2-0 libunistring2 libldap-2.5-0 libsasl2-2 libsasl2-modules-db libdb5.3 libnghttp2-14 libpsl5
  librtmp1 libgnutls30 libhogweed6 libnettle8 libgmp10 libp11-kit0 libffi8 libtasn1-6 libssh2-1 libssl3
  libzstd1 libcrypt1
  libfftw3-dev libfftw3-double3 libfftw3-mpi3 libfftw3-mpi-dev libgomp1
  libtomlplusplus-dev libtomlplusplus3 nlohmann-json3-dev libgtest-dev
  pkgconf pkgconf-bin libpkgconf3
)
log "downloading ${#pkgs[@]} Debian packages"
mkdir -p "$tmp/debs" "$tmp/p"
(cd "$tmp/debs" && apt-get download -q "${pkgs[@]}" 2>&1 | grep -v '^W: Download is performed unsandboxed' | tail -n 3) || true
n=$(ls "$tmp/debs"/*.deb | wc -l)
[ "$n" = "${#pkgs[@]}" ] || { echo "gpu-prepare: downloaded $n of ${#pkgs[@]} packages (apt-get update?)" >&2; exit 1; }
debsize=$(du -sb "$tmp/debs" | cut -f1)
for d in "$tmp/debs"/*.deb; do dpkg-deb -x "$d" "$tmp/p"; done
P=$tmp/p
L=$P/usr/lib/x86_64-linux-gnu
log "trimming the prefix ($(du -sm "$P" | cut -f1) MiB unpacked)"
rm -rf "$P"/usr/share/{doc,man,info,lintian,bug,javascript} "$P"/etc "$P"/lib/udev "$P"/usr/lib/systemd \
  "$P"/usr/lib/*/openmpi/lib/*.mod "$P"/usr/include/*/openmpi/*.mod
# static archives, except GoogleTest's (the only form Debian ships)
find "$P" -name '*.a' ! -name 'libgtest.a' ! -name 'libgtest_main.a' -delete
find "$P" -name '*.la' -delete
# Fortran MPI, the long/single/quad FFTW variants, the HDF5 bindings softflow does not use, gmock
rm -f "$L"/openmpi/lib/libmpi_mpifh* "$L"/openmpi/lib/libmpi_usempi* "$L"/openmpi/lib/libmpi_java* \
  "$L"/openmpi/lib/libompitrace* "$L"/openmpi/lib/libmpi_cxx* "$L"/libmpi_cxx* \
  "$L"/libfftw3[flq]* "$L"/libfftw3_mpi*[flq]_* "$L"/libhdf5_openmpi_{fortran,hl,cpp,hl_cpp,hlfortran}* \
  "$L"/hdf5/openmpi/lib*{fortran,_hl,_cpp}* "$L"/libgmock*
rm -rf "$P"/usr/include/gmock "$P"/usr/lib/*/cmake/GTest/*gmock* 2>/dev/null || true
# Debian's alternatives links (dpkg -x skips them): mpirun, mpiexec, mpicc, h5pcc
for t in mpirun mpiexec mpicc; do ln -sf $t.openmpi "$P/usr/bin/$t"; done
ln -sf h5pcc.openmpi "$P/usr/bin/h5pcc"
ln -sf pkgconf "$P/usr/bin/pkg-config"
# keep only the programs the build and the runs use
for f in "$P"/usr/bin/*; do
  case $(basename "$f") in
    mpirun|mpiexec|mpicc|*.openmpi|orterun|orted|opal_wrapper|ompi_info|h5pcc|pkgconf|pkg-config) ;;
    *) rm -f "$f" ;;
  esac
done
# Debian 12's toml++ 3.3 has toml++/toml.h but no toml++/toml.hpp (softflow's include)
[ -e "$P/usr/include/toml++/toml.hpp" ] || echo '#include <toml++/toml.h>' > "$P/usr/include/toml++/toml.hpp"

# Every ELF file's needed libraries must be in the prefix or the C/C++
# runtime any machine with a compiler has; Open MPI plug-ins that need what
# is left out (InfiniBand, UCX, OFI, PSM, X11, CUDA) are removed.
base='^(libc|libm|libdl|libpthread|librt|libresolv|libutil|libstdc\+\+|libgcc_s|ld-linux-x86-64)\.so'
have() { [ -n "$(find "$P" -name "$1" -print -quit)" ]; }
changed=1
while [ $changed = 1 ]; do
  changed=0
  while IFS= read -r -d '' f; do
    file_is_elf=$(head -c 4 "$f" | od -An -c | tr -d ' ')
    [ "$file_is_elf" = '177ELF' ] || continue
    for lib in $(readelf -d "$f" 2>/dev/null | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p'); do
      [[ $lib =~ $base ]] && continue
      have "$lib" && continue
      case $f in
        */openmpi/*/mca_*|*/libmca_common_*|*/pmix/mca_*|*/hwloc/hwloc_*) rm -f "$f"; changed=1; break ;;
        *) echo "gpu-prepare: $f needs $lib, which the prefix lacks" >&2; exit 1 ;;
      esac
    done
  done < <(find "$P" -type f -print0)
done
# links whose target is gone
find "$P" -xtype l -delete
find "$P" -type d -empty -delete

# Relocation: text files that name /usr get a placeholder that
# gpu-check.sh replaces with the folder it unpacks the prefix in.
grep -rlI --null -e '/usr' "$P/usr/bin" "$P/usr/lib" "$P/usr/share" 2>/dev/null | while IFS= read -r -d '' f; do
  case $f in *.pc|*.cmake|*/h5pcc.openmpi|*-wrapper-data.txt|*/pkgconf-personality*) ;; *) continue ;; esac
  # keep interpreter lines (#!/usr/bin/env, #!/bin/sh) as they are
  perl -pi -e 'next if $. == 1 && /^#!/; s{(?:(?<=^)|(?<=[\s"\x27=(;:,])|(?<=-I)|(?<=-L))/usr(?=/|\b)}{\@SOFTFLOW_KIT\@/usr}g' "$f"
done
# h5pcc (CMake's FindHDF5 asks it) links the static libhdf5 and libhdf5_hl,
# plus -lcrypto -lcurl -lsz -lz, none of which the prefix has: make it link
# the shared libhdf5 alone, which names its own dependencies
perl -pi -e 's/^H5BLD_LIBS=.*/H5BLD_LIBS=" "/; s/^STATIC_AVAILABLE=.*/STATIC_AVAILABLE="no"/; s/^HL=.*/HL=""/' \
  "$P/usr/bin/h5pcc.openmpi"
grep -q '^STATIC_AVAILABLE="no"' "$P/usr/bin/h5pcc.openmpi" && grep -q '^HL=""' "$P/usr/bin/h5pcc.openmpi" ||
  { echo "gpu-prepare: h5pcc not as expected" >&2; exit 1; }
tar -C "$P" -czf "$kit/prefix.tar.gz" .

# ---------------------------------------------------------------- manifest
{
  echo "softflow GPU kit, made $(date -u +%FT%TZ) by scripts/gpu-prepare.sh (commit $(git rev-parse --short HEAD 2>/dev/null || echo '?'))"
  echo "Kokkos $kver from $kref, trimmed, CUDA-13 fixes applied"
  echo "Debian $(cat /etc/debian_version) packages ($n, $((debsize / 1048576)) MiB of .deb; prefix $(du -sm "$P" | cut -f1) MiB unpacked):"
  for d in "$tmp/debs"/*.deb; do printf '  %s %s\n' "$(dpkg-deb -f "$d" Package)" "$(dpkg-deb -f "$d" Version)"; done
  echo "files:"
  (cd "$kit" && for f in kokkos-*.tar.gz prefix.tar.gz; do printf '  %s %s bytes sha256 %s\n' "$f" "$(stat -c %s "$f")" "$(sha256sum "$f" | cut -d' ' -f1)"; done)
} > "$kit/MANIFEST.txt"
total=$(du -sm "$kit" | cut -f1)
log "kit ready: $kit ($total MiB): $(cd "$kit" && ls | tr '\n' ' ')"
[ "$total" -lt 60 ] || { echo "gpu-prepare: the kit is $total MiB, over 60 MiB" >&2; exit 1; }
