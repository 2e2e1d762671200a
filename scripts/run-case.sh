#!/usr/bin/env bash
# Builds softflow if needed and runs one case. Works on a fresh Debian 12
# machine (the first call provides the toolchain).
#   scripts/run-case.sh [CASE.toml] [softflow options...]
# Environment: NP (MPI ranks, default 1), OMP_NUM_THREADS (threads per rank,
# default: the cores divided among the ranks).
set -euo pipefail
cd "$(dirname "$0")/.."
case_file=${1:-cases/couette.toml}
[ $# -gt 0 ] && shift
NP=${NP:-1}
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-$(( $(nproc) / NP > 0 ? $(nproc) / NP : 1 ))}
scripts/toolchain.sh setup
scripts/toolchain.sh run bash -c '
  set -e
  cmake -S . -B "$SOFTFLOW_BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$SOFTFLOW_BUILD" >/dev/null
  np=$1; shift
  exec mpiexec -n "$np" --oversubscribe "$SOFTFLOW_BUILD/softflow" "$@"' bash "$NP" "$case_file" "$@"
