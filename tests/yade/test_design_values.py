"""Design values with their scatter: the characteristic value against EN 1990's table, a study of
configurations on several seeds (scripts/study --report: results.csv with units, each
configuration's statistics recomputed from its runs, the design formulas by hand, energy shares
that close, the report), and the main job's --seeds."""
import json
import math
import os
import statistics
import subprocess

import pytest

from conftest import REPO, run_yade
from tol import G

from yadeflex import scatter
from yadeflex.module import cushion, study
from yadeflex.module import study_results as SR

STUDY = os.path.join(REPO, "scripts", "study")
MAIN = os.path.join(REPO, "scripts", "damping_module.py")
# EN 1990:2002 Annex D, table D1, k_n for the 5% fractile, "V_X unknown"
EN1990_KN = {2: 7.73, 3: 3.37, 4: 2.63, 5: 2.33, 6: 2.18, 8: 2.00, 10: 1.92, 30: 1.73}


def test_k_n_is_en1990s_table_d1():
    for n, k in EN1990_KN.items():  # (the table gives two decimals, some rounded, some cut)
        assert abs(scatter.k_n(n) - k) < 0.01, n
    # the table's n = 20 entry, 1.76, lies 0.012 below the Student-t formula it rests on (D.7.2): 1.772
    assert scatter.k_n(20) == pytest.approx(1.7718, abs=1e-4)
    assert scatter.k_n(100000) == pytest.approx(1.6449, abs=1e-3)  # the normal 95% quantile
    with pytest.raises(ValueError, match="n must be a whole number >= 2"):
        scatter.k_n(1)


def test_describe_gives_the_sample_statistics_and_leaves_out_runs_without_a_value():
    d = scatter.describe([1.0, 2.0, 3.0, 4.0, 5.0, None, math.nan])
    assert (d["n"], d["mean"], d["min"], d["max"]) == (5, 3.0, 1.0, 5.0)
    assert d["std"] == pytest.approx(math.sqrt(2.5), rel=1e-15)
    assert d["characteristic"] == pytest.approx(3.0 + scatter.k_n(5) * math.sqrt(2.5), rel=1e-15)
    one = scatter.describe([7.0])
    assert one["mean"] == 7.0 and one["std"] is None and one["characteristic"] is None
    assert scatter.describe([])["mean"] is None


def test_seeds_and_repeat_are_one_column(tmp_path):
    path = tmp_path / "s.csv"
    path.write_text("name,small,seed,seeds\nx,yes,5,3\n")
    runs = study.read_study(str(path))
    assert [(r["name"], r["configuration"], r["params"]["seed"]) for r in runs] == [("x-s5", "x", 5), ("x-s6", "x", 6), ("x-s7", "x", 7)]
    path.write_text("name,small,seeds,repeat\nx,yes,3,3\n")
    with pytest.raises(study.StudyError, match="seeds and repeat are one option"):
        study.read_study(str(path))


def _labiouse_by_hand(mass, density, height, fill):
    """Labiouse et al. (1996) in its own units: F = 1.765 M_E^0.4 R^0.2 (W H)^0.6 [kN], M_E [kN/m2],
    W [kN], R [m]; M_E of the fill's plate-load test (validation/calibration)."""
    with open(os.path.join(REPO, "validation", "calibration", "summary.json")) as fh:
        m_e = json.load(fh)[fill][f"plate_test_{cushion.PLATE_RANGE}"][0] / 1e3
    r = (3 * mass / density / (4 * math.pi)) ** (1 / 3)
    return 1e3 * 1.765 * m_e ** 0.4 * r ** 0.2 * (mass * G / 1e3 * height) ** 0.6


@pytest.fixture(scope="module")
def seeded_study(tmp_path_factory):
    """Two configurations on two seeds each, from the command line to the report."""
    base = tmp_path_factory.mktemp("design")
    path = base / "study.csv"
    path.write_text("name,small,no_vtk,drop_height,seeds\nlow,yes,yes,0.5,2\nhigh,yes,yes,1.5,2\n")
    out = base / "out"
    r = subprocess.run([STUDY, str(path), str(out), "--workers", "2", "--cache-dir", str(base / "cache"), "--report"],
                       capture_output=True, text=True, timeout=1800)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    return str(out), r.stdout


