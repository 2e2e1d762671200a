#!/usr/bin/env python3
"""Runs a list of reference cases at a chosen resolution, resumes what was
interrupted, and collects the run summaries into one table.

  scripts/run-set.py [--cases all|dilute|dense|NAME,NAME,...] [--ppr 4]
                     [--strain 20] [--np 1] [--threads N] [--out output/set]
                     [--viscous implicit] [--box LX,LY,LZ] [--set KEY=VALUE]...
                     [--collect-only]

Each case is cases/NAME.toml (the reference set, 16 points per radius) with
the grid scaled to --ppr points per radius, run to --strain strain units into
OUT/NAME/ (OUT relative to the folder run-set is called from, or absolute;
one the toolchain root cannot see stops it before any run). A case whose summary.json reached the strain is skipped; one with
a checkpoint.h5 is restarted from it (checkpoints every 200 steps). --box
replaces the box (in radii; the particle count follows Phi, the wall speed
follows the gap so that gamma, Re and Ca stay those of the case). Progress lines
carry the whole set's ETA, from the cost per strain unit so far. The table
is OUT/table.csv, one row per case, means and standard errors
(docs/output.md lists the columns).
"""
import argparse
import csv
import fcntl
import json
import math
import os
import re
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# the table's columns taken from summary.json "averages.quantities" (mean and stderr each)
QUANTITIES = ["mu_eff", "mu_bottom", "mu_top", "n1", "n2", "taylor", "taylor_spread", "phi_e", "Phi",
              "intrinsic_viscosity", "detb_min", "detb_max", "a_xy", "b_xy", "angle_deg"]
BUDGET = ["fluid_viscous", "fluid_reynolds", "particle_viscous", "particle_reynolds", "particle_elastic"]


def trend_cell(t):
    """'+1.23 ± 0.45%' (the change across the span), with ' drifts' where
    summary.json says so; empty without a verdict."""
    if t.get("drifts") is None:
        return ""
    return f"{100 * t['change']:+.2f} ± {100 * t['change_stderr']:.2f}%" + (" drifts" if t["drifts"] else "")


def reference_cases():
    rows = list(csv.DictReader(open(os.path.join(ROOT, "cases", "reference.csv"))))
    return {r["name"]: r for r in rows}


def select(spec, ref):
    if spec == "all":
        return list(ref)
    if spec == "dilute":
        return [n for n in ref if n.startswith("phi0016_")]
    if spec.startswith("phi") and spec in {n.split("_")[0] for n in ref}:  # a whole series, e.g. phi011
        return [n for n in ref if n.startswith(spec + "_ca") and "_k" not in n]
    names = spec.split(",")
    for n in names:
        if n not in ref:
            sys.exit(f"run-set: unknown case '{n}' (cases/reference.csv lists them)")
    return names


def read_key(text, table, key):
    m = re.search(r"^\[" + table + r"\](.*?)(^\[|\Z)", text, re.S | re.M)
    k = re.search(r"^" + key + r"\s*=\s*([^\s#]+)", m.group(1), re.M) if m else None
    return float(k.group(1)) if k else None


def case_overrides(name, args):
    text = open(os.path.join(ROOT, "cases", name + ".toml")).read()
    r = read_key(text, "particles", "radius") or 1.0
    box = [read_key(text, "grid", k) for k in ("lx", "ly", "lz")]
    vw = read_key(text, "walls", "velocity")
    if args.box:
        # keep the shear rate gamma = V_w / h (and so Re and Ca) in the new gap
        new = [float(v) for v in args.box.split(",")]
        vw *= new[1] / box[1]
        box = new
    n = [max(3, round(L / r * args.ppr)) for L in box]
    o = [f"grid.lx={box[0]}", f"grid.ly={box[1]}", f"grid.lz={box[2]}",
         f"grid.nx={n[0]}", f"grid.ny={n[1]}", f"grid.nz={n[2]}", f"walls.velocity={vw}",
         f"time.end_strain={args.strain}", f'time.viscous="{args.viscous}"',
         f'output.dir="{os.path.join(args.out, name)}"', "output.fields_every=0.0",
         "output.checkpoint_every=200", f"output.progress_every={args.progress_every}",
         f"output.series_every={args.series_every}"] + args.set
    return o, n


