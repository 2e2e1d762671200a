#!/usr/bin/env bash
# Provides softflow's dependencies on a Debian 12 machine and runs commands with them.
#
# Why a separate root: Debian 12 has no usable Kokkos (Trilinos' 3.4, Serial
# only). Debian unstable's libkokkos-dev (OpenMP backend) needs glibc >= 2.38,
# so we build a Debian 13 (trixie) root once, in a cache folder outside the
# repository, add unstable's two Kokkos packages to it, and bind-mount the
# repository into it. softflow's CMake does not know about any of this: on a
# machine that has Kokkos, MPI, HDF5 and FFTW, plain cmake works.
#
# Usage (sourced by the other scripts, or run directly):
#   scripts/toolchain.sh setup          build the root if it is missing
#   scripts/toolchain.sh run CMD...     run CMD inside the root, in the repo
# Environment: SOFTFLOW_ROOT (default /var/cache/softflow/trixie-v1).
set -euo pipefail

SOFTFLOW_ROOT=${SOFTFLOW_ROOT:-/var/cache/softflow/trixie-v1}
REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
MIRROR=http://deb.debian.org/debian
PACKAGES=(g++ cmake ninja-build make libopenmpi-dev openmpi-bin libhdf5-openmpi-dev
  hdf5-tools libfftw3-dev libfftw3-mpi-dev libgtest-dev libbenchmark-dev
  libtomlplusplus-dev nlohmann-json3-dev python3-matplotlib python3-h5py python3-numpy
  pkgconf git ca-certificates)
# the version measured to work (glibc and libstdc++ of trixie); if the archive
# no longer serves it, whatever unstable has now is taken instead
KOKKOS_VERSION=5.2.2-2
KOKKOS_DEBS=(libkokkos5.2 libkokkos-dev)

log() { echo "[toolchain] $*" >&2; }

need_root_user() {
  if [ "$(id -u)" != 0 ]; then
    log "this script needs root (debootstrap, chroot, mount); run it with sudo"
    exit 1
  fi
}

# /proc, /sys and /dev inside the root (hwloc and Open MPI need them)
mount_system() {
  local r=$SOFTFLOW_ROOT
  for d in proc sys dev; do
    mkdir -p "$r/$d"
    mountpoint -q "$r/$d" || mount --rbind "/$d" "$r/$d"
  done
}

