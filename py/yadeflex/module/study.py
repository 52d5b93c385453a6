"""Parametric studies: many runs of the main job (scripts/damping_module.py) from one CSV file,
on this machine's cores (backend "local"), inside an MPI allocation ("mpi", mpi4py.futures) or
as a Slurm job array ("slurm"). scripts/study is the command line; from Python:

    from yadeflex.module import study
    runs = study.read_study("configurations.csv")      # every row checked, or StudyError
    rows = study.run_study("configurations.csv", "out", backend="local", workers=2)

The study file: one row per run; the columns are the main job's option names (drop_height or
drop-height; `damping_module.py --help` lists them), an empty cell leaves the job's default,
small and no_vtk take yes/no, impact_offset takes "x y". Besides the options: name (the run's
folder name; default row001, ...) and repeat (N runs of the row, with seeds seed, seed+1, ...,
named NAME-sSEED). The whole file is checked with the job's own checks (yadeflex.module.cli)
before anything runs: StudyError lists every bad cell by its row and column.

Every run is one YADE process with one thread (bitwise reproducible: the same row gives the same
numbers whatever the backend and the worker count), writing OUT_DIR/runs/NAME/ (the main job's
files, log.txt, study_run.json). The distinct filled modules are filled first, once each, into
the module cache (the main job's --fill-only; cache_dir: on a cluster, a shared folder), so that
every run loads its fill (a run that built its own fill would differ by round-off from one that
loads it); a run whose fill failed is recorded as failed without running. A run that
fails, crashes or times out is recorded with its status and log, the others go on; resume reruns
only the rows not done. The results gather into OUT_DIR/results.csv (RESULT_COLUMNS) and plots
(yadeflex.module.study_plots).
"""
import concurrent.futures
import csv
import math
import os
import re
import shlex
import signal
import subprocess
import sys
import threading
import time

from ..files import write_atomic, write_json
from .study_task import read_json, TERM_GRACE, die_with_parent
from . import study_results as SR

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))  # (py/yadeflex/module/ in the checkout)
RUN_SCRIPT = os.path.join(REPO, "scripts", "damping_module.py")
TASK_SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "study_task.py")
YADE_PY = "/usr/lib/x86_64-linux-gnu/yade-double/py"  # Debian's YADE modules (for the runs' PYTHONPATH)
BACKENDS = ("local", "mpi", "slurm")
FLAGS = ("small", "no_vtk")           # the job's options without a value: a yes/no cell
STUDY_COLUMNS = ("name", "seeds", "repeat")  # the study's own columns (seed is the job's --seed; repeat: seeds' older name)
SET_BY_STUDY = ("out", "cache_dir")   # options the study sets for every run
NAME_RE = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]{0,99}")
MAX_REPEAT = 1000  # runs of one row (each a fill of its own)
STATUS_FILE, SUMMARY_FILE, LOG_FILE = "study_run.json", "summary.json", "log.txt"
EXIT_BAD_STUDY, EXIT_RUNS_FAILED = 1, 3  # scripts/study's exit status (0: every run done)

# results.csv: the inputs, then these summary.json values, then energy_<term> (energy_end, J)
# and the run's bookkeeping
SUMMARY_COLUMNS = ("impact_energy", "peak_impact_force_filtered", "peak_impact_force", "peak_deceleration", "penetration_max",
                   "impact_duration", "rebound", "slab_force_max_filtered", "slab_force_max", "slab_pressure_peak", "slab_pressure_peak_filtered",
                   "slab_loaded_radius",
                   "bulge_max", "ring_top_force_max", "ring_bottom_force_max", "rope_force_max",
                   "broken_wire_legs", "broken_ring_segments", "broken_rope_segments", "broken_lining_facets",
                   "broken_other_elements", "broken_elements_total", "energy_absorbed", "gravity_work_after_contact", "boulder_energy_end",
                   "energy_residual_max_fraction", "impact_steps")
RUN_COLUMNS = ("status", "exit_status", "message", "run_time_s", "fill_time_s", "wall_time_s", "host", "log")
TIMING_COLUMNS = ("run_time_s", "fill_time_s", "wall_time_s", "host", "log")  # differ between identical runs
DONE = "done"


class StudyError(ValueError):
    """A study that cannot run: .errors, one line each (a bad cell names its row and column)."""

    def __init__(self, errors):
        self.errors = list(errors)
        super().__init__("\n".join(self.errors))


def column_option(column):
    """The option name of a study-file column: 'drop-height', '--drop-height', 'drop_height' ->
    'drop_height'."""
    return column.strip().lstrip("-").replace("-", "_").lower()


def job_options():
    """Names of the main job's options a study file may set."""
    import dataclasses
    from ..module import ModuleParams
    from .cli import RUN_LIMITS
    return set(FLAGS) | set(RUN_LIMITS) | {f.name for f in dataclasses.fields(ModuleParams)}


