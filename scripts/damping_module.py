# The main job: a cylindrical damping module hit by a boulder (GPL-2.0-or-later).
#
#     yade-double -n -x scripts/damping_module.py [--out results/module] [options]
#     (scripts/run does this; --help lists the options)
#
# Builds (or loads from the cache) the filled module, adds the boulder, runs the impact and
# writes into --out: params.json, timeseries.csv, energy.csv, summary.json, plots (*.png)
# and, unless --no-vtk, a VTK time series (vtk/flex.pvd) for ParaView. The files an earlier run
# wrote there are removed first; the time series are on disk row by row, and summary.json says
# how the run ended ("status": done, unstable, interrupted, failed; "running" if the process
# was killed outright), so a run stopped anyhow leaves what it recorded. --fill-only: only the
# filled module, into the cache (exit status 0 once it is there, 1 if the fill failed). --seeds N:
# the same run on N fills built alike, into OUT/seedS/, and the scatter of the results in OUT.
# Exit status (also in --help): 0 done; 1 bad input (one line on stderr names the option and the
# values allowed; nothing is filled or written), an output folder that cannot be written, or another
# error; 2 a NaN, an unstable state or a collapsed time step (the message names the body); 3 the
# energy balance residual exceeded --max-residual; 130 interrupted by SIGINT (Ctrl-C), 143 by
# SIGTERM. The options and their checks: yadeflex/module/cli.py; the run: yadeflex/module/impact.py.
import dataclasses
import os
import sys

HERE = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if a.endswith("damping_module.py")), os.getcwd())
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "py"))

from yadeflex.module.impact import run_impact, fill_only, PROG  # noqa: E402
from yadeflex.module.cli import parse, run_settings, OptionError  # noqa: E402


def main():
    me = next((k for k, a in enumerate(sys.argv) if a.endswith("damping_module.py")), 0)
    try:
        a, p = parse(sys.argv[me + 1:])
    except OptionError as e:  # every option is checked before anything is filled or built
        print(f"{PROG}: {e}", file=sys.stderr)
        return 1
    from yade import O
    cpus = len(os.sched_getaffinity(0))
    if O.numThreads > cpus:  # (YADE's ForceResetter crashes with many more threads than CPUs)
        print(f"{PROG}: YADE runs {O.numThreads} threads (yade-double -j) but {cpus} CPUs are available here: give -j {cpus} or fewer", file=sys.stderr)
        return 1
    if a.fill_only:
        return max(fill_only(dataclasses.replace(p, seed=p.seed + k), a.cache_dir) for k in range(a.seeds))
    if a.seeds > 1:
        from yadeflex.module.seeds import run_seeds
        return run_seeds(p, a.out, a.seeds, cache_dir=a.cache_dir, **run_settings(a))
    return run_impact(p, a.out, cache_dir=a.cache_dir, **run_settings(a))["exit_status"]


sys.exit(main())
