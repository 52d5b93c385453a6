# Runs every validation case and writes OUT/README.md and OUT/summary.json (validation/report.py).
#     PYTHONPATH=py yade-double -n -j1 -x validation/run.py [--full] [OUT] [--cache-dir DIR] [--groups a,b]
# (scripts/validate is the same.) OUT defaults to this folder. The reduced version (default) runs in
# the test suite; --full runs the finer and longer cases.
import argparse
import json
import os
import platform
import shutil
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(next((a for a in sys.argv if a.endswith("run.py")), __file__)))
sys.path.insert(0, HERE)

from yade import O  # noqa: E402

import analytic  # noqa: E402
import builtin_cases  # noqa: E402
import cushion_cases  # noqa: E402
import report  # noqa: E402
import tensile_cases  # noqa: E402

GROUPS = {"analytic": analytic, "tensile": tensile_cases, "cushion": cushion_cases, "builtin": builtin_cases}
REDUCED = ("analytic", "tensile", "cushion")  # the built-in comparison (its own process, ~30 s) runs in --full


def main():
    me = next((k for k, a in enumerate(sys.argv) if a.endswith("run.py")), 0)
    ap = argparse.ArgumentParser(prog="scripts/validate", description="Run the validation cases, write README.md and summary.json.")
    ap.add_argument("out", nargs="?", default=HERE, help="output folder (default: validation/)")
    ap.add_argument("--full", action="store_true", help="the full version: finer discretisations, more cases and points")
    ap.add_argument("--cache-dir", default=None, help="filled-module cache (default: the main job's, ~/.cache/yadeflex/modules)")
    ap.add_argument("--groups", default=None, help=f"comma-separated subset of {','.join(GROUPS)}")
    a = ap.parse_args(sys.argv[me + 1:])
    groups = a.groups.split(",") if a.groups else list(GROUPS if a.full else REDUCED)
    bad = [g for g in groups if g not in GROUPS]
    if bad:
        ap.error(f"unknown group(s) {', '.join(bad)}; choose from {', '.join(GROUPS)}")
    os.makedirs(a.out, exist_ok=True)
    runs = tempfile.mkdtemp(prefix="yadeflex-validation-")  # the impact runs' folders: not part of the report
    t0 = time.time()
    cases = []
    try:
        for g in groups:
            t = time.time()
            mod = GROUPS[g]
            kw = dict(cache_dir=a.cache_dir) if g in ("cushion", "builtin") else {}
            got = mod.run(a.full, a.out, **kw) if g not in ("cushion", "builtin") else _with_runs(mod, a.full, a.out, runs, **kw)
            cases += got
            print(f"{g}: {len(got)} cases in {time.time() - t:.0f} s: " + ", ".join(f"{c.name} {c.verdict}" for c in got), flush=True)
    finally:
        shutil.rmtree(runs, ignore_errors=True)
    secs = time.time() - t0
    mode = "full" if a.full else "reduced"
    timings = _timings(a.out)
    if not a.groups:
        timings[mode] = round(secs, 1)
    machine = f"{platform.processor() or platform.machine()}, {os.cpu_count()} CPUs, {O.numThreads} thread(s)"
    s = report.write(a.out, cases, mode, secs, machine, timings, {GROUPS[g].GROUP: GROUPS[g].PLOTS for g in groups})
    print(f"{mode}: {s['counts']} in {secs:.0f} s; wrote {os.path.join(a.out, 'README.md')} and summary.json")


def _with_runs(mod, full, out, runs, cache_dir=None):
    """The impact cases write their run folders under `runs` and their plots under `out`."""
    res = mod.run(full, runs, cache_dir=cache_dir)
    os.makedirs(os.path.join(out, "plots"), exist_ok=True)
    for png in ("cushion.png", "module_compare_small.png"):
        if os.path.exists(os.path.join(runs, png)):
            shutil.copy(os.path.join(runs, png), os.path.join(out, "plots", png))
    return res


def _timings(out):
    """The run times of both versions kept from the last summary.json in out."""
    try:
        with open(os.path.join(out, "summary.json")) as f:
            return dict(json.load(f).get("timings_s", {}))
    except (OSError, ValueError):
        return {}


main()
