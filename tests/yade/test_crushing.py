"""The grain-crushing screen (yadeflex.crushing): the point-load failure load against its
definition (ISRM 1985), the per-grain peak forces against hand-made contact lists, and the scene's
contact forces against a column of spheres at rest (each contact carries the weight above it)."""
import math

import numpy as np
import pytest
from yade import O

import yadeflex as yf
import yadeflex.harness.scenes as S
from yadeflex.harness import cases
from yadeflex import crushing as K


def test_failure_load_is_the_point_load_index_times_the_size_squared_with_isrm_size_correction():
    # at the reference size 50 mm the correction is 1: P = Is50 D^2
    assert K.failure_load(0.05, 4e6) == pytest.approx(4e6 * 0.05 ** 2, rel=1e-15)
    # P ~ D^(2 - 0.45): twice the size, 2^1.55 the load
    assert K.failure_load(0.1, 4e6) / K.failure_load(0.05, 4e6) == pytest.approx(2 ** 1.55, rel=1e-14)
    # Is = P / D^2 and Is50 = (D / 50 mm)^0.45 Is, by hand for D = 32 mm
    d = 0.032
    assert (0.032 / 0.05) ** 0.45 * K.failure_load(d, 1.5e6) / d ** 2 == pytest.approx(1.5e6, rel=1e-14)
    np.testing.assert_allclose(K.failure_load([0.05, 0.1], 1e6), [2.5e3, 2.5e3 * 2 ** 1.55], rtol=1e-14)


@pytest.mark.parametrize("d, is50", [(0.0, 1e6), (-0.01, 1e6), (math.nan, 1e6), (0.05, 0.0), (0.05, -1e6), (0.05, math.inf)])
def test_failure_load_refuses_sizes_and_strengths_that_are_not_positive_numbers(d, is50):
    with pytest.raises(ValueError, match="diameter|is50"):
        K.failure_load(d, is50)


def test_peak_grain_forces_keeps_each_grains_largest_contact_force_and_when_it_broke():
    # grains 5, 7, 9 of 50 mm: failure loads 2.5 kN at 1 MPa and 10 kN at 4 MPa
    s = K.PeakGrainForces([5, 7, 9], [0.05] * 3, [1e6, 4e6])
    # contacts: 5-7, 7-100 (100: the boulder, not a grain), 0-9 (0: not a grain), 1-2 (no grain)
    s.update([5, 7, 0, 1], [7, 100, 9, 2], [1e3, 3e3, 2e3, 9e4], 0.01)
    np.testing.assert_array_equal(s.peak, [1e3, 3e3, 2e3])
    np.testing.assert_array_equal(s.broken(0), [False, True, False])
    s.update([9, 5], [5, 7], [-12e3, 500.0], 0.03)  # (a negative sign is a direction: the magnitude counts)
    np.testing.assert_array_equal(s.peak, [12e3, 3e3, 12e3])
    np.testing.assert_array_equal(s.first[0], [0.03, 0.01, 0.03])  # each at its first reaching, not again
    np.testing.assert_array_equal(s.first[1], [0.03, np.nan, 0.03])
    s.update([], [], [], 0.05)  # no contacts: nothing changes
    np.testing.assert_array_equal(s.peak, [12e3, 3e3, 12e3])


def test_peak_grain_forces_refuses_bad_input():
    with pytest.raises(ValueError, match="grains and diameters"):
        K.PeakGrainForces([1, 2], [0.05], [1e6])
    with pytest.raises(ValueError, match="distinct"):
        K.PeakGrainForces([1, 1], [0.05, 0.05], [1e6])
    with pytest.raises(ValueError, match="diameter"):
        K.PeakGrainForces([1], [0.0], [1e6])
    with pytest.raises(ValueError, match="strength"):
        K.PeakGrainForces([1], [0.05], [0.0])
    s = K.PeakGrainForces([1], [0.05], [1e6])
    with pytest.raises(ValueError, match="finite"):
        s.update([1], [2], [math.nan], 0.0)
    with pytest.raises(ValueError, match="2 ids for 1 forces"):
        s.update([1, 2], [2, 3], [1.0], 0.0)