def test_a_seeded_study_gives_each_configurations_scatter(seeded_study):
    out, stdout = seeded_study
    with open(os.path.join(out, "results.csv")) as fh:
        head = fh.readline().strip().split(",")
    for h in ("peak_impact_force[N]", "peak_impact_force_filtered[N]", "penetration_max[m]", "boulder_mass[kg]", "drop_height[m]",
              "grain_min[m]", "formula_labiouse_1996[N]", "energy_flexFriction[J]", "fill"):
        assert h in head, h
    rows = study.read_results(os.path.join(out, "results.csv"))
    assert [(r["name"], r["configuration"], r["seed"]) for r in rows] == [
        ("low-s1", "low", "1"), ("low-s2", "low", "2"), ("high-s1", "high", "1"), ("high-s2", "high", "2")]
    assert all(r["status"] == "done" for r in rows)
    confs = {c["configuration"]: c for c in SR.read_table(os.path.join(out, "configurations.csv"))}
    assert list(confs) == ["low", "high"]
    for name, c in confs.items():
        mine = [r for r in rows if r["configuration"] == name]
        assert c["n_done"] == "2"
        for key in ("peak_impact_force_filtered", "slab_force_max", "penetration_max", "impact_duration"):
            v = [float(r[key]) for r in mine]
            assert float(c[f"{key}_mean"]) == pytest.approx(statistics.mean(v), rel=1e-12), key
            assert float(c[f"{key}_std"]) == pytest.approx(statistics.stdev(v), rel=1e-9), key
            assert float(c[f"{key}_characteristic"]) == pytest.approx(statistics.mean(v) + scatter.k_n(2) * statistics.stdev(v), rel=1e-9), key
        # Labiouse's formula by hand from the fill's plate-load modulus, 100 kg cube of 2400 kg/m3
        h = float(mine[0]["drop_height"])
        assert float(c["formula_labiouse_1996"]) == pytest.approx(_labiouse_by_hand(100.0, 2400.0, h, "gravel"), rel=1e-12)
    assert "study: low: peak force " in stdout and "characteristic peak force" in stdout
    with open(os.path.join(out, "summary.json")) as fh:
        s = json.load(fh)
    assert s["characteristic_value"] == scatter.CHARACTERISTIC and [c["seeds"] for c in s["configurations"]] == [[1, 2], [1, 2]]


def test_the_energy_shares_close_on_the_energy_brought_in(seeded_study):
    """Every term but gravity's work, over the impact energy plus gravity's work on the boulder
    after its first contact, sums to 1 within the balance residual and gravity's work on the grains
    and the mesh as they sink under the boulder (a few mm: below 1% of the energy here)."""
    rows = study.read_results(os.path.join(seeded_study[0], "results.csv"))
    for r in rows:
        terms = sum(float(v) for k, v in r.items() if k.startswith("energy_") and k not in ("energy_gravWork", "energy_residual_max_fraction",
                                                                                              "energy_absorbed") and v)
        brought_in = float(r["impact_energy"]) + float(r["gravity_work_after_contact"])
        assert abs(terms / brought_in - 1.0) < 0.01 + float(r["energy_residual_max_fraction"]), (r["name"], terms, brought_in)


def test_the_report_holds_the_tables_and_the_pictures(seeded_study):
    out, stdout = seeded_study
    path = os.path.join(out, "report.html")
    assert f"study: report {path}" in stdout
    text = open(path).read()
    for what in ("Design values", "Inputs", "Results with their scatter", "Against the design formulas", "Load on the slab",
                 "Broken elements", "Warnings", "Fixed parameters", "Labiouse", "EN 1990", "low", "high", "60-80 mm"):
        assert what in text, what
    assert text.count("data:image/png;base64,") >= 2  # response.png, energy_shares.png inside the page
    r = subprocess.run([os.path.join(REPO, "scripts", "report"), os.path.join(out, "nothing")], capture_output=True, text=True, timeout=300)
    assert r.returncode == 1 and "holds no finished study" in r.stderr


def test_the_main_job_runs_a_configuration_on_several_seeds(tmp_path):
    out = tmp_path / "seeds"
    stdout = run_yade(MAIN, args=["--small", "--no-vtk", "--seeds", "2", "--duration", "0.02", "--out", out,
                                  "--cache-dir", tmp_path / "cache"], timeout=1200)
    assert "=== fill 2 of 2: seed 2" in stdout and "over 2 fill(s): peak force" in stdout
    for f in ("seed1/summary.json", "seed2/summary.json", "configurations.csv", "summary.json", "scatter.png"):
        assert os.path.exists(out / f), f
    c = SR.read_table(str(out / "configurations.csv"))[0]
    peaks = [json.load(open(out / f"seed{k}" / "summary.json"))["peak_impact_force"] for k in (1, 2)]
    assert float(c["peak_impact_force_mean"]) == pytest.approx(sum(peaks) / 2, rel=1e-12)
    with pytest.raises(RuntimeError, match=r"bad option --seeds: got '0'; allowed a whole number in \[1, 1000\]"):
        run_yade(MAIN, args=["--small", "--seeds", "0", "--out", tmp_path / "x"])
