#!/usr/bin/env python3
"""The stationarity check of issue 12 (scripts/stationarity.py check), on
synthetic run folders whose answer is known: a steady noisy run passes and
shows no trend; a run that climbs by 1.6% over strain [10, 50) passes the
window test (its windows differ by 0.8%, under the 1% bound) and its trend
is reported as a drift of 1.6% per 40 strain units; det B out of [0.97,
1.03], the stress in low-phi cells and a volume change each fail the run;
the trend of where a suspension's solid sits across the gap (profiles);
whether the window test resolves the answer (a limit cycle of one period
per window passes it with a tolerance of 22% and a 10-strain swing of 45%);
the count of phi's connected bodies that the shape report gives; what
carries phi's z axis (creep); and the
windows' standard error with correlated data (the autocorrelation time
read from AR(1) series, and the false-alarm rate of the window test).
Exits non-zero if any check failed."""
import csv
import json
import math
import os
import random
import subprocess
import sys
import tempfile

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
SCRIPT = os.path.join(ROOT, "scripts", "stationarity.py")
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import stationarity as st  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from py_checks import check, finish  # noqa: E402


BOX = [16.0, 10.0, 16.0]
VOL = 4 / 3 * math.pi  # one sphere of radius 1: Phi = 0.0016, a dilute run ([mu])


def write_run(folder, mu=lambda s: 2.5, noise=0.01, detb=(0.999, 1.001), lowphi=0.02, volume=lambda s: VOL,
              strain_end=50.0, rows=2001, seed=1, taylor=lambda s: 0.2, mu_eff=None, shear_rate=1.0):
    """A run folder: series.csv and particles.csv every 0.025 strain units,
    [mu](strain) plus white noise of relative size `noise` (or mu/mu_f =
    mu_eff(strain) where given, for a dense run), T = taylor(strain) (0.2)
    with the same noise, time = strain / shear_rate, and summary.json."""
    rng = random.Random(seed)
    os.makedirs(folder)
    phi = VOL / (BOX[0] * BOX[1] * BOX[2])
    with open(os.path.join(folder, "series.csv"), "w", newline="") as fs, \
            open(os.path.join(folder, "particles.csv"), "w", newline="") as fp:
        ws = csv.writer(fs)
        wp = csv.writer(fp)
        ws.writerow(["step", "time", "strain", "mu_eff", "solid_volume", "detb_raw_min", "detb_raw_max",
                     "unimodular_removed", "elastic_share_lowphi", "solid_share_lowphi"])
        wp.writerow(["step", "strain", "taylor_mean", "taylor_b_mean", "a_mean", "b_mean", "c_mean"])
        for i in range(rows):
            s = strain_end * i / (rows - 1)
            m = mu(s) * (1 + noise * rng.gauss(0, 1))
            eff = 1 + phi * m if mu_eff is None else mu_eff(s) * (1 + noise * rng.gauss(0, 1))
            ws.writerow([10 * i, s / shear_rate, s, eff, volume(s), detb[0], detb[1], 1e-6, lowphi, 0.001])
            t = taylor(s) * (1 + noise * rng.gauss(0, 1))
            wp.writerow([10 * i, s, t, t, 1.2, 0.83, 1.0])
    json.dump({"case": {"box": BOX, "grid": [64, 40, 64]}, "performance": {"wall_seconds": 100.0}},
              open(os.path.join(folder, "summary.json"), "w"))
    return folder


def run_check(folder):
    return st.check(st.Run(folder), [10.0, 30.0, 50.0])


