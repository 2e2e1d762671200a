#!/usr/bin/env python3
"""Fits the closures of METHOD.md to a run-set table (scripts/run-set.py) and
writes them as a table.

  scripts/closures.py TABLE.csv OUT_DIR    -> OUT_DIR/closures.csv, closures.md

- [mu](Ca) = (mu/mu_f - 1) / Phi from the dilute runs (Phi < 0.01), with its
  standard error;
- B_B(Ca): mu/mu_f = 1 + [mu] Phi + B_B Phi^2, least squares over the Phi of
  each Ca (K = 1 runs), [mu] from the dilute run at that Ca;
- Eilers, mu/mu_f = (1 + B_E Phi / (1 - Phi / Phi_m))^2, fitted by least
  squares on the runs of the smallest Ca (the most rigid): B_E and Phi_m if
  three or more Phi are available, else B_E with Phi_m = 0.6 (the study's);
- Phi_e(Phi, Ca) = Phi / (1 + (Ca / Ca_0)^n): -> Phi as Ca -> 0, -> 0 as
  Ca -> infinity, linear in Phi; Ca_0 and n by least squares on the measured
  Phi_e / Phi;
- the collapse: relative RMS of mu/mu_f against Eilers(Phi_e) with the
  study's constants and with the fitted ones, over the K = 1 runs with Phi >= 0.01.
The fits use numpy only (grid search refined by Gauss-Newton steps).
"""
import csv
import math
import os
import sys

import numpy as np

STUDY_BE, STUDY_PHIM = 1.7, 0.6


def eilers(phi, be=STUDY_BE, phim=STUDY_PHIM):
    phi = np.asarray(phi, float)
    return (1 + be * phi / (1 - phi / phim)) ** 2


def phi_e_model(phi, ca, ca0, n):
    return np.asarray(phi, float) / (1 + (np.asarray(ca, float) / ca0) ** n)


def load(path):
    rows = list(csv.DictReader(open(path)))

    def num(v):
        try:
            return float(v)
        except (TypeError, ValueError):
            return math.nan

    return [{k: (num(v) if k not in ("name", "grid", "box", "version") else v) for k, v in r.items()} for r in rows]


def least_squares(residual, p0, grids):
    """Minimise sum(residual(p)^2): coarse grid search over `grids`, then Gauss-Newton."""
    best, bp = math.inf, np.array(p0, float)
    for p in np.array(np.meshgrid(*grids, indexing="ij")).reshape(len(grids), -1).T:
        r = residual(p)
        s = float(np.sum(r * r)) if np.all(np.isfinite(r)) else math.inf
        if s < best:
            best, bp = s, p.copy()
    p = bp
    for _ in range(50):
        r = residual(p)
        J = np.empty((len(r), len(p)))
        for k in range(len(p)):
            h = 1e-6 * max(abs(p[k]), 1e-3)
            q = p.copy()
            q[k] += h
            J[:, k] = (residual(q) - r) / h
        step, *_ = np.linalg.lstsq(J, -r, rcond=None)
        q = p + step
        rq = residual(q)
        if not np.all(np.isfinite(rq)) or np.sum(rq * rq) > np.sum(r * r):
            break
        p = q
        if np.max(np.abs(step)) < 1e-12:
            break
    return p, float(np.sqrt(np.mean(residual(p) ** 2)))


def fit(rows):
    out = {}
    k1 = [r for r in rows if r["K"] == 1 and math.isfinite(r["mu_eff"])]
    dilute = {r["Ca"]: r for r in k1 if r["Phi_case"] < 0.01}
    # [mu](Ca) from the dilute runs, with the measured Phi
    out["intrinsic"] = [{"Ca": ca, "intrinsic_viscosity": (r["mu_eff"] - 1) / r["Phi"],
                         "stderr": r["mu_eff_stderr"] / r["Phi"] if math.isfinite(r["mu_eff_stderr"]) else math.nan,
                         "taylor": r["taylor"], "taylor_stderr": r["taylor_stderr"]}
                        for ca, r in sorted(dilute.items())]
    imu = {d["Ca"]: d["intrinsic_viscosity"] for d in out["intrinsic"]}
    # B_B(Ca): one-parameter least squares, sum Phi^2 (mu - 1 - [mu] Phi) / sum Phi^4
    bb = []
    for ca in sorted({r["Ca"] for r in k1}):
        if ca not in imu:
            continue
        dense = [r for r in k1 if r["Ca"] == ca and r["Phi_case"] >= 0.01]
        if not dense:
            continue
        phi = np.array([r["Phi"] for r in dense])
        y = np.array([r["mu_eff"] - 1 - imu[ca] * r["Phi"] for r in dense])
        b = float(np.sum(phi ** 2 * y) / np.sum(phi ** 4))
        res = y - b * phi ** 2
        bb.append({"Ca": ca, "B_B": b, "rms": float(np.sqrt(np.mean(res ** 2))), "n_phi": len(dense)})
    out["second_order"] = bb
    # Eilers on the most rigid series
    rigid = [r for r in k1 if r["Ca"] == min(r2["Ca"] for r2 in k1)] if k1 else []
    phis = np.array([r["Phi"] for r in rigid])
    mus = np.array([r["mu_eff"] for r in rigid])
    if len(rigid) >= 3:
        p, rms = least_squares(lambda p: eilers(phis, p[0], p[1]) - mus, [1.7, 0.6],
                               [np.linspace(0.5, 3, 26), np.linspace(0.4, 0.8, 21)])
        out["eilers"] = {"B_E": p[0], "Phi_m": p[1], "rms": rms, "fitted": "B_E and Phi_m"}
    elif len(rigid) >= 1:
        p, rms = least_squares(lambda p: eilers(phis, p[0], STUDY_PHIM) - mus, [1.7], [np.linspace(0.1, 4, 40)])
        out["eilers"] = {"B_E": p[0], "Phi_m": STUDY_PHIM, "rms": rms, "fitted": "B_E (Phi_m = 0.6 held)"}
    if "eilers" in out:
        out["eilers"]["Ca"] = rigid[0]["Ca"]
        out["eilers"]["runs"] = len(rigid)
    # Phi_e / Phi = 1 / (1 + (Ca / Ca0)^n)
    pe = [r for r in rows if math.isfinite(r.get("phi_e", math.nan)) and r["Phi"] > 0]
    if len(pe) >= 2:
        ca = np.array([r["Ca"] for r in pe])
        ratio = np.array([r["phi_e"] / r["Phi"] for r in pe])
        p, rms = least_squares(lambda p: 1 / (1 + (ca / abs(p[0])) ** p[1]) - ratio, [1.0, 1.0],
                               [np.logspace(-2, 2, 41), np.linspace(0.2, 3, 29)])
        out["phi_e"] = {"Ca_0": abs(p[0]), "n": p[1], "rms_ratio": rms, "runs": len(pe)}
        # the collapse of mu onto Eilers(Phi_e)
        dense = [r for r in k1 if r["Phi_case"] >= 0.01 and math.isfinite(r.get("phi_e", math.nan))]
        if dense:
            mu = np.array([r["mu_eff"] for r in dense])
            pm = np.array([r["phi_e"] for r in dense])
            pf = phi_e_model([r["Phi"] for r in dense], [r["Ca"] for r in dense], out["phi_e"]["Ca_0"], out["phi_e"]["n"])
            coll = {"runs": len(dense),
                    "rel_rms_measured_phi_e_study": float(np.sqrt(np.mean((mu / eilers(pm) - 1) ** 2))),
                    "rel_rms_fitted_phi_e_study": float(np.sqrt(np.mean((mu / eilers(pf) - 1) ** 2))),
                    "rel_rms_phi_study": float(np.sqrt(np.mean((mu / eilers([r["Phi"] for r in dense]) - 1) ** 2)))}
            if "eilers" in out:
                be, pmx = out["eilers"]["B_E"], out["eilers"]["Phi_m"]
                coll["rel_rms_measured_phi_e_fitted"] = float(np.sqrt(np.mean((mu / eilers(pm, be, pmx) - 1) ** 2)))
            out["collapse"] = coll
    return out


