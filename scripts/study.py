# A parametric study of the main job from one CSV file (GPL-2.0-or-later); scripts/study runs
# this with the system Python (the runs themselves are YADE processes):
#
#     /usr/bin/python3 scripts/study.py STUDY.csv OUT_DIR [--backend local|slurm|mpi] [--workers N] [--resume] ...
#
# The study file, the outputs and the backends: yadeflex/module/study.py; --help lists the options.
import argparse
import builtins
import contextlib
import io
import os
import sys

# run by mpi4py.futures (runpy), this script's __builtins__ is a dict; YADE's start-up sets
# attributes on the builtins module through it
__builtins__ = builtins

HERE = os.path.dirname(os.path.abspath(__file__))
YADE_PY = os.environ.get("YADE_PY", "/usr/lib/x86_64-linux-gnu/yade-double/py")
sys.path[:0] = [os.path.join(os.path.dirname(HERE), "py"), YADE_PY]


def main(argv):
    ap = argparse.ArgumentParser(prog="study", description="Run a parametric study of the damping-module impact.",
                                 epilog="exit status: 0 every run done; 1 the study, an option or the setup refused (nothing ran); "
                                        "3 some runs did not finish (their status and log are in results.csv); 130, 143 stopped by "
                                        "Ctrl-C (SIGINT), SIGTERM: the queue cancelled, the running rows stopped with their partial "
                                        "results, results.csv written for every row")
    ap.add_argument("study_file", help="CSV: a header of the main job's option names (plus name, seeds), a row per configuration")
    ap.add_argument("out_dir", help="results folder: runs/NAME/, results.csv, plots")
    ap.add_argument("--backend", default="local", help="local (default), mpi (under mpirun) or slurm")
    ap.add_argument("--workers", type=int, default=None, help="parallel runs (local: default the CPUs this process may run on; slurm: array throttle)")
    ap.add_argument("--resume", action="store_true", help="keep the runs already done, rerun the missing or failed ones")
    ap.add_argument("--cache-dir", default=None, help="filled-module cache (default ~/.cache/yadeflex/modules; on a cluster: a shared folder)")
    ap.add_argument("--timeout", type=float, default=None, help="wall seconds after which a run is stopped (recorded as timeout)")
    ap.add_argument("--yade", default="yade-double", help="the YADE executable (default yade-double)")
    ap.add_argument("--partition", default=None, help="slurm: the partition (sbatch --partition)")
    ap.add_argument("--account", default=None, help="slurm: the account (sbatch --account)")
    ap.add_argument("--time-limit", default=None, help="slurm: time limit of each run, e.g. 1:00:00 (sbatch --time)")
    ap.add_argument("--sbatch-arg", action="append", default=[], help="slurm: an extra sbatch argument (repeatable), e.g. --sbatch-arg=--qos=short")
    ap.add_argument("--poll", type=float, default=5.0, help="slurm: seconds between squeue polls (default 5)")
    ap.add_argument("--sbatch-setup", action="append", default=[], help="slurm: a shell line each job runs first (repeatable), e.g. --sbatch-setup='module load yade'")
    ap.add_argument("--report", action="store_true", help="then write OUT_DIR/report.html (as scripts/report OUT_DIR does)")
    a = ap.parse_args(argv)
    try:
        with contextlib.redirect_stdout(io.StringIO()):  # (YADE's import prints its Python version: the coordinator stays quiet)
            from yadeflex.module import study
    except ImportError as e:
        print(f"study: yadeflex cannot be imported ({e}): it needs YADE ({YADE_PY}) and the yade-flex plugin installed "
              "(scripts/setup, or scripts/run once)", file=sys.stderr)
        return 1
    try:
        slurm = study.Slurm(a.partition, a.account, a.time_limit, a.sbatch_arg, a.poll, a.workers, a.sbatch_setup)
        rows = study.run_study(a.study_file, a.out_dir, backend=a.backend, workers=a.workers, resume=a.resume,
                               cache_dir=a.cache_dir, timeout=a.timeout, yade=a.yade, slurm=slurm)
    except study.StudyError as e:
        for line in e.errors:
            print(f"study: {line}", file=sys.stderr)
        return study.EXIT_BAD_STUDY
    except study.StudyInterrupted as e:
        return 128 + e.signum
    if a.report:
        from yadeflex.module.study_report import write_report
        print(f"study: report {write_report(a.out_dir)}", flush=True)
    return 0 if all(r["status"] == study.DONE for r in rows) else study.EXIT_RUNS_FAILED


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
