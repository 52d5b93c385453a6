"""Runs of the damping module a user can trust (issue 32, item 4): a run stopped by a signal
leaves its rows and a summary saying so; an earlier run's files never stand next to new ones; an
output or cache folder that cannot be written is refused before the fill; concurrent runs share
a cache folder and an output folder safely; a cache file that is not this module is filled
again; broken elements are counted by kind; numerical damping leaves the free fall alone; the
progress line's time left follows the expected end."""
import csv
import fcntl
import gzip
import json
import math
import os
import random
import shutil
import signal
import subprocess
import time

import pytest

from conftest import HERE, REPO
from test_module import SCRIPT, _run
from tol import G


@pytest.fixture(scope="module")
def first_run(tmp_path_factory):
    """A complete --small run (filling the cache) into a folder holding an earlier run's files
    and a file of the user's."""
    base = tmp_path_factory.mktemp("runs")
    out = base / "first"
    (out / "vtk").mkdir(parents=True)
    earlier = ["summary.json", "impact.png", "energy.png", "energy.csv", "timeseries.csv.tmp", ".tmp-x1y2.json", "vtk/flex.pvd",
               "vtk/flex_nodes_000999.vtu", "vtk/flex_spheres_empty.vtu"]
    for f in earlier:
        (out / f).write_text("from an earlier run\n")
    for f in ("notes.txt", "vtk/mine.txt"):
        (out / f).write_text("the user's\n")
    r, _ = _run(out, base / "cache", "--small", "--no-vtk")
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    return base, r, earlier


def _rows(path):
    """Rows keyed by the bare column names (headers read NAME[UNIT])."""
    with open(path, newline="") as fh:
        return [{k.split("[")[0]: v for k, v in r.items()} for r in csv.DictReader(fh)]


def test_an_earlier_runs_files_do_not_survive(first_run):
    base, _, earlier = first_run
    out = base / "first"
    for f in earlier:
        p = out / f
        assert not p.exists() or "from an earlier run" not in p.read_text(errors="replace"), f
    assert not (out / "vtk" / "flex.pvd").exists() and not (out / "vtk" / "flex_nodes_000999.vtu").exists()  # --no-vtk
    assert (out / "notes.txt").read_text() == "the user's\n" and (out / "vtk" / "mine.txt").exists()  # not ours: kept
    assert json.loads((out / "summary.json").read_text())["status"] == "done"


def test_the_impact_time_is_split_into_its_parts(first_run):
    """summary.json's impact_time_s: the wall time after the fill and its parts, which leave out
    only the set-up of the impact and the summary; the steps take most of it; no VTK frames timed
    in a --no-vtk run."""
    base, _, _ = first_run
    s = json.loads((base / "first" / "summary.json").read_text())
    t = s["impact_time_s"]
    assert set(t) == {"total", "free_fall", "steps", "records", "vtk_frames"}
    assert t["total"] <= s["run_time_s"]
    assert t["vtk_frames"] == 0 and t["free_fall"] > 0 and t["records"] > 0
    parts = t["free_fall"] + t["steps"] + t["records"]
    assert 0.5 * t["total"] < parts < t["total"] and t["steps"] > max(t["free_fall"], t["records"])


def test_the_library_runner_writes_the_rows_of_the_job(first_run, tmp_path, scene):
    """yadeflex.module.impact.run_impact called in this process (no progress lines) writes the rows the
    main job writes from the same cached fill, bit for bit (one thread): the job is its options and
    this one call."""
    from yadeflex.module.impact import run_impact
    from yadeflex.module import ModuleParams
    base, _, _ = first_run
    r, _ = _run(tmp_path / "job", base / "cache", "--small", "--no-vtk")
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    s = run_impact(ModuleParams.small(), str(tmp_path / "lib"), cache_dir=str(base / "cache"), progress=False, no_vtk=True)
    assert s["status"] == "done" and s["exit_status"] == 0 and s["filled_from_cache"]
    assert s == json.loads((tmp_path / "lib" / "summary.json").read_text())
    for f in ("timeseries.csv", "energy.csv", "params.json"):
        assert (tmp_path / "lib" / f).read_bytes() == (tmp_path / "job" / f).read_bytes(), f


