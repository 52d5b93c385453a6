"""SIGINT and SIGTERM during a run (yadeflex.module.impact.run_impact): raised as Interrupted at once,
except while a record is being written, which they end first; once the run is over they are only
noted, so that its summary is written whole."""
import contextlib
import signal
import threading


class Interrupted(Exception):
    """SIGINT (Ctrl-C) or SIGTERM (kill, a batch system's time limit, timeout): args[0] names it."""


class Signals:
    """SIGINT and SIGTERM raise Interrupted in the main thread, at once, except inside a
    deferred() block (a record: one row to each time series), which they end first. Once one
    has raised, or after hold() (the run is over), further ones are only noted: the summary is
    written whole. A SIGINT the run was started to ignore (nohup, a background job) stays
    ignored. restore() puts the handlers back. Outside the main thread (a run started from a
    worker thread, where Python delivers no signal) nothing is installed."""

    def __init__(self):
        main = threading.current_thread() is threading.main_thread()
        self.saved = {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGTERM)} if main else {}
        self.deferring = self.holding = False
        self.pending = None
        for sig, h in self.saved.items():
            if h != signal.SIG_IGN:
                signal.signal(sig, self._handler)

    def _handler(self, signum, frame):
        name = signal.Signals(signum).name
        if self.deferring or self.holding:
            self.pending = self.pending or name
            return
        self._raise(name)

    def _raise(self, name):
        self.holding = True
        raise Interrupted(name)

    @contextlib.contextmanager
    def deferred(self):
        self.deferring = True
        try:
            yield
        finally:
            self.deferring = False
        if self.pending and not self.holding:
            self._raise(self.pending)

    def hold(self):
        self.holding = True

    def restore(self):
        for sig, h in self.saved.items():
            signal.signal(sig, h)
