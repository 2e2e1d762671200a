#!/usr/bin/env bash
# Builds softflow if needed and runs one case. Works on a fresh Debian 12
# machine (the first call provides the toolchain).
#   scripts/run-case.sh [CASE.toml] [softflow options...]
# Every path (the case file, --restart, output.dir in the case file or in a
# --set) is relative to the folder you call it from, or absolute, as with
# softflow itself; the default case is this repository's cases/couette.toml.
# A path the toolchain root cannot see stops the run with a message naming it.
# Environment: NP (MPI ranks, default 1), OMP_NUM_THREADS (threads per rank,
# default: the cores divided among the ranks), SOFTFLOW_EXE (run this
# softflow executable, visible inside the root, instead of building one).
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd -P)
case_file=${1:-}
[ $# -gt 0 ] && shift
NP=${NP:-1}
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-$(( $(nproc) / NP > 0 ? $(nproc) / NP : 1 ))}
"$repo/scripts/toolchain.sh" setup
# no cd: the command starts inside the root in this same folder
"$repo/scripts/toolchain.sh" run bash -c '
  set -e
  exe=$SOFTFLOW_EXE
  if [ -z "$exe" ]; then
    (cd "$SOFTFLOW_REPO" && cmake -S . -B "$SOFTFLOW_BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null &&
      cmake --build "$SOFTFLOW_BUILD" --target softflow >/dev/null)
    case $SOFTFLOW_BUILD in /*) exe=$SOFTFLOW_BUILD/softflow ;; *) exe=$SOFTFLOW_REPO/$SOFTFLOW_BUILD/softflow ;; esac
  fi
  np=$1 case_file=${2:-$SOFTFLOW_REPO/cases/couette.toml}; shift 2
  exec mpiexec -n "$np" --oversubscribe "$exe" "$case_file" "$@"' bash "$NP" "$case_file" "$@"
