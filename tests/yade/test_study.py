"""Parametric studies (yadeflex.module.study, scripts/study): a bad cell is named by its row and column
before anything runs; a 12-run study of small modules runs through the local backend, each run
with the inputs of its row and its module filled once; the mpi and slurm backends give the same
results.csv values; a worker killed loses only its run, a failed run is a result, and --resume
completes the study."""
import ast
import csv
import importlib.util
import json
import math
import os
import shutil
import signal
import subprocess
import sys
import time

import pytest

from conftest import REPO
from local_slurm import LocalSlurm, unavailable
from tol import G

from yadeflex.module import study

STUDY = os.path.join(REPO, "scripts", "study")
# small modules, a 20 ms impact: about 5 s a run (one fill of 15 s shared by all)
COMMON = dict(small="yes", no_vtk="yes", duration="0.02")
GRID = [dict(name=f"m{m}-h{h}", boulder_mass=str(m), drop_height=str(h), **COMMON) for m in (80, 100, 150) for h in (0.5, 1, 1.5, 2)]
SUBSET = GRID  # the mpi and slurm backends repeat the whole 12-run study


def write_study(path, rows):
    cols = list(dict.fromkeys(k for r in rows for k in r))
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=cols, restval="")
        w.writeheader()
        w.writerows(rows)
    return str(path)


def read_results(out):
    return {r["name"]: r for r in study.read_results(os.path.join(out, "results.csv"))}


def assert_same_run(a, b):
    """Two results.csv rows of the same inputs hold the same values, to the last digit, but for
    what differs between identical runs (wall times, host, paths) and the row number."""
    keys = (set(a) & set(b)) - set(study.TIMING_COLUMNS) - {"row"}
    assert set(study.SUMMARY_COLUMNS) <= keys
    assert {k: a[k] for k in keys} == {k: b[k] for k in keys}, a["name"]


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    return str(tmp_path_factory.mktemp("study_cache"))


@pytest.fixture(scope="module")
def local_study(tmp_path_factory, cache):
    """The 12-run study through the local backend, two workers."""
    base = tmp_path_factory.mktemp("study")
    lines = []
    out = str(base / "local")
    rows = study.run_study(write_study(base / "grid.csv", GRID), out, backend="local", workers=2, cache_dir=cache,
                           progress=lines.append)
    return out, rows, lines


def test_bad_cells_are_named_by_row_and_column_before_anything_runs(tmp_path):
    bad = [dict(name="ok", small="yes", drop_height="1", fill="gravel"),
           dict(name="b", small="yes", drop_height="-3", fill="gravel"),
           dict(name="c", small="maybe", drop_height="1", fill="granite"),
           dict(name="d", small="yes", drop_height="1", record_every="0.5"),
           dict(name="ok", small="yes", drop_height="1", repeat="0")]
    out = tmp_path / "out"
    with pytest.raises(study.StudyError) as err:
        study.run_study(write_study(tmp_path / "bad.csv", bad), str(out))
    assert err.value.errors == [
        "row 2 (line 3), column drop_height: bad option --drop-height: got -3.0; allowed (0, 127.421] m (an impact speed up to 50 m/s)",
        "row 3 (line 4), column small: got 'maybe'; allowed true/false/yes/no/1/0",
        "row 3 (line 4), column fill: bad option --fill: got 'granite'; allowed one of 'gravel', 'sand'",
        "row 4 (line 5), column record_every: " + err.value.errors[3].split(": ", 1)[1],
        "row 5 (line 6), column repeat: got '0'; allowed a whole number in [1, 1000] (a fill each)",
        "row 5 (line 6), column name: the run name 'ok' is already row 1's"], err.value.errors
    assert "bad option --record-every: got 0.5; allowed [1e-06, 0.001] s" in err.value.errors[3]
    assert not out.exists()  # refused before anything was made or run
    with pytest.raises(study.StudyError) as err:
        study.read_study(write_study(tmp_path / "cols.csv", [dict(drop_hieght="1", out="x", small="yes")]))
    assert err.value.errors[0].startswith("column 'drop_hieght' (line 1): not an option of the main job (allowed: ")
    assert err.value.errors[1].startswith("column 'out' (line 1): set by the study for every run")


