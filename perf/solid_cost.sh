#!/usr/bin/env bash
# Cost of the solid phase's numerics (issue 12): the dense scene
# (cases/phi011_ca02.toml at 64 x 40 x 64, Phi = 0.11, Ca = 0.2, implicit)
# with the old numerics (WENO5 phi, B by its own equation everywhere, no B
# fallback, no det B projection) and with the default ones (MTHINC phi,
# B of the 0.5 <= phi < 0.9 band from the core and of the outer band from
# the solid side, B fallback, det B projected), alternated ROUNDS times in
# one run so that all see the same machine load; then the ratio of the
# median step times. More VARIANTS: issue (the code as it was when issue 12
# was filed, commit REFERENCE, default cb87e6d, with its own defaults: the
# issue's "today's" step; built once into build-reference/), thinc (THINC
# phi, b_solid_phi 0.5: the default until round 15), thinc09 (THINC, 0.9),
# mthinc05 (MTHINC, 0.5), colours (the default numerics with one colour field
# per particle, particles.colour_fields = 67, and the colours' tails cut at
# phi's 1e-10, particles.colour_cut: the option until round 23), colours6 and
# colours4 (the same with colour_cut = 1e-6 and 1e-4, the option's default
# since round 23: with one colour per sphere the default numerics since round
# 24), colours4nb (colours4 without the bound on the colours' sum,
# particles.colour_sum_bound = false: round 24-27's default), allstages
# (colours4 with B's extension after every RK3 stage,
# particles.b_extension_stages = "all": the default until round 28; every
# other variant but issue pins one phi field, colour_fields = 0), before (the
# code at commit BEFORE, default a2bfecf, the end of round 29, built once into
# build-before/, run as colours4: the step before round 30 batched the
# colours' per-box passes).
#   perf/solid_cost.sh                      # -> perf/results/solid_cost/{old,new}_N.json, solid_cost.md
#   VARIANTS="issue old new" perf/solid_cost.sh
# Environment: ROUNDS (default 3), VARIANTS (default "old new"),
# OMP_NUM_THREADS (default all cores), BIN, REFERENCE, BEFORE.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${BIN:-build/perf/softflow-perf}
rounds=${ROUNDS:-3}
variants=${VARIANTS:-old new}
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-$(nproc)}
out=perf/results/solid_cost
mkdir -p "$out"
ref_bin=build-reference/src/build/perf/softflow-perf
if [[ " $variants " == *" issue "* ]] && [ ! -x "$ref_bin" ]; then
  ref=${REFERENCE:-cb87e6d}
  [ -d build-reference/src ] || git worktree add --detach build-reference/src "$ref" >&2
  scripts/toolchain.sh run bash -c 'cd build-reference/src && cmake --preset openmp >/dev/null &&
    cmake --build build --target softflow-perf >/dev/null'
fi
before_bin=build-before/src/build/perf/softflow-perf
if [[ " $variants " == *" before "* ]] && [ ! -x "$before_bin" ]; then
  [ -d build-before/src ] || git worktree add --detach build-before/src "${BEFORE:-a2bfecf}" >&2
  scripts/toolchain.sh run bash -c 'cd build-before/src && cmake --preset openmp >/dev/null &&
    cmake --build build --target softflow-perf >/dev/null'
fi
old=(--set particles.phi_scheme=weno5 --set particles.b_extension=false --set particles.unimodular_b=false
     --set particles.b_fallback=false)
for r in $(seq 1 "$rounds"); do
  for v in $variants; do
    extra=()
    run_bin=$bin
    [ $v = old ] && extra=("${old[@]}")
    [ $v = issue ] && run_bin=$ref_bin
    [ $v = before ] && run_bin=$before_bin
    case $v in thinc | thinc09) extra=(--set particles.phi_scheme=thinc) ;; esac
    case $v in thinc | mthinc05) extra+=(--set particles.b_solid_phi=0.5) ;; esac
    case $v in colours | colours6 | colours4 | colours4nb | allstages | before) extra=(--set particles.colour_fields=67) ;; esac
    [ $v = colours ] && extra+=(--set particles.colour_cut=1e-10)
    [ $v = colours6 ] && extra+=(--set particles.colour_cut=1e-6)
    case $v in colours4 | before) extra+=(--set particles.colour_cut=1e-4) ;; esac
    [ $v = allstages ] && extra+=(--set particles.colour_cut=1e-4 --set 'particles.b_extension_stages="all"')
    [ $v = colours4nb ] && extra+=(--set particles.colour_cut=1e-4 --set particles.colour_sum_bound=false)
    # and the gap it knows (min_gap alone; the issue-time code has no min_gap_cells),
    # and one phi field where the variant has no colours (they are the default since round 24)
    [ $v != issue ] && extra+=(--set particles.min_gap_cells=0)
    case $v in issue | colours | colours6 | colours4 | colours4nb | allstages | before) ;; *) extra+=(--set particles.colour_fields=0) ;; esac
    # independent draws: the placement the issue-time code knows (and the baselines')
    scripts/toolchain.sh run "$run_bin" cases/phi011_ca02.toml --set grid.nx=64 --set grid.ny=40 --set grid.nz=64 \
      --set 'particles.placement="random"' \
      ${extra[@]+"${extra[@]}"} --warmup 3 --steps 5 --reps 5 --json "$out/${v}_$r.json" >/dev/null
    echo "solid_cost: round $r $v done" >&2
  done