with tempfile.TemporaryDirectory() as tmp:
    # 1. The trend fit recovers a known slope through noise-free data.
    x = [i * 0.1 for i in range(400)]
    slope, se = st.trend(x, [3 - 0.02 * v for v in x])
    check("trend of a line", abs(slope + 0.02) < 1e-12 and se < 1e-12, f"slope {slope:.3e}, se {se:.1e}")

    # 2. Steady with 1% noise: passes, and no quantity drifts beyond 2 se
    #    (for the mean of white noise, a false alarm at 2 se has a chance of
    #    about 5% per quantity; the seed is fixed, so the result is too).
    r = run_check(write_run(os.path.join(tmp, "steady")))
    t = r["trends"]["[mu]"]
    check("steady run passes", r["pass"], f"[mu] {r['mu1'][0]:.4f} / {r['mu2'][0]:.4f}")
    check("steady run: no trend", abs(t[0]) <= 2 * t[1] and abs(t[0]) < 0.005,
          f"drift {100 * t[0]:+.3f} ± {100 * t[1]:.3f}% per 40")

    # 3. Climbing by 1.6% over [10, 50): the windows agree (0.8% < 1%), the
    #    trend reads the drift to a tenth of itself and flags it.
    r = run_check(write_run(os.path.join(tmp, "climbing"), mu=lambda s: 2.5 * (1 + 0.016 * (s - 30) / 40),
                            noise=0.002, seed=2))
    t = r["trends"]["[mu]"]
    check("slow climb passes the windows", r["mu_ok"] and r["pass"],
          f"[mu] {r['mu1'][0]:.4f} / {r['mu2'][0]:.4f} (tol {r['tol_mu']:.4f})")
    check("slow climb: trend measured", abs(t[0] - 0.016) < 0.0016 and abs(t[0]) > 2 * t[1],
          f"drift {100 * t[0]:+.3f} ± {100 * t[1]:.3f}% per 40 (want +1.6%)")

    # 4. Climbing by 3%: the windows disagree (1.5% > 1%).
    r = run_check(write_run(os.path.join(tmp, "fast"), mu=lambda s: 2.5 * (1 + 0.03 * (s - 30) / 40),
                            noise=0.002, seed=3))
    check("faster climb fails", not r["mu_ok"] and not r["pass"], f"[mu] {r['mu1'][0]:.4f} / {r['mu2'][0]:.4f}")

    # 5. Each other condition fails a steady run on its own.
    for name, kw, key in (("det B 1.031", {"detb": (0.999, 1.031)}, "detb_ok"),
                          ("low-phi share 5%", {"lowphi": 0.05}, "lowphi_ok"),
                          ("volume 2e-12", {"volume": lambda s: VOL * (1 + 2e-12 * s / 50)}, "volume_ok")):
        r = run_check(write_run(os.path.join(tmp, name.replace(" ", "_")), **kw))
        check(f"{name} fails", not r[key] and not r["pass"], f"{key} = {r[key]}")

    # 6. The command line: exit 0 when every run passes, 1 when one fails,
    #    and the trend table in its output.
    ok = subprocess.run([sys.executable, SCRIPT, "check", os.path.join(tmp, "steady")], capture_output=True,
                        text=True)
    bad = subprocess.run([sys.executable, SCRIPT, "check", os.path.join(tmp, "steady"), os.path.join(tmp, "fast")],
                         capture_output=True, text=True)
    check("exit codes", ok.returncode == 0 and bad.returncode == 1, f"{ok.returncode}, {bad.returncode}")
    check("trend table printed", "Linear trends over [10, 50)" in ok.stdout and "| steady |" in ok.stdout,
          ok.stdout.splitlines()[-1] if ok.stdout else ok.stderr)

    # 6b. Where the solid sits across the gap (a dense run's profiles): a
    #    share w of the solid at |y| = 2 and the rest at |y| = 0.5, with w
    #    falling linearly from 0.5 at strain 10 to 0.25 at 50, so mean |y| =
    #    0.5 + 1.5 w goes 1.25 -> 0.875: -0.375 over [10, 50), relative to the
    #    mean of the rows at strain 10, 10.25 ... 49.75 (1.06367), -35.25% per
    #    40, read exactly from noise-free profiles.
    dense_vol = 0.11 * BOX[0] * BOX[1] * BOX[2]
    run = write_run(os.path.join(tmp, "migrating"), volume=lambda s: dense_vol)
    with open(os.path.join(run, "profiles_series.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["step", "strain", "row", "y_centre", "phi_mean"])
        for i in range(201):
            strain = 0.25 * i
            share = 0.5 - 0.25 * min(max(strain - 10, 0), 40) / 40
            for k, (yc, ph) in enumerate(((-2, share / 2), (-0.5, (1 - share) / 2), (0.5, (1 - share) / 2),
                                          (2, share / 2))):
                w.writerow([i, strain, k, yc, ph])
            w.writerow([i, strain, 4, "", ""])  # the wall faces' row
    spread = st.solid_spread(run)
    check("solid spread read", abs(spread[0][1] - 1.25) < 1e-12 and abs(spread[-1][1] - 0.875) < 1e-12,
          f"{spread[0]}, {spread[-1]}")
    t = run_check(run)["trends"][st.SPREAD]
    want = -0.375 / (0.5 + 1.5 * (0.5 - 0.25 * (29.875 - 10) / 40))
    check("migration trend", abs(t[0] - want) < 1e-9, f"{100 * t[0]:+.3f}% per 40 (want {100 * want:+.3f}%)")

    # 6c. The window table (`windows`): the same migrating run's mean |y|
    #    per 10-strain window, and the share of its solid within one radius
    #    of a wall (|y| > 4 in this 10-high box): none here, as all of it
    #    sits at |y| <= 2; then a copy with the outer share moved to |y| =
    #    4.5, where that share is w itself, 0.5 over [0, 10) and 0.5 - 0.25
    #    (s - 10) / 40 after (window means of the rows at 10, 10.25 ...).
    rows = st.window_means(st.Run(run), 10.0)
    mean_w = lambda lo: sum(0.5 - 0.25 * (s / 4 - 10) / 40 for s in range(4 * lo, 4 * lo + 40)) / 40  # noqa: E731
    check("windows: 5 of them, mean |y| and no wall share",
          len(rows) == 5 and abs(rows[0]["abs_y"] - 1.25) < 1e-12
          and abs(rows[2]["abs_y"] - (0.5 + 1.5 * mean_w(20))) < 1e-12 and max(r["wall"] for r in rows) == 0,
          f"{[(r['from'], round(r['abs_y'], 4), r['wall']) for r in rows]}")
    # the cells next to the walls: the outermost rows (|y| = 2 here), phi w / 2 in each
    check("windows: phi in the cells next to a wall",
          abs(rows[0]["wall_cells"] - 0.25) < 1e-12 and abs(rows[2]["wall_cells"] - mean_w(20) / 2) < 1e-12,
          f"{[(r['from'], round(r['wall_cells'], 5)) for r in rows]}")
    near = write_run(os.path.join(tmp, "near_walls"), volume=lambda s: dense_vol)
    with open(os.path.join(run, "profiles_series.csv")) as f, \
            open(os.path.join(near, "profiles_series.csv"), "w", newline="") as g:
        w = csv.writer(g)
        for r in csv.reader(f):
            w.writerow(r[:3] + [{"-2": "-4.5", "2": "4.5"}.get(r[3], r[3])] + r[4:])
    rows = st.window_means(st.Run(near), 10.0)
    check("windows: the share within r of a wall",
          abs(rows[0]["wall"] - 0.5) < 1e-12 and abs(rows[3]["wall"] - mean_w(30)) < 1e-12,
          f"{[(r['from'], round(r['wall'], 5)) for r in rows]} (want 0.5, ..., {mean_w(30):.5f} at 30)")
    out = subprocess.run([sys.executable, SCRIPT, "windows", near], capture_output=True, text=True)
    check("windows printed", "| [40, 50) |" in out.stdout and "50.00%" in out.stdout, out.stdout[-400:] + out.stderr)

    # 6d. What the window test can resolve. A limit cycle of one period per
    #     window (period 20 strain units, [mu] and T +-35%, as the thin
    #     setting's Ca = 2 sphere, results/README.md round 40) has equal
    #     window means and passes; its correlation time (about 1.5 strain
    #     units by Sokal's window on a sine of 800 rows) makes the tolerance
    #     about 20% of [mu] and of T (22% read), so it does not resolve the
    #     10% / 5% the issue asks of the answer; its 10-strain windows (half periods,
    #     mean +-0.35 * 2/pi) swing by 4 * 0.35 / pi = 44.6%. The steady run
    #     resolves both, and its swing is its noise (400 rows a window, 1%:
    #     under 0.5%).
    cycle = lambda s: 1 + 0.35 * math.sin(2 * math.pi * s / 20)  # noqa: E731
    r = run_check(write_run(os.path.join(tmp, "cycle"), mu=lambda s: 2.5 * cycle(s),
                            taylor=lambda s: 0.2 * cycle(s), noise=0.002, seed=4))
    want = 4 * 0.35 / math.pi
    check("limit cycle: passes the windows, does not resolve",
          r["pass"] and not r["resolves"] and r["rel_tol_mu"] > 0.1 and r["rel_tol_t"] > 0.05,
          f"pass {r['pass']}, tol/value {100 * r['rel_tol_mu']:.1f}% / {100 * r['rel_tol_t']:.1f}%")
    check("limit cycle: the swing is its amplitude",
          abs(r["swing_mu"] - want) < 0.01 and abs(r["swing_t"] - want) < 0.01,
          f"{100 * r['swing_mu']:.2f}% / {100 * r['swing_t']:.2f}% (want {100 * want:.2f}%)")
    r = run_check(os.path.join(tmp, "steady"))
    check("steady run resolves, swing under 0.5%", r["resolves"] and max(r["swing_mu"], r["swing_t"]) < 0.005,
          f"tol/value {100 * r['rel_tol_mu']:.2f}% / {100 * r['rel_tol_t']:.2f}%, "
          f"swing {100 * r['swing_mu']:.2f}% / {100 * r['swing_t']:.2f}%")
    # a dense run (Phi = 0.11, mu/mu_f = 1.3 with 0.1% noise): the 1% bound,
    # 0.013, is the tolerance, and it is read against mu/mu_f - 1 = 0.3
    r = run_check(write_run(os.path.join(tmp, "dense_tol"), volume=lambda s: dense_vol,
                            mu_eff=lambda s: 1.3, noise=0.001, seed=5))
    check("dense: tolerance over the particles' part", abs(r["rel_tol_mu"] - 0.013 / 0.3) < 1e-3,
          f"{100 * r['rel_tol_mu']:.3f}% (want {100 * 0.013 / 0.3:.3f}%)")
    out = subprocess.run([sys.executable, SCRIPT, "check", os.path.join(tmp, "cycle")], capture_output=True,
                         text=True)
    check("resolution columns printed", "| NO (mu, T) |" in out.stdout, out.stdout[:300] + out.stderr)

# 7. Bodies of phi (the shape report's fusion count): two balls apart are
#    two; one cut by the periodic x boundary is one; two touching only
#    across the walls (y) stay two; a lower level joins a thin bridge.
import numpy as np  # noqa: E402  (numpy: in the toolchain's root, as h5py for `shape`)

z, y, x = np.meshgrid(np.arange(16), np.arange(12), np.arange(20), indexing="ij")


def ball(cz, cy, cx, r=3.0):
    return (((z - cz) ** 2 + (y - cy) ** 2 + (x - cx) ** 2) <= r * r).astype(float)


two = ball(8, 6, 5) + ball(8, 6, 14)
wrapped = ball(8, 6, 0)  # half of it at x = 17..19
walls = ball(8, 0, 10, 2.0) + ball(8, 11, 10, 2.0)  # at the bottom and top wall
bridged = two.copy()
bridged[8, 6, 8:12] = 0.6  # a strip of phi = 0.6 between the two
got = (st.clusters(two, 0.5), st.clusters(wrapped, 0.5), st.clusters(walls, 0.5), st.clusters(bridged, 0.5),
       st.clusters(bridged, 0.9))
check("bodies of phi", got == (2, 1, 2, 1, 2), f"{got} (want (2, 1, 2, 1, 2))")

# 8. Where the low-phi stress sits (`lowphi`): a sphere of radius 1 (phi = 1,
#    B = I) at 4 cells per radius, with a thread of phi = 0.05 along +x from
#    its surface (8 cells, centres at x = 1.125 ... 2.875: 1 within 1.25
#    radii, 3 between 1.25 and 2, 4 beyond) and a detached 2x2x2 drop of
#    phi = 0.05 at x = -5 (beyond 2). B_xy = 1 in those cells only, so they
#    carry all the stress: shares 1/16, 3/16, 12/16 and 8/16 detached.
import h5py  # noqa: E402

with tempfile.TemporaryDirectory() as tmp:
    run = write_run(os.path.join(tmp, "threads"), rows=41, strain_end=2.0)
    n = (64, 40, 64)
    c = [(np.arange(m) + 0.5) * 0.25 - L / 2 for m, L in zip(n, BOX)]  # cell centres, x y z
    X, Y, Z = np.meshgrid(*c, indexing="ij")
    phi = (X * X + Y * Y + Z * Z <= 1.0).astype(float)
    bxy = np.zeros(n)
    row = (np.abs(Y - 0.125) < 1e-9) & (np.abs(Z - 0.125) < 1e-9)
    thread = row & (X > 1.0) & (X < 3.0)
    drop = (np.abs(X + 5.0) < 0.25) & (np.abs(Y) < 0.25) & (np.abs(Z) < 0.25)
    for m in (thread, drop):
        phi[m] = 0.05
        bxy[m] = 1.0
    for name in ("fields_00000000.h5", "fields_00000400.h5"):
        with h5py.File(os.path.join(run, name), "w") as h:  # stored z, y, x, as softflow writes
            for key, v in (("phi", phi), ("Bxx", np.ones(n)), ("Bxy", bxy), ("Bxz", np.zeros(n)),
                           ("Byy", np.ones(n)), ("Byz", np.zeros(n)), ("Bzz", np.ones(n))):
                h[key] = v.transpose(2, 1, 0)
    out = subprocess.run([sys.executable, SCRIPT, "lowphi", run], capture_output=True, text=True)
    last = out.stdout.strip().splitlines()[-1].split("|")[1:-1] if out.stdout.strip() else []
    got = [x.strip() for x in last]
    want = ["threads", "2.0", "100.0%", "6.2%", "18.8%", "75.0%", "50.0%"]
    check("low-phi stress by distance (thread, drop)", got[:7] == want, f"{got} (want {want} ...)" + out.stderr[-300:])

# 8b. What carries phi's z axis (`creep`): a sphere of radius 1 at 4 cells
#     per radius with a smooth edge (phi = (1 - tanh((r - 1) / 0.25)) / 2),
#     centred 0.3 from the periodic z seam and between cell centres in x and
#     y, shear rate 2. At strain 10 every
#     cell moves with w = eps dz (eps = 1e-3 a time unit): the axis grows at
#     eps per time, eps / 2 per strain, 2.00% per 40 strain units, summed
#     over the bands. At strain 20 the sphere is stretched along z by 2% and
#     only its 0.1 <= phi < 0.5 cells move: the other bands read 0, and the
#     measured change, 40 ln(1.02) / 10 = 7.92% per 40, to the printed
#     0.01 (a smooth edge's moments on the grid are exact to far less; a
#     linear edge 2 cells wide, sampled, read 8.36).
with tempfile.TemporaryDirectory() as tmp:
    run = write_run(os.path.join(tmp, "creep"), rows=41, strain_end=20.0, shear_rate=2.0)
    n = (64, 40, 64)
    c = [(np.arange(m) + 0.5) * 0.25 for m in n]
    X, Y, Z = np.meshgrid(*c, indexing="ij")
    dz = (Z - 0.3 + 8.0) % 16.0 - 8.0

    def sphere(stretch):
        return 0.5 * (1 - np.tanh((np.sqrt((X - 8.1) ** 2 + (Y - 5.05) ** 2 + (dz / stretch) ** 2) - 1) / 0.25))

    eps = 1e-3
    edge = (sphere(1.02) >= 0.1) & (sphere(1.02) < 0.5)
    for name, p, w in (("fields_00000000.h5", sphere(1.0), 0 * X), ("fields_00000200.h5", sphere(1.0), eps * dz),
                       ("fields_00000400.h5", sphere(1.02), np.where(edge, eps * dz, 0.0))):
        with h5py.File(os.path.join(run, name), "w") as h:  # stored z, y, x, as softflow writes
            h["phi"] = p.transpose(2, 1, 0)
            h["w"] = w.transpose(2, 1, 0)
    out = subprocess.run([sys.executable, SCRIPT, "creep", run], capture_output=True, text=True)
    rows = [[x.strip().rstrip("%") for x in r.split("|")[1:-1]] for r in out.stdout.splitlines()[2:]]
    ok = len(rows) == 2
    check("creep: a row per snapshot after the first", ok, out.stdout + out.stderr[-300:])
    if ok:
        first, second = rows
        check("creep: a uniform stretch eps z reads eps per time in all", first[8] == "+2.00" and
              float(first[4]) > 0 and first[9] == "-", f"{first}")
        check("creep: only the moving band carries it", second[4:8] == ["+0.00", "+0.00", second[6], "+0.00"]
              and float(second[6]) > 0, f"{second}")
        check("creep: measured axis change of a 2% stretch", abs(float(second[9]) - 7.92) < 0.015, f"{second[9]}")
        # the pole: phi = 1/2 at r = 1 (1.02 stretched), through a column between cells (fractions
        # a = 0.9, b = 0.7 in x and y), across the seam. The bilinear column misses phi's curvature
        # across the axis, phi'/r = -2 at the pole: by (a(1 - a) + b(1 - b)) h^2 / 2 * 2 = 0.019 in
        # phi, 0.0094 in z at the edge's slope 2; 0.012 allowed
        check("creep: the pole at phi = 1/2", abs(float(first[3]) - 1.0) < 0.012 and
              abs(float(second[3]) - 1.02) < 0.012, f"{first[3]}, {second[3]}")
    # the centroid across the seam: the same sphere moved to mid-box gives the same axis
    a_seam, _ = st.creep_rows(sphere(1.0), 0 * X, 16.0, 1.0)
    a_mid, _ = st.creep_rows(np.roll(sphere(1.0), 32, axis=2), 0 * X, 16.0, 1.0)
    check("creep: the axis across the periodic seam", abs(a_seam - a_mid) < 1e-12, f"{a_seam} {a_mid}")

# 9. The windows' standard error with correlated data. AR(1) series
#    x_k = rho x_{k-1} + e_k have tau = (1 + rho) / (1 - rho) rows.
def ar1(n, rho, rng):
    x, v = [], rng.gauss(0, 1) / math.sqrt(1 - rho * rho)  # started stationary
    for _ in range(n):
        v = rho * v + rng.gauss(0, 1)
        x.append(v)
    return x


rng = random.Random(5)
# 9a. integrated_time reads a known tau from a long series. Its own
#     relative error is about sqrt(2 (2 M + 1) / n) (Sokal 1997), M ~ 5 tau
#     the window: 6% for tau 9 and 2% for white noise over 50000 rows;
#     2.5 of those allowed.
got = st.integrated_time(ar1(50000, 0.8, rng))
check("integrated time of AR(1), tau 9", abs(got / 9 - 1) < 0.15, f"{got:.2f} rows (want 9)")
got = st.integrated_time(ar1(50000, 0.0, rng))
check("integrated time of white noise, tau 1", abs(got - 1) < 0.05, f"{got:.3f} rows (want 1)")

# 9b. The false-alarm rate of the window test on stationary data. The
#     span's correlation time is 3 strain units at 10 rows a strain (tau 30
#     rows, as the dense runs' T: 2-4 strain units), windows of 20 strain
#     (200 rows). At 2 true standard errors 4.6% of pairs fail. Each
#     window's own 10 batch means (20 rows a batch, under tau) make the
#     error too small: 22.5% false alarms here, the span's tau 9.5% (the
#     span's tau is itself estimated from 13 correlation times, a little
#     low). Limits: the span's tau under 12%, the batches over 15%, each
#     more than one sampling error of 200 pairs (2%, 3%) from what it read.
rho = 29 / 31
alarms = {"batches": 0, "tau": 0}
pairs = 200
for _ in range(pairs):
    x = ar1(400, rho, rng)
    a, b = x[:200], x[200:]
    tau = st.integrated_time(x)
    for name, (m1, s1), (m2, s2) in (("batches", st.batch_mean(a), st.batch_mean(b)),
                                     ("tau", st.mean_se(a, tau), st.mean_se(b, tau))):
        alarms[name] += abs(m2 - m1) > 2 * math.hypot(s1, s2)
rate = {k: v / pairs for k, v in alarms.items()}
check("false alarms with the span's tau near nominal", rate["tau"] < 0.12, f"{100 * rate['tau']:.1f}% (nominal 4.6%)")
check("false alarms with 10 batch means too many", rate["batches"] > 0.15, f"{100 * rate['batches']:.1f}%")

# 9c. check() reports the span's tau in strain units: the steady run's white
#     noise (40 rows a strain) has tau 1 row, 0.025 strain units (1600 rows
#     of span: the estimate within 8%; 20% allowed).
with tempfile.TemporaryDirectory() as tmp:
    r = run_check(write_run(os.path.join(tmp, "white")))
    got = r["tau"]
    check("tau reported in strain units", all(abs(got[k] / 0.025 - 1) < 0.2 for k in ("mu", "T")), f"{got}")
    b = st.check(st.Run(os.path.join(tmp, "white")), [10.0, 30.0, 50.0], se="batches")
    check("--se batches: no tau, a verdict", b["tau"] == {} and b["pass"], f"{b['tau']}, {b['pass']}")

finish()
