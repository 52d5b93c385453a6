# Where the whole default impact's time goes, engine by engine, at one and two threads; and how
# long the run would take if some of its engines cost nothing (GPL-2.0-or-later).
#
#     /usr/bin/python3 bench/impact_budget.py [--reps 3] [--threads 1 2] [--out bench/results/impact_budget.csv]
#
# For each repetition, each thread count in turn, a child process
#     yade-double -n -j T -x bench/impact_budget.py --child ...
# runs the main job as `scripts/damping_module.py` runs it without options (the same parse and
# run_impact: the cached fill, VTK frames, records and plots), with O.timingEnabled from its
# start. The parent times the whole child process, as a user waits for it. The child reports each
# engine's execTime summed over the impact, the impact's steps and summary.json's run_time_s.
# Parts of the process (the child notes the wall clock when the script starts and when run_impact
# returns, the parent when it starts the child and when the child has exited):
#   - "YADE's start": to the script's first line;
#   - one row per engine (by label), summed over the impact;
#   - "in the run, between the engines": run_time_s less the engines (the fill loaded, the scene
#     built, the records and VTK frames written between steps);
#   - "after the run's clock": from run_time_s to run_impact's return (the plots and the slab
#     map's files, written after the summary), with the job's option parsing before it;
#   - "exit": from run_impact's return to the process's end.
# The rows "floor: ..." are the process's time with the named engines' time taken out: how long the
# run would take were they free, its steps and its other work unchanged.
# The cached fill must exist (a first `scripts/damping_module.py` run makes it).
# Writes --out (threads,part,seconds,us_per_step,share,runs: medians), <out>_runs.csv (every run),
# the machine line, and prints the table.
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

HERE = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if a.endswith("impact_budget.py")), os.path.join(os.getcwd(), "bench"))
REPO = os.path.dirname(HERE)

START = "YADE's start"
BETWEEN = "in the run, between the engines"
AFTER = "after the run's clock: plots, slab map"
EXIT = "exit"
PROCESS = "whole process"
# the floors: the engines whose time is taken out
FLOORS = {"floor: interaction loop and grain engine free": ("interactionLoop", "grainEngine"),
          "floor: every engine free": None}


def parse():
    me = next((k for k, a in enumerate(sys.argv) if a.endswith("impact_budget.py")), 0)
    ap = argparse.ArgumentParser(prog="impact_budget.py", description="Where the default impact's time goes, engine by engine.")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--out", default=os.path.join(HERE, "results", "impact_budget.csv"))
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--json", default=None, help=argparse.SUPPRESS)
    ap.add_argument("--run-out", default=None, help=argparse.SUPPRESS)
    a = ap.parse_args(sys.argv[me + 1:])
    if a.reps < 1 or any(t < 1 for t in a.threads):
        ap.error("--reps and --threads must be positive")
    return a


def child(a):
    """In YADE: the main job with every engine timed; its numbers into a.json."""
    sys.path.insert(0, os.path.join(REPO, "py"))
    t_entry = time.time()
    from yade import O
    from yadeflex.module.cli import parse as parse_job, run_settings
    from yadeflex.module.impact import run_impact
    opts, params = parse_job(["--out", a.run_out])
    O.timingEnabled = True
    summary = run_impact(params, opts.out, cache_dir=opts.cache_dir, progress=False, **run_settings(opts))
    t_return = time.time()
    O.timingEnabled = False
    if summary.get("exit_status") != 0:
        raise SystemExit(f"impact_budget: the main job ended with {summary.get('status')}: {summary.get('message')}")
    if not summary.get("filled_from_cache"):
        raise SystemExit("impact_budget: the fill was not in the cache (run scripts/damping_module.py once first): this run's time includes it")
    engines = {}
    for e in O.engines:
        name = e.label or type(e).__name__
        engines[name] = engines.get(name, 0.0) + e.execTime * 1e-9
    with open(a.json, "w") as f:
        json.dump(dict(engines=engines, t_entry=t_entry, t_return=t_return, steps=summary["impact_steps"], run_time_s=summary["run_time_s"],
                       peak_kN=summary["peak_impact_force"] / 1e3, penetration_mm=summary["penetration_max"] * 1e3,
                       residual=summary["energy_residual_max_fraction"]), f)
    return 0


