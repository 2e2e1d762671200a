#!/usr/bin/env bash
# Cost of the solid phase's numerics (issue 12): the dense scene
# (cases/phi011_ca02.toml at 64 x 40 x 64, Phi = 0.11, Ca = 0.2, implicit)
# with the old numerics (WENO5 phi, B by its own equation everywhere, no B
# fallback, no det B projection) and with the default ones (THINC phi, B
# fallback, B extended from the solid side, det B projected), alternated ROUNDS times in one run so both
# see the same machine load; then the ratio of the median step times.
#   perf/solid_cost.sh            # -> perf/results/solid_cost/{old,new}_N.json, solid_cost.md
# Environment: ROUNDS (default 3), OMP_NUM_THREADS (default all cores), BIN.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${BIN:-build/perf/softflow-perf}
rounds=${ROUNDS:-3}
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-$(nproc)}
out=perf/results/solid_cost
mkdir -p "$out"
old=(--set particles.phi_scheme=weno5 --set particles.b_extension=false --set particles.unimodular_b=false
     --set particles.b_fallback=false)
for r in $(seq 1 "$rounds"); do
  for v in old new; do
    extra=()
    [ $v = old ] && extra=("${old[@]}")
    scripts/toolchain.sh run "$bin" cases/phi011_ca02.toml --set grid.nx=64 --set grid.ny=40 --set grid.nz=64 \
      "${extra[@]}" --warmup 3 --steps 5 --reps 5 --json "$out/${v}_$r.json" >/dev/null
    echo "solid_cost: round $r $v done" >&2
  done
done
python3 - "$out" "$rounds" <<'PY'
import json, statistics, sys
out, rounds = sys.argv[1], int(sys.argv[2])
def step(v, r):
    return json.load(open(f"{out}/{v}_{r}.json"))["step"]["seconds"]["median"]
def kern(v, r):
    k = json.load(open(f"{out}/{v}_{r}.json"))["kernels"]
    return {n: d["seconds_per_step"]["median"] for n, d in k.items() if "solid" in n}
old = [step("old", r) for r in range(1, rounds + 1)]
new = [step("new", r) for r in range(1, rounds + 1)]
ratios = [n / o for n, o in zip(new, old)]
lines = ["# Cost of the solid phase's numerics (perf/solid_cost.sh)", "",
         "Dense scene (cases/phi011_ca02.toml, 64 x 40 x 64, Phi = 0.11, Ca = 0.2, implicit), "
         "the old numerics (WENO5 phi, no B fallback, no B extension, no projection) and the default ones, "
         f"alternated {rounds} times; median step seconds of each harness run.", "",
         "| round | old step (ms) | new step (ms) | new / old |", "|---|---|---|---|"]
for r in range(rounds):
    lines.append(f"| {r + 1} | {1e3 * old[r]:.1f} | {1e3 * new[r]:.1f} | {ratios[r]:.3f} |")
lines += ["", f"Median ratio new / old: {statistics.median(ratios):.3f} (the issue's limit: 1.3).", "",
          "Solid kernels, median seconds per step in the last round:", "",
          "| kernel | old | new |", "|---|---|---|"]
ko, kn = kern("old", rounds), kern("new", rounds)
for n in sorted(set(ko) | set(kn)):
    lines.append(f"| {n} | {1e3 * ko.get(n, 0):.2f} ms | {1e3 * kn.get(n, 0):.2f} ms |")
open(f"{out}/solid_cost.md", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
PY