def test_a_cell_is_one_value_and_a_row_has_every_cell(tmp_path):
    """An impact_offset cell with more than its two numbers ran the words after them as options
    ('0 0 --drop-height 3' from 3 m while results.csv said 1 m); a short row ran with defaults; a
    spreadsheet's byte-order mark became part of the first column's name; repeat=100000 started
    99,999 fills. Each refused (or, the mark, accepted) before anything runs."""
    path = tmp_path / "s.csv"
    path.write_text("name,small,drop_height,impact_offset\n"
                    "a,yes,1,0 0 --drop-height 3\n"
                    "b,yes,1,0 0 0.01\n"
                    "c,yes,1\n"
                    "d,yes,1,0.1 0\n")
    with pytest.raises(study.StudyError) as err:
        study.read_study(str(path))
    assert err.value.errors == [
        "row 1 (line 2), column impact_offset: got '0 0 --drop-height 3'; allowed two numbers, the offset x y [m] (e.g. '0.1 0')",
        "row 2 (line 3), column impact_offset: got '0 0 0.01'; allowed two numbers, the offset x y [m] (e.g. '0.1 0')",
        "row 3 (line 4): 3 cells, the header has 4 columns"], err.value.errors
    path.write_bytes("\ufeffname,small,drop_height,impact_offset\nd,yes,1,0.1 0\n".encode("utf-8"))
    runs = study.read_study(str(path))
    assert [r["name"] for r in runs] == ["d"] and runs[0]["argv"][-3:] == ["--impact-offset", "0.1", "0"]
    with pytest.raises(study.StudyError, match=r"column repeat: got '100000'; allowed a whole number in \[1, 1000\]"):
        study.read_study(write_study(tmp_path / "r.csv", [dict(name="x", small="yes", repeat="100000")]))


def test_repeat_gives_one_run_per_seed(tmp_path):
    runs = study.read_study(write_study(tmp_path / "r.csv", [dict(name="x", small="yes", seed="5", repeat="3")]))
    assert [(r["name"], r["inputs"]["seed"], r["argv"][-2:]) for r in runs] == [
        ("x-s5", "5", ["--seed", "5"]), ("x-s6", "6", ["--seed", "6"]), ("x-s7", "7", ["--seed", "7"])]
    assert len({r["fill_key"] for r in runs}) == 3  # the seed places the grains


def test_progress_eta_is_the_median_run_times_the_rounds_left():
    lines, tasks = [], [dict(status=f"/nonexistent/{k}") for k in range(7)]
    p = study.StudyProgress(7, 2, failed_of=lambda t: t is tasks[1], out=lines.append, clock=lambda: 0.0)
    p.walls = [10.0, 30.0]
    p.ended(tasks[0])
    p.ended(tasks[1])
    p.walls.append(20.0)
    p.show(2)
    # 5 runs left on 2 workers: 3 rounds of the median run (20 s)
    assert lines == ["study: 1 of 7 done, 1 failed, 2 running, ~60 s left"]
    assert p.show(2) is None  # nothing changed


