#!/usr/bin/env python3
"""Deformable cylinders: yade-flex against YADE's built-in GridNode/GridConnection/CohFrict,
same scenes, same YADE, same run.

    python3 bench/bench_cylinders.py [--repeats 5] [--steps 2000] [--threads 1 2] [--no-cantilever]

Prints a table and writes bench/results/cylinders_timing.csv, cylinders_cantilever.csv
(medians of the repeats; the machine and date in bench/results/cylinders_machine.txt).
"""
import argparse
import csv
import json
import os
import platform
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "results")


def run_case(args, threads, timeout=3600):
    cmd = ["yade-double", "-n", "-j", str(threads), "-x", os.path.join(HERE, "cylinder_cases.py"), *map(str, args)]
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), PYTHONPATH=HERE + os.pathsep + os.environ.get("PYTHONPATH", ""))
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env, cwd="/tmp")
    rows = [json.loads(l[7:]) for l in res.stdout.splitlines() if l.startswith("RESULT ")]
    if res.returncode != 0 or not rows:
        sys.exit(f"{' '.join(cmd)} failed:\n{res.stdout[-2000:]}\n{res.stderr[-2000:]}")
    return rows


def machine():
    cpu = "unknown"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return f"{platform.node()}; {cpu}; {os.cpu_count()} cores; {time.strftime('%Y-%m-%d %H:%M')}"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--warmup", type=int, default=200)
    ap.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--no-cantilever", action="store_true")
    a = ap.parse_args()
    os.makedirs(OUT, exist_ok=True)
    rows = []
    for j in a.threads:
        print(f"timing with -j{j} ...", flush=True)
        rows += run_case(["timing", a.steps, a.repeats, a.warmup], j)
    table = []
    for j in a.threads:
        for scene in ("helix", "net"):
            med = {}
            info = {}
            for impl in ("builtin", "flex"):
                sel = [r for r in rows if r["threads"] == j and r["scene"] == scene and r["impl"] == impl]
                med[impl] = statistics.median(r["s_per_step"] for r in sel)
                info[impl] = sel[0]
            table.append(dict(scene=scene, threads=j,
                              builtin_us_per_step=1e6 * med["builtin"], flex_us_per_step=1e6 * med["flex"],
                              speedup_per_step=med["builtin"] / med["flex"],
                              builtin_dt=info["builtin"]["dt"], flex_dt=info["flex"]["dt"],
                              speedup_per_simulated_second=(med["builtin"] / info["builtin"]["dt"]) / (med["flex"] / info["flex"]["dt"]),
                              builtin_bodies=info["builtin"]["bodies"], flex_bodies=info["flex"]["bodies"],
                              builtin_interactions=info["builtin"]["interactions"], flex_interactions=info["flex"]["interactions"],
                              repeats=len([r for r in rows if r["threads"] == j and r["scene"] == scene and r["impl"] == "flex"])))
    with open(os.path.join(OUT, "cylinders_timing.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(table[0]))
        w.writeheader()
        w.writerows(table)
    with open(os.path.join(OUT, "cylinders_timing_raw.jsonl"), "w") as f:
        for r in rows:
            f.write(json.dumps(r) + "\n")
    print(f"\n{'scene':6} {'-j':>3} {'built-in us/step':>17} {'yade-flex us/step':>18} {'per step':>9} {'dt built-in':>12} {'dt flex':>10} {'per sim. s':>11}")
    for t in table:
        print(f"{t['scene']:6} {t['threads']:>3} {t['builtin_us_per_step']:17.1f} {t['flex_us_per_step']:18.1f} {t['speedup_per_step']:8.2f}x"
              f" {t['builtin_dt']:12.3g} {t['flex_dt']:10.3g} {t['speedup_per_simulated_second']:10.1f}x")
    if not a.no_cantilever:
        print("\ncantilever accuracy (-j1) ...", flush=True)
        cant = run_case(["cantilever"], 1)
        with open(os.path.join(OUT, "cylinders_cantilever.csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=["impl", "load", "segments", "ratio", "converged", "iterations"])
            w.writeheader()
            for r in cant:
                w.writerow({k: r[k] for k in w.fieldnames})
        print(f"\n{'load':5} {'segments':>8} {'built-in ratio':>15} {'yade-flex ratio':>16}   (tip deflection / Euler-Bernoulli)")
        for load in ("tip", "self"):
            for n in (2, 5, 10, 20):
                b = [r for r in cant if r["impl"] == "builtin" and r["load"] == load and r["segments"] == n][0]
                x = [r for r in cant if r["impl"] == "flex" and r["load"] == load and r["segments"] == n][0]
                print(f"{load:5} {n:8d} {b['ratio']:15.5f} {x['ratio']:16.6f}" + ("" if b["converged"] else "  (built-in not converged)"))
    with open(os.path.join(OUT, "cylinders_machine.txt"), "w") as f:
        f.write(machine() + "\n")
    print("\nmachine:", machine())


if __name__ == "__main__":
    main()
