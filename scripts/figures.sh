#!/usr/bin/env bash
# Figures and closures from a run-set folder:
#   scripts/figures.sh SET_DIR OUT_DIR [--shapes DENSE_CASE,DILUTE_CASE]
# Installs Debian's python3-matplotlib, python3-numpy and python3-h5py when
# missing (needs root), then runs scripts/figures.py.
set -euo pipefail
cd "$(dirname "$0")/.."
# Debian's interpreter, where apt puts the packages (not a pyenv or venv one)
PY=python3
[ -x /usr/bin/python3 ] && PY=/usr/bin/python3
if ! "$PY" -c "import matplotlib, numpy, h5py" 2>/dev/null; then
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -q >/dev/null
  apt-get install -y -q python3-matplotlib python3-numpy python3-h5py >/dev/null
fi
exec "$PY" scripts/figures.py "$@"
