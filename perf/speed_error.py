#!/usr/bin/env python3
"""Speed against error: what accuracy each second of wall time buys.

    perf/speed_error.py run [--only particle|startup] [--strain S] [--threads N]
    perf/speed_error.py report          # -> perf/results/speed_error.{md,csv,png}

Two sweeps, each run with build/softflow (through scripts/toolchain.sh), one
OpenMP thread by default, outputs in output/speed_error/<run>/ (runs already
finished are kept, so an interrupted sweep resumes):

- particle: one sphere (Ca = 0.2, K = 1, Re = 0.1) at the centre of an
  8r x 6r x 8r box, implicit viscosity, to strain S (default 1), at 3, 4, 6,
  8 and 12 points per radius (ppr); at 6 ppr also with the time step halved
  and quartered; the explicit scheme at 4 ppr. Errors of T and of
  [mu] = (mu_eff - 1) / Phi at the final strain, against the 12-ppr run
  (the finest; its own error is estimated by Richardson extrapolation from
  8 and 12 ppr with the observed order, reported alongside).
- startup: plane Couette flow started from rest (h = 5, nu = 10, V_w = 5) to
  t = 0.25 = 0.1 h^2 / nu, ny = 10 to 80 (4 x ny x 4 cubic cells), both schemes; the error is
  max_y |<u>(y) - u_exact(y)| / V_w with the exact series solution; for the
  implicit scheme also dt_max sweeps at ny = 80 (time error).

The box is smaller than the reference 16r x 10r x 16r so the finest runs stay
affordable here: the numbers measure the numerics' convergence, not the dilute
limit (Phi = 0.011 here, and the walls are 2r from the sphere).
"""
import argparse
import csv
import glob
import json
import math
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = "output/speed_error"
RESULTS = os.path.join(ROOT, "perf", "results")

PARTICLE = """[grid]
nx = {nx}
ny = {ny}
nz = {nz}
lx = 8.0
ly = 6.0
lz = 8.0
[fluid]
rho = 1.0
mu = 10.0
[walls]
velocity = 3.0
[particles]
radius = 1.0
count = 1
placement = "centre"
capillary = 0.2
viscosity_ratio = 1.0
[time]
end_strain = {strain}
cfl = {cfl}
viscous = "{scheme}"
[output]
dir = "{dir}"
progress_every = 200
series_every = 5
profiles_every = 0
fields_every = 0.0
checkpoint_every = 0
"""

STARTUP = """[grid]
nx = 4
ny = {ny}
nz = 4
lx = {lx}
ly = 10.0
lz = {lx}
[fluid]
rho = 1.0
mu = 10.0
[walls]
velocity = 5.0
[time]
end_time = 0.25
cfl = 0.9
dt_max = {dt_max}
viscous = "{scheme}"
[initial]
type = "rest"
[output]
dir = "{dir}"
progress_every = 0
series_every = 0
profiles_every = 0
fields_every = 0.0
checkpoint_every = 0
"""


def particle_runs(strain):
    runs = []
    for ppr in (3, 4, 6, 8, 12):
        runs.append((f"particle_implicit_r{ppr}", "particle", ppr, "implicit", 0.9))
    for cfl in (0.45, 0.225):
        runs.append((f"particle_implicit_r6_cfl{cfl}", "particle", 6, "implicit", cfl))
    runs.append(("particle_explicit_r4", "particle", 4, "explicit", 0.9))
    return [(n, k, p, s, c, strain) for n, k, p, s, c in runs]


def startup_runs():
    runs = []
    for scheme in ("explicit", "implicit"):
        for ny in (10, 20, 40, 80):
            runs.append((f"startup_{scheme}_ny{ny}", "startup", ny, scheme, 1e30))
    for dt in (0.05, 0.025, 0.0125, 0.00625):
        runs.append((f"startup_implicit_ny80_dt{dt}", "startup", 80, "implicit", dt))
    return runs


def run_one(name, text, threads):
    d = os.path.join(OUT, name)
    if os.path.exists(os.path.join(ROOT, d, "summary.json")):
        print(f"speed_error: {name}: done before, kept")
        return
    os.makedirs(os.path.join(ROOT, OUT, "cases"), exist_ok=True)
    case = os.path.join(OUT, "cases", name + ".toml")
    with open(os.path.join(ROOT, case), "w") as f:
        f.write(text)
    subprocess.run(["rm", "-rf", os.path.join(ROOT, d)], check=True)
    print(f"speed_error: running {name}", flush=True)
    log = open(os.path.join(ROOT, OUT, name + ".log"), "w")
    subprocess.run([os.path.join(ROOT, "scripts/toolchain.sh"), "run", "env", f"OMP_NUM_THREADS={threads}",
                    os.environ.get("SOFTFLOW_BIN", "build/softflow"), case],
                   cwd=ROOT, check=True, stdout=log, stderr=subprocess.STDOUT)


