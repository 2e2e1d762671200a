#!/usr/bin/env python3
"""Compares two runs' outputs of the same case: every dataset of every HDF5
file (snapshots, checkpoint) and every column of series.csv and
particles.csv. Prints the largest difference relative to the largest value
of each quantity (max |div u|, round-off in both, relative to max |u| / dx),
and fails if one exceeds the tolerance.

  compare_outputs.py DIR_A DIR_B [TOLERANCE]   (default 1e-10)
"""
import csv
import glob
import json
import math
import os
import sys

import h5py
import numpy as np


def rel(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    if a.shape != b.shape:
        return math.inf
    if not (np.isfinite(a).all() and np.isfinite(b).all()):
        return math.inf
    scale = max(np.abs(a).max(initial=0), np.abs(b).max(initial=0))
    return float(np.abs(a - b).max(initial=0) / scale) if scale > 0 else 0.0


def div_scale(d, rows):
    """max_div is round-off in both runs: compared against the velocity
    gradient scale max_speed / (smallest cell size), not against itself."""
    s = json.load(open(os.path.join(d, "summary.json")))["case"]
    h = min(L / n for L, n in zip(s["box"], s["grid"]))
    return max(float(r["max_speed"]) for r in rows) / h


def main():
    da, db = sys.argv[1], sys.argv[2]
    tol = float(sys.argv[3]) if len(sys.argv) > 3 else 1e-10
    worst = {}  # quantity -> (relative difference, where)
    files = sorted(os.path.basename(p) for p in glob.glob(os.path.join(da, "*.h5")))
    if not files:
        sys.exit(f"compare_outputs: no HDF5 files in {da}")
    for name in files:
        with h5py.File(os.path.join(da, name)) as fa, h5py.File(os.path.join(db, name)) as fb:
            for key in fa:
                d = rel(fa[key][()], fb[key][()])
                if d >= worst.get(key, (-1,))[0]:
                    worst[key] = (d, name)
    for name in ("series.csv", "particles.csv"):
        ra = list(csv.DictReader(open(os.path.join(da, name))))
        rb = list(csv.DictReader(open(os.path.join(db, name))))
        if len(ra) != len(rb):
            worst[name] = (math.inf, "row count")
            continue
        for col in ra[0]:
            a, b = [float(r[col]) for r in ra], [float(r[col]) for r in rb]
            if col == "max_div":
                d = float(np.abs(np.subtract(a, b)).max()) / div_scale(da, ra)
            else:
                d = rel(a, b)
            worst[f"{name}:{col}"] = (d, name)
    bad = 0
    for k, (d, where) in sorted(worst.items()):
        flag = "" if d <= tol else "   <-- above the tolerance"
        bad += d > tol
        print(f"  {k:32s} {d:9.2e}  ({where}){flag}")
    m = max(d for d, _ in worst.values())
    print(f"compare_outputs: {len(files)} HDF5 files, largest relative difference {m:.2e} (tolerance {tol:g})")
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
