# Time to a result for a new configuration: the fill and the impact of the main job's default
# module, an earlier build against this one, alternating run by run (GPL-2.0-or-later).
#
#     /usr/bin/python3 bench/time_to_result.py --before DIR [--after DIR] [--reps 3] [--small]
#         [--threads-reps 2] [--fill-once] [--out bench/results/time_to_result.csv]
#     /usr/bin/python3 bench/time_to_result.py --threads-only [--threads-reps 5] [--after DIR]
#
# A build is a checkout DIR: its scripts/damping_module.py and py/ are run with the plugin
# installed in DIR/.prefix (`cd DIR && YADE_PREFIX=$PWD/.prefix scripts/setup`), or the system's
# plugin when DIR has no .prefix (--after defaults to this checkout and the system plugin, as
# scripts/setup installs it). For each repetition, before then after:
#   fill:   yade-double -n -j1 -x DIR/scripts/damping_module.py --fill-only --cache-dir <new empty folder>
#   impact: yade-double -n -j1 -x DIR/scripts/damping_module.py --cache-dir <that folder> --out <folder>
# (the main job's defaults, VTK frames included). Each stage's time is the wall time of the whole
# process, YADE's start included: what a user waits for. Then --threads-reps impacts of the after
# build at -j1 and -j2, alternating, from its first fill (both cores must be free); each row has
# the whole process's time and the impact's as the run reports it (summary.json's impact_time_s:
# after the fill is loaded, up to the summary; the plots and YADE's start not included) with its
# steps. --threads-only: only these, from the after build's fill in a new cache folder (filled first).
# Writes --out (stage,before_s,after_s: rows fill and impact, medians), <out>_runs.csv (every
# run with its peak force, penetration, energy residual and the fill's state: grains, solid
# fraction, coordination, grains on the lining), <out>_threads.csv, the machine line, and
# prints the tables.
import argparse
import csv
import json
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from machine import machine_line  # noqa: E402

FILL_STATE = os.path.join(HERE, "fill_state.py")


def parse():
    ap = argparse.ArgumentParser(prog="time_to_result.py", description=__doc__)
    ap.add_argument("--before", metavar="DIR", help="checkout of the earlier build (its plugin in DIR/.prefix)")
    ap.add_argument("--after", default=REPO, metavar="DIR", help="checkout of the new build (default: this one)")
    ap.add_argument("--reps", type=int, default=3, help="repetitions of fill + impact per build (medians)")
    ap.add_argument("--threads-reps", type=int, default=2, help="impacts of the new build at -j1 and at -j2 each (0: none)")
    ap.add_argument("--small", action="store_true", help="the reduced module (a quick try, not the acceptance)")
    ap.add_argument("--fill-once", action="store_true",
                    help="fill each build once, in the first repetition, and run every impact from that fill (the fill's time is then one run)")
    ap.add_argument("--threads-only", action="store_true", help="only the -j1/-j2 impacts of the after build (writes <out>_threads.csv)")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "time_to_result.csv"))
    a = ap.parse_args()
    if not a.threads_only and not a.before:
        ap.error("--before DIR is needed (or --threads-only)")
    if a.threads_only and a.threads_reps < 1:
        ap.error("--threads-only needs --threads-reps of at least 1")
    return a


def env_for(checkout):
    env = dict(os.environ, PYTHONPATH=os.path.join(checkout, "py"))
    prefix = os.path.join(checkout, ".prefix")
    if os.path.isdir(prefix):
        env["YADE_PREFIX"] = prefix
    else:
        env.pop("YADE_PREFIX", None)
    return env


def yade(checkout, threads, args, log):
    """Run the checkout's main job; (wall time [s], exit status)."""
    env = env_for(checkout)
    env["OMP_NUM_THREADS"] = str(threads)
    cmd = ["yade-double", "-n", "-j", str(threads), "-x", os.path.join(checkout, "scripts", "damping_module.py"), *args]
    t0 = time.time()
    with open(log, "w") as f:
        rc = subprocess.call(cmd, stdout=f, stderr=subprocess.STDOUT, env=env, cwd=checkout)
    return time.time() - t0, rc


def fill_state(cache_dir, small):
    """The settled fill's numbers (bench/fill_state.py, this checkout's, on either build's fill)."""
    env = env_for(REPO)
    env["OMP_NUM_THREADS"] = "1"
    out = subprocess.run(["yade-double", "-n", "-j1", "-x", FILL_STATE, cache_dir] + (["--small"] if small else []),
                         capture_output=True, text=True, env=env, cwd=REPO)
    line = next((x for x in out.stdout.splitlines() if x.startswith("FILLSTATE ")), None)
    if line is None:
        raise RuntimeError(f"fill_state.py failed:\n{out.stdout[-2000:]}\n{out.stderr[-2000:]}")
    return json.loads(line[len("FILLSTATE "):])


