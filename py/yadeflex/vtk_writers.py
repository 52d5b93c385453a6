"""VTK files written by forked child processes: the frames' writes shared out by cost among
processes that are copies of this one (so the frames' data need not be sent), their errors
brought back to this process."""
import os
import signal


def write_jobs(jobs, workers):
    """Runs the writes jobs: (cost, write) pairs, write() builds and writes one file. With workers
    > 1, the jobs are shared out by cost (the largest first, each to the least loaded process) and
    all but the first share run in child processes forked for the purpose (each a copy of this
    one, so the frames' data need not be sent), while this process runs the first; it returns
    when all are done (a share whose fork fails runs here). Raises the first error (a child's as
    OSError with its message). The children run only numpy and VTK, never YADE or OpenMP, whose
    threads they do not have."""
    shares = [[] for _ in range(max(1, min(int(workers), len(jobs))))]
    # a child starts once forked (the copy of this process's page tables) and copies the pages it
    # writes: it takes a tenth of a share less (bench/README.md, "Two threads, fifth round")
    load = [0.0] + [0.1 * sum(c for c, _ in jobs) / len(shares)] * (len(shares) - 1)
    for cost, write in sorted(jobs, key=lambda j: -j[0]):
        k = load.index(min(load))
        shares[k].append(write)
        load[k] += cost
    children, here = [], list(shares[0])
    try:
        for share in shares[1:]:
            child = _fork_writer(share)
            if child is None:
                here += share
            else:
                children.append(child)
        for write in here:
            write()
    finally:
        failed = _reap(children)
    if failed:
        raise OSError("VTK files written by a child process failed: " + "; ".join(failed))


def _fork_writer(share):
    """A child process that runs the writes of share and exits: (pid, the read end of its pipe
    for an error message), or None if the fork failed."""
    r, w = os.pipe()
    try:
        pid = os.fork()
    except OSError:
        os.close(r)
        os.close(w)
        return None
    if pid == 0:  # the child: its share, then out without Python's exit handlers (the parent's)
        status = 1
        try:
            os.close(r)
            signal.signal(signal.SIGINT, signal.SIG_IGN)  # (the parent handles a signal once the frames are written)
            signal.signal(signal.SIGTERM, signal.SIG_IGN)
            for write in share:
                write()
            status = 0
        except BaseException as e:  # (reported to the parent, whatever it is)
            os.write(w, f"{type(e).__name__}: {e}".encode()[:4000])
        finally:
            os._exit(status)
    os.close(w)
    return pid, r


def _reap(children):
    """Waits for every child of _fork_writer, even if interrupted while waiting for one; returns
    the messages of those that failed."""
    failed = []
    for k, (pid, r) in enumerate(children):
        try:
            with os.fdopen(r, "rb") as f:
                msg = f.read().decode(errors="replace")
            code = os.waitstatus_to_exitcode(os.waitpid(pid, 0)[1])
        except BaseException:
            for pid_, r_ in children[k + 1:]:
                os.close(r_)
            for pid_, _ in children[k:]:
                try:
                    os.waitpid(pid_, 0)
                except ChildProcessError:
                    pass
            raise
        if code != 0:
            failed.append(msg or (f"killed by signal {-code}" if code < 0 else f"exit status {code}"))
    return failed
