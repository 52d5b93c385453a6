# A main job whose plots receive a signal (test_module_runs.test_a_signal_while_plotting_...):
#   yade-double -n -x signal_in_plots.py OUT CACHE SIGNAL
import os
import signal
import sys

from yadeflex.module import impact
from yadeflex.module import ModuleParams

out, cache, sig = sys.argv[1], sys.argv[2], getattr(signal, sys.argv[3])
real = impact.write_plots


def plots(*args, **kw):
    os.kill(os.getpid(), sig)  # delivered now, in the main thread, between the plots' bytecodes
    return real(*args, **kw)


impact.write_plots = plots
s = impact.run_impact(ModuleParams.small(), out, cache_dir=cache, progress=False, no_vtk=True, duration=0.005)
sys.exit(s["exit_status"])
