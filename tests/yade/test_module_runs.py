"""Runs of the damping module a user can trust (issue 32, item 4): concurrent runs share a
cache folder safely; a cache file that is not this module is filled again; broken elements are
counted by kind; the progress line's time left follows the expected end."""
import gzip
import json
import math
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


def _label_counts(ruptured, labels):
    out = {}
    for i in ruptured:
        out[labels[i]] = out.get(labels[i], 0) + 1
    return out


def test_broken_elements_are_counted_by_kind(first_run, scene):
    """Wire legs, ring segments and lining facets broken on purpose (two mesh nodes pulled 3 cm
    outwards, one on the top ring; ring steel and geotextile made weak): the counts by kind
    equal those by material, and add up to the engine's total."""
    from yade.minieigenHP import Vector3
    from yadeflex.impact import BrokenElements
    from yadeflex.module import ModuleParams, filled_module
    base, _ = first_run
    p = ModuleParams.small()
    ids, _, _ = filled_module(p, cache_dir=str(base / "cache"))
    labels = {b.id: b.material.label for b in scene.bodies if b is not None}
    mats = {m.label: m for m in scene.materials}
    mats["ring_steel"].tensileStrength = 1e6
    mats["geotextile"].strength = 10.0
    for n in (scene.bodies[ids["ring_top"][0]].shape.node1, ids["mesh_nodes"][len(ids["mesh_nodes"]) // 2]):
        st = scene.bodies[n].state
        radial = Vector3(st.pos[0], st.pos[1], 0)
        st.pos = st.pos + 0.03 * radial / radial.norm()
    scene.run(5, True)
    el = next(e for e in scene.engines if e.label == "flexElements")
    c = BrokenElements(ids).counts(el.rupturedIds)
    by_label = _label_counts(el.rupturedIds, labels)
    assert by_label.get("tecco_wire", 0) > 0 and by_label.get("ring_steel", 0) > 0 and by_label.get("geotextile", 0) > 0, by_label
    assert c == dict(broken_wire_legs=by_label.get("tecco_wire", 0), broken_ring_segments=by_label.get("ring_steel", 0),
                     broken_rope_segments=0, broken_lining_facets=by_label.get("geotextile", 0), broken_other_elements=0,
                     broken_elements_total=el.nRuptured)


def test_broken_elements_of_every_module_and_the_rope():
    """The kinds come from every module's ids, not the first module's only (which the top level
    of the ids repeats), and the rope's."""
    from yadeflex.impact import BrokenElements
    m0 = dict(mesh_cylinders=[1, 2], ring_top=[3], ring_bottom=[4], lining=[5])
    m1 = dict(mesh_cylinders=[11, 12], ring_top=[13], ring_bottom=[14], lining=[15])
    ids = dict(m0, modules=[m0, m1], rope=[21, 22], grains=[30])
    c = BrokenElements(ids).counts([12, 2, 14, 15, 5, 22, 99])
    assert c == dict(broken_wire_legs=2, broken_ring_segments=1, broken_rope_segments=1, broken_lining_facets=2,
                     broken_other_elements=1, broken_elements_total=7)


# ---- when the run ends, and the time left ---------------------------------------------------

def _contact(times, v0, accel, dt=2e-4):
    """Feed ImpactTimes a contact from t = 0: vz(t) = -v0 + accel(t) integrated; until the end."""
    t, vz, seen = 0.0, -v0, []
    while t < times.end:
        times.observe(t, vz, touching=True)
        seen.append((t, times.expected_end()))
        vz += accel(t) * dt
        t += dt
    return seen


def test_the_expected_end_of_a_constant_deceleration_is_exact():
    from yadeflex.impact import ImpactTimes
    v0, a = 4.0, 200.0  # stops at 20 ms, rebound then, end 10 ms later (the least margin)
    times = ImpactTimes(start=0.0)
    seen = _contact(times, v0, lambda t: a)
    assert times.end == pytest.approx(v0 / a + ImpactTimes.MIN_MARGIN, abs=5e-4)
    late = [e for t, e in seen if 0.1 * v0 / a < t]
    assert max(abs(e - times.end) for e in late) < 5e-4


def test_the_time_left_follows_the_expected_end():
    """A linear-spring contact (speed -v0 cos(w t), stopped at 22 ms, the run ending 10 ms later,
    the least margin) simulated at 1000 s of wall time per simulated second (a fake clock): from 70% of
    the contact on (a linear spring stiffens as it goes: the estimate comes down to the end
    from above), the time left is within 35% of the real one; the maximum duration, 0.3 s,
    would say 268 s or more."""
    from yadeflex.impact import ImpactTimes, Progress
    v0, t_stop = 4.4, 0.022
    w = math.pi / 2 / t_stop
    times = ImpactTimes(start=0.0)
    now = [0.0]
    lines = []
    prog = Progress(start=0.0, every=0.0, clock=lambda: now[0], out=lines.append)
    t, dt = 0.0, 2e-4
    checked = 0
    while t < times.end:
        vz = -v0 * math.cos(w * t)
        times.observe(t, vz, touching=True)
        now[0] = 1000.0 * t
        line = prog(t, int(t / 1e-6), times.expected_end())
        left = 1000.0 * (t_stop + ImpactTimes.MIN_MARGIN - t)
        if t > 0.7 * t_stop and left > 3:
            eta = float(line.split("~")[1].split(" s left")[0])
            assert abs(eta - left) < 0.35 * left, (t, eta, left)
            checked += 1
        t += dt
    assert times.t_rebound == pytest.approx(t_stop, abs=dt) and times.end == pytest.approx(t_stop + ImpactTimes.MIN_MARGIN, abs=2 * dt)
    assert checked > 20


def test_a_given_duration_counts_from_the_first_contact():
    from yadeflex.impact import ImpactTimes
    times = ImpactTimes(start=1.0, duration=0.05)
    assert times.end == pytest.approx(1.05)
    times.observe(1.001, -4.0, touching=False)
    times.observe(1.002, -4.0, touching=True)
    assert times.end == pytest.approx(1.052) and times.expected_end() == times.end
    times.observe(1.01, 0.1, touching=True)  # rebound: the given duration still holds
    assert times.end == pytest.approx(1.052)