def _where(row, line, column=None):
    return f"row {row} (line {line})" + (f", column {column}" if column else "")


def _row_argv(cells, row, line, errors):
    """The job's arguments of one row's cells {option: text} (empty cells left out)."""
    from .. import checks as C
    argv, given = [], {}
    for opt, text in cells.items():
        text = (text or "").strip()
        if not text or opt in STUDY_COLUMNS:
            continue
        flag = "--" + opt.replace("_", "-")
        given[flag] = opt
        if opt in FLAGS:
            try:
                if C.boolean(opt, text):
                    argv.append(flag)
            except C.BadValue as e:
                errors.append(f"{_where(row, line, opt)}: got {text!r}; allowed {e.allowed}")
        elif opt == "impact_offset":  # one cell, one value: two numbers, nothing else taken as arguments
            parts = text.split()
            try:
                ok = len(parts) == 2 and all(math.isfinite(float(p)) for p in parts)
            except ValueError:
                ok = False
            if ok:
                argv += [flag, *parts]
            else:
                errors.append(f"{_where(row, line, opt)}: got {text!r}; allowed two numbers, the offset x y [m] (e.g. '0.1 0')")
        else:
            argv += [flag, text]
    return argv, given


def read_study(path, out_dir=None):
    """The runs of the study file at path, every cell checked: a list of dicts with name, row
    (1-based data row), line (in the file), inputs ({column: cell text}, and seed for a repeated
    row), argv (the job's options) and fill_key. Raises StudyError listing every problem, each
    naming its row and column."""
    from .cli import parse, OptionError
    try:
        with open(path, newline="", encoding="utf-8-sig") as fh:  # (a spreadsheet's byte-order mark is not a column name)
            table = [r for r in csv.reader(fh) if r and any(c.strip() for c in r) and not r[0].lstrip().startswith("#")]
    except OSError as e:
        raise StudyError([f"study file {path}: {e.strerror or e}"]) from None
    if len(table) < 2:
        raise StudyError([f"study file {path}: needs a header line of option names and at least one row"])
    header = [column_option(c) for c in table[0]]
    allowed = job_options() | set(STUDY_COLUMNS)
    errors = [f"column {c!r} (line 1): not an option of the main job (allowed: {', '.join(sorted(allowed))})"
              for c, o in zip(table[0], header) if o not in allowed and o not in SET_BY_STUDY]
    errors += [f"column {c!r} (line 1): set by the study for every run (the --cache-dir option of the study, its OUT_DIR)"
               for c, o in zip(table[0], header) if o in SET_BY_STUDY]
    errors += [f"column {o!r} (line 1): given twice" for k, o in enumerate(header) if o in header[:k]]
    if errors:
        raise StudyError(errors)
    out_root = os.path.abspath(out_dir or ".")
    runs, names = [], {}
    for row, cells_list in enumerate(table[1:], 1):
        line = row + 1  # (after the header; comment and blank lines not counted)
        if len(cells_list) != len(header):  # (a short row is refused too: its missing cells would run with defaults)
            errors.append(f"{_where(row, line)}: {len(cells_list)} cells, the header has {len(header)} columns")
            continue
        cells = dict(zip(header, [c.strip() for c in cells_list]))
        name = cells.get("name") or f"row{row:03d}"
        if not NAME_RE.fullmatch(name):
            errors.append(f"{_where(row, line, 'name')}: got {name!r}; allowed letters, digits, '.', '_', '-' (a folder name)")
        repeat = 1
        if cells.get("seeds") and cells.get("repeat"):
            errors.append(f"{_where(row, line, 'repeat')}: seeds and repeat are one option (repeat is its older name): give one")
        col = "seeds" if cells.get("seeds") else "repeat"
        if cells.get(col):
            try:
                repeat = int(cells[col])
                if not 1 <= repeat <= MAX_REPEAT:
                    raise ValueError
            except ValueError:
                errors.append(f"{_where(row, line, col)}: got {cells[col]!r}; allowed a whole number in [1, {MAX_REPEAT}] (a fill each)")
                repeat = 1
        argv, given = _row_argv(cells, row, line, errors)
        seed0 = None
        for k in range(repeat):
            run_argv = list(argv)
            inputs = {c: cells.get(c, "") for c in header if c not in ("repeat", "seeds")}
            run_name = name
            if repeat > 1:
                if seed0 is None:
                    from ..module import ModuleParams
                    try:
                        seed0 = int(cells.get("seed") or ModuleParams.seed)
                    except ValueError:
                        seed0 = ModuleParams.seed  # (parse below names the bad seed)
                if "--seed" in run_argv:
                    i = run_argv.index("--seed")
                    del run_argv[i:i + 2]
                run_argv += ["--seed", str(seed0 + k)]
                inputs["seed"] = str(seed0 + k)
                run_name = f"{name}-s{seed0 + k}"
            try:
                _, p = parse(run_argv + ["--out", os.path.join(out_root, "runs", run_name)])
            except OptionError as e:
                m = re.match(r"bad option (--[\w-]+)", str(e))
                col = given.get(m.group(1)) if m else None
                errors.append(f"{_where(row, line, col)}: {e}" + ("" if col else " (the job's default with this row's other values)"))
                break
            if run_name in names:
                errors.append(f"{_where(row, line, 'name')}: the run name {run_name!r} is already row {names[run_name]}'s")
                break
            names[run_name] = row
            runs.append(dict(name=run_name, configuration=name, row=row, line=line, inputs=inputs, argv=run_argv, fill_key=p.fill_key(),
                             params=p.resolved()))
    if errors:
        raise StudyError(errors)
    return runs


