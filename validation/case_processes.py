"""Cases run one per yade-double process, a few at a time, each writing OUT/cases/NAME.json (the
fill calibration's and the grain-crushing study's) (GPL-2.0-or-later)."""
import argparse
import concurrent.futures
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)


def spawn(script, out, name):
    """Runs `yade-double -n -j1 -x script out --case name` (one OpenMP thread, the checkout's
    package first on PYTHONPATH), its output in OUT/cases/NAME.log; returns (name, exit status, log)."""
    env = dict(os.environ, OMP_NUM_THREADS="1", OMP_PROC_BIND="false",  # (not pinned: OMP_PROC_BIND=true would put every case on one CPU)
               PYTHONPATH=os.pathsep.join([os.path.join(REPO, "py")] + [p for p in [os.environ.get("PYTHONPATH")] if p]))
    log = os.path.join(out, "cases", name + ".log")
    with open(log, "w") as f:
        r = subprocess.run(["yade-double", "-n", "-j1", "-x", script, out, "--case", name], stdin=subprocess.DEVNULL, stdout=f,
                           stderr=subprocess.STDOUT, env=env)
    return name, r.returncode, log


def run_all(script, out, names, workers):
    """Runs the cases `names`, `workers` at a time, printing each as it ends; returns the names of
    those that failed."""
    os.makedirs(os.path.join(out, "cases"), exist_ok=True)
    cpus = len(os.sched_getaffinity(0))
    if workers > cpus:  # (a YADE started with OMP_PROC_BIND=true is pinned to one CPU, and so are the cases it starts)
        print(f"WARNING: {workers} workers share the {cpus} CPU(s) this process may run on: each case takes longer"
              + (" (OMP_PROC_BIND is set: unset it)" if os.environ.get("OMP_PROC_BIND", "").lower() not in ("", "false") else ""), flush=True)
    t = time.time()
    failed = []
    with concurrent.futures.ThreadPoolExecutor(max(1, workers)) as pool:
        for name, rc, log in pool.map(lambda n: spawn(script, out, n), names):
            print(f"[{time.time() - t:6.0f} s] {name}: {'done' if rc == 0 else f'FAILED (exit {rc}), see {log}'}", flush=True)
            if rc:
                failed.append(name)
    print(f"{len(names) - len(failed)} of {len(names)} cases in {time.time() - t:.0f} s", flush=True)
    return failed


def load(out, names):
    """{name: the case's JSON} of the cases in `names` that wrote OUT/cases/NAME.json."""
    res = {}
    for name in names:
        path = os.path.join(out, "cases", name + ".json")
        if os.path.isfile(path):
            with open(path) as f:
                res[name] = json.load(f)
    return res


def parse(script, description, cases, to_help):
    """The command line of such a script: OUT, --to DIR (to_help says what is written there),
    --workers, --cases a,b (checked against `cases`), --report-only and the hidden --case NAME of
    the child processes; returns (args, the case names to run)."""
    me = next((k for k, a in enumerate(sys.argv) if a.endswith(script)), 0)
    ap = argparse.ArgumentParser(prog=f"validation/{script}", description=description)
    ap.add_argument("out", help="folder of the runs (cases/) and of the report")
    ap.add_argument("--to", default=None, help=to_help)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--cases", default=None, help=f"comma-separated subset of {', '.join(cases)}")
    ap.add_argument("--case", default=None, help=argparse.SUPPRESS)
    ap.add_argument("--report-only", action="store_true", help="rewrite the report from OUT/cases without running anything")
    a = ap.parse_args(sys.argv[me + 1:])
    if a.case is not None and a.case not in cases:
        ap.error(f"unknown case {a.case}; choose from {', '.join(cases)}")
    names = a.cases.split(",") if a.cases else list(cases)
    bad = [n for n in names if n not in cases]
    if bad:
        ap.error(f"unknown case(s) {', '.join(bad)}; choose from {', '.join(cases)}")
    return a, names


def main(script, description, cases, run_case, write, to_help):
    """A case script's main: under --case NAME, run_case(NAME, OUT) in this process; else run the
    cases in child processes (unless --report-only), then write(folder, results) into OUT and
    --to; returns what write returned for OUT (None for a child)."""
    a, names = parse(script, description, cases, to_help)
    if a.case:
        run_case(a.case, a.out)
        return None
    if not a.report_only:
        run_all(os.path.join(HERE, script), a.out, names, a.workers)
    res = load(a.out, cases)
    written = write(a.out, res)
    if a.to:
        write(a.to, res)
    return written
