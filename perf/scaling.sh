#!/usr/bin/env bash
# Strong and weak scaling at 1, 2 and 4 MPI ranks with the perf harness:
# correctness of the communication (bytes per step measured by the halo and
# transpose counters against the model of perf/scaling.py) and the time per
# step. On the 2-core CI-class machine 4 ranks oversubscribe the cores, so
# the times say nothing about speed-up; the volumes are exact.
#
#   perf/scaling.sh          # -> output/scaling/*.json, then perf/scaling.py -> perf/results/scaling.md
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${BIN:-build/perf/softflow-perf}
out=output/scaling
mkdir -p "$out"
scripts/toolchain.sh setup >/dev/null
mpi=(env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1 mpirun --oversubscribe -np)
run() {  # name ranks case nx ny nz
  scripts/toolchain.sh run "${mpi[@]}" "$2" "$bin" "$3" --set grid.nx="$4" --set grid.ny="$5" --set grid.nz="$6" \
    --warmup 1 --steps 2 --reps 3 --stream-mb 64 --json "$out/$1.json" > /dev/null
  echo "scaling: $1 done"
}
for scene in single particle; do
  case $scene in single) file=cases/couette.toml ;; particle) file=cases/phi0016_ca02.toml ;; esac
  # strong: one 64 x 40 x 64 grid; weak: 32 x 40 x 32 cells per rank
  for np in 1 2 4; do run "${scene}_strong_np$np" $np $file 64 40 64; done
  run "${scene}_weak_np1" 1 $file 32 40 32
  run "${scene}_weak_np2" 2 $file 64 40 32
  run "${scene}_weak_np4" 4 $file 64 40 64
done
python3 perf/scaling.py "$out" > perf/results/scaling.md
echo "scaling: perf/results/scaling.md"