# ---- tasks -------------------------------------------------------------------------------------

def _env():
    path = [os.path.join(REPO, "py"), YADE_PY] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    # one thread per run, not pinned: with OMP_PROC_BIND=true (an HPC habit) OpenMP binds each
    # run's only thread to the first CPU it may use, the same CPU for every run of the pool
    return dict(OMP_NUM_THREADS="1", OMP_PROC_BIND="false", PYTHONPATH=os.pathsep.join(path))


def run_folder(out_dir, name):
    return os.path.join(out_dir, "runs", name)


def run_tasks(runs, out_dir, cache_dir, timeout=None, yade="yade-double", fills=()):
    """The study_task tasks of runs (see yadeflex/module/study_task.py); a run whose module is among
    the fill tasks `fills` starts only if that fill succeeded."""
    after = {t["key"]: t["status"] for t in fills}
    tasks = []
    for r in runs:
        folder = run_folder(out_dir, r["name"])
        cmd = [yade, "-n", "-j", "1", "-x", RUN_SCRIPT, "--out", folder, "--cache-dir", cache_dir, *r["argv"]]
        tasks.append(dict(name=r["name"], cmd=cmd, folder=folder, status=os.path.join(folder, STATUS_FILE), timeout=timeout, env=_env(),
                          after=after.get(r["fill_key"])))
    return tasks


def fill_tasks(runs, out_dir, cache_dir, yade="yade-double"):
    """A task per distinct filled module of runs that the cache does not hold yet."""
    from .cli import parse
    from ..module import cache_files
    tasks, seen = [], set()
    for r in runs:
        key = r["fill_key"]
        if key in seen:
            continue
        seen.add(key)
        folder = os.path.join(out_dir, "fills", key)
        _, p = parse(r["argv"] + ["--out", folder])
        scene, meta, _ = cache_files(p, cache_dir)
        if os.path.exists(scene) and os.path.exists(meta):
            continue  # (a run that finds it damaged fills it again, under the cache's lock)
        cmd = [yade, "-n", "-j", "1", "-x", RUN_SCRIPT, "--fill-only", "--out", folder, "--cache-dir", cache_dir, *r["argv"]]
        tasks.append(dict(name=f"fill-{key}", key=key, cmd=cmd, folder=folder, status=os.path.join(folder, STATUS_FILE), timeout=None, env=_env()))
    return tasks


def task_command(tasks_file, index):
    """The command that runs task `index` of tasks_file (a worker's only job)."""
    return [sys.executable, TASK_SCRIPT, tasks_file, str(index)]


# ---- outcome of a run --------------------------------------------------------------------------

def _job_options(cmd):
    """The job's own options of a run's command (what follows --cache-dir DIR): a resume compares
    these, not the paths of the folder, the cache or YADE (a study moved or given another cache
    keeps its runs)."""
    cmd = list(cmd)
    return cmd[cmd.index("--cache-dir") + 2:] if "--cache-dir" in cmd else cmd


def run_outcome(folder):
    """(status, task outcome or None, summary.json or None) of a run's folder. status: done,
    unstable, residual (balance residual above the limit), interrupted (SIGINT, SIGTERM to the run or
    its task), failed, timeout, crashed (killed by a signal, or with its worker: no outcome but a
    summary that says "running"), missing (never started)."""
    task = read_json(os.path.join(folder, STATUS_FILE))
    summary = read_json(os.path.join(folder, SUMMARY_FILE))
    if task is None:
        return ("missing" if summary is None else "crashed"), None, summary
    rc = task["exit_status"]
    if task.get("skipped"):
        return "failed", task, summary
    if task.get("interrupted"):
        return "interrupted", task, summary
    if task.get("timed_out"):
        return "timeout", task, summary
    if rc < 0 or summary is None or summary.get("status") == "running":
        return "crashed", task, summary
    if rc == 0:
        return DONE, task, summary
    if rc == 3:
        return "residual", task, summary
    status = summary.get("status")
    return (status if status in ("unstable", "interrupted", "failed") else "failed"), task, summary


