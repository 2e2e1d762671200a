#!/usr/bin/env python3
"""Tabulates perf/scaling.sh: time per step and communication per step at
1, 2 and 4 ranks, the transposes' volume against the model

    V_transpose = n_solves * 4 * 8 B * N * ((px - 1) / px + (pz - 1) / pz)

(all ranks, per step; N global cells; each Poisson or Helmholtz solve does 4
transposes in the x groups and 4 in the z groups, each sending the local
array less the rank's own block; n_solves = 3 per step with explicit
viscosity, 12 with implicit: 3 Helmholtz + 1 pressure per stage), and the
halo volume as a whole number of field exchanges of

    V_field = P * 8 B * 2 ng (ny + 2 ng) (nzl [px > 1] + (nxl + 2 ng) [pz > 1]).

    perf/scaling.py output/scaling > perf/results/scaling.md
"""
import glob
import json
import os
import sys

NG = 3


def model(j):
    nx, ny, nz = j["grid"]
    px, pz = j["rank_grid"]
    p = j["ranks"]
    n = nx * ny * nz
    solves = 12 if j["physics"]["viscous"] == "implicit" else 3
    tr = solves * 4 * 8 * n * ((px - 1) / px + (pz - 1) / pz)
    nxl, nzl = nx // px, nz // pz
    field = p * 8 * 2 * NG * (ny + 2 * NG) * ((nzl if px > 1 else 0) + ((nxl + 2 * NG) if pz > 1 else 0))
    return tr, field


def main():
    folder = sys.argv[1] if len(sys.argv) > 1 else "output/scaling"
    runs = sorted(glob.glob(os.path.join(folder, "*.json")))
    print("# Scaling at 1, 2 and 4 ranks (communication per step, measured and modelled)\n")
    print("Produced by `perf/scaling.sh` (softflow-perf under mpirun, 1 OpenMP thread per rank, on the 2-core "
          "CI-class VM: 4 ranks oversubscribe it, so the times are not a speed-up measurement). "
          "Volumes are all ranks' bytes sent to other ranks per step.\n")
    print("| run | ranks (px x pz) | grid | ms/step | cell-steps/s | transposes B/step (model) | "
          "halo B/step | field exchanges/step |")
    print("|---|---|---|---|---|---|---|---|")
    for path in runs:
        j = json.load(open(path))
        c = j["communication"]
        tr_model, field = model(j)
        tr = c["transpose_bytes_per_step_all_ranks"]
        halo = c["halo_bytes_per_step_all_ranks"]
        ex = f"{halo / field:.2f}" if field else "-"
        ok = "" if abs(tr - tr_model) <= 1e-9 * max(tr_model, 1) else " MISMATCH"
        print(f"| {os.path.basename(path)[:-5]} | {j['ranks']} ({j['rank_grid'][0]} x {j['rank_grid'][1]}) | "
              f"{'x'.join(map(str, j['grid']))} | {j['step']['seconds']['median'] * 1e3:.1f} | "
              f"{j['step']['cell_steps_per_second']['median']:.3g} | {tr:.4g} ({tr_model:.4g}){ok} | "
              f"{halo:.4g} | {ex} |")


if __name__ == "__main__":
    main()
