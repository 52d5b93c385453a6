# Benchmark: two builds of yade-flex on the module's gravel bed, alternating in one sitting
# (GPL-2.0-or-later).
#
#     /usr/bin/python3 bench/grains_builds.py --before DIR [--after DIR] [--rounds 4] [--steps 3000]
#         [--cases flex:rest,flex:impact,flex_norol:rest,flex_norol:impact]
#
# Each run is one yade-double -n -j1 process (OMP_NUM_THREADS=1) of bench/lammps_grains.py's scene
# (its build_yade: the cached default module's settled grains, our engines at the fixed step
# 3.25e-5 s, the bed at rest or under the 800 kg sphere), 200 untimed steps, then --steps timed
# steps; it prints microseconds per particle-step, the collider's runs, the real contacts and the
# potential pairs. A build is a checkout DIR: its py/ and, when DIR/.prefix exists, the plugin
# installed there (`cd DIR && YADE_PREFIX=$PWD/.prefix scripts/setup`); --after defaults to this
# checkout and the system's plugin. The builds alternate run by run (before, after, before, ...),
# each round in another order of the cases. Writes bench/results/grains_builds.csv (medians,
# ranges, after/before ratio of the medians) and grains_builds_raw.csv, and prints a table.
import argparse
import csv
import os
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from machine import machine_line  # noqa: E402

CHILD = r'''
import os, sys, time
sys.path.insert(0, os.environ["GB_BENCH"])
sys.argv = ["lammps_grains.py"]
import lammps_grains as LG
from yadeflex.module import ModuleParams
kind, case, steps = os.environ["GB_KIND"], os.environ["GB_CASE"], int(os.environ["GB_STEPS"])
a = LG.parse()
p = ModuleParams()
grains, _ = LG.bed(p, a.cache_dir)
n, imp = LG.build_yade(a, p, grains, kind, 1, case)
O.run(a.warmup, True)
col = next(e for e in O.engines if e.label == "collider")
runs0 = col.numAction
t0 = time.perf_counter()
O.run(steps, True)
t = time.perf_counter() - t0
print(f"GB_RESULT {1e6 * t / (steps * n):.6f} {col.numAction - runs0} {O.interactions.countReal()} {len(O.interactions.all(False))}")
'''


def parse():
    ap = argparse.ArgumentParser(prog="grains_builds.py", description="Two builds on the module's gravel bed, alternating, one thread.")
    ap.add_argument("--before", required=True, metavar="DIR")
    ap.add_argument("--after", default=REPO, metavar="DIR")
    ap.add_argument("--rounds", type=int, default=4)
    ap.add_argument("--steps", type=int, default=3000)
    ap.add_argument("--cases", default="flex:rest,flex:impact,flex_norol:rest,flex_norol:impact")
    ap.add_argument("--out", default=os.path.join(HERE, "results"))
    a = ap.parse_args()
    a.cases = [tuple(c.split(":")) for c in a.cases.split(",")]
    if a.rounds < 1 or a.steps < 1 or any(len(c) != 2 or c[1] not in ("rest", "impact") for c in a.cases):
        ap.error("--rounds and --steps must be positive, --cases KIND:rest|impact,...")
    return a


def run(checkout, kind, case, steps, script):
    env = dict(os.environ, PYTHONPATH=os.path.join(checkout, "py"), OMP_NUM_THREADS="1", GB_BENCH=HERE, GB_KIND=kind, GB_CASE=case, GB_STEPS=str(steps))
    prefix = os.path.join(checkout, ".prefix")
    if os.path.isdir(prefix):
        env["YADE_PREFIX"] = prefix
    else:
        env.pop("YADE_PREFIX", None)
    out = subprocess.run(["yade-double", "-n", "-j1", "-x", script], env=env, capture_output=True, text=True)
    line = next((s for s in out.stdout.splitlines() if s.startswith("GB_RESULT")), None)
    if line is None:
        sys.exit(f"grains_builds: {checkout} {kind} {case} printed no result:\n{out.stdout[-2000:]}\n{out.stderr[-2000:]}")
    us, runs, real, pairs = line.split()[1:]
    return dict(us=float(us), collider_runs=int(runs), contacts=int(real), pairs=int(pairs))


def main():
    a = parse()
    os.makedirs(a.out, exist_ok=True)
    script = os.path.join(tempfile.mkdtemp(prefix="grains_builds-"), "child.py")
    with open(script, "w") as fh:
        fh.write(CHILD)
    line0 = machine_line()
    print(f"grains_builds: before {a.before}, after {a.after}; {line0.strip()}", flush=True)
    raw = []
    for rnd in range(a.rounds):
        cases = a.cases[rnd % len(a.cases):] + a.cases[:rnd % len(a.cases)]
        for kind, case in cases:
            for build, checkout in (("before", a.before), ("after", a.after)) if rnd % 2 == 0 else (("after", a.after), ("before", a.before)):
                t0 = time.time()
                r = run(checkout, kind, case, a.steps, script)
                r.update(round=rnd, build=build, engine=kind, case=case)
                raw.append(r)
                print(f"  round {rnd} {build:6s} {kind:10s} {case:6s} {r['us']:.3f} us/particle-step, collider runs {r['collider_runs']}, "
                      f"contacts {r['contacts']}, pairs {r['pairs']}  [{time.time() - t0:.0f} s]", flush=True)
    line1 = machine_line()
    keys = ["round", "build", "engine", "case", "us", "collider_runs", "contacts", "pairs"]
    with open(os.path.join(a.out, "grains_builds_raw.csv"), "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        w.writerows(raw)
    rows = []
    for kind, case in a.cases:
        m = {}
        for b in ("before", "after"):
            v = [r for r in raw if r["engine"] == kind and r["case"] == case and r["build"] == b]
            us = [r["us"] for r in v]
            m[b] = dict(us=statistics.median(us), lo=min(us), hi=max(us), runs=statistics.median(r["collider_runs"] for r in v),
                        pairs=statistics.median(r["pairs"] for r in v))
        rows.append(dict(engine=kind, case=case, before_us=f"{m['before']['us']:.4f}", before_range=f"{m['before']['lo']:.3f}-{m['before']['hi']:.3f}",
                         after_us=f"{m['after']['us']:.4f}", after_range=f"{m['after']['lo']:.3f}-{m['after']['hi']:.3f}",
                         speedup=f"{m['before']['us'] / m['after']['us']:.3f}", collider_runs_before=m["before"]["runs"],
                         collider_runs_after=m["after"]["runs"], pairs_before=m["before"]["pairs"], pairs_after=m["after"]["pairs"],
                         steps=a.steps, rounds=a.rounds))
    path = os.path.join(a.out, "grains_builds.csv")
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(a.out, "grains_builds_machine.txt"), "w") as fh:
        fh.write(f"start: {line0}end: {line1}before: {a.before}; after: {a.after}\n")
    print(f"\nus per particle-step, median (range) of {a.rounds} alternated runs, one thread; collider runs in {a.steps} steps")
    print(f"{'case':22s} {'before':>22s} {'after':>22s} {'speed-up':>8s} {'collider runs':>14s} {'potential pairs':>16s}")
    for r in rows:
        print(f"{r['engine'] + ', ' + r['case']:22s} {r['before_us'] + ' (' + r['before_range'] + ')':>22s} {r['after_us'] + ' (' + r['after_range'] + ')':>22s} "
              f"{r['speedup']:>8s} {str(r['collider_runs_before']) + ' -> ' + str(r['collider_runs_after']):>14s} "
              f"{str(r['pairs_before']) + ' -> ' + str(r['pairs_after']):>16s}")
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
