#!/usr/bin/env python3
"""The exact dilute theory in time: one viscous neo-Hookean sphere alone in
unbounded simple shear at zero Reynolds number, from rest (B = I) to its
steady state.

  scripts/ellipsoid_theory.py run --ca 2 [--k 1] [--strain 60] [--dt 0.002] [--csv OUT.csv]
  scripts/ellipsoid_theory.py check [--spec PATH/dilute_theory.csv]
  scripts/ellipsoid_theory.py steady-b --ca 2 [--k 1]   (the case override
      particles.initial_b=[...] that starts a run from the steady shape)
  (numpy: run it through scripts/toolchain.sh run python3 ... on a machine
  without it)

shared/spec/dilute_theory.csv holds this problem's steady state only. Runs
are judged by windows from strain 10 on, so the question of how long the
particle takes to get there (at large Ca it overshoots and relaxes slowly)
needs the transient too. The particle stays an exact ellipsoid with uniform
interior fields (Eshelby; Gao, Hu & Ponte Castaneda, J. Fluid Mech. 687,
2011), so B(t) obeys an ODE:

  dB/dt = L B + B L^T,   L = D_in + W_in, the interior velocity gradient,

with the ellipsoid x^T B^-1 x = r^2 (semi-axes r sqrt(eig B)). Its interior
stress is -p I + 2 K mu D_in + tau, tau = G (B - I). The equivalent
inclusion of an incompressible (nu = 1/2) matrix of viscosity mu: the
eigen-rate e* = (1 - K) D_in - tau / (2 mu) gives
  D_in = D_inf + S : e*,   W_in = W_inf + Pi : e*,
with Eshelby's S and Pi of the current ellipsoid (Mura, Micromechanics of
Defects in Solids, 1987, section 11), in its principal frame (no sum):
  S_iiii = 3 a_i^2 I_ii / (4 pi),  S_iijj = a_j^2 I_ij / (4 pi),
  S_ijij = (a_i^2 + a_j^2) I_ij / (8 pi),  Pi_ijij = (I_j - I_i) / (8 pi),
  I_i = 2 pi a1 a2 a3 int_0^inf ds / ((a_i^2 + s) Delta(s)),
  I_ij = the same with (a_i^2 + s)(a_j^2 + s),  Delta = prod_k sqrt(a_k^2 + s).
The particle's stresslet per volume is 2 mu (K - 1) D_in + tau, so
[mu] = (2 (K - 1) D_in,xy + tau_xy) / (mu gamma) and N1 / Phi its xx - yy
difference over mu gamma (units of METHOD.md: r = gamma = mu_f = 1,
G = 1 / Ca). Checks built in: the sphere's S is 2/5 on deviators
(Einstein's 5/2 at Ca -> 0), Pi gives Jeffery's rotation of a rigid
ellipsoid, and `check` compares the steady state with dilute_theory.csv,
computed elsewhere (every row within 0.2%: the same theory).
"""
import argparse
import csv
import math
import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# Gauss-Legendre on t in (0, 1), s = t^2 / (1 - t)^2 (the integrands fall as
# s^-5/2 and faster; 96 nodes give the sphere's integrals to 1e-12)
_T, _W = np.polynomial.legendre.leggauss(96)
_T, _W = 0.5 * (_T + 1), 0.5 * _W
_S = (_T / (1 - _T)) ** 2
_DS = _W * 2 * _T / (1 - _T) ** 3


def eshelby_integrals(a):
    """I_i and I_ij (3 x 3, symmetric; I_ii on the diagonal) of semi-axes a."""
    a2 = np.asarray(a, float) ** 2
    delta = np.sqrt(np.prod(a2[:, None] + _S[None, :], axis=0))
    g = 2 * math.pi * np.prod(a) * _DS / delta
    inv = 1.0 / (a2[:, None] + _S[None, :])
    ii = inv @ g
    iij = (inv[:, None, :] * inv[None, :, :]) @ g
    return ii, iij