def cmd_run(a):
    if a.only in (None, "startup"):
        for name, _, ny, scheme, dt in startup_runs():
            # cubic cells (dx = dy), as in the real cases: the implicit step's
            # advective floor |V_w| / dx then sets dt ~ dy
            run_one(name, STARTUP.format(ny=ny, lx=4 * 10.0 / ny, scheme=scheme, dt_max=dt,
                                         dir=os.path.join(OUT, name)), a.threads)
    if a.only in (None, "particle"):
        for name, _, ppr, scheme, cfl, strain in particle_runs(a.strain):
            text = PARTICLE.format(nx=8 * ppr, ny=6 * ppr, nz=8 * ppr, strain=strain, cfl=cfl, scheme=scheme,
                                   dir=os.path.join(OUT, name))
            run_one(name, text, a.threads)


def last_row(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return rows[-1]


def startup_exact(y, t, h=5.0, V=5.0, nu=10.0):
    eta = y / h
    s = eta
    for n in range(1, 20000):
        d = math.exp(-nu * n * n * math.pi ** 2 * t / h ** 2)
        if d < 1e-20:
            break
        s += 2 * (-1) ** n / (n * math.pi) * math.sin(n * math.pi * eta) * d
    return V * s


def startup_error(d):
    import h5py
    import numpy as np
    f = sorted(glob.glob(os.path.join(d, "fields_*.h5")))[-1]
    with h5py.File(f) as h:
        u = np.array(h["u"])
        t = float(h.attrs["time"])
    ny = u.shape[1]
    prof = u.mean(axis=(0, 2))
    dy = 10.0 / ny
    return max(abs(prof[j] - startup_exact(-5 + (j + 0.5) * dy, t)) for j in range(ny)) / 5.0


def cmd_report(a):
    rows = []
    for name, _, ny, scheme, dt in startup_runs():
        d = os.path.join(ROOT, OUT, name)
        if not os.path.exists(os.path.join(d, "summary.json")):
            continue
        s = json.load(open(os.path.join(d, "summary.json")))
        rows.append({"sweep": "startup", "run": name, "scheme": scheme, "resolution": f"ny={ny}",
                     "dt": "cfl" if dt > 1 else dt, "steps": s["performance"]["steps"],
                     "wall_s": s["performance"]["wall_seconds"], "err_u": startup_error(d)})
    part = {}
    for name, _, ppr, scheme, cfl, strain in particle_runs(a.strain):
        d = os.path.join(ROOT, OUT, name)
        if not os.path.exists(os.path.join(d, "summary.json")):
            continue
        s = json.load(open(os.path.join(d, "summary.json")))
        phi = (4 / 3 * math.pi) / (8 * 6 * 8)
        mu = float(last_row(os.path.join(d, "series.csv"))["mu_eff"])
        T = float(last_row(os.path.join(d, "particles.csv"))["taylor_mean"])
        part[name] = {"sweep": "particle", "run": name, "scheme": scheme, "resolution": f"{ppr} ppr",
                      "dt": f"cfl {cfl}", "steps": s["performance"]["steps"],
                      "wall_s": s["performance"]["wall_seconds"], "T": T, "intrinsic": (mu - 1) / phi, "ppr": ppr}
    ref = part.get("particle_implicit_r12")
    notes = []
    if ref:
        for r in part.values():
            r["err_T"] = abs(r["T"] - ref["T"]) if r is not ref else None
            r["err_intrinsic"] = abs(r["intrinsic"] - ref["intrinsic"]) if r is not ref else None
        r8 = part.get("particle_implicit_r8")
        r6 = part.get("particle_implicit_r6")
        if r8 and r6:
            for key in ("T", "intrinsic"):
                e6, e8 = abs(r6[key] - ref[key]), abs(r8[key] - ref[key])
                # observed order from 6, 8 against 12, then the 12-ppr run's own error by Richardson
                p = math.log(e6 / e8) / math.log(8 / 6) if e6 > 0 and e8 > 0 else float("nan")
                rich = abs(r8[key] - ref[key]) / ((12 / 8) ** p - 1) if p == p and p > 0 else float("nan")
                notes.append(f"{key}: observed order {p:.2f} (6, 8 ppr against 12); the 12-ppr value "
                             f"{ref[key]:.4f} is itself off by about {rich:.2g} (Richardson)")
    rows += list(part.values())
    os.makedirs(RESULTS, exist_ok=True)
    keys = ["sweep", "run", "scheme", "resolution", "dt", "steps", "wall_s", "err_u", "T", "err_T", "intrinsic",
            "err_intrinsic"]
    with open(os.path.join(RESULTS, "speed_error.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow(r)
    with open(os.path.join(RESULTS, "speed_error.md"), "w") as f:
        f.write("# Speed against error\n\nProduced by `perf/speed_error.py run` then `perf/speed_error.py report` "
                "(see its docstring for the set-up). One OpenMP thread per run on the 2-core CI-class VM; "
                "wall times from each run's summary.json.\n\n")
        f.write("| run | scheme | resolution | dt | steps | wall s | error |\n|---|---|---|---|---|---|---|\n")
        for r in rows:
            if r["sweep"] == "startup":
                err = f"u: {r['err_u']:.2e}"
            else:
                err = (f"T = {r['T']:.4f}, [mu] = {r['intrinsic']:.3f}" +
                       ("" if r.get("err_T") is None else f"; dT = {r['err_T']:.2e}, d[mu] = {r['err_intrinsic']:.2e}"))
            f.write(f"| {r['run']} | {r['scheme']} | {r['resolution']} | {r['dt']} | {r['steps']} | "
                    f"{r['wall_s']:.1f} | {err} |\n")
        if notes:
            f.write("\n" + "\n".join("- " + n for n in notes) + "\n")
        payoff(f)
    plot(rows)
    print(f"speed_error: wrote {RESULTS}/speed_error.md, .csv, .png")


def payoff(f):
    """The explicit/implicit comparisons of perf/viscous_payoff.sh, when their tables are here."""
    path = os.path.join(RESULTS, "viscous_payoff_r5.csv")
    if not os.path.exists(path):
        return
    f.write("\n## Explicit against implicit viscosity (perf/viscous_payoff.sh, 5 points per radius)\n\n"
            "Steps and the final averages; wall times in viscous_payoff_r5.md (taken under uneven load; "
            "equal-load ratios there).\n\n| case | run | grid | steps | T | mu/mu_f |\n|---|---|---|---|---|---|\n")
    with open(path) as c:
        for r in csv.DictReader(c):
            def pm(m, e):
                return f"{float(m):.4f}" + (f" ± {float(e):.4f}" if e not in ("", "None") else "")
            f.write(f"| {r['case']} | {r['run']} | {r['grid']} | {r['steps']} | {pm(r['taylor'], r['taylor_stderr'])} | "
                    f"{pm(r['mu_eff'], r['mu_eff_stderr'])} |\n")


def plot(rows):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    for scheme, mk in (("explicit", "s"), ("implicit", "o")):
        s = [r for r in rows if r["sweep"] == "startup" and r["scheme"] == scheme and r["dt"] == "cfl"]
        if s:
            ax[0].loglog([r["wall_s"] for r in s], [r["err_u"] for r in s], mk + "-", label=f"{scheme}, dt from CFL")
        t = [r for r in rows if r["sweep"] == "startup" and r["scheme"] == scheme and r["dt"] != "cfl"]
        if t:
            ax[0].loglog([r["wall_s"] for r in t], [r["err_u"] for r in t], mk + ":", label=f"{scheme}, ny = 80, dt_max")
    ax[0].set_xlabel("wall time [s]")
    ax[0].set_ylabel("max |<u> - u_exact| / V_w")
    ax[0].set_title("start-up Couette flow, t = 0.1 h^2/nu")
    ax[0].legend(fontsize=8)
    for key, lab, mk in (("err_T", "T", "o"), ("err_intrinsic", "[mu]", "^")):
        for scheme, ls in (("implicit", "-"), ("explicit", "--")):
            s = [r for r in rows if r["sweep"] == "particle" and r["scheme"] == scheme and r.get(key)
                 and r["dt"] == "cfl 0.9"]
            if s:
                ax[1].loglog([r["wall_s"] for r in s], [r[key] for r in s], mk + ls, label=f"{lab}, {scheme}")
                for r in s:
                    ax[1].annotate(r["resolution"], (r["wall_s"], r[key]), fontsize=7)
    ax[1].set_xlabel("wall time [s]")
    ax[1].set_ylabel("|value - value(12 ppr)|")
    ax[1].set_title("one sphere, Ca = 0.2: error against the 12-ppr run")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(RESULTS, "speed_error.png"), dpi=130)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("command", choices=["run", "report"])
    ap.add_argument("--only", choices=["particle", "startup"])
    ap.add_argument("--strain", type=float, default=1.0)
    ap.add_argument("--threads", type=int, default=1)
    a = ap.parse_args()
    os.chdir(ROOT)
    return cmd_run(a) if a.command == "run" else cmd_report(a)


if __name__ == "__main__":
    sys.exit(main())