def test_scene_contacts_of_a_column_at_rest_carry_the_weight_above_them(scene):
    """Three free spheres stacked on a fixed one, at rest: the contact under the k-th sphere from
    the top carries k weights, so the grains' largest contact forces are 3, 2 and 1 weights."""
    R, rho, g = 0.02, 2500.0, 9.81
    ids = [S.sphere((0, 0, 2 * R * k), R, density=rho, young=1e8) for k in range(4)]
    O.bodies[ids[0]].state.blockedDOFs = "xyzXYZ"
    for i in ids[1:]:
        O.bodies[i].state.blockedDOFs = "xyXYZ"  # a column that cannot buckle
    O.engines = yf.engines(gravity=(0, 0, -g), damping=0.8)
    yf.step_until(math.inf, 20000)
    assert max(abs(O.bodies[i].state.vel[2]) for i in ids) < 1e-9
    w = rho * 4 / 3 * math.pi * R ** 3 * g
    id1, id2, fn = K.scene_contacts()
    assert len(fn) == 3
    s = K.PeakGrainForces(ids[1:], [2 * R] * 3, [1e6])
    s.update(id1, id2, fn, 0.0)
    np.testing.assert_allclose(s.peak, [3 * w, 2 * w, w], rtol=1e-9)


def test_the_study_report_counts_the_grains_of_each_strength_and_fills_its_table(tmp_path):
    """validation/grain_crushing.py's report from hand-made cases: the counts per strength, those
    reached in the second half of the penetration, and the table written between the README's
    markers."""
    import json
    import os
    import sys
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "validation"))
    import grain_crushing as G
    os.makedirs(tmp_path / "cases")
    series = [dict(t=1e-3 * k, penetration=0.01 * k, force=1e4 * k, grain_force_max=100.0 * k, broken=[k, 0, 0]) for k in range(1, 11)]
    broken = [dict(is50=s, count=n, under_boulder=n, load_ratio_max=r, first_penetration=p[0] if p else None,
                   depth_below_boulder=[0.01] * n, penetrations=p)
              for s, n, r, p in ((1.5e6, 3, 2.0, [0.02, 0.05, 0.09]), (4e6, 1, 1.1, [0.06]), (10e6, 0, 0.45, []))]
    case = dict(name="H2", mass=800.0, height=2.0, seed=1, crushing_is50=0.0, impact_energy=15696.0, crushing_energy=0.0, grains=100, deepest=dict(penetration=0.1, force=9e4), stopped=True,
                peak_force=1e5, grain_force_max=1e3, grain_force_p99=800.0, broken=broken, series=series)
    with open(tmp_path / "cases" / "H2.json", "w") as f:
        json.dump(case, f)
    (tmp_path / "README.md").write_text(f"before\n{G.MARK[0]}\nold\n{G.MARK[1]}\nafter\n")
    rows = G.write(str(tmp_path), G.load(str(tmp_path)))
    r = rows[0]
    # second half: reached at 0.05 m of penetration or deeper, of 0.1 m
    assert (r["broken_1.5MPa"], r["broken_second_half_1.5MPa"], r["broken_4MPa"], r["broken_second_half_4MPa"]) == (3, 2, 1, 1)
    assert (r["first_break_penetration_mm_1.5MPa"], r["first_break_penetration_mm_10MPa"]) == (pytest.approx(20.0), None)
    text = (tmp_path / "README.md").read_text()
    assert text.startswith("before\n") and text.endswith("after\n") and "old" not in text
    assert "| H2 | 800 | 2 | 1 | 100 | 100 | 1.0 (0.8) | 3 (3, 2) | 1 (1, 1) | 0 (0, 0) | 20 | 60 | - | 0.45 |" in text
    assert (tmp_path / "summary.csv").is_file() and (tmp_path / "crushing.png").stat().st_size > 0
    # the crushing model's summary: one elastic run of five, no exponent from one point
    m = G.model_rows(G.load(str(tmp_path)))[0]
    assert (m["crushing_is50_MPa"], m["fill_seed"], m["runs"], m["peak_kN_H2"], m["peak_height_exp"]) == (0.0, 1, 1, 100.0, None)
    assert not (tmp_path / "crushing_section.png").exists()  # no case of the section plot
    # the section plot of a run that has its grains' state: two 50 mm grains in the plane, one at its failure load
    P = K.failure_load(0.05, 1.5e6)
    with open(tmp_path / "cases" / "H1.json", "w") as f:
        json.dump(dict(case, name="H1", height=1.0, grain_state=dict(pos=[[0, 0, 0.1], [0.1, 0.5, 0.1]], d=[0.05, 0.05], peak=[P, 0.5 * P]),
                       boulder=dict(center=[0, 0, 0.5], size=0.69)), f)
    G.write(str(tmp_path), G.load(str(tmp_path)))
    assert (tmp_path / "crushing_section.png").stat().st_size > 0


