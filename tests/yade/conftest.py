"""pytest on the system interpreter (/usr/bin/python3) driving Debian's YADE in-process.

O is one global scene per process: every test starts from O.reset() (fixture `scene`).
Tests that need another thread count run yade-double in a subprocess (see run_yade).
"""
import os
import subprocess
import sys

import pytest

# In-process tests run single-threaded, hence bitwise reproducible (YADE's InteractionLoop
# with 2 threads is reproducible only to round-off); thread counts are tested in subprocesses.
os.environ["OMP_NUM_THREADS"] = "1"
YADE_PY = "/usr/lib/x86_64-linux-gnu/yade-double/py"
if YADE_PY not in sys.path:
    sys.path.insert(0, YADE_PY)
HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(REPO, "py"))  # the checkout's package, not a stale install
sys.path.insert(0, HERE)

import yade  # noqa: E402  (starts YADE, loads the installed libyadeflex.so)
from yade import O  # noqa: E402

assert O.numThreads == 1, "in-process YADE tests must run with one OpenMP thread"


@pytest.fixture(scope="session")
def module_cache(tmp_path_factory, request):
    """The folder of the filled modules the tests load (the reduced module filled when the folder
    is first asked for, the others on first use, then loaded from there): a temporary one, never
    the user's cache. Under pytest-xdist (scripts/test runs two workers) the workers share one:
    the cache's lock makes the second wait for a module the first is filling, then load it."""
    if not hasattr(request.config, "workerinput"):  # not an xdist worker
        path = str(tmp_path_factory.mktemp("module_cache"))
    else:
        shared = tmp_path_factory.getbasetemp().parent / "module_cache"  # the session's folder, above each worker's
        shared.mkdir(exist_ok=True)
        path = str(shared)
    _fill_reduced_module(path)
    return path


def _fill_reduced_module(cache_dir):
    """The reduced module filled here, in this process (one thread), before a test uses the folder.
    Otherwise the first test to ask fills it, and test_threads asks from yade-double -j2: a fill on
    two threads differs by round-off from run to run, and the tests that load it then start from
    another state in each session (test_loop's fixture had from 76 to over 100 contacts)."""
    from yadeflex.module import ModuleParams, filled_module
    filled_module(ModuleParams.small(), cache_dir=cache_dir)
    O.reset()


# the test files that take longest (their share of a whole run), started first so that two
# workers end together; the others follow in their order
LONGEST_FIRST = ("test_study.py", "test_contact.py", "test_module.py", "test_timestep.py", "test_module_runs.py", "test_validation.py",
                 "test_stability.py", "test_tensile.py", "test_facet.py", "test_paraview.py", "test_threads.py")


def pytest_collection_modifyitems(session, config, items):
    rank = {name: k for k, name in enumerate(LONGEST_FIRST)}
    items.sort(key=lambda it: rank.get(os.path.basename(str(it.fspath)), len(rank)))  # (stable: each file keeps its order)


@pytest.fixture
def scene():
    O.reset()
    O.trackEnergy = False
    yield O
    O.reset()


def run_yade(script, threads=1, args=(), timeout=600, display=False):
    """Run a script in yade-double with `threads` OpenMP threads; return its stdout.
    display: with YADE's Qt GUI on a virtual X server of its own (yadeflex.xdisplay), for the 3D view."""
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), PYTHONPATH=os.path.join(REPO, "py") + os.pathsep + HERE)
    cmd = ["yade-double", *([] if display else ["-n"]), "-j", str(threads), "-x", script, *map(str, args)]
    if display:
        from yadeflex.xdisplay import virtual_display
        with virtual_display(1024, 768) as d:
            res = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=dict(env, DISPLAY=d), cwd=REPO)
    else:
        res = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env, cwd=REPO)
    if res.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({res.returncode}):\n{res.stdout[-3000:]}\n{res.stderr[-3000:]}")
    return res.stdout
