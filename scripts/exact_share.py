#!/usr/bin/env python3
"""How much of an exact particle's solid a grid puts in phi < 0.1 cells.

  scripts/toolchain.sh run python3 scripts/exact_share.py [--ca 2] [--k 1]
      [--ppr 4,5,6,8] [--offsets 6] [--sub 10] [--spec PATH/dilute_theory.csv]

Issue 12 bounds the share of the elastic stress carried by cells with
phi < 0.1 at 5%. The exact dilute particle is an ellipsoid with a uniform B
(shared/spec/dilute_theory.md), so its stress share in those cells equals
its solid-volume share there: a property of the shape and the grid alone.
This script samples the steady ellipsoid of shared/spec/dilute_theory.csv
(axes a, b, c in r; the major axis at the inclination from the flow
direction x in the x-y plane) on cubic cells of h = r / ppr, each cell's
phi the fraction of sub^3 points inside, at `offsets` random positions of
the centre within a cell, and prints the mean, least and largest share of
the solid volume in cells with 0 < phi < 0.1. Compare it with a run's
`solid_share_lowphi` (series.csv): the excess is the scheme's, not the
grid's. Needs numpy (the toolchain root has it).
"""
import argparse
import csv
import os

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def steady_shape(spec, ca, k):
    for row in csv.DictReader(open(spec)):
        if abs(float(row["Ca"]) - ca) < 1e-9 and abs(float(row["K"]) - k) < 1e-9:
            axes = tuple(float(row[a]) for a in ("axis_a", "axis_b", "axis_c"))
            return axes, float(row["inclination_deg"])
    raise SystemExit(f"exact_share: no row K = {k}, Ca = {ca} in {spec}")


def sampled_phi(axes, incl_deg, ppr, offset, sub):
    """phi of the ellipsoid on the cells about it, centre at `offset` (in r)
    from a cell centre"""
    a, b, c = axes
    h = 1.0 / ppr
    n = int(np.ceil(max(axes) / h)) + 2
    centres = np.arange(-n, n + 1) * h
    s = ((np.arange(sub) + 0.5) / sub - 0.5) * h  # sub-points within a cell
    # every sub-point's coordinate along each axis: (cells, sub)
    x = (centres[:, None] + s[None, :] - offset[0]).reshape(-1)
    y = (centres[:, None] + s[None, :] - offset[1]).reshape(-1)
    z = (centres[:, None] + s[None, :] - offset[2]).reshape(-1)
    ct, st = np.cos(np.radians(incl_deg)), np.sin(np.radians(incl_deg))
    xp = ct * x[:, None] + st * y[None, :]  # body frame, in the x-y plane
    yp = -st * x[:, None] + ct * y[None, :]
    in_xy = (xp / a) ** 2 + (yp / b) ** 2  # (x, y) sub-points
    inside = in_xy[:, :, None] + (z / c)[None, None, :] ** 2 <= 1
    m = 2 * n + 1
    return inside.reshape(m, sub, m, sub, m, sub).mean(axis=(1, 3, 5))


def low_phi_share(phi, below=0.1):
    return phi[phi < below].sum() / phi.sum()


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--ca", type=float, default=2.0)
    p.add_argument("--k", type=float, default=1.0)
    p.add_argument("--ppr", default="4,5,6,8")
    p.add_argument("--offsets", type=int, default=6)
    p.add_argument("--sub", type=int, default=10)
    p.add_argument("--spec", default=os.path.join(ROOT, "..", "shared", "spec", "dilute_theory.csv"))
    args = p.parse_args()
    axes, incl = steady_shape(args.spec, args.ca, args.k)
    print(f"K = {args.k:g}, Ca = {args.ca:g}: axes {axes} r, inclination {incl:g} deg; "
          f"{args.sub}^3 points a cell, {args.offsets} centre offsets")
    rng = np.random.default_rng(1)
    for ppr in (int(v) for v in args.ppr.split(",")):
        shares = [low_phi_share(sampled_phi(axes, incl, ppr, rng.uniform(-0.5, 0.5, 3) / ppr, args.sub))
                  for _ in range(args.offsets)]
        print(f"{ppr:3d} ppr: solid share in phi < 0.1 cells {100 * np.mean(shares):.2f}% "
              f"({100 * min(shares):.2f}-{100 * max(shares):.2f}%)")


if __name__ == "__main__":
    main()
