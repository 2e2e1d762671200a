#!/usr/bin/env bash
# The performance benchmarks: softflow-perf on the three scenes, JSON per
# scene, then a markdown report. Before merging a change, compare with the
# committed baseline of your machine class:
#
#   perf/bench.sh                        # -> perf/results/<class>/{single,particle,dense}.json, report.md
#   perf/compare.py perf/baselines/<class>/single.json perf/results/<class>/single.json
#
# Environment: GRID (default 64x40x64: 4 points per radius in the reference
# 16r x 10r x 16r box), RANKS (default 1), OUT (default perf/results/<class>),
# BIN (default build/perf/softflow-perf), STEPS/REPS/WARMUP (5/5/3),
# SCENES (default "single particle dense"), CLASS (the machine class; default
# the harness's backend-threads). OpenMP threads: OMP_NUM_THREADS (default all).
set -euo pipefail
cd "$(dirname "$0")/.."
grid=${GRID:-64x40x64}
IFS=x read -r nx ny nz <<< "$grid"
ranks=${RANKS:-1}
bin=${BIN:-build/perf/softflow-perf}
scenes=${SCENES:-single particle dense}
scripts/toolchain.sh setup >/dev/null
# all cores unless told (the toolchain wrapper alone would default to 1 thread)
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-$(( $(nproc) / ranks > 0 ? $(nproc) / ranks : 1 ))}
[ -x "$bin" ] || { echo "bench: $bin not built (cmake --build build)" >&2; exit 2; }

case_of() {
  case $1 in
    single) echo cases/couette.toml ;;                 # fluid only (explicit viscosity, as CaNS)
    particle) echo cases/phi0016_ca02.toml ;;          # one sphere, Ca = 0.2 (dilute reference case; implicit)
    dense) echo cases/phi011_ca02.toml ;;              # Phi = 0.11, Ca = 0.2 (implicit; placement and gap pinned below)
    *) echo "bench: unknown scene $1" >&2; exit 2 ;;
  esac
}
class_args=()
[ -n "${CLASS:-}" ] && class_args=(--machine-class "$CLASS")
launch=()
if [ "$ranks" -gt 1 ]; then
  launch=(env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun --oversubscribe -np "$ranks")
fi
first=1
for scene in $scenes; do
  tmp=output/bench-tmp  # inside the repository: the toolchain root sees it at the same relative path
  mkdir -p "$tmp"
  # the dense scene keeps the independent draws of the baselines (rounds <= 20):
  # the stratified default would move its 67 spheres; it runs the default
  # numerics, one colour field per sphere (baselines re-recorded in round 25)
  scene_args=()
  [ "$scene" = dense ] && scene_args=(--set 'particles.placement="random"' --set particles.min_gap_cells=0)
  scripts/toolchain.sh run "${launch[@]}" "$bin" "$(case_of "$scene")" "${scene_args[@]}" \
    --set grid.nx="$nx" --set grid.ny="$ny" --set grid.nz="$nz" \
    --warmup "${WARMUP:-3}" --steps "${STEPS:-5}" --reps "${REPS:-5}" "${class_args[@]}" \
    --json "$tmp/$scene.json" > /dev/null
  if [ $first = 1 ]; then
    cls=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['machine_class'])" "$tmp/$scene.json")
    out=${OUT:-perf/results/$cls}
    mkdir -p "$out"
    first=0
  fi
  mv "$tmp/$scene.json" "$out/$scene.json"
done
python3 perf/report.py "$out"/*.json > "$out/report.md"
echo "bench: results in $out (report.md)"
