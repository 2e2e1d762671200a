#!/usr/bin/env python3
"""Performance regression gate: compare a softflow-perf result with a baseline.

    perf/compare.py BASELINE.json NEW.json [--threshold F] [--min-share S]
    perf/compare.py --noise RUN1.json RUN2.json [RUN3.json ...] [--write-gate GATE.json]

Compares machine-normalised times, measured within each run: a kernel's (or
the step's) median time divided by the time the same run's STREAM triad needs
to move one Real per cell ("normalized" in the JSON), the smallest over the
repetitions. Absolute times on shared machines drift with the load; the
ratio of the least disturbed repetition drifts much less.

Prints each kernel's change against the baseline and exits 1 when the step, or
a kernel taking at least --min-share of the step, is slower by more than its
threshold. Thresholds come from gate.json next to the baseline, written by
--noise --write-gate from repeated runs of one build: per case, twice the
measured spread (max - min) / median of the step and of each kernel, and at
least --floor (0.25). --threshold overrides them all. Exits 2 when the two
runs are not comparable (case, grid, ranks, backend or harness differ).
"""
import argparse
import json
import os
import statistics
import sys

# the least disturbed repetition: interference only ever adds time
STAT = "min"
SAME = ("case", "grid", "ranks", "backend", "harness_version", "physics")


def load(path):
    with open(path) as f:
        return json.load(f)


def entries(run):
    """name -> (normalized time, share of step) for the step and each kernel."""
    out = {"<step>": (run["step"]["normalized"][STAT], 1.0)}
    for label, k in run["kernels"].items():
        out[label] = (k["normalized"][STAT], k["share_of_step"])
    return out


def noise(paths, gate_path, floor, min_share):
    case = load(paths[0])["case"]
    # one case's repeats only: runs of several scenes mixed would gate one
    # case with the others' spread (their step times differ 20-fold)
    others = sorted({load(p)["case"] for p in paths} - {case})
    if others:
        print(f"compare: --noise takes repeated runs of one case; got {case} and {', '.join(others)}",
              file=sys.stderr)
        sys.exit(2)
    runs = [entries(load(p)) for p in paths]
    names = set.intersection(*(set(r) for r in runs))
    worst = 0.0
    thresholds, spreads = {}, {}
    print(f"{'kernel':34s} {'share':>7s} {'spread':>8s} {'gate':>6s}")
    for n in sorted(names, key=lambda n: -runs[0][n][1]):
        vals = [r[n][0] for r in runs]
        share = statistics.median(r[n][1] for r in runs)
        spread = (max(vals) - min(vals)) / statistics.median(vals)
        spreads[n] = round(spread, 4)
        thresholds[n] = round(max(floor, 2 * spread), 3)
        gated = n == "<step>" or share >= min_share
        print(f"{n:34s} {share:7.3f} {spread:8.3f} {thresholds[n] if gated else '-':>6}")
        if gated:
            worst = max(worst, spread)
    print(f"largest relative spread (max - min) / median of the gated entries: {worst:.3f}")
    if gate_path:
        gate = load(gate_path) if os.path.exists(gate_path) else {}
        gate[case] = {"runs": len(paths), "floor": floor, "min_share": min_share,
                      "spread": spreads, "threshold": thresholds}
        with open(gate_path, "w") as f:
            json.dump(gate, f, indent=1, sort_keys=True)
        print(f"wrote the thresholds of '{case}' to {gate_path}")
    return 0


def compare(base_path, new_path, threshold, min_share):
    base, new = load(base_path), load(new_path)
    per_kernel = {}
    for key in SAME:
        if base.get(key) != new.get(key):
            print(f"compare: not comparable: '{key}' is {base.get(key)!r} in the baseline, {new.get(key)!r} now")
            return 2
    if threshold is None:
        gate = os.path.join(os.path.dirname(os.path.abspath(base_path)), "gate.json")
        if os.path.exists(gate) and base["case"] in load(gate):
            per_kernel = load(gate)[base["case"]]["threshold"]
            min_share = load(gate)[base["case"]]["min_share"]
        threshold = 0.25
    b, n = entries(base), entries(new)
    print(f"baseline {base['commit']} ({base['machine']['cpu']}), now {new['commit']}; "
          f"thresholds: {'per kernel from gate.json' if per_kernel else f'+{threshold:.0%}'}")
    print(f"{'kernel':34s} {'share':>7s} {'base':>9s} {'now':>9s} {'change':>8s} {'gate':>6s}")
    failed = []
    for name in sorted(b, key=lambda k: -b[k][1]):
        if name not in n:
            print(f"{name:34s} {b[name][1]:7.3f} {b[name][0]:9.3f} {'-':>9s}  (not run now)")
            continue
        change = n[name][0] / b[name][0] - 1
        gated = name == "<step>" or b[name][1] >= min_share
        limit = per_kernel.get(name, threshold)
        flag = ""
        if gated and change > limit:
            flag = "  REGRESSION"
            failed.append(name)
        elif not gated:
            flag = "  (below min share, not gated)"
        print(f"{name:34s} {b[name][1]:7.3f} {b[name][0]:9.3f} {n[name][0]:9.3f} {change:+8.1%} "
              f"{'+' + format(limit, '.0%') if gated else '-':>6}{flag}")
    for name in sorted(set(n) - set(b)):
        print(f"{name:34s} {n[name][1]:7.3f} {'-':>9s} {n[name][0]:9.3f}  (new kernel)")
    cs_b = base["step"]["cell_steps_per_second"]["median"]
    cs_n = new["step"]["cell_steps_per_second"]["median"]
    print(f"cell-steps/s (absolute, for information): baseline {cs_b:.3e}, now {cs_n:.3e}")
    if failed:
        print("compare: FAILED: slower than the baseline beyond the threshold: " + ", ".join(failed))
        return 1
    print("compare: passed")
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("files", nargs="+")
    ap.add_argument("--noise", action="store_true", help="report the spread of several runs of one build")
    ap.add_argument("--threshold", type=float, default=None)
    ap.add_argument("--min-share", type=float, default=0.05, help="gate kernels with this share of the step")
    ap.add_argument("--floor", type=float, default=0.25, help="smallest threshold --write-gate sets")
    ap.add_argument("--write-gate", help="with --noise: add this case's thresholds to this gate.json")
    a = ap.parse_args()
    if a.noise:
        return noise(a.files, a.write_gate, a.floor, a.min_share)
    if len(a.files) != 2:
        ap.error("give BASELINE.json and NEW.json")
    return compare(a.files[0], a.files[1], a.threshold, a.min_share)


if __name__ == "__main__":
    sys.exit(main())