def interior_rates(b, ca, k):
    """D_in and W_in (lab frame) of the ellipsoid whose B is b, in shear u = y e_x."""
    lam, q = np.linalg.eigh(b)
    a = np.sqrt(lam)
    ii, iij = eshelby_integrals(a)
    linf = np.zeros((3, 3))
    linf[0, 1] = 1.0
    dinf, winf = q.T @ (0.5 * (linf + linf.T)) @ q, q.T @ (0.5 * (linf - linf.T)) @ q
    tau = (1.0 / ca) * (np.diag(lam) - np.eye(3))  # G (B - I) in the principal frame
    tau -= np.trace(tau) / 3 * np.eye(3)          # its isotropic part goes to the pressure
    a2 = a ** 2
    s_n = np.array([[(3 if i == j else 1) * a2[j] * iij[i, j] / (4 * math.pi) for j in range(3)]
                    for i in range(3)])
    d = np.zeros((3, 3))
    # normal rates: (I - (1 - K) S_n) d = d_inf - S_n tau_n / 2 (mu = 1)
    d[np.diag_indices(3)] = np.linalg.solve(np.eye(3) - (1 - k) * s_n,
                                            np.diag(dinf) - s_n @ np.diag(tau) / 2)
    w = winf.copy()
    for i in range(3):
        for j in range(3):
            if i != j:
                s_ij = (a2[i] + a2[j]) * iij[i, j] / (8 * math.pi)
                d[i, j] = (dinf[i, j] - 2 * s_ij * tau[i, j] / 2) / (1 - (1 - k) * 2 * s_ij)
                e_ij = (1 - k) * d[i, j] - tau[i, j] / 2
                w[i, j] = winf[i, j] + 2 * (ii[j] - ii[i]) / (8 * math.pi) * e_ij
    return q @ d @ q.T, q @ w @ q.T


def observables(b, ca, k):
    """T and inclination of the x-y section, the axes, [mu], N1 / Phi, N2 / Phi."""
    d, _ = interior_rates(b, ca, k)
    lam2, v2 = np.linalg.eigh(b[:2, :2])  # the section of x^T B^-1 x = 1 by z = 0 (B_xz = B_yz = 0)
    ax, ay = math.sqrt(lam2[1]), math.sqrt(lam2[0])
    angle = math.degrees(math.atan2(v2[1, 1], v2[0, 1]))
    angle = (angle + 90) % 180 - 90
    sigma = 2 * (k - 1) * d + (b - np.eye(3)) / ca  # the particle's stresslet per volume
    axes = np.sqrt(np.sort(np.linalg.eigvalsh(b))[::-1])
    return {"taylor_D": (ax - ay) / (ax + ay), "inclination_deg": angle, "axis_a": ax, "axis_b": ay,
            "axis_c": math.sqrt(b[2, 2]), "intrinsic_viscosity": sigma[0, 1],
            "N1_per_Phi": sigma[0, 0] - sigma[1, 1], "N2_per_Phi": sigma[1, 1] - sigma[2, 2],
            "a": axes[0], "b": axes[1], "c": axes[2]}


def rhs(b, ca, k):
    d, w = interior_rates(b, ca, k)
    lin = d + w
    return lin @ b + b @ lin.T


def evolve(ca, k, strain, dt, every=None):
    """B from I by classical RK4; yields (strain, B) every `every` strain units."""
    b = np.eye(3)
    n = int(round(strain / dt))
    every_n = max(1, int(round((every or dt) / dt)))
    yield 0.0, b
    for m in range(1, n + 1):
        k1 = rhs(b, ca, k)
        k2 = rhs(b + 0.5 * dt * k1, ca, k)
        k3 = rhs(b + 0.5 * dt * k2, ca, k)
        k4 = rhs(b + dt * k3, ca, k)
        b = b + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        b = 0.5 * (b + b.T)
        if m % every_n == 0 or m == n:
            yield m * dt, b


def steady_b(ca, k, strain, dt):
    """B at the end of a run from B = I (steady when strain is past the start-up)."""
    for _, b in evolve(ca, k, strain, dt, strain):
        pass
    return b


def steady_observables(ca, k, strain, dt):
    """The observables at the end of a run from B = I (the steady state when
    strain is past the start-up)."""
    return observables(steady_b(ca, k, strain, dt), ca, k)


def self_checks():
    """The sphere's integrals and Eshelby tensor, and Jeffery's rotation."""
    ii, iij = eshelby_integrals([1.0, 1.0, 1.0])
    assert np.allclose(ii, 4 * math.pi / 3, rtol=1e-10), ii
    assert np.allclose(iij, 4 * math.pi / 5, rtol=1e-10), iij
    # Mura's identity 3 I_11 + I_12 + I_13 = 4 pi / a1^2 on an ellipsoid
    a = np.array([2.0, 0.7, 1.1])
    ii, iij = eshelby_integrals(a)
    assert abs(3 * iij[0, 0] + iij[0, 1] + iij[0, 2] - 4 * math.pi / a[0] ** 2) < 1e-9
    assert abs(ii.sum() - 4 * math.pi) < 1e-9
    # a rigid ellipsoid (K -> inf, no elastic stress) aligned with x turns at
    # Jeffery's rate gamma / (r^2 + 1), r = a1 / a2
    b = np.diag(a ** 2)
    d, w = interior_rates(b, 1e12, 1e9)
    r = a[0] / a[1]
    assert abs(w[0, 1] - 1 / (r * r + 1)) < 1e-6, (w[0, 1], 1 / (r * r + 1))
    assert np.abs(d).max() < 1e-6