# The host folders a user's paths can lie in: every top-level folder that is
# not part of the operating system. Inside the root they appear at the same
# absolute paths, so a case file, --out or --restart given as /tmp/x, ~/x or
# relative to the caller's folder means the same file inside as outside.
# The OS folders (/usr, /etc, /var, ...) are the root's own.
SYSTEM_DIRS=" bin boot dev etc lib lib32 lib64 libx32 lost+found proc run sbin sys usr var "
user_dirs() {
  local d
  for d in /*/; do
    d=${d%/}
    [ -L "$d" ] && continue
    case "$SYSTEM_DIRS" in *" ${d#/} "*) continue ;; esac
    echo "$d"
  done
}

# Runs CMD inside the root, in a private mount namespace of its own: the
# bind mounts exist for this invocation only, so any number of invocations
# from any number of clones run side by side without seeing each other's
# mounts (the old scheme rebound one shared /src to the newest caller and
# broke the runs in flight). The repository is at /src and at its own path;
# the command starts in the caller's folder when the root can see it, else
# in /src.
in_root() {
  local r=$SOFTFLOW_ROOT here
  here=$(pwd -P)
  # shellcheck disable=SC2016
  unshare --mount --propagation private -- /bin/bash -c '
    set -e
    r=$1 repo=$2 here=$3; shift 3
    for d in proc sys dev; do mkdir -p "$r/$d"; mount --rbind "/$d" "$r/$d"; done
    while read -r d; do
      [ -d "$d" ] || continue
      mkdir -p "$r$d" 2>/dev/null || continue
      mount --rbind "$d" "$r$d"
    done < <(printf "%s
" $SOFTFLOW_USER_DIRS)
    mkdir -p "$r/src"
    mount --bind "$repo" "$r/src"
    [ -d "$r$here" ] && [ "$(stat -c %d:%i "$r$here" 2>/dev/null)" = "$(stat -c %d:%i "$here")" ] || here=/src
    exec chroot "$r" /usr/bin/env -i HOME=/root PATH=/usr/local/bin:/usr/bin:/bin \
      LANG=C.UTF-8 TERM="${TERM:-dumb}" CI="${CI:-}" \
      OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 \
      OMPI_MCA_rmaps_base_oversubscribe=1 OMPI_MCA_btl=self,sm \
      OMP_PROC_BIND=false OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}" \
      SOFTFLOW_BUILD="${SOFTFLOW_BUILD:-build}" SOFTFLOW_REPO="$repo" \
      /bin/bash -c '"'"'cd "$0" && "$@"'"'"' "$here" "$@"' \
    bash "$r" "$REPO" "$here" "$@"
}

setup_root() {
  local r=$SOFTFLOW_ROOT
  # the stamp names the package set, so adding a package re-runs only apt
  local stamp="$r/.softflow-ready-$(echo "${PACKAGES[*]} ${KOKKOS_DEBS[*]} $KOKKOS_VERSION" | md5sum | cut -c1-12)"
  if [ -f "$stamp" ]; then
    log "using the root at $r"
    return
  fi
  need_root_user
  if [ ! -f "$r/.softflow-base" ]; then
    command -v debootstrap >/dev/null || {
      log "installing debootstrap"
      apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq debootstrap >/dev/null
    }
    log "creating a Debian 13 root at $r (about 1 minute)"
    rm -rf "$r"
    mkdir -p "$r"
    debootstrap --variant=minbase trixie "$r" "$MIRROR" >/dev/null
    echo "deb $MIRROR trixie main" >"$r/etc/apt/sources.list"
    touch "$r/.softflow-base"
  fi
  mount_system
  log "installing compilers and libraries in the root (about 2 minutes)"
  chroot "$r" /bin/bash -c "apt-get update -qq && DEBIAN_FRONTEND=noninteractive \
    apt-get install -y -qq --no-install-recommends ${PACKAGES[*]} >/dev/null"
  log "adding Kokkos (OpenMP) from Debian unstable"
  chroot "$r" /bin/bash -c "set -e
    mkdir -p /tmp/sid/lists/partial /tmp/sid/debs
    echo 'deb $MIRROR unstable main' >/tmp/sid/sources.list
    o='-o Dir::Etc::SourceList=/tmp/sid/sources.list -o Dir::Etc::SourceParts=- \
       -o Dir::State::Lists=/tmp/sid/lists -o Acquire::Check-Valid-Until=false \
       -o APT::Sandbox::User=root'
    apt-get \$o update -qq
    cd /tmp/sid/debs
    apt-get \$o download ${KOKKOS_DEBS[*]/%/=$KOKKOS_VERSION} >/dev/null 2>&1 ||
      { rm -f ./*.deb; apt-get \$o download ${KOKKOS_DEBS[*]} >/dev/null; }
    dpkg --force-depends -i /tmp/sid/debs/*.deb >/dev/null
    rm -rf /tmp/sid"
  # Packaging bug in libkokkos-dev 5.2.2: its CMake export names two archives
  # the package does not ship. Empty archives satisfy find_package(Kokkos).
  chroot "$r" /bin/bash -c 'rm -f /libkokkosalgorithms.a /libkokkossimd.a
    for f in $(grep -ho "/[^\"]*libkokkos\(algorithms\|simd\)\.a" /usr/lib/*/cmake/Kokkos/*.cmake | sort -u); do
      [ -e "$f" ] || ar rcs "$f"; done'
  chroot "$r" /bin/bash -c 'apt-get clean'
  rm -f "$r"/.softflow-ready*
  touch "$stamp"
  log "root ready"
}

case "${1:-}" in
  setup) setup_root ;;
  run)
    shift
    setup_root
    SOFTFLOW_USER_DIRS=$(user_dirs)
    export SOFTFLOW_USER_DIRS
    in_root "$@"
    ;;
  *) echo "usage: $0 setup | run CMD..." >&2; exit 2 ;;
esac
