# Runs per hour of a parametric study (yadeflex.module.study) with 1 and 2 local workers and through a
# real single-node Slurm on this machine (GPL-2.0-or-later).
#
#     /usr/bin/python3 bench/bench_study.py [--runs 6] [--reps 3] [--duration 0.02] [--no-slurm]
#
# The study: --runs small modules (--small --no-vtk --duration D, drop heights spread over
# 0.5-2 m), one filled module, filled before the timing (every timed run loads it). Each setting
# runs the whole study --reps times into fresh folders, the settings interleaved round by round
# so that all see the same machine load; runs per hour = runs / wall time of the study (the
# coordinator's start-up, dispatch and gathering included). Prints the median per setting and
# writes bench/results/study_throughput.csv (one row per study) and study_throughput_machine.txt.
# Slurm needs root and Debian's slurm-wlm and munge (tests/yade/local_slurm.py starts it).
import argparse
import csv
import os
import statistics
import sys
import tempfile
import time

BENCH = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(BENCH)
sys.path[:0] = [BENCH, os.path.join(REPO, "py"), os.path.join(REPO, "tests", "yade"), "/usr/lib/x86_64-linux-gnu/yade-double/py"]

from machine import machine_line  # noqa: E402
from local_slurm import LocalSlurm, unavailable  # noqa: E402
from yadeflex.module import study  # noqa: E402


def write_study(path, n, duration):
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["name", "small", "no_vtk", "duration", "drop_height"])
        for k in range(n):
            w.writerow([f"r{k:02d}", "yes", "yes", duration, f"{0.5 + 1.5 * k / max(1, n - 1):.3g}"])
    return path


def main(argv):
    ap = argparse.ArgumentParser(prog="bench_study.py", description="Runs per hour of a study: 1 and 2 local workers, Slurm.")
    ap.add_argument("--runs", type=int, default=6, help="runs in the study (default 6)")
    ap.add_argument("--reps", type=int, default=3, help="studies per setting (default 3)")
    ap.add_argument("--duration", default="0.02", help="simulated impact per run [s] (default 0.02)")
    ap.add_argument("--no-slurm", action="store_true")
    a = ap.parse_args(argv)
    base = tempfile.mkdtemp(prefix="bench-study-")
    cache = os.path.join(base, "cache")
    f = write_study(os.path.join(base, "study.csv"), a.runs, a.duration)
    quiet = lambda line: None  # noqa: E731
    # fill the module (not timed), and check that every run ends
    rows = study.run_study(f, os.path.join(base, "warmup"), workers=2, cache_dir=cache, progress=quiet)
    assert all(r["status"] == study.DONE for r in rows), [(r["name"], r["status"], r["message"]) for r in rows]
    settings = [("local, 1 worker", dict(backend="local", workers=1)), ("local, 2 workers", dict(backend="local", workers=2))]
    why = "--no-slurm" if a.no_slurm else unavailable()
    cluster = None
    if why is None:
        cluster = LocalSlurm(os.path.join(base, "slurm")).start()
        os.environ.update(cluster.env)
        settings.append((f"slurm (1 node, {os.cpu_count()} CPUs)", dict(backend="slurm", slurm=study.Slurm(poll=1.0))))
    out = []
    try:
        for rep in range(a.reps):
            for name, kw in settings:
                t0 = time.time()
                rows = study.run_study(f, os.path.join(base, f"{rep}-{kw['backend']}-{kw.get('workers', 0)}"), cache_dir=cache,
                                       progress=quiet, **kw)
                wall = time.time() - t0
                assert all(r["status"] == study.DONE for r in rows)
                run_wall = statistics.median(r["wall_time_s"] for r in rows)
                out.append(dict(setting=name, rep=rep, runs=a.runs, wall_s=round(wall, 2), runs_per_hour=round(3600 * a.runs / wall, 1),
                                median_run_wall_s=round(run_wall, 2)))
                print(f"  {name}: {a.runs} runs in {wall:.1f} s", flush=True)
    finally:
        if cluster is not None:
            cluster.stop()
    print(f"\n{'setting':<28} {'runs/hour (median)':>19} {'study wall [s]':>15} {'one run [s]':>12}")
    for name, _ in settings:
        rs = [r for r in out if r["setting"] == name]
        print(f"{name:<28} {statistics.median(r['runs_per_hour'] for r in rs):>19.0f} {statistics.median(r['wall_s'] for r in rs):>15.1f} "
              f"{statistics.median(r['median_run_wall_s'] for r in rs):>12.1f}")
    if why:
        print(f"(no Slurm: {why})")
    res = os.path.join(BENCH, "results")
    with open(os.path.join(res, "study_throughput.csv"), "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(out[0]))
        w.writeheader()
        w.writerows(out)
    with open(os.path.join(res, "study_throughput_machine.txt"), "w") as fh:
        fh.write(machine_line() + f"study: {a.runs} runs of --small --no-vtk --duration {a.duration}, one thread each\n")
    print(f"wrote {os.path.join(res, 'study_throughput.csv')}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