def main():
    a = parse()
    builds = [("before", a.before and os.path.abspath(a.before)), ("after", os.path.abspath(a.after))]
    size = ["--small"] if a.small else []
    work = tempfile.mkdtemp(prefix="time_to_result-")
    runs, first_cache = [], {}
    try:
        if a.threads_only:
            first_cache["after"] = os.path.join(work, "after-cache")
            os.makedirs(first_cache["after"])
            _, rc = yade(builds[1][1], 1, ["--fill-only", "--cache-dir", first_cache["after"], *size], os.path.join(work, "after-fill.log"))
            if rc != 0:
                raise RuntimeError(f"fill failed (exit {rc}), see {work}")
        for rep in range(0 if a.threads_only else a.reps):
            for label, checkout in builds:
                out = os.path.join(work, f"{label}-{rep}-run")
                if a.fill_once and label in first_cache:
                    cache, t_fill = first_cache[label], None
                else:
                    cache = os.path.join(work, f"{label}-{rep}-cache")
                    os.makedirs(cache)
                    t_fill, rc = yade(checkout, 1, ["--fill-only", "--cache-dir", cache, *size], os.path.join(work, f"{label}-{rep}-fill.log"))
                    if rc != 0:
                        raise RuntimeError(f"{label} fill failed (exit {rc}), see {work}")
                    state = fill_state(cache, a.small)
                t_imp, rc = yade(checkout, 1, ["--cache-dir", cache, "--out", out, *size], os.path.join(work, f"{label}-{rep}-impact.log"))
                with open(os.path.join(out, "summary.json")) as f:
                    s = json.load(f)
                row = dict(build=label, rep=rep, fill_s=None if t_fill is None else round(t_fill, 1), impact_s=round(t_imp, 1), exit_status=rc,
                           peak_force_kN=round(s["peak_impact_force"] / 1e3, 2), penetration_mm=round(1e3 * s["penetration_max"], 1),
                           energy_residual_pct=round(100 * s["energy_residual_max_fraction"], 3))
                row.update(state)
                runs.append(row)
                first_cache.setdefault(label, cache)
                print(" ".join(f"{k}={v}" for k, v in row.items()), flush=True)
        threads = []
        for rep in range(a.threads_reps):
            for t in (1, 2):
                out = os.path.join(work, f"threads-{t}-{rep}")
                wall, rc = yade(builds[1][1], t, ["--cache-dir", first_cache["after"], "--out", out, *size], os.path.join(work, f"threads-{t}-{rep}.log"))
                with open(os.path.join(out, "summary.json")) as f:
                    it = json.load(f).get("impact_time_s") or {}
                threads.append(dict(threads=t, rep=rep, impact_s=round(wall, 2), exit_status=rc, impact_stage_s=round(it.get("total", math.nan), 2),
                                    steps_s=round(it.get("steps", math.nan), 2), vtk_frames_s=round(it.get("vtk_frames", math.nan), 2)))
                print(" ".join(f"{k}={v}" for k, v in threads[-1].items()), flush=True)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    stem = os.path.splitext(a.out)[0]
    with open(stem + "_machine.txt", "w") as f:
        f.write(machine_line())
    if a.threads_only:
        write_threads(stem, threads)
        return
    med = {(b, k): statistics.median(r[k] for r in runs if r["build"] == b and r[k] is not None) for b, _ in builds for k in ("fill_s", "impact_s")}
    with open(a.out, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["stage", "before_s", "after_s"])
        for stage in ("fill", "impact"):
            w.writerow([stage, round(med[("before", stage + "_s")], 1), round(med[("after", stage + "_s")], 1)])
    write_rows(stem + "_runs.csv", runs)
    print(f"\n{'stage':8s} {'before [s]':>11s} {'after [s]':>10s} {'speed-up':>9s}   (medians of {a.reps}, one core{', small module' if a.small else ''})")
    for stage in ("fill", "impact"):
        b, c = med[("before", stage + "_s")], med[("after", stage + "_s")]
        print(f"{stage:8s} {b:11.1f} {c:10.1f} {b / c:8.2f}x")
    if threads:
        write_threads(stem, threads)
    print(f"\nwrote {a.out}, {stem}_runs.csv")


def write_rows(path, rows):
    """A CSV of dicts, the columns those of the first."""
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)


def write_threads(stem, threads):
    """<stem>_threads.csv (every run) and the medians at -j1 and -j2, with their ratio."""
    write_rows(stem + "_threads.csv", threads)
    print(f"\n{'after, medians':34s} {'-j1 [s]':>8s} {'-j2 [s]':>8s} {'ratio':>6s}   ({len(threads) // 2} runs each)")
    for k, what in (("impact_s", "whole process"), ("impact_stage_s", "impact (summary's impact_time_s)"), ("steps_s", "its steps")):
        j1 = statistics.median(r[k] for r in threads if r["threads"] == 1)
        j2 = statistics.median(r[k] for r in threads if r["threads"] == 2)
        print(f"{what:34s} {j1:8.2f} {j2:8.2f} {j1 / j2:5.2f}x")
    print(f"wrote {stem}_threads.csv")


if __name__ == "__main__":
    main()
