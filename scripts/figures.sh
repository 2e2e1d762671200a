#!/usr/bin/env bash
# Figures and closures from a run-set folder:
#   scripts/figures.sh SET_DIR OUT_DIR [--shapes DENSE_CASE,DILUTE_CASE]
# SET_DIR and OUT_DIR are relative to the folder you call it from, or
# absolute. Installs Debian's python3-matplotlib, python3-numpy and
# python3-h5py when missing (needs root), then runs scripts/figures.py.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd -P)
if [ $# -ge 1 ] && [ "${1#-}" = "$1" ] && [ ! -f "$1/table.csv" ]; then
  echo "softflow: error: '$1' ($(realpath -m -- "$1")) has no table.csv: give a folder written by scripts/run-set.py" >&2
  exit 2
fi
# Debian's interpreter, where apt puts the packages (not a pyenv or venv one)
PY=python3
[ -x /usr/bin/python3 ] && PY=/usr/bin/python3
if ! "$PY" -c "import matplotlib, numpy, h5py" 2>/dev/null; then
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -q >/dev/null
  apt-get install -y -q python3-matplotlib python3-numpy python3-h5py >/dev/null
fi
# no cd: the folders stay relative to the caller's folder
exec "$PY" "$repo/scripts/figures.py" "$@"