def test_local_study_runs_every_row_with_its_inputs(local_study, cache):
    out, rows, lines = local_study
    assert [r["status"] for r in rows] == ["done"] * len(GRID), [(r["name"], r["status"], r["message"]) for r in rows]
    assert "study: 12 runs, 0 already done, 12 to run (local, 2 workers)" in lines
    assert lines[-1].startswith("study: 12 of 12 runs done; results in ")
    table = read_results(out)
    assert list(table) == [g["name"] for g in GRID]
    for g in GRID:
        r = table[g["name"]]
        m, h = float(g["boulder_mass"]), float(g["drop_height"])
        # the run got its row's inputs: its impact energy is the boulder's m g h
        assert math.isclose(float(r["impact_energy"]), m * G * h, rel_tol=1e-12), (g, r["impact_energy"])
        assert float(r["peak_deceleration"]) == pytest.approx(float(r["peak_impact_force"]) / m, rel=1e-12)
        for k in ("energy_flexFriction", "broken_lining_facets", "impact_steps", "energy_residual_max_fraction", "slab_force_max"):
            assert r[k] != "", k
        assert r["exit_status"] == "0" and os.path.exists(r["log"])
        summary = json.load(open(os.path.join(out, "runs", g["name"], "summary.json")))
        assert summary["filled_from_cache"] is True  # filled once before the runs, loaded by each
    # one distinct module, filled once
    assert len(os.listdir(os.path.join(out, "fills"))) == 1
    assert len([f for f in os.listdir(cache) if f.endswith(".yade.gz")]) == 1
    # more energy at the same mass goes deeper (the peak force of a few grains under the boulder
    # scatters between neighbouring inputs: 71 kN from 1.5 m, 70 kN from 2 m at 100 kg)
    for m in (80, 100, 150):
        v = [float(table[g["name"]]["penetration_max"]) for g in GRID if g["boulder_mass"] == str(m)]
        assert v == sorted(v), (m, v)
    for f in ("response.png", "energy_shares.png", "surface.png"):  # two inputs vary: the surface too
        assert os.path.getsize(os.path.join(out, f)) > 10000, f


def _same_as_local(local_study, out):
    local = read_results(local_study[0])
    got = read_results(out)
    assert list(got) == [g["name"] for g in SUBSET]
    for name, row in got.items():
        assert row["status"] == "done", row
        assert_same_run(row, local[name])


def test_mpi_backend_gives_the_local_results(local_study, cache, tmp_path):
    if importlib.util.find_spec("mpi4py") is None or shutil.which("mpirun") is None:
        pytest.skip("the mpi backend needs mpirun (Open MPI) and Debian's python3-mpi4py")
    out = str(tmp_path / "mpi")
    cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-n", "3", STUDY, write_study(tmp_path / "s.csv", SUBSET), out,
           "--backend", "mpi", "--cache-dir", cache]
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    assert res.returncode == 0, res.stdout[-3000:] + res.stderr[-3000:]
    assert "(mpi, 2 workers)" in res.stdout
    _same_as_local(local_study, out)


def test_slurm_backend_gives_the_local_results(local_study, cache, tmp_path, monkeypatch):
    why = unavailable()
    if why:
        pytest.skip(why)
    out = str(tmp_path / "slurm")
    with LocalSlurm(tmp_path / "slurm-cluster") as cluster:
        for k, v in cluster.env.items():
            monkeypatch.setenv(k, v)
        lines = []
        study.run_study(write_study(tmp_path / "s.csv", SUBSET), out, backend="slurm", cache_dir=cache,
                        slurm=study.Slurm(poll=1.0), progress=lines.append)
    assert any(line.startswith("study: Slurm job ") for line in lines), lines
    assert os.path.exists(os.path.join(out, "slurm", "yadeflex-study.sbatch"))
    _same_as_local(local_study, out)


def test_resume_keeps_the_runs_of_a_moved_study_with_another_cache(local_study, tmp_path):
    """--resume compared the runs' whole commands, absolute paths included: a study folder moved,
    or given another --cache-dir, ran everything again. It compares the job's options now."""
    import shutil
    moved = str(tmp_path / "moved")
    shutil.copytree(local_study[0], moved)
    lines = []
    rows = study.run_study(write_study(tmp_path / "grid.csv", GRID), moved, resume=True, cache_dir=str(tmp_path / "elsewhere"),
                           progress=lines.append)
    assert lines[0].startswith(f"study: {len(GRID)} runs, {len(GRID)} already done ("), lines
    assert all(r["status"] == "done" for r in rows) and not list((tmp_path / "elsewhere").glob("*.yade.gz"))  # nothing filled, nothing run


