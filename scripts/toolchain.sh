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
#   scripts/toolchain.sh run CMD...     run CMD inside the root, in the caller's folder
#   scripts/toolchain.sh check PATH...  exit 2 with a message naming the first
#                                       PATH the root cannot see
# Paths: the host's non-system top-level folders (/work, /tmp, /root, /home,
# ...) appear at their own paths inside the root, and this repository also at
# /src. CMD starts in the caller's folder (or its /src twin inside this
# repository); a caller's folder the root cannot see stops the run with a
# message. Inside, SOFTFLOW_REPO is where the repository is and
# SOFTFLOW_SHARED_DIRS lists the shared folders (softflow refuses a case
# file, output folder or checkpoint outside them: it would be the root's own).
# Environment: SOFTFLOW_ROOT (default /var/cache/softflow/trixie-v1).
set -euo pipefail

SOFTFLOW_ROOT=${SOFTFLOW_ROOT:-/var/cache/softflow/trixie-v1}
REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd -P)
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
# The OS folders (/usr, /etc, /var, ...) are the root's own; /src is this
# repository's.
SYSTEM_DIRS=" bin boot dev etc lib lib32 lib64 libx32 lost+found proc run sbin sys usr var src "
user_dirs() {
  local d
  for d in /*/; do
    d=${d%/}
    [ -L "$d" ] && continue
    case "$SYSTEM_DIRS" in *" ${d#/} "*) continue ;; esac
    echo "$d"
  done
}

# Where absolute host path $1 is inside the root: the same path under a
# shared folder, /src/... inside this repository; nothing (status 1) else.
in_root_path() {
  local p=$1 d
  while read -r d; do
    [ -n "$d" ] || continue
    case "$p/" in "$d"/*) echo "$p"; return 0 ;; esac
  done <<<"$SOFTFLOW_USER_DIRS"
  case "$p/" in "$REPO"/*) echo "/src${p#"$REPO"}"; return 0 ;; esac
  return 1
}

# `check PATH...`: each PATH (relative to the caller's folder, or absolute)
# must be visible inside the root
check_paths() {
  local p abs
  for p in "$@"; do
    abs=$(realpath -m -- "$p")
    if ! in_root_path "$abs" >/dev/null; then
      echo "softflow: error: '$p' ($abs) cannot be reached from inside the toolchain root:" \
        "only $(echo $SOFTFLOW_USER_DIRS | sed 's/ /, /g') and this repository are shared;" \
        "use a path under one of them" >&2
      return 2
    fi
  done
}

# Runs CMD inside the root, in a private mount namespace of its own: the
# bind mounts exist for this invocation only, so any number of invocations
# from any number of clones run side by side without seeing each other's
# mounts (the old scheme rebound one shared /src to the newest caller and
# broke the runs in flight). The repository is at /src and at its own path
# (when that lies in a shared folder); the command starts in the caller's
# folder, which the root must be able to see.
in_root() {
  local r=$SOFTFLOW_ROOT here repo_in shared
  here=$(in_root_path "$(pwd -P)") || {
    echo "softflow: error: the current folder '$(pwd -P)' cannot be reached from inside the toolchain" \
      "root: only $(echo $SOFTFLOW_USER_DIRS | sed 's/ /, /g') and this repository are shared;" \
      "run from a folder under one of them" >&2
    return 2
  }
  repo_in=$(in_root_path "$REPO")
  # /proc, /sys and /dev are the host's too (bound below)
  shared=$(echo $SOFTFLOW_USER_DIRS /src /proc /sys /dev | tr ' ' :)
  # shellcheck disable=SC2016
  SOFTFLOW_REPO_IN=$repo_in SOFTFLOW_SHARED_DIRS=$shared unshare --mount --propagation private -- /bin/bash -c '
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
    exec chroot "$r" /usr/bin/env -i HOME=/root PATH=/usr/local/bin:/usr/bin:/bin \
      LANG=C.UTF-8 TERM="${TERM:-dumb}" CI="${CI:-}" \
      OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 \
      OMPI_MCA_rmaps_base_oversubscribe=1 OMPI_MCA_btl=self,sm \
      OMP_PROC_BIND=false OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}" \
      SOFTFLOW_BUILD="${SOFTFLOW_BUILD:-build}" SOFTFLOW_REPO="$SOFTFLOW_REPO_IN" \
      SOFTFLOW_SHARED_DIRS="$SOFTFLOW_SHARED_DIRS" SOFTFLOW_EXE="${SOFTFLOW_EXE:-}" \
      SOFTFLOW_IN_ROOT=1 /bin/bash -c '"'"'cd "$0" && "$@"'"'"' "$here" "$@"' \
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

# Called from inside the root (a script that runs the toolchain's python,
# e.g. `scripts/toolchain.sh run python3 scripts/run-set.py`, calls this
# script again): the root is there already, and a command runs as it is
if [ "${SOFTFLOW_IN_ROOT:-}" = 1 ]; then
  case "${1:-}" in
    setup) exit 0 ;;
    run) shift; exec "$@" ;;
    check)
      # a path is reachable when it lies in one of the shared folders
      shift
      for p in "$@"; do
        abs=$(realpath -m -- "$p") ok=no
        IFS=: read -ra dirs <<<"${SOFTFLOW_SHARED_DIRS:-}"
        for d in "${dirs[@]}"; do case "$abs/" in "$d"/*) ok=yes ;; esac; done
        [ $ok = yes ] || { echo "softflow: error: '$p' ($abs) is not in a shared folder (${SOFTFLOW_SHARED_DIRS:-})" >&2; exit 2; }
      done
      exit 0
      ;;
  esac
fi

case "${1:-}" in
  setup) setup_root ;;
  run)
    shift
    setup_root
    SOFTFLOW_USER_DIRS=$(user_dirs)
    export SOFTFLOW_USER_DIRS
    in_root "$@"
    ;;
  check)
    shift
    SOFTFLOW_USER_DIRS=$(user_dirs)
    check_paths "$@"
    ;;
  *) echo "usage: $0 setup | run CMD... | check PATH..." >&2; exit 2 ;;
esac