def done_strain(folder):
    try:
        return json.load(open(os.path.join(folder, "summary.json")))["final"]["strain"]
    except (OSError, KeyError, ValueError):
        return None


def hms(s):
    if not math.isfinite(s) or s < 0:
        return "--:--:--"
    s = int(s + 0.5)
    return f"{s // 3600:02d}:{s // 60 % 60:02d}:{s % 60:02d}"


def run_case(name, args, state):
    folder = os.path.join(args.out, name)
    o, n = case_overrides(name, args)
    cmd = ["mpiexec", "-n", str(args.np), "--oversubscribe", os.path.join(args.build, "softflow"),
           os.path.join("cases", name + ".toml")]
    for s in o:
        cmd += ["--set", s]
    ckpt = os.path.join(folder, "checkpoint.h5")
    if os.path.exists(ckpt):
        cmd += ["--restart", ckpt]
        print(f"run-set: {name}: resuming from {ckpt}", flush=True)
    env = dict(os.environ, OMP_NUM_THREADS=str(args.threads))
    full = [os.path.join(ROOT, "scripts", "toolchain.sh"), "run"] + cmd
    t0 = time.time()
    case_start = None if os.path.exists(ckpt) else 0.0  # resumed: the first progress line's strain
    p = subprocess.Popen(full, cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    log = open(os.path.join(args.out, name + ".log"), "a")
    for line in p.stdout:
        log.write(line)
        m = re.search(r"strain\s+([0-9.eE+-]+)", line)
        if m and line.startswith("step"):
            s = float(m.group(1))
            if case_start is None:
                case_start = s
            advanced = state["advanced"] + s - case_start
            rate = (state["elapsed"] + time.time() - t0) / max(advanced, 1e-9)
            left = (args.strain - s) + args.strain * (state["n"] - state["k"])
            line = f"[{state['k']}/{state['n']} {name}, set ETA {hms(rate * left) if advanced > 0 else '--'}] " + line
            state["last"] = s - case_start
        sys.stdout.write(line)
        sys.stdout.flush()
    rc = p.wait()
    state["elapsed"] += time.time() - t0
    state["advanced"] += args.strain - (case_start or 0.0)
    if rc != 0:
        sys.exit(f"run-set: {name} failed (exit {rc}); see {os.path.join(args.out, name + '.log')}")


def batch_mean(v, batches=10):
    """Mean and 10-batch-means standard error, as src/averaging.cpp."""
    v = [x for x in v if math.isfinite(x)]
    if not v:
        return math.nan, math.nan
    m = sum(v) / len(v)
    if len(v) < 20:
        return m, math.nan
    n = len(v) // batches
    skip = len(v) - n * batches
    bm = [sum(v[skip + b * n: skip + (b + 1) * n]) / n for b in range(batches)]
    mb = sum(bm) / batches
    return m, math.sqrt(sum((x - mb) ** 2 for x in bm) / (batches - 1) / batches)


def volume_scaled_phi_e(folder, radius, from_strain):
    """Phi_e for runs made before the tracker scaled the axes to the particle
    volume (particles.csv without axes_scale_mean): b_xy^3 scaled by
    r^3 / (a b c) from the per-sample means (exact for one particle)."""
    path = os.path.join(folder, "particles.csv")
    if not os.path.exists(path):
        return None
    rows = list(csv.DictReader(open(path)))
    if not rows or "axes_scale_mean" in rows[0]:
        return None
    v = [float(r["phi_e"]) * radius ** 3 / (float(r["a_mean"]) * float(r["b_mean"]) * float(r["c_mean"]))
         for r in rows if int(r["step"]) > 0 and float(r["strain"]) >= from_strain - 1e-12]
    return batch_mean(v)


def collect(names, args, ref):
    rows = []
    for name in names:
        folder = os.path.join(args.out, name)
        try:
            s = json.load(open(os.path.join(folder, "summary.json")))
        except (OSError, ValueError):
            continue
        c = ref[name]
        a = s.get("averages", {})
        q = a.get("quantities", {})
        g = s["case"]["grid"]
        row = {"name": name, "Phi_case": c["Phi"], "Ca": c["Ca"], "K": c["K"], "Re": c["Re"],
               "ppr": round(g[0] / s["case"]["box"][0] * s["case"]["particles"]["radius"], 3),
               "grid": "x".join(map(str, g)), "box": "x".join(map(str, s["case"]["box"])),
               "particles": s["case"]["particles"]["count"], "strain": s["final"]["strain"],
               "steps": s["final"]["step"],
               "from_strain": a.get("from_strain"), "steps_this_run": s["performance"]["steps"],
               "wall_seconds_this_run": s["performance"]["wall_seconds"], "version": s["code"]["version"]}
        for k in QUANTITIES:
            v = q.get(k) or {}
            row[k], row[k + "_stderr"] = v.get("mean"), v.get("stderr")
        old = volume_scaled_phi_e(folder, s["case"]["particles"]["radius"], a.get("from_strain", 0))
        if old:
            row["phi_e"], row["phi_e_stderr"] = old
        for k in BUDGET:
            v = (q.get("budget_share") or {}).get(k) or {}
            row["share_" + k], row["share_" + k + "_stderr"] = v.get("mean"), v.get("stderr")
        # whether the averaging span's two halves agree, and its trend
        # (summary.json averages.halves and .trend; empty for a run from
        # before them)
        h, t = a.get("halves") or {}, a.get("trend") or {}
        for k in ("mu", "taylor"):
            row[k + "_halves_agree"] = (h.get(k) or {}).get("agree")
            row[k + "_trend"] = trend_cell(t.get(k) or {})
        rows.append(row)
    if not rows:
        return None
    path = os.path.join(args.out, "table.csv")
    with open(path + ".tmp", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    os.replace(path + ".tmp", path)
    return path


def build_solver(build):
    """The toolchain root, then softflow configured and built in `build`, one
    run-set at a time: two run-sets started together ran two cmakes in one
    build folder, and one of them failed before its first run."""
    os.makedirs(build, exist_ok=True)
    with open(os.path.join(build, ".run-set-build.lock"), "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # released when the file closes
        subprocess.run([os.path.join(ROOT, "scripts", "toolchain.sh"), "setup"], check=True)
        subprocess.run([os.path.join(ROOT, "scripts", "toolchain.sh"), "run", "bash", "-c",
                        f'cmake -S . -B "{build}" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null && '
                        f'cmake --build "{build}" --target softflow >/dev/null'], check=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", default="all")
    ap.add_argument("--ppr", type=float, default=4)
    ap.add_argument("--strain", type=float, default=20)
    ap.add_argument("--np", type=int, default=1)
    ap.add_argument("--threads", type=int, default=max(1, os.cpu_count() or 1))
    ap.add_argument("--out", default="output/set")
    ap.add_argument("--viscous", default="implicit", choices=["implicit", "explicit"])
    ap.add_argument("--box", default=None)
    ap.add_argument("--build", default=os.environ.get("SOFTFLOW_BUILD", "build"))
    ap.add_argument("--progress-every", type=int, default=100)
    # the averages want >= 20 samples after the transient even in short runs
    ap.add_argument("--series-every", type=int, default=5)
    ap.add_argument("--collect-only", action="store_true")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="a further case-file override for every case (repeatable)")
    args = ap.parse_args()
    ref = reference_cases()
    names = select(args.cases, ref)
    # --out is relative to the caller's folder (or absolute): resolved before
    # the chdir, and checked visible inside the toolchain root before any run
    args.out = os.path.abspath(args.out)
    if not args.collect_only:
        rc = subprocess.run([os.path.join(ROOT, "scripts", "toolchain.sh"), "check", args.out]).returncode
        if rc != 0:
            sys.exit(rc)
    os.makedirs(args.out, exist_ok=True)
    os.chdir(ROOT)
    if not args.collect_only:
        build_solver(args.build)
        todo = []
        for name in names:
            s = done_strain(os.path.join(args.out, name))
            if s is not None and s >= args.strain * (1 - 1e-9):
                print(f"run-set: {name}: done (strain {s:g})", flush=True)
            else:
                todo.append(name)
        state = {"n": len(todo), "elapsed": 0.0, "advanced": 0.0, "k": 0}
        for k, name in enumerate(todo, 1):
            state["k"] = k
            run_case(name, args, state)
            collect(names, args, ref)
    path = collect(names, args, ref)
    print(f"run-set: table in {path}" if path else "run-set: no summaries yet")


if __name__ == "__main__":
    main()