def result_row(run, folder, stopped=None):
    """One row of results.csv: the run's inputs, its summary's numbers, its status and log.
    stopped: the signal that stopped the study (a row never started is then 'cancelled')."""
    status, task, s = run_outcome(folder)
    if status == "missing" and stopped:
        status = "cancelled"
    s = s or {}
    params = run.get("params") or {}
    row = dict(name=run["name"], configuration=run.get("configuration", run["name"]), row=run["row"])
    row.update({k: v for k, v in run["inputs"].items() if k not in params and k != "name"})  # (small, no_vtk, the run limits)
    row.update(params)
    row.update({k: s.get(k) for k in SUMMARY_COLUMNS})
    if params:
        row.update(SR.design_values(params)[0])
    row.update({f"energy_{k}": v for k, v in (s.get("energy_end") or {}).items()})
    message = s.get("message")
    if task is not None and task.get("skipped"):
        message = task["skipped"]
    elif status == "cancelled":
        message = f"not run: the study was stopped by {stopped}"
    elif status == "interrupted" and task is not None and task.get("interrupted") and not message:
        message = f"stopped by {task['interrupted']} before the run wrote its results"
    elif status == "timeout":
        message = f"stopped after the study's timeout of {task['wall_time_s']:.0f} s" + (f"; {message}" if message else "")
    elif status == "crashed":
        message = (f"killed by signal {-task['exit_status']}" if task and task["exit_status"] < 0 else
                   "ended without a summary (killed with its worker, or the process died)") + (f"; {message}" if message else "")
    row.update(status=status, exit_status=None if task is None else task["exit_status"], message=message,
               run_time_s=s.get("run_time_s"), fill_time_s=s.get("fill_time_s"),
               wall_time_s=None if task is None else task["wall_time_s"], host=None if task is None else task["host"],
               log=task["log"] if task else os.path.join(folder, LOG_FILE) if os.path.exists(os.path.join(folder, LOG_FILE)) else None)
    return row


def gather(runs, out_dir, stopped=None):
    """The rows of results.csv (one per run, in the study's order) and its columns; stopped: the
    signal that stopped the study, if one did."""
    rows = [result_row(r, run_folder(out_dir, r["name"]), stopped) for r in runs]
    given = list(dict.fromkeys(k for r in runs for k in r["inputs"] if k not in r["params"] and k != "name"))
    params = list(dict.fromkeys(k for r in runs for k in r["params"]))
    energy = sorted({k for r in rows for k in r if k.startswith("energy_") and k not in SUMMARY_COLUMNS})
    formulas = [SR.formula_column(f) for f in SR.FORMULAS]
    return rows, ["name", "configuration", "row", "seed"] + given + [k for k in params if k != "seed"] + list(SUMMARY_COLUMNS) + formulas + \
        energy + list(RUN_COLUMNS)


def param_units():
    """Unit of each resolved parameter (results.csv's input columns)."""
    from .params import PARAMS
    units = {k: p.unit for k, (_, p) in PARAMS.items() if p.unit}
    units.update(fill_density="kg/m3", boulder_size="m", seed="-")
    return units


def write_results(rows, columns, path):
    """results.csv (headers NAME[UNIT]), written whole through a rename."""
    SR.write_table(rows, columns, path, param_units())


def read_results(path):
    """results.csv's rows as dicts keyed by the bare column names (texts)."""
    return SR.read_table(path)


# ---- progress ----------------------------------------------------------------------------------