def cmd_run(args):
    self_checks()
    cols = ["strain", "taylor_D", "inclination_deg", "axis_a", "axis_b", "axis_c", "intrinsic_viscosity",
            "N1_per_Phi", "N2_per_Phi", "a", "b", "c"]
    out = open(args.csv + ".tmp", "w") if args.csv else sys.stdout
    w = csv.writer(out)
    w.writerow(cols)
    for s, b in evolve(args.ca, args.k, args.strain, args.dt, args.every):
        o = observables(b, args.ca, args.k)
        w.writerow([f"{s:.4f}"] + [f"{o[c]:.6f}" for c in cols[1:]])
    if args.csv:
        out.close()
        os.replace(args.csv + ".tmp", args.csv)


def cmd_check(args):
    """The steady state (the ODE run to strain 80, or 150 at K > 1) against the table."""
    self_checks()
    keys = ["taylor_D", "inclination_deg", "axis_a", "axis_b", "axis_c", "intrinsic_viscosity",
            "N1_per_Phi", "N2_per_Phi"]
    worst = 0.0
    print("| K | Ca | " + " | ".join(keys) + " |")
    print("|---" * (len(keys) + 2) + "|")
    for row in csv.DictReader(open(args.spec)):
        ca, k = float(row["Ca"]), float(row["K"])
        if args.only and (ca, k) not in args.only:
            continue
        o = steady_observables(ca, k, steady_strain(k), 0.01)
        cells = []
        for c in keys:
            ref = float(row[c])
            rel = (o[c] - ref) / abs(ref) if ref else o[c]
            worst = max(worst, abs(rel))
            cells.append(f"{o[c]:.4f} ({rel:+.2%})")
        print(f"| {k:g} | {ca:g} | " + " | ".join(cells) + " |")
    print(f"\nlargest relative difference from {args.spec}: {worst:.2%}")
    return 0 if worst < args.tol else 1


def steady_strain(k):
    """How long the start-up lasts: 80 strain units, 150 for a viscous
    particle (test_ellipsoid_theory: 120 at K = 10, Ca = 0.2)."""
    return 80 if k <= 1 else 150


def cmd_steady_b(args):
    """The steady B as softflow's override (xx, xy, xz, yy, yz, zz), det B = 1."""
    self_checks()
    b = steady_b(args.ca, args.k, steady_strain(args.k), 0.01)
    b = b / np.linalg.det(b) ** (1 / 3)
    o = observables(b, args.ca, args.k)
    print(f"# steady state, Ca = {args.ca:g}, K = {args.k:g}: T = {o['taylor_D']:.4f}, "
          f"inclination {o['inclination_deg']:.2f} deg, [mu] = {o['intrinsic_viscosity']:.4f}")
    comps = [b[0, 0], b[0, 1], b[0, 2], b[1, 1], b[1, 2], b[2, 2]]
    print("particles.initial_b=[" + ",".join(f"{x:.10f}" for x in comps) + "]")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run")
    r.add_argument("--ca", type=float, required=True)
    r.add_argument("--k", type=float, default=1.0)
    r.add_argument("--strain", type=float, default=60.0)
    r.add_argument("--dt", type=float, default=0.002, help="RK4 step in strain units")
    r.add_argument("--every", type=float, default=0.1, help="output every this many strain units")
    r.add_argument("--csv", default=None, help="write here (temporary name, then renamed) instead of stdout")
    c = sub.add_parser("check")
    c.add_argument("--spec", default=os.path.join(ROOT, "..", "shared", "spec", "dilute_theory.csv"))
    c.add_argument("--tol", type=float, default=0.002, help="largest relative difference allowed")
    c.add_argument("--only", default=None, help="K:Ca,... rows to check")
    sb = sub.add_parser("steady-b")
    sb.add_argument("--ca", type=float, required=True)
    sb.add_argument("--k", type=float, default=1.0)
    a = ap.parse_args()
    if a.cmd == "steady-b":
        if a.ca <= 0 or a.k <= 0:
            sys.exit("ellipsoid_theory: --ca and --k must be positive")
        cmd_steady_b(a)
        return 0
    if a.cmd == "run":
        if a.ca <= 0 or a.k <= 0 or a.strain <= 0 or a.dt <= 0:
            sys.exit("ellipsoid_theory: --ca, --k, --strain and --dt must be positive")
        cmd_run(a)
        return 0
    if not os.path.isfile(a.spec):
        sys.exit(f"ellipsoid_theory: no table at {a.spec} (give --spec)")
    a.only = ({(float(x.split(":")[1]), float(x.split(":")[0])) for x in a.only.split(",")}
              if a.only else None)
    return cmd_check(a)


if __name__ == "__main__":
    sys.exit(main())