def one_run(threads, work):
    js = os.path.join(work, "run.json")
    out = os.path.join(work, "module")
    cmd = ["yade-double", "-n", "-j", str(threads), "-x", os.path.abspath(__file__), "--child", "--json", js, "--run-out", out]
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    t_spawn = time.time()
    p = subprocess.run(cmd, cwd=REPO, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    t_exit = time.time()
    if p.returncode != 0 or not os.path.exists(js):
        raise SystemExit(f"impact_budget: the run at -j{threads} failed (exit {p.returncode}):\n{p.stderr[-2000:]}")
    with open(js) as f:
        r = json.load(f)
    os.remove(js)
    r["process_s"] = t_exit - t_spawn
    r["start_s"] = r["t_entry"] - t_spawn
    r["exit_s"] = t_exit - r["t_return"]
    r["after_s"] = r["t_return"] - r["t_entry"] - r["run_time_s"]
    return r


def parts(r):
    """{part: seconds} of one run, the process's parts adding up to the process."""
    eng = r["engines"]
    p = {START: r["start_s"]}
    p.update(eng)
    p[BETWEEN] = r["run_time_s"] - sum(eng.values())
    p[AFTER] = r["after_s"]
    p[EXIT] = r["exit_s"]
    p[PROCESS] = r["process_s"]
    for name, free in FLOORS.items():
        p[name] = r["process_s"] - sum(v for k, v in eng.items() if free is None or k in free)
    return p


def main():
    a = parse()
    if a.child:
        return child(a)
    sys.path.insert(0, HERE)
    from machine import machine_line
    runs = {t: [] for t in a.threads}
    with tempfile.TemporaryDirectory(prefix="impact_budget_") as work:
        for rep in range(a.reps):
            for t in a.threads:
                r = one_run(t, work)
                runs[t].append(r)
                print(f"rep {rep} -j{t}: {r['process_s']:.1f} s, {r['steps']} steps, peak {r['peak_kN']:.2f} kN, "
                      f"penetration {r['penetration_mm']:.1f} mm, residual {100 * r['residual']:.3f}%", flush=True)
    rows, every = [], []
    for t in a.threads:
        ps = [parts(r) for r in runs[t]]
        steps = statistics.median(r["steps"] for r in runs[t])
        names = list(ps[0])
        proc = statistics.median(p[PROCESS] for p in ps)
        for name in names:
            sec = statistics.median(p.get(name, 0.0) for p in ps)
            per_step = 1e6 * sec / steps if name in runs[t][0]["engines"] else ""
            rows.append(dict(threads=t, part=name, seconds=f"{sec:.2f}", us_per_step=f"{per_step:.0f}" if per_step != "" else "",
                             share=f"{sec / proc:.3f}", runs=" ".join(f"{p.get(name, 0.0):.2f}" for p in ps)))
        for k, (r, p) in enumerate(zip(runs[t], ps)):
            every.append(dict(threads=t, rep=k, steps=r["steps"], peak_kN=f"{r['peak_kN']:.2f}", penetration_mm=f"{r['penetration_mm']:.1f}",
                              residual_pct=f"{100 * r['residual']:.3f}", **{name: f"{v:.3f}" for name, v in p.items()}))
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    with open(a.out, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["threads", "part", "seconds", "us_per_step", "share", "runs"])
        w.writeheader()
        w.writerows(rows)
    base = os.path.splitext(a.out)[0]
    with open(base + "_runs.csv", "w", newline="") as f:
        fields = list(dict.fromkeys(k for e in every for k in e))
        w = csv.DictWriter(f, fieldnames=fields, restval="")
        w.writeheader()
        w.writerows(every)
    with open(base + "_machine.txt", "w") as f:
        f.write(machine_line())
    print(f"\nthe default impact, medians of {a.reps} ({a.out}):")
    print(f"{'threads':>7}  {'part':48} {'s':>7} {'us/step':>8} {'share':>6}")
    for r in rows:
        print(f"{r['threads']:>7}  {r['part']:48} {r['seconds']:>7} {r['us_per_step']:>8} {r['share']:>6}")
    return 0


if __name__ == "__main__":
    rc = main()
    if rc:
        sys.exit(rc)