done
python3 - "$out" "$rounds" $variants <<'PY'
import json, statistics, sys
out, rounds, variants = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
def step(v, r):
    return json.load(open(f"{out}/{v}_{r}.json"))["step"]["seconds"]["median"]
def kern(v, r):
    k = json.load(open(f"{out}/{v}_{r}.json"))["kernels"]
    return {n: d["seconds_per_step"]["median"] for n, d in k.items() if "solid" in n or "colour" in n}
names = {"old": "old", "new": "one phi (MTHINC, 0.9)", "thinc": "THINC, 0.5", "thinc09": "THINC, 0.9",
         "mthinc05": "MTHINC, 0.5", "colours": "67 colours, cut 1e-10", "colours6": "67 colours, cut 1e-6",
         "colours4": "67 colours, cut 1e-4", "colours4nb": "67 colours, cut 1e-4, no sum bound",
         "allstages": "67 colours, cut 1e-4, B extended after every stage",
         "issue": "issue-time code", "before": "67 colours, cut 1e-4, round 29's code (a2bfecf)"}
steps = {v: [step(v, r) for r in range(1, rounds + 1)] for v in variants}
# each variant against the old numerics and, when it ran, the issue-time code
refs = [b for b in ("old", "issue", "before") if b in variants]
pairs = [(v, b) for b in refs for v in variants
         if v not in ("old", "issue", "before") or (v in ("old", "before") and b == "issue")]
lines = ["# Cost of the solid phase's numerics (perf/solid_cost.sh)", "",
         "Dense scene (cases/phi011_ca02.toml, 64 x 40 x 64, Phi = 0.11, Ca = 0.2, implicit), "
         "the old numerics (WENO5 phi, no B fallback, no B extension, no projection) and the default ones "
         "(MTHINC phi, particles.b_solid_phi = 0.9, B fallback, B extension, projection)"
         + ("; the issue-time code: commit cb87e6d (or REFERENCE) built as it was, its own defaults, "
            "the issue's \"today's\" step" if "issue" in variants else "")
         + ("; the others: the default numerics with phi_scheme and b_solid_phi as named"
            if len(set(variants) - {"old", "new", "issue"}) else "") + ", "
         f"alternated {rounds} times; median step seconds of each harness run.", "",
         "| round | " + " | ".join(f"{names[v]} step (ms)" for v in variants) + " | "
         + " | ".join(f"{names[v]} / {names[b]}" for v, b in pairs) + " |",
         "|---|" + "---|" * (len(variants) + len(pairs))]
for r in range(rounds):
    lines.append(f"| {r + 1} | " + " | ".join(f"{1e3 * steps[v][r]:.1f}" for v in variants) + " | "
                 + " | ".join(f"{steps[v][r] / steps[b][r]:.3f}" for v, b in pairs) + " |")
lines.append("")
for v, b in pairs:
    ratio = statistics.median(s / o for s, o in zip(steps[v], steps[b]))
    lines.append(f"Median ratio {names[v]} / {names[b]}: {ratio:.3f}"
                 + (" (the issue's limit: 1.3)." if b == "issue" and v != "old" else "."))
lines += ["", "Solid kernels, median seconds per step in the last round:", "",
          "| kernel | " + " | ".join(names[v] for v in variants) + " |", "|---|" + "---|" * len(variants)]
ks = {v: kern(v, rounds) for v in variants}
for n in sorted(set().union(*ks.values())):
    lines.append(f"| {n} | " + " | ".join(f"{1e3 * ks[v].get(n, 0):.2f} ms" for v in variants) + " |")
open(f"{out}/solid_cost.md", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
PY