def test_killed_worker_loses_only_its_run_and_resume_completes_it(local_study, cache, tmp_path):
    rows = [dict(GRID[5]), dict(GRID[6], name="tight", max_residual="1e-4"), dict(GRID[7])]
    f = write_study(tmp_path / "k.csv", rows)
    out = str(tmp_path / "k")
    victim = rows[2]["name"]
    proc = subprocess.Popen([sys.executable, os.path.join(REPO, "scripts", "study.py"), f, out, "--workers", "2", "--cache-dir", cache],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    summary = os.path.join(out, "runs", victim, "summary.json")
    t0 = time.time()
    while not os.path.exists(summary):
        assert proc.poll() is None and time.time() - t0 < 300, "the victim's run never started"
        time.sleep(0.05)
    pid = json.load(open(summary))["pid"]  # the run's YADE process; its parent is the worker (study_task)
    with open(f"/proc/{pid}/stat") as fh:
        worker = int(fh.read().rsplit(")", 1)[1].split()[1])
    os.kill(worker, signal.SIGKILL)
    log, _ = proc.communicate(timeout=300)
    assert proc.returncode == study.EXIT_RUNS_FAILED, log
    table = read_results(out)
    assert table[rows[0]["name"]]["status"] == "done"
    assert table["tight"]["status"] == "residual" and table["tight"]["exit_status"] == "3"
    assert table["tight"]["message"].startswith("energy balance residual "), table["tight"]
    assert table[victim]["status"] == "crashed" and "killed with its worker" in table[victim]["message"], table[victim]
    assert json.load(open(summary))["status"] == "running"  # the run died with its worker
    kept = os.path.join(out, "runs", rows[0]["name"], study.STATUS_FILE)
    stamp = os.stat(kept).st_mtime_ns

    res = subprocess.run([STUDY, f, out, "--resume", "--workers", "2", "--cache-dir", cache], capture_output=True, text=True, timeout=300)
    assert res.returncode == study.EXIT_RUNS_FAILED, res.stdout + res.stderr  # (the tight row fails again)
    assert "study: 3 runs, 1 already done, 2 to run" in res.stdout
    assert os.stat(kept).st_mtime_ns == stamp  # the run done was not run again
    table = read_results(out)
    assert table["tight"]["status"] == "residual"
    local = read_results(local_study[0])
    for name in (rows[0]["name"], victim):
        assert_same_run(table[name], local[name])


def test_the_runs_of_a_study_are_not_pinned_to_one_cpu(tmp_path, monkeypatch):
    """With OMP_PROC_BIND=true in the environment (an HPC habit), OpenMP pins a one-thread YADE to
    the first CPU it may use, the same CPU for every run of a local pool. A study's run keeps every
    CPU of the study."""
    from yadeflex.module.study_task import run_task
    cpus = sorted(os.sched_getaffinity(0))
    if len(cpus) < 2:
        pytest.skip("one CPU: nothing to pin")
    monkeypatch.setenv("OMP_PROC_BIND", "true")
    script = tmp_path / "cpus.py"
    script.write_text("import os, sys\nopen(sys.argv[-1], 'w').write(repr(sorted(os.sched_getaffinity(0))))\n")
    plain = subprocess.run(["yade-double", "-n", "-j", "1", "-x", str(script), str(tmp_path / "plain.txt")], capture_output=True, text=True)
    assert plain.returncode == 0, plain.stderr[-2000:]
    if len(ast.literal_eval((tmp_path / "plain.txt").read_text())) != 1:
        pytest.skip("this OpenMP runtime does not pin a one-thread YADE at its start")  # (libgomp does)
    task = study.run_tasks([dict(name="r", argv=[], fill_key="k")], str(tmp_path), str(tmp_path / "cache"))[0]
    task["cmd"] = ["yade-double", "-n", "-j", "1", "-x", str(script), str(tmp_path / "run.txt")]  # the run's environment, this script
    assert run_task(task)["exit_status"] == 0
    assert ast.literal_eval((tmp_path / "run.txt").read_text()) == cpus


def test_more_workers_than_cpus_are_named_before_the_runs(tmp_path, cache, monkeypatch):
    """A local study on fewer CPUs than workers (a taskset, a cgroup, a YADE session pinned by
    OMP_PROC_BIND) says so in its first lines; by default it starts as many workers as CPUs."""
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0})
    monkeypatch.setattr(os, "cpu_count", lambda: 2)
    rows = [dict(name="r", boulder_mass="100", drop_height="0.5", **COMMON)]
    for workers, bind, warned in ((2, "true", "2 workers share the 1 CPU(s)"), (None, "true", "1 of the machine's 2 CPUs: one run at a time"),
                                  (None, "false", None), (1, "", None)):
        monkeypatch.setenv("OMP_PROC_BIND", bind)
        lines = []
        out = str(tmp_path / f"w{workers}{bind}")
        study.run_study(write_study(tmp_path / "one.csv", rows), out, backend="local", workers=workers, cache_dir=cache, progress=lines.append)
        assert lines[0].endswith(f"(local, {workers or 1} workers)")
        warning = [x for x in lines if "WARNING" in x]
        assert len(warning) == (1 if warned else 0), lines
        if warned:
            assert warned in warning[0] and ("OMP_PROC_BIND" in warning[0]) == (bind == "true"), warning


