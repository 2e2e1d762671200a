#!/usr/bin/env python3
"""Draws the rheology figures from a run-set folder (scripts/run-set.py).

  scripts/figures.py SET_DIR OUT_DIR [--shapes DENSE_CASE,DILUTE_CASE]

Reads SET_DIR/table.csv, the averaged SET_DIR/<case>/profiles.csv and the
last field snapshot of the --shapes cases; writes PNG and PDF into OUT_DIR,
and the closures (scripts/closures.py) beside them. Error bars are the
batch-means standard errors of the time averages.
"""
import argparse
import glob
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import closures  # noqa: E402

BUDGET = [("fluid_viscous", "fluid viscous"), ("fluid_reynolds", "fluid Reynolds"),
          ("particle_viscous", "particle viscous"), ("particle_reynolds", "particle Reynolds"),
          ("particle_elastic", "particle elastic")]


def save(fig, out, name):
    fig.tight_layout()
    for ext in ("png", "pdf"):
        fig.savefig(os.path.join(out, f"{name}.{ext}"), dpi=150)
    plt.close(fig)


def err(rows, key):
    return [r.get(key + "_stderr") if math.isfinite(r.get(key + "_stderr", math.nan)) else 0 for r in rows]


def series(rows, by, key_filter=None):
    groups = {}
    for r in rows:
        if key_filter and not key_filter(r):
            continue
        groups.setdefault(r[by], []).append(r)
    return {k: sorted(v, key=lambda r: (r["Ca"], r["Phi"])) for k, v in sorted(groups.items())}