def _start(out, cache, *args, log=None, threads=1):
    """The main job in the background, SIGINT at its default (a shell may start it ignored);
    its output goes to the file `log` (default OUT.log)."""
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), PYTHONPATH=os.path.join(REPO, "py"))
    log = open(log or str(out) + ".log", "w+")
    p = subprocess.Popen(["yade-double", "-n", f"-j{threads}", "-x", SCRIPT, "--out", str(out), "--cache-dir", str(cache), *map(str, args)],
                         stdout=log, stderr=subprocess.STDOUT, env=env, cwd=REPO,
                         preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    return p, log


def _wait_for(log, text, p, timeout=120):
    t0 = time.time()
    while time.time() - t0 < timeout:
        log.seek(0)
        if text in log.read():
            return
        assert p.poll() is None, f"ended before {text!r}:\n" + log.read()[-3000:]
        time.sleep(0.2)
    raise AssertionError(f"no {text!r} in {timeout} s")


@pytest.mark.parametrize("sig", ["SIGTERM", "SIGINT"])
def test_a_signal_while_plotting_keeps_summary_and_exit_status_in_step(first_run, sig):
    """A signal while the plots are drawn (summary.json already written, "done"): SIGTERM ended the
    process with 143 and no plots, SIGINT with 1 and a traceback. Now the run is over and the
    signal only noted: exit 0 as the summary says, the plots drawn."""
    base, _, _ = first_run
    out = base / f"plotsig_{sig}"
    env = dict(os.environ, OMP_NUM_THREADS="1", PYTHONPATH=os.path.join(REPO, "py"))
    r = subprocess.run(["yade-double", "-n", "-j1", "-x", os.path.join(HERE, "scripts", "signal_in_plots.py"), str(out), str(base / "cache"), sig],
                       capture_output=True, text=True, timeout=600, env=env, cwd=REPO,
                       preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    s = json.loads((out / "summary.json").read_text())
    assert r.returncode == 0 == s["exit_status"] and s["status"] == "done", (r.returncode, s["status"], r.stderr[-2000:])
    assert "Traceback" not in r.stderr and (out / "impact.png").exists() and (out / "energy.png").exists()


@pytest.mark.parametrize("sig, code", [(signal.SIGTERM, 143), (signal.SIGINT, 130)])
def test_a_signal_leaves_the_rows_and_an_interrupted_summary(first_run, sig, code):
    """Stopped during the impact (a long --duration, so that it is still running), the run
    leaves every row recorded so far, complete, and a summary that says so and agrees with them."""
    base, _, _ = first_run
    out = base / f"sig{int(sig)}"
    p, log = _start(out, base / "cache", "--small", "--no-vtk", "--duration", 0.3)
    _wait_for(log, "  t = ", p)
    time.sleep(1.0)
    p.send_signal(sig)
    assert p.wait(60) == code
    log.seek(0)
    assert "interrupted by " + signal.Signals(sig).name in log.read()
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "interrupted" and s["stage"] == "impact" and s["exit_status"] == code
    rows = _rows(out / "timeseries.csv")
    assert len(rows) >= 10 and all(None not in r.values() and "" not in r.values() for r in rows)
    assert float(rows[-1]["t"]) < 0.3  # cut short
    assert len(_rows(out / "energy.csv")) == len(rows)
    assert s["penetration_max"] == pytest.approx(max(float(r["penetration"]) for r in rows), rel=1e-12)


def _vtu(folder):
    """The frame files in folder so far (none if it is not there yet)."""
    try:
        return [f for f in os.listdir(folder) if f.endswith(".vtu") and "_empty" not in f]
    except FileNotFoundError:
        return []


def _series(folder):
    """The .pvd's frames (file names by group) and their times [s], in order, and the frame files on disk."""
    import xml.etree.ElementTree as ET
    frames = {}
    for d in ET.parse(folder / "flex.pvd").getroot().iter("DataSet"):
        frames.setdefault(float(d.get("timestep")), []).append(d.get("file"))
    on_disk = sorted(_vtu(folder))
    return [frames[t] for t in sorted(frames)], sorted(frames), on_disk


@pytest.mark.parametrize("stop", [None, signal.SIGINT])
def test_frames_of_a_run_on_two_threads_are_all_written(first_run, stop):
    """On two threads the frames are written by two processes, 8 at a time: at the end of the
    run, and when a signal stops it, every frame taken is in the .pvd, in order, with its files
    (none missing, none left out of the .pvd)."""
    base, _, _ = first_run
    out = base / f"frames_j2_{stop}"
    p, log = _start(out, base / "cache", "--small", "--duration", 0.3 if stop else 0.025, threads=2)
    if stop:
        # the event: frames of at least three instants are on disk (the run is well into its
        # frames, however loaded the machine), then the signal
        _wait_for(log, "  t = ", p)
        t0 = time.time()
        while len({f.rsplit("_", 1)[1][:6] for f in _vtu(out / "vtk")}) < 3:
            assert p.poll() is None, "ended before its third frame:\n" + log.read()[-3000:]
            assert time.time() - t0 < 600, "no third frame in 600 s"
            time.sleep(0.2)
        p.send_signal(stop)
    assert p.wait(300) == (130 if stop else 0), log.read()[-3000:]
    frames, times, on_disk = _series(out / "vtk")
    assert len(frames) >= 3
    listed = sorted(f for fr in frames for f in fr if "_empty" not in f)
    assert listed == on_disk
    assert [int(f.rsplit("_", 1)[1][:6]) for f in (fr[0] for fr in frames)] == list(range(len(frames)))
    s = json.loads((out / "summary.json").read_text())
    assert s["threads"] == 2 and s["impact_time_s"]["vtk_frames"] > 0
    # the last frame taken is written: a frame per 1 ms from the first contact, up to the last record
    # (the records' clock starts at the run's start, the frames' at the first contact)
    last_record = float(_rows(out / "timeseries.csv")[-1]["t"]) - s["free_fall_check"]["t"]
    assert last_record - 1e-3 - 2e-4 <= times[-1] <= last_record + 2e-4


@pytest.mark.parametrize("make", ["under a file", "a file"])
def test_an_output_folder_that_cannot_be_written_is_refused_before_the_fill(tmp_path, make):
    (tmp_path / "f").write_text("a regular file\n")
    out = tmp_path / "f" / "out" if make == "under a file" else tmp_path / "f"
    r, t = _run(out, tmp_path / "cache", "--small", timeout=120)
    assert r.returncode == 1 and "cannot be written" in r.stderr and str(out) in r.stderr, r.stderr[-2000:]
    assert "settles until" not in r.stdout and not (tmp_path / "cache").exists()


def test_a_cache_folder_under_a_file_is_refused_with_the_options(tmp_path):
    """Seen in the options (yadeflex.module.cli): status 1 and one line, nothing written."""
    (tmp_path / "f").write_text("a regular file\n")
    cache = tmp_path / "f" / "cache"
    r, _ = _run(tmp_path / "out", cache, "--small", "--no-vtk", timeout=120)
    assert r.returncode == 1 and "bad option --cache-dir" in r.stderr and f"{cache} cannot be written" in r.stderr, r.stderr[-2000:]
    assert "settles until" not in r.stdout and not (tmp_path / "out").exists()


def test_a_cache_folder_that_cannot_be_written_fails_the_run_before_the_fill(tmp_path):
    """One the options cannot foresee (a link to a folder that is not there, as to a drive
    not mounted): the run fails at the fill stage, before filling, with a failed summary."""
    os.symlink(tmp_path / "not mounted" / "cache", tmp_path / "cache")
    r, _ = _run(tmp_path / "out", tmp_path / "cache", "--small", "--no-vtk", timeout=120)
    assert r.returncode == 1 and "module cache folder" in r.stderr and "cannot be written" in r.stderr, r.stderr[-2000:]
    assert "settles until" not in r.stdout
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert s["status"] == "failed" and s["stage"] == "fill" and "cannot be written" in s["message"]


def test_two_runs_fill_a_fresh_cache_once(first_run, scene):
    """Started at once with the same empty cache folder: one fills, the other waits and loads
    that fill; both succeed and the cache is whole afterwards."""
    from yadeflex.module import ModuleParams, cache_problem, filled_module
    base, _, _ = first_run
    cache = base / "shared_cache"
    runs = [_start(base / f"conc{k}", cache, "--small", "--no-vtk") for k in (0, 1)]
    logs = []
    for p, log in runs:
        assert p.wait(300) == 0
        log.seek(0)
        logs.append(log.read())
    assert sum("built and saved" in lg for lg in logs) == 1 and sum("loaded from" in lg for lg in logs) == 1, [lg[-1500:] for lg in logs]
    assert [json.loads((base / f"conc{k}" / "summary.json").read_text())["status"] for k in (0, 1)] == ["done", "done"]
    p = ModuleParams.small()
    assert cache_problem(p, str(cache)) is None
    assert not [f for f in os.listdir(cache) if f.startswith(".")]  # no temporary file left
    assert filled_module(p, cache_dir=str(cache))[2]


def test_two_runs_into_one_folder_take_turns(first_run):
    base, _, _ = first_run
    out = base / "same"
    runs = [_start(out, base / "cache", "--small", "--no-vtk", "--drop-height", h, log=base / f"same{h}.log") for h in (1.0, 0.8)]
    logs = []
    for p, log in runs:
        assert p.wait(300) == 0
        log.seek(0)
        logs.append(log.read())
    assert sum("waiting for the other run writing into" in lg for lg in logs) == 1, [lg[-1500:] for lg in logs]
    # the folder holds one run's files, consistent with each other
    prm, s, rows = json.loads((out / "params.json").read_text()), json.loads((out / "summary.json").read_text()), _rows(out / "timeseries.csv")
    assert s["status"] == "done" and s["impact_speed_expected"] == pytest.approx(math.sqrt(2 * G * prm["drop_height"]))
    assert s["penetration_max"] == pytest.approx(max(float(r["penetration"]) for r in rows), rel=1e-12)


def _copy_cache(src, dst, params_from, params_to):
    from yadeflex.module import cache_files
    dst.mkdir(exist_ok=True)
    for a, b in zip(cache_files(params_from, str(src))[:2], cache_files(params_to, str(dst))[:2]):
        shutil.copy(a, b)
    return cache_files(params_to, str(dst))[:2]


def test_cache_files_that_are_not_this_module_are_refused_before_loading(first_run, tmp_path):
    from yadeflex.module import ModuleParams, cache_problem
    base, _, _ = first_run
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
    base, _, _ = first_run
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
    from yadeflex.module.impact import BrokenElements
    from yadeflex.module import ModuleParams, filled_module
    base, _, _ = first_run
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
    from yadeflex.module.impact import BrokenElements
    m0 = dict(mesh_cylinders=[1, 2], ring_top=[3], ring_bottom=[4], lining=[5])
    m1 = dict(mesh_cylinders=[11, 12], ring_top=[13], ring_bottom=[14], lining=[15])
    ids = dict(m0, modules=[m0, m1], rope=[21, 22], grains=[30])
    c = BrokenElements(ids).counts([12, 2, 14, 15, 5, 22, 99])
    assert c == dict(broken_wire_legs=2, broken_ring_segments=1, broken_rope_segments=1, broken_lining_facets=2,
                     broken_other_elements=1, broken_elements_total=7)


def test_numerical_damping_leaves_the_free_fall_alone(first_run):
    """--damping 0.2: the boulder falls freely up to its first contact (fall height and time as
    undamped, the speed sqrt(2 g h)); the damping acts from there on."""
    base, _, _ = first_run
    r, _ = _run(base / "damped", base / "cache", "--small", "--no-vtk", "--damping", 0.2)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    damped = json.loads((base / "damped" / "summary.json").read_text())
    free = json.loads((base / "first" / "summary.json").read_text())["free_fall_check"]
    ff = damped["free_fall_check"]
    assert abs(ff["v_measured"] / ff["v_expected"] - 1) < 1e-3
    assert ff["fall_height"] == pytest.approx(free["fall_height"], rel=1e-4)
    assert ff["t"] == pytest.approx(free["t"], rel=0.02)
    assert ff["v_measured"] == pytest.approx(math.sqrt(2 * G * 1.0), rel=1e-3)  # --small: 1 m
    assert damped["numerical_damping_share"] > 0.05


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
    from yadeflex.runner import ImpactTimes
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
    from yadeflex.runner import ImpactTimes, Progress
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
    from yadeflex.runner import ImpactTimes
    times = ImpactTimes(start=1.0, duration=0.05)
    assert times.end == pytest.approx(1.05)
    times.observe(1.001, -4.0, touching=False)
    times.observe(1.002, -4.0, touching=True)
    assert times.end == pytest.approx(1.052) and times.expected_end() == times.end
    times.observe(1.01, 0.1, touching=True)  # rebound: the given duration still holds
    assert times.end == pytest.approx(1.052)


# ---- setup ----------------------------------------------------------------------------------

def test_setup_waits_for_another_setup(tmp_path):
    """Two setups with one build folder run one after the other: while the lock is held (here
    by the test, as a first setup would), a second waits before it touches the YADE headers,
    the build or the install; released, it goes on (here to a quick stop: YADE_SOURCE_DIR points
    at an empty folder, so that nothing is built)."""
    build = tmp_path / "build"
    build.mkdir()
    env = dict(os.environ, YADE_PREFIX=str(tmp_path / "prefix"), BUILD_DIR=str(build), YADE_SOURCE_DIR=str(tmp_path / "no_source"))
    lock = open(build / ".setup.lock", "w")
    fcntl.flock(lock, fcntl.LOCK_EX)
    p = subprocess.Popen(["bash", os.path.join(REPO, "scripts", "setup")], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         env=env, cwd=str(tmp_path))
    try:
        # the event: the second setup says it waits (however long it takes to get there on a
        # loaded machine), and has not ended: nothing of it came before (the headers' error would)
        first = p.stderr.readline()
        assert "waiting for another setup" in first, first + p.stderr.read()[-2000:]
        assert p.poll() is None
    finally:
        lock.close()  # releases the lock
    out, err = p.communicate(timeout=600)
    assert p.returncode == 1
    assert "does not hold YADE's source" in err, err[-2000:]
    assert not (tmp_path / "prefix").exists()


def test_signal_handlers_in_the_main_thread_only():
    """run_impact's Signals: in the main thread SIGTERM's handler is replaced and put back; in
    another thread (a run started from a worker thread) nothing is touched and nothing raises."""
    import threading
    from yadeflex.signals import Signals
    before = signal.getsignal(signal.SIGTERM)
    s = Signals()
    assert signal.getsignal(signal.SIGTERM) == s._handler
    s.restore()
    assert signal.getsignal(signal.SIGTERM) == before
    out = {}

    def work():
        try:
            t = Signals()
            t.restore()
            out["saved"] = t.saved
        except Exception as e:  # noqa: BLE001
            out["error"] = repr(e)

    th = threading.Thread(target=work)
    th.start()
    th.join()
    assert out == {"saved": {}} and signal.getsignal(signal.SIGTERM) == before
