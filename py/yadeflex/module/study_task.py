"""One task of a parametric study (yadeflex.module.study): one YADE process, its log, its outcome.

The file needs only the standard library, and runs as a script, so that every backend's worker
(a local thread, an MPI rank, a Slurm array task) starts a task the same way without starting
YADE itself:

    /usr/bin/python3 py/yadeflex/module/study_task.py TASKS.json INDEX

TASKS.json (written by yadeflex.module.study) holds a list of tasks, each a dict:
    name       the run's name
    cmd        the YADE command line (list of words)
    folder     the folder the process writes into (created); its log goes to folder/log.txt
    status     path of the outcome file (JSON) the task writes when the process ends
    timeout    wall seconds after which the process is stopped (SIGTERM, then SIGKILL); None: never
    env        environment variables set for the process (OMP_NUM_THREADS=1, PYTHONPATH)
    after      optional: the outcome file of a task this one needs (the fill of its module); if
               that task failed, this one does not start and records why (skipped)

The outcome file: name, cmd, exit_status (the process's; a negative value -N: killed by signal
N), timed_out, wall_time_s, host, log, skipped (None, or why the task did not start) and
interrupted (None, or the signal that stopped the task: SIGINT or SIGTERM). It is written through a temporary file and a rename, after
the process ended, so its presence means the task ran to its end; a task killed with its worker
leaves none. The task's own exit status is the process's (128 + N if killed by signal N).

SIGINT or SIGTERM to the task (Ctrl-C to the study's process group, the study's coordinator, a
batch system's cancel) is passed on to the run, which writes its partial results and ends; the
task then writes its outcome (interrupted) and exits 130 or 143. Further signals are ignored
meanwhile: the run gets TERM_GRACE seconds, then SIGKILL. The run also dies with the task
(PR_SET_PDEATHSIG), so that no run is left without it.
"""
import json
import os
import signal
import socket
import subprocess
import sys
import time

PR_SET_PDEATHSIG = 1  # prctl(2): the signal a process gets when its parent (the task) dies
TERM_GRACE = 30.0  # [s] a timed-out run writes its summary on SIGTERM; SIGKILL after this


def _write_json(path, obj):
    tmp = f"{path}.tmp-{os.getpid()}"
    with open(tmp, "w") as fh:
        json.dump(obj, fh, indent=1)
        fh.write("\n")
    os.replace(tmp, path)


def read_json(path):
    """The JSON file at path, None if missing or unreadable (being written: it is renamed into place whole)."""
    try:
        with open(path) as fh:
            return json.load(fh)
    except (OSError, ValueError):
        return None


def _last_line(path):
    """The last line of a log that names an error, else its last line."""
    try:
        with open(path, errors="replace") as fh:
            lines = [ln.strip() for ln in fh if ln.strip()]
    except OSError:
        return "no log"
    return next((ln for ln in reversed(lines) if "Error" in ln or ln.startswith("damping_module:")), lines[-1] if lines else "empty log")


def die_with_parent():
    """In the run's process before exec: SIGKILL when the task process dies, so that a killed
    worker leaves no run going on without it (Linux; elsewhere a no-op)."""
    try:
        import ctypes
        ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGKILL)
    except (OSError, AttributeError):
        pass


class Stopped(BaseException):
    """SIGINT or SIGTERM reached the task (see the module's docstring); signum: which."""

    def __init__(self, signum):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


def _stop(signum, frame):
    for sig in (signal.SIGINT, signal.SIGTERM):  # once: the run is being stopped
        signal.signal(sig, signal.SIG_IGN)
    raise Stopped(signum)


def stop_on_signals():
    """SIGINT and SIGTERM raise Stopped (main thread; a signal ignored when the task started, as
    under nohup, stays ignored)."""
    for sig in (signal.SIGINT, signal.SIGTERM):
        if signal.getsignal(sig) != signal.SIG_IGN:
            signal.signal(sig, _stop)


def _end(proc, signum, grace):
    """Send signum to the run's process group, wait grace seconds, then SIGKILL; the exit status."""
    try:
        os.killpg(proc.pid, signum)
    except ProcessLookupError:
        pass
    try:
        return proc.wait(timeout=grace)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        return proc.wait()


def _run_preexec():
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT, signal.SIGTERM})
    die_with_parent()


def run_task(task):
    """Run one task (a dict as above); returns its outcome (as written to task["status"])."""
    os.makedirs(task["folder"], exist_ok=True)
    if os.path.exists(task["status"]):
        os.unlink(task["status"])  # an earlier attempt's outcome must not stand for this one
    log = os.path.join(task["folder"], "log.txt")
    before = read_json(task["after"]) if task.get("after") else None
    if before is not None and before["exit_status"] != 0:
        out = dict(name=task["name"], cmd=task["cmd"], exit_status=1, timed_out=False, wall_time_s=0.0, host=socket.gethostname(),
                   log=before["log"], skipped=f"not run: {before['name']} failed ({_last_line(before['log'])}; log {before['log']})")
        _write_json(task["status"], out)
        return out
    env = dict(os.environ, **task.get("env", {}))
    t0 = time.time()
    timed_out, interrupted = False, None
    with open(log, "w") as fh:
        fh.write("$ " + " ".join(task["cmd"]) + "\n")
        fh.flush()
        # its own session: a timeout stops the run and whatever it started, and a signal sent to
        # the study's process group (Ctrl-C) reaches this task, which stops its run itself. The
        # signals wait while the run starts (a Stopped raised inside Popen would leave no outcome),
        # and the run starts with them unblocked.
        stops = {signal.SIGINT, signal.SIGTERM}
        signal.pthread_sigmask(signal.SIG_BLOCK, stops)
        try:
            proc = subprocess.Popen(task["cmd"], stdin=subprocess.DEVNULL, stdout=fh, stderr=subprocess.STDOUT, env=env,
                                    start_new_session=True, preexec_fn=_run_preexec)
        except BaseException:
            signal.pthread_sigmask(signal.SIG_UNBLOCK, stops)
            raise
        try:
            signal.pthread_sigmask(signal.SIG_UNBLOCK, stops)  # (a signal that came meanwhile is raised here)
            rc = proc.wait(timeout=task.get("timeout"))
        except subprocess.TimeoutExpired:
            timed_out = True
            rc = _end(proc, signal.SIGTERM, TERM_GRACE)
        except Stopped as e:  # passed on: the run writes its partial results and ends
            interrupted = e.args[0]
            rc = _end(proc, e.signum, TERM_GRACE)
        except BaseException:
            _end(proc, signal.SIGTERM, TERM_GRACE)
            raise
    out = dict(name=task["name"], cmd=task["cmd"], exit_status=rc, timed_out=timed_out, wall_time_s=time.time() - t0,
               host=socket.gethostname(), log=log, skipped=None, interrupted=interrupted)
    _write_json(task["status"], out)
    return out


def main(argv):
    if len(argv) != 2:
        print("usage: study_task.py TASKS.json INDEX", file=sys.stderr)
        return 1
    stop_on_signals()
    try:
        with open(argv[0]) as fh:
            tasks = json.load(fh)
        out = run_task(tasks[int(argv[1])])
    except Stopped as e:  # before the run started: nothing to record
        return 128 + e.signum
    if out.get("interrupted"):
        return 128 + signal.Signals[out["interrupted"]].value
    rc = out["exit_status"]
    return 128 - rc if rc < 0 else rc


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