def write(out, folder):
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "closures.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["closure", "parameter", "Ca", "value", "uncertainty_or_rms"])
        for d in out.get("intrinsic", []):
            w.writerow(["intrinsic_viscosity", "[mu]", d["Ca"], d["intrinsic_viscosity"], d["stderr"]])
        for d in out.get("second_order", []):
            w.writerow(["second_order", "B_B", d["Ca"], d["B_B"], d["rms"]])
        if "eilers" in out:
            e = out["eilers"]
            w.writerow(["eilers", "B_E", e["Ca"], e["B_E"], e["rms"]])
            w.writerow(["eilers", "Phi_m", e["Ca"], e["Phi_m"], e["rms"]])
        if "phi_e" in out:
            w.writerow(["phi_e", "Ca_0", "", out["phi_e"]["Ca_0"], out["phi_e"]["rms_ratio"]])
            w.writerow(["phi_e", "n", "", out["phi_e"]["n"], out["phi_e"]["rms_ratio"]])
        for k, v in out.get("collapse", {}).items():
            w.writerow(["collapse", k, "", v, ""])
    md = ["# Closures fitted on the run-set table", "",
          "## Intrinsic viscosity [mu] = (mu/mu_f - 1) / Phi (dilute runs)", "",
          "| Ca | [mu] | stderr | T | stderr |", "|---|---|---|---|---|"]
    for d in out.get("intrinsic", []):
        md.append(f"| {d['Ca']:g} | {d['intrinsic_viscosity']:.3f} | {d['stderr']:.3f} | {d['taylor']:.4f} | {d['taylor_stderr']:.4f} |")
    md += ["", "## Second order: mu/mu_f = 1 + [mu] Phi + B_B Phi^2", "", "| Ca | B_B | rms residual | Phi values |", "|---|---|---|---|"]
    for d in out.get("second_order", []):
        md.append(f"| {d['Ca']:g} | {d['B_B']:.2f} | {d['rms']:.2e} | {d['n_phi']} |")
    if "eilers" in out:
        e = out["eilers"]
        md += ["", f"## Eilers (fitted {e['fitted']} on the {e['runs']} runs at Ca = {e['Ca']:g})", "",
               f"B_E = {e['B_E']:.3f}, Phi_m = {e['Phi_m']:.3f}, rms residual {e['rms']:.3e} (study: B_E = 1.7, Phi_m = 0.6)"]
    if "phi_e" in out:
        p = out["phi_e"]
        md += ["", "## Effective volume fraction Phi_e = Phi / (1 + (Ca / Ca_0)^n)", "",
               f"Ca_0 = {p['Ca_0']:.3f}, n = {p['n']:.3f}; rms of Phi_e / Phi {p['rms_ratio']:.3e} over {p['runs']} runs"]
    if "collapse" in out:
        md += ["", "## Collapse of mu/mu_f onto Eilers (relative rms over the dense K = 1 runs)", ""]
        for k, v in out["collapse"].items():
            md.append(f"- {k}: {v:.4g}")
    open(os.path.join(folder, "closures.md"), "w").write("\n".join(md) + "\n")


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__.split("\n\n")[1])
    out = fit(load(sys.argv[1]))
    write(out, sys.argv[2])
    print(open(os.path.join(sys.argv[2], "closures.md")).read())


if __name__ == "__main__":
    main()
