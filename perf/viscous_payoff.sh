#!/usr/bin/env bash
# Explicit against implicit viscosity on the dilute reference case at Ca = 0.2
# and on a dense case (Phi = 0.11, Ca = 0.2, K = 1), at 4 points per radius,
# plus the implicit runs at 3 points per radius for the size of the spatial
# error. Two lanes of one thread each run side by side, so both schemes see
# the same machine load. Then perf/viscous_payoff.py tabulates.
#
#   perf/viscous_payoff.sh [STRAIN]     (default 3; output in output/payoff/)
# ONLY=implicit (or explicit) reruns one scheme's runs and keeps the others.
# PPR=5 runs at 5 points per radius (and the coarse runs at PPR - 1); default 4.
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
r=${PPR:-4}
c=$((r - 1))
grid() { echo --set grid.nx=$(($1 * $2)) --set grid.ny=$(($1 * $3)) --set grid.nz=$(($1 * $2)); }
# dilute: the reference box 16r x 10r x 16r; dense: its case's box 8r x 6r x 8r
dilute=(cases/phi0016_ca02.toml $(grid $r 16 10))
dilute_c=(cases/phi0016_ca02.toml $(grid $c 16 10))
# one phi field, as the committed results (colours are the default since round 24)
dense=(cases/hard/phi011_ca02_k001.toml --set particles.viscosity_ratio=1.0 --set particles.colour_fields=0 $(grid $r 8 6))
dense_c=(cases/hard/phi011_ca02_k001.toml --set particles.viscosity_ratio=1.0 --set particles.colour_fields=0 $(grid $c 8 6))
(run dilute_explicit_r$r "${dilute[0]}" explicit "${dilute[@]:1}") &
(run dilute_implicit_r$r "${dilute[0]}" implicit "${dilute[@]:1}"
 run dense_explicit_r$r "${dense[0]}" explicit "${dense[@]:1}"
 run dense_implicit_r$r "${dense[0]}" implicit "${dense[@]:1}"
 run dilute_implicit_r$c "${dilute_c[0]}" implicit "${dilute_c[@]:1}"
 run dense_implicit_r$c "${dense_c[0]}" implicit "${dense_c[@]:1}") &
wait
python3 perf/viscous_payoff.py output/payoff "$r"
