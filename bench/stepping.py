# Benchmarks' stepping: n steps as scripts run them (GPL-2.0-or-later).
import time

from yade import O


def run_steps(n, poll=5e-4):
    """n steps by O.run(n): YADE's run thread, no Python between the steps, as a script's O.run.
    Waited for by polling O.running every `poll` seconds (O.run(n, True) waits through
    O.wait(), which polls every 40 ms: each call could overshoot by up to 40 ms, which swamps
    short timed runs). Raises what stopped the run, if anything did."""
    O.run(n)
    while O.running:
        time.sleep(poll)
    O.wait()
