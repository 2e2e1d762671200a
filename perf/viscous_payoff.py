#!/usr/bin/env python3
"""Tabulates perf/viscous_payoff.sh: steps, wall time, T and mu/mu_f of the
explicit and implicit viscous schemes at R points per radius, and the
R - 1 -> R change as the scale of the discretization error. Writes
payoff_rR.csv and payoff_rR.md in the folder given.

    perf/viscous_payoff.py [FOLDER (default output/payoff)] [R (default 4)]"""
import csv
import json
import os
import sys


def load(folder, name):
    path = os.path.join(folder, name, "summary.json")
    if not os.path.exists(path):
        return None
    return json.load(open(path))


def q(s, name):
    a = s["averages"]["quantities"].get(name)
    return (a["mean"], a["stderr"]) if a else (float("nan"), None)


def fmt(v):
    m, e = v
    return f"{m:.4f}" + (f" ± {e:.4f}" if e is not None else "")


def main():
    folder = sys.argv[1] if len(sys.argv) > 1 else "output/payoff"
    ppr = int(sys.argv[2]) if len(sys.argv) > 2 else 4
    fine_e, fine_i, coarse = f"explicit_r{ppr}", f"implicit_r{ppr}", f"implicit_r{ppr - 1}"
    rows = []
    for case in ("dilute", "dense"):
        runs = {k: load(folder, f"{case}_{k}") for k in (fine_e, fine_i, coarse)}
        if not runs[fine_e] or not runs[fine_i]:
            continue
        for k, s in runs.items():
            if not s:
                continue
            p = s["performance"]
            rows.append({"case": case, "run": k, "grid": "x".join(map(str, s["case"]["grid"])),
                         "steps": p["steps"], "wall_s": round(p["wall_seconds"], 1),
                         "ms_per_step": round(1e3 * p["wall_seconds"] / p["steps"], 1),
                         "taylor": q(s, "taylor"), "mu_eff": q(s, "mu_eff"),
                         "from_strain": s["averages"]["from_strain"], "to_strain": s["averages"]["to_strain"]})
    with open(os.path.join(folder, f"payoff_r{ppr}.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["case", "run", "grid", "steps", "wall_s", "ms_per_step", "taylor", "taylor_stderr",
                    "mu_eff", "mu_eff_stderr", "from_strain", "to_strain"])
        for r in rows:
            w.writerow([r["case"], r["run"], r["grid"], r["steps"], r["wall_s"], r["ms_per_step"], *r["taylor"],
                        *r["mu_eff"], r["from_strain"], r["to_strain"]])
    lines = ["| case | run | grid | steps | wall s | ms/step | T | mu/mu_f |", "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['case']} | {r['run']} | {r['grid']} | {r['steps']} | {r['wall_s']} | "
                     f"{r['ms_per_step']} | {fmt(r['taylor'])} | {fmt(r['mu_eff'])} |")
    lines.append("")
    for case in ("dilute", "dense"):
        by = {r["run"]: r for r in rows if r["case"] == case}
        if fine_e not in by or fine_i not in by:
            continue
        e, i = by[fine_e], by[fine_i]
        line = (f"- {case}: implicit takes {e['steps'] / i['steps']:.1f}x fewer steps and "
                f"{e['wall_s'] / i['wall_s']:.1f}x less wall time; |dT| = {abs(e['taylor'][0] - i['taylor'][0]):.4f}, "
                f"|d mu| = {abs(e['mu_eff'][0] - i['mu_eff'][0]):.4f}")
        if coarse in by:
            c = by[coarse]
            line += (f"; the {ppr - 1} -> {ppr} points-per-radius change (spatial error scale): "
                     f"|dT| = {abs(c['taylor'][0] - i['taylor'][0]):.4f}, |d mu| = {abs(c['mu_eff'][0] - i['mu_eff'][0]):.4f}")
        lines.append(line)
    open(os.path.join(folder, f"payoff_r{ppr}.md"), "w").write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