def test_a_run_past_its_timeout_is_stopped_and_recorded(tmp_path):
    from yadeflex.module.study_task import run_task
    folder = str(tmp_path / "run")
    t = dict(name="slow", cmd=["sleep", "30"], folder=folder, status=os.path.join(folder, study.STATUS_FILE), timeout=0.5)
    t0 = time.time()
    out = run_task(t)
    assert time.time() - t0 < 10 and out["timed_out"] and out["exit_status"] == -signal.SIGTERM
    status, outcome, _ = study.run_outcome(folder)
    assert status == "timeout" and outcome == out


def test_a_run_whose_fill_failed_is_recorded_without_running(tmp_path):
    from yadeflex.module.study_task import run_task
    fill = dict(name="fill-x", cmd=["sh", "-c", "echo 'RuntimeError: the fill did not settle'; exit 1"], folder=str(tmp_path / "fill"),
                status=str(tmp_path / "fill" / study.STATUS_FILE))
    assert run_task(fill)["exit_status"] == 1
    folder = str(tmp_path / "run")
    out = run_task(dict(name="r", cmd=["touch", str(tmp_path / "ran")], folder=folder, status=os.path.join(folder, study.STATUS_FILE),
                        after=fill["status"]))
    assert not (tmp_path / "ran").exists()
    assert out["skipped"] == f"not run: fill-x failed (RuntimeError: the fill did not settle; log {tmp_path}/fill/log.txt)"
    row = study.result_row(dict(name="r", row=1, inputs={}), folder)
    assert (row["status"], row["exit_status"], row["message"], row["log"]) == ("failed", 1, out["skipped"], f"{tmp_path}/fill/log.txt")


def test_slurm_job_scripts_run_the_setup_lines_first(tmp_path):
    """Clusters load their software with `module load` lines: --sbatch-setup puts them in every
    job script (the fills' and the runs'), before the run; a line break inside one is refused."""
    s = study.Slurm(time_limit="1:00:00", setup=["module load yade", "source /opt/env.sh"])
    lines = s.script(str(tmp_path / "tasks.json"), 3, str(tmp_path), "x").splitlines()
    exec_at = next(k for k, ln in enumerate(lines) if ln.startswith("exec "))
    assert lines.index("module load yade") < lines.index("source /opt/env.sh") < exec_at
    assert "#SBATCH --time=1:00:00" in lines
    with pytest.raises(study.StudyError, match="line break"):
        study.Slurm(setup=["module load yade\nrm -rf /"])


def test_the_coordinator_prints_only_its_own_lines(tmp_path):
    """YADE's import printed 'Using python version ...' into the coordinator's output."""
    path = tmp_path / "s.csv"
    path.write_text("name,small,repeat\nx,yes,0\n")
    r = subprocess.run([STUDY, str(path), str(tmp_path / "out")], capture_output=True, text=True, timeout=300)
    assert r.returncode == study.EXIT_BAD_STUDY and r.stdout == "", r.stdout
    assert r.stderr.strip().splitlines() == ["study: row 1 (line 2), column repeat: got '0'; allowed a whole number in [1, 1000] (a fill each)"], r.stderr