def read_profiles(path):
    import csv
    rows = [r for r in csv.DictReader(l for l in open(path) if not l.startswith("#"))]

    def col(name):
        return np.array([float(r[name]) if r[name] not in ("", None) else np.nan for r in rows])

    return col


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("set_dir")
    ap.add_argument("out")
    ap.add_argument("--shapes", default="")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = closures.load(os.path.join(args.set_dir, "table.csv"))
    fits = closures.fit(rows)
    closures.write(fits, args.out)
    k1 = [r for r in rows if r["K"] == 1]
    by_ca = series(k1, "Ca")
    by_phi = series(k1, "Phi_case")
    cmap = plt.get_cmap("viridis")

    # mu against Phi, per Ca, with Eilers and the rigid limit
    fig, ax = plt.subplots(figsize=(5.5, 4))
    p = np.linspace(0, 0.4, 200)
    ax.plot(p, closures.eilers(p), "k-", lw=1, label="Eilers, rigid (B_E 1.7, Phi_m 0.6)")
    ax.plot(p, 1 + 2.5 * p, "k:", lw=1, label="Einstein 1 + 2.5 Phi")
    if "eilers" in fits:
        e = fits["eilers"]
        ax.plot(p, closures.eilers(p, e["B_E"], e["Phi_m"]), "k--", lw=1,
                label=f"Eilers fitted at Ca {e['Ca']:g} (B_E {e['B_E']:.2f})")
    for n, (ca, rs) in enumerate(by_ca.items()):
        ax.errorbar([r["Phi"] for r in rs], [r["mu_eff"] for r in rs], yerr=err(rs, "mu_eff"), fmt="o-",
                    color=cmap(n / max(1, len(by_ca) - 1)), ms=4, capsize=2, label=f"Ca = {ca:g}")
    ax.set_xlabel("Phi")
    ax.set_ylabel("mu / mu_f")
    ax.legend(fontsize=7)
    save(fig, args.out, "mu_vs_phi")

    # mu against Ca, per Phi, with each Phi's rigid limit
    fig, ax = plt.subplots(figsize=(5.5, 4))
    for n, (phi, rs) in enumerate(by_phi.items()):
        c = cmap(n / max(1, len(by_phi) - 1))
        ax.errorbar([r["Ca"] for r in rs], [r["mu_eff"] for r in rs], yerr=err(rs, "mu_eff"), fmt="o-", color=c,
                    ms=4, capsize=2, label=f"Phi = {phi:g}")
        ax.axhline(float(closures.eilers(phi)), color=c, ls="--", lw=0.8)
    ax.set_xscale("log")
    ax.set_xlabel("Ca")
    ax.set_ylabel("mu / mu_f")
    ax.set_title("dashed: rigid limit (Eilers) of each Phi", fontsize=8)
    ax.legend(fontsize=7)
    save(fig, args.out, "mu_vs_ca")

    # T against Ca, per Phi
    fig, ax = plt.subplots(figsize=(5.5, 4))
    ca = np.logspace(-2, np.log10(0.5), 50)
    ax.plot(ca, 1.25 * ca, "k:", lw=1, label="small deformation, 5/4 Ca")
    for n, (phi, rs) in enumerate(by_phi.items()):
        c = cmap(n / max(1, len(by_phi) - 1))
        x = [r["Ca"] for r in rs]
        ax.errorbar(x, [r["taylor"] for r in rs], yerr=err(rs, "taylor"), fmt="o-", color=c, ms=4, capsize=2,
                    label=f"Phi = {phi:g}")
        ax.fill_between(x, [r["taylor"] - r["taylor_spread"] for r in rs],
                        [r["taylor"] + r["taylor_spread"] for r in rs], color=c, alpha=0.15, lw=0)
    ax.set_xscale("log")
    ax.set_ylim(0, 1)
    ax.set_xlabel("Ca")
    ax.set_ylabel("T = (a - b) / (a + b)")
    ax.set_title("bands: spread over the particles", fontsize=8)
    ax.legend(fontsize=7)
    save(fig, args.out, "taylor_vs_ca")

    # N1 and N2 against Ca
    fig, axs = plt.subplots(1, 2, figsize=(9, 3.8))
    for key, ax in zip(("n1", "n2"), axs):
        for n, (phi, rs) in enumerate(by_phi.items()):
            ax.errorbar([r["Ca"] for r in rs], [r[key] for r in rs], yerr=err(rs, key), fmt="o-",
                        color=cmap(n / max(1, len(by_phi) - 1)), ms=4, capsize=2, label=f"Phi = {phi:g}")
        ax.axhline(0, color="k", lw=0.5)
        ax.set_xscale("log")
        ax.set_xlabel("Ca")
        ax.set_ylabel(f"{key.upper()} / (mu_f gamma)")
    axs[0].legend(fontsize=7)
    save(fig, args.out, "normal_stresses_vs_ca")

    # budget shares against Ca, per Phi (dense series)
    dense_phis = [phi for phi in by_phi if phi >= 0.01]
    if dense_phis:
        fig, axs = plt.subplots(1, len(dense_phis), figsize=(4.5 * len(dense_phis), 3.8), squeeze=False)
        for ax, phi in zip(axs[0], dense_phis):
            rs = by_phi[phi]
            for key, label in BUDGET:
                ax.errorbar([r["Ca"] for r in rs], [r["share_" + key] for r in rs], yerr=err(rs, "share_" + key),
                            fmt="o-", ms=4, capsize=2, label=label)
            ax.set_xscale("log")
            ax.set_xlabel("Ca")
            ax.set_ylabel("share of the shear stress")
            ax.set_title(f"Phi = {phi:g}", fontsize=9)
        axs[0][0].legend(fontsize=7)
        save(fig, args.out, "budget_shares_vs_ca")

    # profiles across the gap: budget, <u>, <phi>
    cases = [r for phi in dense_phis for r in by_phi[phi]] or k1
    prof = {r["name"]: read_profiles(os.path.join(args.set_dir, r["name"], "profiles.csv")) for r in cases
            if os.path.exists(os.path.join(args.set_dir, r["name"], "profiles.csv"))}
    if prof:
        names = list(prof)
        fig, axs = plt.subplots(1, len(names), figsize=(3.2 * len(names), 3.6), squeeze=False, sharey=True)
        for ax, name in zip(axs[0], names):
            col = prof[name]
            for key, label in BUDGET:
                ax.plot(col(key), col("y_face"), label=label)
            ax.set_title(name, fontsize=8)
            ax.set_xlabel("stress / (mu_f gamma)")
        axs[0][0].set_ylabel("y / r")
        axs[0][0].legend(fontsize=6)
        save(fig, args.out, "budget_profiles")
        fig, axs = plt.subplots(1, 2, figsize=(8, 3.8), sharey=True)
        for n, name in enumerate(names):
            col = prof[name]
            c = cmap(n / max(1, len(names) - 1))
            axs[0].plot(col("u_mean"), col("y_centre"), color=c, label=name)
            axs[1].plot(col("phi_mean"), col("y_centre"), color=c, label=name)
        axs[0].set_xlabel("<u> / V_w")
        axs[1].set_xlabel("<phi>")
        axs[0].set_ylabel("y / r")
        axs[0].legend(fontsize=6)
        save(fig, args.out, "profiles_u_phi")

    # Phi_e against Phi with its fit; mu against Phi_e onto Eilers
    fig, axs = plt.subplots(1, 2, figsize=(9, 3.8))
    for n, (c_, rs) in enumerate(by_ca.items()):
        c = cmap(n / max(1, len(by_ca) - 1))
        axs[0].errorbar([r["Phi"] for r in rs], [r["phi_e"] for r in rs], yerr=err(rs, "phi_e"), fmt="o", color=c,
                        ms=4, capsize=2, label=f"Ca = {c_:g}")
        if "phi_e" in fits:
            pp = np.linspace(0, 0.4, 20)
            axs[0].plot(pp, closures.phi_e_model(pp, c_, fits["phi_e"]["Ca_0"], fits["phi_e"]["n"]), "-", color=c, lw=0.8)
        axs[1].errorbar([r["phi_e"] for r in rs], [r["mu_eff"] for r in rs], yerr=err(rs, "mu_eff"), fmt="o",
                        color=c, ms=4, capsize=2, label=f"Ca = {c_:g}")
    axs[0].plot([0, 0.4], [0, 0.4], "k:", lw=0.8)
    axs[0].set_xlabel("Phi")
    axs[0].set_ylabel("Phi_e")
    axs[0].legend(fontsize=7)
    p = np.linspace(0, 0.45, 200)
    axs[1].plot(p, closures.eilers(p), "k-", lw=1, label="Eilers (1.7, 0.6)")
    axs[1].set_xlabel("Phi_e")
    axs[1].set_ylabel("mu / mu_f")
    axs[1].legend(fontsize=7)
    save(fig, args.out, "phi_e")

    # mu and T against K
    kr = sorted([r for r in rows if abs(r["Phi_case"] - 0.11) < 1e-9 and abs(r["Ca"] - 0.2) < 1e-9],
                key=lambda r: r["K"])
    if len(kr) >= 2:
        fig, axs = plt.subplots(1, 2, figsize=(9, 3.8))
        axs[0].errorbar([r["K"] for r in kr], [r["mu_eff"] for r in kr], yerr=err(kr, "mu_eff"), fmt="o-", capsize=2)
        axs[1].errorbar([r["K"] for r in kr], [r["taylor"] for r in kr], yerr=err(kr, "taylor"), fmt="o-", capsize=2)
        for ax, lab in zip(axs, ("mu / mu_f", "T")):
            ax.set_xscale("log")
            ax.set_xlabel("K = mu_s / mu_f")
            ax.set_ylabel(lab)
        fig.suptitle("Phi = 0.11, Ca = 0.2", fontsize=9)
        save(fig, args.out, "k_dependence")

    # the particles' shapes: cells with phi > 0.5 in the last snapshot
    names = [n for n in args.shapes.split(",") if n]
    if names:
        import h5py
        fig = plt.figure(figsize=(5 * len(names), 4.5))
        for n, name in enumerate(names):
            snaps = sorted(glob.glob(os.path.join(args.set_dir, name, "fields_*.h5")))
            if not snaps:
                continue
            with h5py.File(snaps[-1], "r") as f:
                phi = np.array(f["phi"])  # (z, y, x)
                t = f.attrs["time"]
            ax = fig.add_subplot(1, len(names), n + 1, projection="3d")
            filled = np.transpose(phi > 0.5, (2, 0, 1))  # x, z, y: y up
            ax.voxels(filled, facecolors="tab:orange", edgecolor="none")
            ax.set_box_aspect(filled.shape)
            ax.set_xlabel("x")
            ax.set_ylabel("z")
            ax.set_zlabel("y")
            ax.set_title(f"{name}, strain {t:g}: phi > 0.5", fontsize=8)
        save(fig, args.out, "shapes")


if __name__ == "__main__":
    main()
