#!/usr/bin/env bash
# Cost of the experimental reference map (particles.solid_model =
# "reference_map", with its volume correction) against the default phi/B
# model, on the scene it is written for: one sphere at the centre of the
# reference box (cases/phi0016_ca02.toml at 64 x 40 x 64, 4 ppr, Ca = 0.2,
# from the Couette profile). Variants, alternated ROUNDS times in one run so
# that all see the same machine load:
#   phi_b   the default model (this build);
#   map     the map (this build: its passes in the work box around the
#           particle, ReferenceMap::begin_step, round 36; two correction
#           passes a step, the default since round 37);
#   map1    the same with one correction pass (particles.map_correction_passes = 1);
#   before  the map at commit BEFORE (default d45a7ef, the end of round 35:
#           every pass over the whole box), built once into build-map-before/.
#   perf/map_cost.sh            # -> perf/results/map_cost/{variant}_{round}.json, map_cost.md
# Environment: ROUNDS (default 3), VARIANTS (default "phi_b map before"), OUT,
# OMP_NUM_THREADS (default all cores), BIN, BEFORE.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${BIN:-build/perf/softflow-perf}
rounds=${ROUNDS:-3}
variants=${VARIANTS:-phi_b map before}
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-$(nproc)}
out=${OUT:-perf/results/map_cost}
mkdir -p "$out"
before_bin=build-map-before/src/build/perf/softflow-perf
if [[ " $variants " == *" before "* ]] && [ ! -x "$before_bin" ]; then
  [ -d build-map-before/src ] || git worktree add --detach build-map-before/src "${BEFORE:-d45a7ef}" >&2
  scripts/toolchain.sh run bash -c 'cd build-map-before/src && cmake --preset openmp >/dev/null &&
    cmake --build build --target softflow-perf >/dev/null'
fi
map=(--set 'particles.solid_model="reference_map"' --set particles.map_volume_correction=true)
for r in $(seq 1 "$rounds"); do
  for v in $variants; do
    extra=()
    run_bin=$bin
    [ "$v" != phi_b ] && extra=("${map[@]}")
    [ "$v" = map1 ] && extra+=(--set particles.map_correction_passes=1)
    [ "$v" = before ] && run_bin=$before_bin
    scripts/toolchain.sh run "$run_bin" cases/phi0016_ca02.toml --set grid.nx=64 --set grid.ny=40 --set grid.nz=64 \
      --set 'initial.type="couette"' --set 'particles.placement="centre"' \
      ${extra[@]+"${extra[@]}"} --warmup 20 --steps 20 --reps 3 --json "$out/${v}_$r.json" >/dev/null
    echo "map_cost: round $r $v done" >&2
  done
done
python3 - "$out" "$rounds" $variants <<'PY'
import json, statistics, sys
out, rounds, variants = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
def run(v, r):
    return json.load(open(f"{out}/{v}_{r}.json"))
names = {"phi_b": "phi/B (default)", "map": "map, work box, two passes", "map1": "map, one pass",
         "before": "map, whole box (round 35)"}
steps = {v: [run(v, r)["step"]["seconds"]["median"] for r in range(1, rounds + 1)] for v in variants}
pairs = [(a, b) for a, b in (("map", "before"), ("map", "map1"), ("map", "phi_b"), ("map1", "phi_b"),
                             ("before", "phi_b"))
         if a in variants and b in variants]
lines = ["# Cost of the reference map (perf/map_cost.sh)", "",
         "One sphere at the centre of the reference box (cases/phi0016_ca02.toml, 64 x 40 x 64, 4 ppr, "
         "Ca = 0.2, Couette start), the map with its volume correction; alternated "
         f"{rounds} times, 20 warm-up steps, median step of 3 x 20 steps per harness run, "
         f"OpenMP {run(variants[0], 1)['concurrency']} threads.", "",
         "| round | " + " | ".join(f"{names[v]} step (ms)" for v in variants) + " | "
         + " | ".join(f"{names[a]} / {names[b]}" for a, b in pairs) + " |",
         "|---|" + "---|" * (len(variants) + len(pairs))]
for r in range(rounds):
    lines.append(f"| {r + 1} | " + " | ".join(f"{1e3 * steps[v][r]:.1f}" for v in variants) + " | "
                 + " | ".join(f"{steps[a][r] / steps[b][r]:.3f}" for a, b in pairs) + " |")
lines.append("")
for a, b in pairs:
    lines.append(f"Median ratio {names[a]} / {names[b]}: "
                 f"{statistics.median(x / y for x, y in zip(steps[a], steps[b])):.3f}.")
lines += ["", "The map's kernels (and the transport's, which it calls), median ms per step in the last round:", "",
          "| kernel | " + " | ".join(names[v] for v in variants) + " |", "|---|" + "---|" * len(variants)]
ks = {v: {n: d["seconds_per_step"]["median"] for n, d in run(v, rounds)["kernels"].items()
          if n.startswith(("refmap", "solid_near", "solid_transport"))} for v in variants}
for n in sorted(set().union(*ks.values()), key=lambda n: -max(ks[v].get(n, 0) for v in variants)):
    lines.append(f"| {n} | " + " | ".join(f"{1e3 * ks[v].get(n, 0):.2f}" for v in variants) + " |")
open(f"{out}/map_cost.md", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
PY