class StudyProgress:
    """The study's progress: ended(task) counts a task that ended (done, or failed as
    failed_of(task) says), show(running) prints the line: runs done, failed, running of the
    total, and the time left (the median wall time of the tasks ended so far x the rounds of
    `workers` left). A line is printed when a count changes, else at most every `every` s."""

    def __init__(self, total, workers, failed_of, out=None, every=30.0, clock=time.time):
        self.total, self.workers, self.failed_of, self.every, self.clock = total, max(1, workers or 1), failed_of, every, clock
        self.out = out or (lambda line: print(line, flush=True))
        self.done = self.failed = 0
        self.walls, self.last, self.last_at = [], None, None

    def ended(self, task):
        outcome = read_json(task["status"])
        if outcome:
            self.walls.append(outcome["wall_time_s"])
        if self.failed_of(task):
            self.failed += 1
        else:
            self.done += 1

    def eta(self):
        left = self.total - self.done - self.failed
        if not self.walls or left <= 0:
            return None
        return sorted(self.walls)[len(self.walls) // 2] * math.ceil(left / self.workers)

    def show(self, running):
        now = self.clock()
        state = (self.done, self.failed, running)
        if state == self.last and now - self.last_at < self.every:
            return None
        self.last, self.last_at = state, now
        eta = self.eta()
        line = (f"study: {self.done} of {self.total} done, {self.failed} failed, {running} running"
                + ("" if eta is None else f", ~{eta:.0f} s left"))
        self.out(line)
        return line


# ---- backends ----------------------------------------------------------------------------------

def _write_tasks(tasks, path):
    write_json(path, tasks)
    return path


class StudyInterrupted(Exception):
    """SIGINT or SIGTERM stopped the study (run_study): the queue was cancelled, the running rows
    were stopped (each writes its partial results, recorded as interrupted) and results.csv was
    written for every row. signum: the signal; rows: results.csv's rows."""

    def __init__(self, signum, rows=None):
        super().__init__(signal.Signals(signum).name)
        self.signum, self.rows = signum, rows


class _Stop(BaseException):
    """The coordinator's SIGINT or SIGTERM (raised in the main thread by _on_signals' handler)."""

    def __init__(self, signum):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


class _on_signals:
    """While it lasts, SIGINT and SIGTERM raise _Stop in the main thread, once: the study is then
    stopping, and a second signal is ignored (the tasks bound their wait; none is left behind).
    Outside the main thread (a study run from a worker thread) nothing is installed."""

    def __enter__(self):
        self.saved = {}
        if threading.current_thread() is threading.main_thread():
            for sig in (signal.SIGINT, signal.SIGTERM):
                self.saved[sig] = signal.getsignal(sig)
                if self.saved[sig] != signal.SIG_IGN:
                    signal.signal(sig, self._raise)
        return self

    def _raise(self, signum, frame):
        for sig in self.saved:
            signal.signal(sig, signal.SIG_IGN)
        raise _Stop(signum)

    def __exit__(self, *exc):
        for sig, h in self.saved.items():
            signal.signal(sig, h)
        return False


class _TaskProcesses:
    """The task processes the local backend's threads started: each thread's call starts one and
    waits; stop(signum) passes the signal on to those running (each stops its run and writes its
    outcome) and keeps any more from starting."""

    def __init__(self):
        self.lock, self.running, self.stopped = threading.Lock(), set(), None

    def call(self, cmd):
        with self.lock:
            if self.stopped is not None:
                return None  # cancelled: the study is stopping
            p = subprocess.Popen(cmd, preexec_fn=die_with_parent)  # (a coordinator killed outright takes its tasks along)
            self.running.add(p)
        try:
            return p.wait()
        finally:
            with self.lock:
                self.running.discard(p)

    def stop(self, signum):
        with self.lock:
            self.stopped = signum
            for p in self.running:
                try:
                    p.send_signal(signum)
                except ProcessLookupError:
                    pass
            return len(self.running)


def _run_futures(executor, tasks, tasks_file, progress, call=subprocess.call):
    """Submit every task of tasks_file to executor (call of task_command) and wait, reporting to
    progress (StudyProgress)."""
    futures = {executor.submit(call, task_command(tasks_file, i)): t for i, t in enumerate(tasks)}
    pending = set(futures)
    while pending:
        ended, pending = concurrent.futures.wait(pending, timeout=5.0, return_when=concurrent.futures.FIRST_COMPLETED)
        for f in ended:
            f.result()  # (a task that could not even start raises here)
            progress.ended(futures[f])
        progress.show(sum(1 for p in pending if p.running()))


def run_local(tasks, tasks_file, workers, progress):
    """Tasks on this machine, `workers` at a time (threads, each waiting on one task process). On
    the coordinator's SIGINT or SIGTERM (_Stop): the queue is cancelled, the running tasks get the
    signal, and this returns once they have ended (each within TERM_GRACE), raising _Stop."""
    procs = _TaskProcesses()
    ex = concurrent.futures.ThreadPoolExecutor(max_workers=workers)
    try:
        _run_futures(ex, tasks, tasks_file, progress, procs.call)
    except _Stop as e:
        n = procs.stop(e.signum)
        progress.out(f"study: {e.args[0]}: the queue is cancelled; waiting for the {n} running row(s) to write their results "
                     f"(at most {TERM_GRACE:.0f} s)")
        raise
    finally:
        ex.shutdown(wait=True, cancel_futures=True)


def mpi_workers():
    """The number of MPI worker ranks of a study started with mpirun ... -m mpi4py.futures
    (the world's size less the coordinator), or StudyError."""
    try:
        from mpi4py import MPI
    except ImportError as e:
        raise StudyError([f"backend mpi: mpi4py cannot be imported ({e}); install Debian's python3-mpi4py"]) from None
    n = MPI.COMM_WORLD.Get_size() - 1
    if n < 1:
        raise StudyError(["backend mpi: no worker ranks; start the study with "
                          "mpirun -n N+1 /usr/bin/python3 -m mpi4py.futures scripts/study.py ... (scripts/study does this for --backend mpi)"])
    return n


def run_mpi(tasks, tasks_file, progress):
    """Tasks on the worker ranks of mpi4py.futures (one task per rank at a time)."""
    from mpi4py.futures import MPIPoolExecutor
    with MPIPoolExecutor() as ex:
        try:
            _run_futures(ex, tasks, tasks_file, progress)
        except _Stop:  # the queue is cancelled; under mpirun the signal reaches the running tasks' ranks too
            ex.shutdown(wait=False, cancel_futures=True)
            raise


class Slurm:
    """Where and how the study's job arrays are submitted: partition, account, time_limit (per
    array task, the fills' and the runs', Slurm's format, e.g. 1:00:00), extra sbatch arguments,
    poll interval [s], setup: shell lines each task runs before its run (e.g. 'module load yade')."""

    def __init__(self, partition=None, account=None, time_limit=None, extra=(), poll=5.0, max_parallel=None, setup=()):
        self.partition, self.account, self.time_limit = partition, account, time_limit
        self.extra, self.poll, self.max_parallel = list(extra), poll, max_parallel
        self.setup = list(setup)
        for line in self.setup:
            if "\n" in line or "\r" in line:
                raise StudyError([f"backend slurm: a setup line holds a line break: {line!r}; give one --sbatch-setup per line"])

    def script(self, tasks_file, n, log_dir, name):
        lines = ["#!/bin/bash", f"#SBATCH --job-name={name}", "#SBATCH --cpus-per-task=1", "#SBATCH --ntasks=1",
                 f"#SBATCH --array=0-{n - 1}" + (f"%{self.max_parallel}" if self.max_parallel else ""),
                 f"#SBATCH --output={log_dir}/%x-%A_%a.out"]
        lines += [f"#SBATCH --{k}={v}" for k, v in (("partition", self.partition), ("account", self.account),
                                                    ("time", self.time_limit)) if v]
        lines += self.setup
        lines += ["export OMP_NUM_THREADS=1",
                  "exec " + shlex.join(task_command(tasks_file, 0)[:-1]) + ' "$SLURM_ARRAY_TASK_ID"']
        return "\n".join(lines) + "\n"

    def submit(self, tasks_file, n, log_dir, name, after=None):
        """sbatch a job array of n tasks; returns the job id."""
        path = os.path.join(log_dir, f"{name}.sbatch")
        write_atomic(path, self.script(tasks_file, n, log_dir, name), mode=0o755)
        cmd = ["sbatch", "--parsable", *self.extra] + ([f"--dependency=afterany:{after}"] if after else []) + [path]
        try:
            res = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
        except FileNotFoundError:
            raise StudyError(["backend slurm: sbatch not found (Slurm's client commands are needed on this machine)"]) from None
        if res.returncode != 0:
            raise StudyError([f"backend slurm: {' '.join(cmd)} failed ({res.returncode}): {res.stderr.strip()}"])
        return res.stdout.strip().split(";")[0]

    @staticmethod
    def states(job):
        """{array task index: Slurm state} of the job's tasks still known to squeue."""
        res = subprocess.run(["squeue", "-h", "-r", "-j", job, "-o", "%K %T"], capture_output=True, text=True, timeout=60)
        out = {}
        for line in res.stdout.split("\n"):
            parts = line.split()
            if len(parts) == 2 and parts[0].isdigit():
                out[int(parts[0])] = parts[1]
        return out

    @staticmethod
    def accounting(job):
        """{array task index: (state, exit code)} from sacct, or {} where accounting is off."""
        try:
            res = subprocess.run(["sacct", "-n", "-P", "-X", "-j", job, "-o", "JobID,State,ExitCode"], capture_output=True,
                                 text=True, timeout=60)
        except (FileNotFoundError, subprocess.TimeoutExpired):
            return {}
        out = {}
        for line in res.stdout.split("\n") if res.returncode == 0 else ():
            parts = line.split("|")
            if len(parts) == 3 and "_" in parts[0] and parts[0].split("_")[1].isdigit():
                out[int(parts[0].split("_")[1])] = (parts[1], parts[2])
        return out

    def wait(self, job, tasks, progress):
        """Watch the array with squeue until no task is left, reporting to progress
        (StudyProgress); returns sacct's view (may be {})."""
        reported = set()
        while True:
            states = self.states(job)
            for i, t in enumerate(tasks):
                if i not in reported and i not in states and (os.path.exists(t["status"]) or not states):
                    reported.add(i)
                    progress.ended(t)
            progress.show(sum(1 for s in states.values() if s == "RUNNING"))
            if not states and len(reported) == len(tasks):
                return self.accounting(job)
            time.sleep(self.poll)


def run_slurm(slurm, fill, runs, out_dir, progress):
    """The fills as one job array, then the runs as another that starts after it (afterany: a
    run whose fill failed records that, without running). Slurm's accounting of the runs, where
    the cluster keeps it (sacct), goes to OUT_DIR/slurm/sacct.json."""
    log_dir = os.path.join(out_dir, "slurm")
    os.makedirs(log_dir, exist_ok=True)
    after = None
    if fill:
        after = slurm.submit(fill[1], len(fill[0]), log_dir, "yadeflex-fill")
        progress.out(f"study: Slurm job {after}: {len(fill[0])} fill(s)")
    job = slurm.submit(runs[1], len(runs[0]), log_dir, "yadeflex-study", after=after)
    progress.out(f"study: Slurm job {job}: {len(runs[0])} run(s)")
    try:
        accounting = slurm.wait(job, runs[0], progress)
    except _Stop as e:  # pending array tasks cancelled, running ones get SIGTERM (and write their results)
        jobs = [j for j in (after, job) if j]
        subprocess.run(["scancel", *jobs], capture_output=True, timeout=120)
        progress.out(f"study: {e.args[0]}: Slurm jobs {', '.join(jobs)} cancelled; waiting for their running tasks to end")
        slurm.wait(job, runs[0], progress)
        raise
    if accounting:
        write_json(os.path.join(log_dir, "sacct.json"), {runs[0][i]["name"]: v for i, v in accounting.items() if i < len(runs[0])})


# ---- the study ---------------------------------------------------------------------------------

def _check_setup(out_dir, cache_dir, backend, yade):
    errors = []
    if backend not in BACKENDS:
        errors.append(f"backend: got {backend!r}; allowed one of {', '.join(BACKENDS)}")
    for what, d in (("OUT_DIR", out_dir), ("cache folder", cache_dir)):
        try:
            os.makedirs(d, exist_ok=True)
            if not os.access(d, os.W_OK | os.X_OK):
                errors.append(f"{what} {d}: not writable")
        except OSError as e:
            errors.append(f"{what} {d}: cannot be created ({e.strerror or e})")
    if not os.path.exists(RUN_SCRIPT):
        errors.append(f"{RUN_SCRIPT} is missing: the study runs the main job from a yade-flex checkout")
    if not any(os.access(os.path.join(p, yade), os.X_OK) for p in os.environ.get("PATH", "").split(os.pathsep)) and not os.access(yade, os.X_OK):
        errors.append(f"YADE executable {yade!r} not found on PATH")
    if errors:
        raise StudyError(errors)


def run_study(study_file, out_dir, backend="local", workers=None, resume=False, cache_dir=None, timeout=None,
              yade="yade-double", slurm=None, progress=None):
    """Run the study file into out_dir (see the module's docstring); returns the rows of
    results.csv (dicts). workers: parallel runs (local: default the CPUs this process may run on; mpi: the worker
    ranks; slurm: the array's throttle, default none). resume: keep the runs already done with
    the same options, rerun the others. cache_dir: the filled modules (default
    ~/.cache/yadeflex/modules; a shared folder for slurm). timeout: wall seconds per run.
    slurm: a Slurm (partition, account, time limit). progress: a function of one line (default
    print). Raises StudyError before anything runs if the study or the setup is refused."""
    out_dir = os.path.abspath(out_dir)
    cache_dir = os.path.abspath(cache_dir or os.path.join(os.path.expanduser("~"), ".cache", "yadeflex", "modules"))
    if timeout is not None and not (isinstance(timeout, (int, float)) and math.isfinite(timeout) and timeout > 0):
        raise StudyError([f"timeout: got {timeout!r}; allowed a number of seconds > 0"])
    if workers is not None and (not isinstance(workers, int) or workers < 1):
        raise StudyError([f"workers: got {workers!r}; allowed a whole number >= 1"])
    runs = read_study(study_file, out_dir)
    _check_setup(out_dir, cache_dir, backend, yade)
    if backend == "mpi":
        workers = mpi_workers()
    elif backend == "local":
        cpus = len(os.sched_getaffinity(0))  # the CPUs this process may run on (taskset, cgroup, an OpenMP binding)
        workers = workers or cpus
    write_json(os.path.join(out_dir, "study.json"), dict(study_file=os.path.abspath(study_file), cache_dir=cache_dir, runs=runs))
    todo = runs
    if resume:
        todo = []
        for r, t in zip(runs, run_tasks(runs, out_dir, cache_dir, timeout, yade)):
            status, outcome, _ = run_outcome(t["folder"])
            if not (status == DONE and outcome and _job_options(outcome["cmd"]) == _job_options(t["cmd"])):
                todo.append(r)
    say = progress or (lambda line: print(line, flush=True))
    kept = len(runs) - len(todo)
    say(f"study: {len(runs)} runs, {kept} already done" + (f", {len(todo)} to run" if todo else "")
        + f" ({backend}{'' if workers is None else f', {workers} workers'})")
    if backend == "local" and todo:
        bound = os.environ.get("OMP_PROC_BIND", "").lower() not in ("", "false")
        hint = " (OMP_PROC_BIND pins a YADE session to one CPU: run scripts/study from a shell, or unset OMP_PROC_BIND)" if bound else ""
        if workers > cpus:
            say(f"study: WARNING {workers} workers share the {cpus} CPU(s) this process may run on: each run takes longer{hint}")
        elif bound and cpus == 1 < (os.cpu_count() or 1):
            say(f"study: WARNING this process may run on 1 of the machine's {os.cpu_count()} CPUs: one run at a time{hint}")
    with _on_signals():
        try:
            _execute(todo, out_dir, cache_dir, timeout, yade, backend, workers, slurm, say)
            stopped = None
        except _Stop as e:
            stopped = e.signum
        try:
            rows = _report(runs, out_dir, stopped, say)
        except _Stop as e:  # (a first signal while the results are written: written again, signals now ignored)
            stopped = e.signum
            rows = _report(runs, out_dir, stopped, say)
    if stopped is not None:
        raise StudyInterrupted(stopped, rows)
    return rows


def _execute(todo, out_dir, cache_dir, timeout, yade, backend, workers, slurm, say):
    """Fill the modules the runs todo need, then run them (run_study's backends)."""
    if todo:
        fills = fill_tasks(todo, out_dir, cache_dir, yade)
        todo = run_tasks(todo, out_dir, cache_dir, timeout, yade, fills)
        fill_file = _write_tasks(fills, os.path.join(out_dir, "tasks-fill.json")) if fills else None
        run_file = _write_tasks(todo, os.path.join(out_dir, "tasks-run.json"))
        run_failed = lambda t: run_outcome(t["folder"])[0] != DONE  # noqa: E731
        fill_failed = lambda t: (read_json(t["status"]) or {}).get("exit_status") != 0  # noqa: E731
        if fills:
            say(f"study: filling {len(fills)} module(s) first, each once, into {cache_dir}")
        if backend == "slurm":
            run_slurm(slurm or Slurm(max_parallel=workers), (fills, fill_file) if fills else None, (todo, run_file), out_dir,
                      StudyProgress(len(todo), workers or len(todo), run_failed, say))
        else:
            execute = (lambda ts, f, p: run_local(ts, f, workers, p)) if backend == "local" else run_mpi
            if fills:
                execute(fills, fill_file, StudyProgress(len(fills), workers, fill_failed, lambda line: say(line.replace("study:", "fills:"))))
            execute(todo, run_file, StudyProgress(len(todo), workers, run_failed, say))


def _report(runs, out_dir, stopped, say):
    """results.csv, the plots and the closing line; returns the rows."""
    rows, columns = gather(runs, out_dir, None if stopped is None else signal.Signals(stopped).name)
    write_results(rows, columns, os.path.join(out_dir, "results.csv"))
    confs = SR.configurations(rows, runs, DONE)
    SR.write_configurations(confs, os.path.join(out_dir, "configurations.csv"), os.path.join(out_dir, "summary.json"), param_units(),
                            dict(study=os.path.join(out_dir, "study.json"), runs=len(rows), runs_done=sum(r["status"] == DONE for r in rows),
                                 software=software_version()))
    for c in confs:
        if c["n_done"]:
            say(f"study: {c['configuration']}: {_scatter_line(c)}")
    try:
        from .study_plots import write_study_plots
        for f in write_study_plots(rows, runs, out_dir, confs, say):
            say(f"study: plot {f}")
    except Exception as e:  # plots are a convenience: the table is the result
        say(f"study: (plots failed: {type(e).__name__}: {e})")
    failed = [r for r in rows if r["status"] != DONE]
    say((f"study: stopped by {signal.Signals(stopped).name}: " if stopped else "study: ")
        + f"{len(rows) - len(failed)} of {len(rows)} runs done" + (f", {len(failed)} not: " + ", ".join(
        f"{r['name']} ({r['status']}, log {r['log']})" for r in failed[:10]) + (" ..." if len(failed) > 10 else "") if failed else "")
        + f"; results in {os.path.join(out_dir, 'results.csv')}")
    return rows


def _scatter_line(c):
    """A configuration's results in one line: peak force and penetration, mean +- sd (n runs)."""
    def q(key, scale, unit):
        m, sd = c[f"{key}_mean"], c[f"{key}_std"]
        if m is None:
            return f"{key} -"
        return f"{m * scale:.1f}" + (f" +- {sd * scale:.1f}" if sd is not None else "") + f" {unit}"
    k = c["peak_impact_force_filtered_characteristic"]
    return (f"peak force {q('peak_impact_force_filtered', 1e-3, 'kN')} (filtered), slab {q('slab_force_max_filtered', 1e-3, 'kN')}, "
            f"penetration {q('penetration_max', 1e3, 'mm')} over {c['n_done']} fill(s)"
            + (f"; characteristic peak force {k / 1e3:.1f} kN" if k is not None else ""))


def software_version():
    """yade-flex's commit (and whether the checkout had changes), YADE's version."""
    def out(cmd):
        try:
            return subprocess.run(cmd, capture_output=True, text=True, timeout=30).stdout.strip()
        except (OSError, subprocess.TimeoutExpired):
            return ""
    head = out(["git", "-C", REPO, "describe", "--always", "--dirty"])
    yade = out(["dpkg-query", "-W", "-f", "${Version}", "yade"])
    return dict(yadeflex=head or "unknown (not a git checkout)", yade=f"Debian package yade {yade}" if yade else "unknown")