def test_crushing_contact_rebounds_with_the_elastic_plastic_restitution(scene):
    """A sphere hits a fixed larger sphere, frictionless, with crushing on (yadeflex.harness.cases.
    crushing_bounce): the normal force stops at the smaller sphere's failure load P; unloading is
    elastic from there, so the rebound carries P^2 / (2 kn) and the speed is P / sqrt(m kn)
    (restitution P / (v0 sqrt(m kn)), the elastic peak force's share); the rest is booked as
    'flexCrushing'. To the leap-frog's error at a twentieth of the critical step (7e-5 and 1e-3
    here; at half the critical step 6% and 9%)."""
    r = cases.crushing_bounce()
    assert r["peak_over_limit"] == pytest.approx(1.0, rel=1e-12)
    assert r["measured"] == pytest.approx(r["reference"], rel=2e-3)
    assert r["crushing_over_loss"] == pytest.approx(1.0, rel=3e-3)


def test_engines_refuse_a_crushing_index_that_is_not_a_rock_strength_in_pa(scene):
    for bad in (-1.0, math.nan, math.inf, 1.5):  # (1.5: MPa given for Pa)
        with pytest.raises(ValueError, match="crushing_is50"):
            yf.engines(crushing_is50=bad)
    with pytest.raises(ValueError, match="crushing_is50: .*flex_sphere_contacts"):
        yf.engines(crushing_is50=4e6, flex_sphere_contacts=False)


def _bounce(is50, stop=None):
    """The trajectory (position, velocity, angular velocity per step) of a 20 mm sphere thrown at a
    fixed 40 mm one, with friction and gravity, crushing at is50 (0: off), and whether they
    touched; stop(interaction) ends it early."""
    a = S.sphere((0, 0, 0), 0.04, young=1e8, friction_deg=30.0)
    b = S.sphere((0, 0, 0.0601), 0.02, young=1e8, friction_deg=30.0, velocity=(0.3, 0, -2.0))
    O.bodies[a].state.blockedDOFs = "xyzXYZ"
    O.engines = yf.engines(gravity=(0, 0, -9.81), crushing_is50=is50, timestep_safety=0.05)
    out, touched = [], False
    for _ in range(300):
        yf.step_until(math.inf, 1)
        out.append((tuple(O.bodies[b].state.pos), tuple(O.bodies[b].state.vel), tuple(O.bodies[b].state.angVel)))
        i = O.interactions[a, b] if O.interactions.has(a, b) else None
        touched = touched or bool(i and i.isReal and i.phys.normalForce.norm() > 0)
        if stop and i and i.isReal and stop(i):
            break
    return out, touched


def test_crushing_that_is_never_reached_changes_nothing(scene):
    """A rock strength far above the contact's force: the same trajectory to the last bit as
    without crushing (the law's arithmetic is the same until a contact yields)."""
    off, touched = _bounce(0.0)
    assert touched
    O.reset()
    assert _bounce(1e9) == (off, True)


def test_plastic_overlap_is_kept_when_the_scene_is_saved(scene, tmp_path):
    """The yielded overlap is part of the contact's state: saved and loaded with the scene, the
    run goes on as it would have."""
    _bounce(1e5, stop=lambda i: i.geom.plasticOverlap > 0)  # a weak rock: the contact yields
    i = next(i for i in O.interactions if i.isReal)
    assert i.geom.plasticOverlap > 0 and i.geom.penetrationDepth > i.geom.plasticOverlap
    ids, saved = (i.id1, i.id2), i.geom.plasticOverlap
    O.saveTmp("crushing")
    O.step()
    after = (tuple(O.bodies[ids[1]].state.vel), O.interactions[ids].geom.plasticOverlap)
    assert after[1] > saved  # still yielding: the next step needs the saved value
    O.loadTmp("crushing")
    assert O.interactions[ids].geom.plasticOverlap == saved
    O.step()
    assert (tuple(O.bodies[ids[1]].state.vel), O.interactions[ids].geom.plasticOverlap) == after


def test_vtk_contacts_show_the_crushed_overlap(scene, tmp_path):
    """The contacts' VTK file carries each contact's plasticOverlap: the crushed contact's own
    value, 0 where nothing crushed."""
    from test_output import _cd, _read
    _bounce(1e5, stop=lambda i: i.geom.plasticOverlap > 0)
    files = yf.VtkRecorder(str(tmp_path))()
    g = _read(files["contacts"])
    inters = yf.output.real_contacts()
    assert g.GetNumberOfCells() == len(inters) == 1
    assert _cd(g, "plasticOverlap")[0] == inters[0].geom.plasticOverlap > 0
    O.reset()
    _bounce(0.0, stop=lambda i: i.phys.normalForce.norm() > 0)
    g = _read(yf.VtkRecorder(str(tmp_path / "off"))()["contacts"])
    assert list(_cd(g, "plasticOverlap")) == [0.0]