def _in_contact(series):
    """Whether a run's timeseries.csv has a row with a force on the boulder (above 1 N)."""
    try:
        with open(series) as fh:
            rows = list(csv.DictReader(fh))
    except OSError:
        return False
    return any(float(v) > 1.0 for r in rows for k, v in r.items() if k and k.startswith("impact_force") and v)


def _alive(pid):
    try:
        with open(f"/proc/{pid}/stat") as fh:
            return fh.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


# One Ctrl-C (SIGINT to the study's process group, as a terminal sends it) or a SIGTERM to the
# coordinator alone: the queued rows never start, the running row stops with its partial
# results (interrupted), results.csv lists every row, the study exits 130 / 143 and no run is
# left behind.
@pytest.mark.parametrize("sig,to_group", [(signal.SIGINT, True), (signal.SIGTERM, False)], ids=["ctrl-c", "sigterm"])
def test_a_signal_cancels_the_queue_and_records_every_row(local_study, cache, tmp_path, sig, to_group):
    rows = [dict(GRID[k], duration="0.2") for k in (0, 1, 2)]
    f = write_study(tmp_path / "s.csv", rows)
    out = str(tmp_path / "s")
    # (as from a terminal: SIGINT at its default, whatever this suite inherited; a suite started
    # in the background of a script has it ignored, and a study started so keeps ignoring it)
    proc = subprocess.Popen([sys.executable, os.path.join(REPO, "scripts", "study.py"), f, out, "--workers", "1", "--cache-dir", cache],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    first = os.path.join(out, "runs", rows[0]["name"], "summary.json")
    series = os.path.join(out, "runs", rows[0]["name"], "timeseries.csv")
    t0 = time.time()
    # until the boulder of the first run is in contact (a recorded force): its partial results
    # then hold a peak, however long the machine takes to get there
    while not (os.path.exists(first) and (json.load(open(first)) or {}).get("stage") == "impact" and _in_contact(series)):
        assert proc.poll() is None and time.time() - t0 < 300, "the first run never reached its impact"
        time.sleep(0.05)
    pid = json.load(open(first))["pid"]
    if to_group:
        os.killpg(proc.pid, sig)
    else:
        os.kill(proc.pid, sig)
    log, _ = proc.communicate(timeout=120)
    assert proc.returncode == 128 + sig, log
    assert "Traceback" not in log, log
    assert not _alive(pid), "the run outlived the study"
    table = read_results(out)
    assert [table[r["name"]]["status"] for r in rows] == ["interrupted", "cancelled", "cancelled"], table
    assert table[rows[0]["name"]]["peak_impact_force"], "the stopped row keeps its partial results"
    assert table[rows[1]["name"]]["message"] == f"not run: the study was stopped by {sig.name}"
    assert not os.path.exists(os.path.join(out, "runs", rows[2]["name"], study.STATUS_FILE))
    assert f"study: stopped by {sig.name}:" in log


def test_a_task_stopped_before_its_run_wrote_results_says_so(tmp_path):
    """A row stopped while YADE starts (no summary yet) is recorded as interrupted, naming the
    signal, not as a crash with only a log."""
    folder = str(tmp_path / "run")
    tasks = tmp_path / "tasks.json"
    tasks.write_text(json.dumps([dict(name="r", cmd=["sleep", "30"], folder=folder, status=os.path.join(folder, study.STATUS_FILE))]))
    p = subprocess.Popen([sys.executable, os.path.join(REPO, "py", "yadeflex", "module", "study_task.py"), str(tasks), "0"])
    children = f"/proc/{p.pid}/task/{p.pid}/children"
    t0 = time.time()
    while not open(children).read().strip():  # until the task has started its process
        assert time.time() - t0 < 30
        time.sleep(0.02)
    p.send_signal(signal.SIGTERM)
    assert p.wait(timeout=60) == 128 + signal.SIGTERM
    row = study.result_row(dict(name="r", row=1, inputs={}), folder)
    assert row["status"] == "interrupted" and row["message"] == "stopped by SIGTERM before the run wrote its results", row
