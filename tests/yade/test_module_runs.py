"""Runs of the damping module a user can trust (issue 32, item 4): concurrent runs share a
cache folder safely; a cache file that is not this module is filled again."""
import gzip
import json
import os
import random
import shutil
import signal
import subprocess

import pytest

from conftest import REPO
from test_module import SCRIPT, _run


@pytest.fixture(scope="module")
def first_run(tmp_path_factory):
    """A complete --small run, filling the cache."""
    base = tmp_path_factory.mktemp("runs")
    r, _ = _run(base / "first", base / "cache", "--small", "--no-vtk")
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    return base, r


def _start(out, cache, *args, log=None):
    """The main job in the background, SIGINT at its default (a shell may start it ignored);
    its output goes to the file `log` (default OUT.log)."""
    env = dict(os.environ, OMP_NUM_THREADS="1", PYTHONPATH=os.path.join(REPO, "py"))
    log = open(log or str(out) + ".log", "w+")
    p = subprocess.Popen(["yade-double", "-n", "-j1", "-x", SCRIPT, "--out", str(out), "--cache-dir", str(cache), *map(str, args)],
                         stdout=log, stderr=subprocess.STDOUT, env=env, cwd=REPO,
                         preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    return p, log


def test_two_runs_fill_a_fresh_cache_once(first_run, scene):
    """Started at once with the same empty cache folder: one fills, the other waits and loads
    that fill; both succeed and the cache is whole afterwards."""
    from yadeflex.module import ModuleParams, cache_problem, filled_module
    base, _ = first_run
    cache = base / "shared_cache"
    runs = [_start(base / f"conc{k}", cache, "--small", "--no-vtk") for k in (0, 1)]
    logs = []
    for p, log in runs:
        assert p.wait(300) == 0
        log.seek(0)
        logs.append(log.read())
    assert sum("built and saved" in lg for lg in logs) == 1 and sum("loaded from" in lg for lg in logs) == 1, [lg[-1500:] for lg in logs]
    p = ModuleParams.small()
    assert cache_problem(p, str(cache)) is None
    assert not [f for f in os.listdir(cache) if f.startswith(".")]  # no temporary file left
    assert filled_module(p, cache_dir=str(cache))[2]


def _copy_cache(src, dst, params_from, params_to):
    from yadeflex.module import cache_files
    dst.mkdir(exist_ok=True)
    for a, b in zip(cache_files(params_from, str(src))[:2], cache_files(params_to, str(dst))[:2]):
        shutil.copy(a, b)
    return cache_files(params_to, str(dst))[:2]


def test_cache_files_that_are_not_this_module_are_refused_before_loading(first_run, tmp_path):
    from yadeflex.module import ModuleParams, cache_problem
    base, _ = first_run
    p = ModuleParams.small()
    cases = {}
    for name in ("whole", "no metadata", "other contents", "other module", "metadata not json", "metadata of something else"):
        d = tmp_path / name.replace(" ", "_")
        to = ModuleParams.small(seed=2) if name == "other module" else p
        f, meta = _copy_cache(base / "cache", d, p, to)
        if name == "no metadata":
            os.unlink(meta)
        elif name == "other contents":
            with gzip.open(f, "wb") as g:
                g.write(b"text, not a scene\n" * 100)
        elif name == "metadata not json":
            open(meta, "w").write("{")
        elif name == "metadata of something else":
            json.dump(dict(format="a list of names", key=p.fill_key()), open(meta, "w"))
        cases[name] = cache_problem(to, str(d))
    assert cases.pop("whole") is None
    assert "no metadata" in cases["no metadata"]
    assert "other size or checksum" in cases["other contents"]
    assert p.fill_key() in cases["other module"] and ModuleParams.small(seed=2).fill_key() in cases["other module"]
    assert all(cases.values()), cases


def test_a_damaged_cache_is_filled_again(first_run, tmp_path):
    """A valid gzip holding a YADE archive whose body is damaged (a reader can crash on it) under
    this module's key, with the metadata of the good file: filled again with a message."""
    from yadeflex.module import ModuleParams, cache_problem
    base, _ = first_run
    p = ModuleParams.small()
    f, _ = _copy_cache(base / "cache", tmp_path / "cache", p, p)
    raw = bytearray(gzip.open(f).read())
    rnd = random.Random(1)
    raw[40:] = bytes(rnd.randrange(256) for _ in range(len(raw) - 40))
    with gzip.open(f, "wb") as g:
        g.write(bytes(raw))
    r, _ = _run(tmp_path / "out", tmp_path / "cache", "--small", "--no-vtk")
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    assert "filling it again" in r.stderr and "built and saved" in r.stdout
    assert cache_problem(p, str(tmp_path / "cache")) is None
