#!/usr/bin/env bash
# Explicit against implicit viscosity on the dilute reference case at Ca = 0.2
# and on a dense case (Phi = 0.11, Ca = 0.2, K = 1), at 4 points per radius,
# plus the implicit runs at 3 points per radius for the size of the spatial
# error. Two lanes of one thread each run side by side, so both schemes see
# the same machine load. Then perf/viscous_payoff.py tabulates.
#
#   perf/viscous_payoff.sh [STRAIN]     (default 3; output in output/payoff/)
# ONLY=implicit (or explicit) reruns one scheme's runs and keeps the others.
set -euo pipefail
cd "$(dirname "$0")/.."
strain=${1:-3}
bin=${SOFTFLOW_BIN:-build/softflow}
scripts/toolchain.sh setup
mkdir -p output/payoff
run() {  # name, case file, scheme, overrides...
  local name=$1 file=$2 scheme=$3
  shift 3
  if [ -n "${ONLY:-}" ] && [ "$scheme" != "$ONLY" ]; then return; fi
  rm -rf "output/payoff/$name"
  scripts/toolchain.sh run env OMP_NUM_THREADS=1 "$bin" "$file" \
    --set "time.viscous=\"$scheme\"" --set "time.end_strain=$strain" \
    --set "output.dir=\"output/payoff/$name\"" --set output.fields_every=0.0 \
    --set output.progress_every=200 --set output.average_from_strain=1.5 "$@" \
    > "output/payoff/$name.log" 2>&1
}
dilute=(cases/phi0016_ca02.toml --set grid.nx=64 --set grid.ny=40 --set grid.nz=64)
dilute3=(cases/phi0016_ca02.toml --set grid.nx=48 --set grid.ny=30 --set grid.nz=48)
dense=(cases/hard/phi011_ca02_k001.toml --set particles.viscosity_ratio=1.0)
dense3=(cases/hard/phi011_ca02_k001.toml --set particles.viscosity_ratio=1.0 --set grid.nx=24 --set grid.ny=18 --set grid.nz=24)
(run dilute_explicit_r4 "${dilute[0]}" explicit "${dilute[@]:1}") &
(run dilute_implicit_r4 "${dilute[0]}" implicit "${dilute[@]:1}"
 run dense_explicit_r4 "${dense[0]}" explicit "${dense[@]:1}"
 run dense_implicit_r4 "${dense[0]}" implicit "${dense[@]:1}"
 run dilute_implicit_r3 "${dilute3[0]}" implicit "${dilute3[@]:1}"
 run dense_implicit_r3 "${dense3[0]}" implicit "${dense3[@]:1}") &
wait
python3 perf/viscous_payoff.py output/payoff
