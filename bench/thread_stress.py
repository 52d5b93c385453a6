# Crash hunt for the multi-threaded step: the small damping module's impact, run again and
# again on several threads while busy loops (`yes >/dev/null`) load every core, counting how
# the runs end (GPL-2.0-or-later). A data race shows as a rare segmentation fault (exit status
# 139, or -11 under `timeout`), which no single run can show.
#
#     /usr/bin/python3 bench/thread_stress.py [--runs 200] [--minutes M] [--threads 2] [--busy 4]
#         [--cache-dir DIR] [--out bench/results/thread_stress.csv]
#
# Each run: yade-double -n -j THREADS -x scripts/damping_module.py --small --no-vtk
# --cache-dir DIR --out <temp folder> (the fill made once, by the first run). The plugin is the
# one installed on the system (scripts/setup). Stops after --runs runs or, with --minutes, at the
# first run that ends after M minutes. Writes one row per run as it ends (run, exit status, wall
# time, peak force, energy residual) after the machine line, and prints the counts.
import argparse
import collections
import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from machine import machine_line  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--runs", type=int, default=200)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--minutes", type=float, default=None, help="stop after this long")
    ap.add_argument("--busy", type=int, default=4, help="busy loops beside the runs")
    ap.add_argument("--cache-dir", default=None)
    ap.add_argument("--out", default=os.path.join(HERE, "results", "thread_stress.csv"))
    a = ap.parse_args()
    work = tempfile.mkdtemp(prefix="thread-stress-")
    cache = a.cache_dir or os.path.join(work, "cache")
    env = dict(os.environ, PYTHONPATH=os.path.join(REPO, "py"), OMP_NUM_THREADS=str(a.threads))
    busy = [subprocess.Popen(["yes"], stdout=subprocess.DEVNULL) for _ in range(a.busy)]  # (as `yes >/dev/null`: the load that showed the race)
    rows = []
    fields = ["run", "exit_status", "wall_s", "peak_force_N", "energy_residual_max_fraction"]
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    f = open(a.out, "w", newline="")
    f.write(f"# {machine_line().strip()}; {a.threads} threads, {a.busy} busy loops\n")
    w = csv.DictWriter(f, fieldnames=fields)
    w.writeheader()
    start = time.monotonic()
    try:
        for k in range(a.runs):
            if a.minutes is not None and time.monotonic() - start > 60 * a.minutes:
                break
            out = os.path.join(work, "run")
            shutil.rmtree(out, ignore_errors=True)
            t0 = time.monotonic()
            r = subprocess.run(["yade-double", "-n", "-j", str(a.threads), "-x", "scripts/damping_module.py", "--small", "--no-vtk",
                                "--cache-dir", cache, "--out", out], cwd=REPO, env=env, stdin=subprocess.DEVNULL,
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            wall = time.monotonic() - t0
            peak = residual = ""
            try:
                s = json.load(open(os.path.join(out, "summary.json")))
                peak, residual = s.get("peak_impact_force", ""), s.get("energy_residual_max_fraction", "")
            except (OSError, ValueError):
                pass
            rows.append(dict(run=k + 1, exit_status=r.returncode, wall_s=f"{wall:.2f}", peak_force_N=peak, energy_residual_max_fraction=residual))
            w.writerow(rows[-1])
            f.flush()
            if r.returncode != 0:
                print(f"run {k + 1}: exit status {r.returncode}; its last lines:\n" + "\n".join(r.stdout.splitlines()[-4:]), flush=True)
            elif (k + 1) % 20 == 0:
                print(f"{k + 1} of {a.runs} runs", flush=True)
    finally:
        for p in busy:
            p.kill()
        f.close()
        shutil.rmtree(work, ignore_errors=True)
    counts = collections.Counter(r["exit_status"] for r in rows)
    print(f"\n| exit status | runs |\n|---|---|")
    for code, n in sorted(counts.items()):
        print(f"| {code} | {n} |")
    print(f"\n{len(rows)} runs at -j{a.threads} beside {a.busy} busy loops; rows in {a.out}")
    return 0 if set(counts) == {0} else 1


if __name__ == "__main__":
    sys.exit(main())
