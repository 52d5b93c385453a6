"""Recorders called every few steps: the base of VtkRecorder and EnergyRecorder.

A recorder writes at a call only if `every` steps have passed since its last write, so a loop can
call it after every step; its runner() is a PyRunner that calls it, found in this module's
registry by a key.
"""
import itertools

from yade import O
from yade.wrapper import PyRunner


def _check_every(every):
    if not (isinstance(every, int) and not isinstance(every, bool) and every >= 1):
        raise ValueError(f"every must be a positive whole number of steps, got {every!r}")
    return every


_REGISTRY = {}
_KEYS = itertools.count()


class Periodic:
    """Writes at a call only if `every` steps have passed since its last write (the first call
    always writes), so it can be called after every step of a loop; runner() gives a PyRunner
    that calls it every `every` steps."""

    def __init__(self, every):
        self.every = _check_every(every)
        self.last_iter = None
        self._key = next(_KEYS)
        _REGISTRY[self._key] = self

    def _due(self):
        return self.last_iter is None or O.iter >= self.last_iter + self.every

    def runner(self, label=""):
        """PyRunner(iterPeriod=every) calling this recorder; put it after the integrator in
        O.engines. The command finds the recorder in this module's registry, so it only works
        in the process that created it (not after O.save/O.load in another one)."""
        return PyRunner(iterPeriod=self.every, initRun=True, label=label,
                        command=f"import yadeflex.recording as _yfr; _yfr._REGISTRY[{self._key}]()")
