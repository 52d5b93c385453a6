"""Chain-link wire law in YADE: single wire displacement-controlled (knots, rupture, cycle,
energy), named state, bad curves, stochastic slack (distribution, reproducibility, -j1 = -j2)."""
import math
import os

import pytest
from yade import O, Vector3
from yade.wrapper import FlexElementEngine

import yadeflex as yf
from yadeflex import wire
from yadeflex.harness import tensile
from conftest import run_yade, HERE
from tol import assert_rel

E_KNOTS = list(wire.TECCO_WIRE_STRAIN)
S_KNOTS = list(wire.TECCO_WIRE_STRESS)
R = 0.0015  # [m] wire radius (d = 3 mm)
A = math.pi * R ** 2
EW = S_KNOTS[0] / E_KNOTS[0]  # elastic (unloading) modulus of the curve [Pa]
KNOT_TOL = 1e-3  # issue 4: force at every knot within 0.1%
CYCLE_ENERGY_TOL = 1e-2  # issue 4: dissipated energy = area of the cycle within 1%


def element_engine():
    return next(e for e in O.engines if isinstance(e, FlexElementEngine))


def straight_wire():
    return wire.wire_material(E_KNOTS, S_KNOTS, slack_scale=0.0)


def test_single_wire_passes_every_knot_and_ruptures_past_the_last(scene):
    mat = straight_wire()
    r = tensile.wire_through_knots(mat, length=0.1, radius=R)
    s, e, f = r["scene"], r["strain"], r["force"]
    assert r["worst"] <= KNOT_TOL, f"force at the knots: worst relative error {r['worst']:.3e}"
    c = O.bodies[s["cylinders"][0]]
    assert c is not None and element_engine().nRuptured == 0, "no rupture at the last point itself"
    # energy: the work done on the wire (trapezoids over the record, O(h)) is what it stores
    # plus what it dissipated
    es, fs = [0.0] + e, [0.0] + f
    work = sum(0.5 * (fs[k] + fs[k - 1]) * (es[k] - es[k - 1]) * 0.1 for k in range(1, len(es)))
    assert_rel(O.energy["flexBondPlastic"] + c.shape.elasticEnergy, work, 1e-3, "work = elastic + dissipated")
    # the input curve is never overwritten
    assert list(mat.wireStrain) == E_KNOTS and list(mat.wireStress) == S_KNOTS
    assert c.shape.maxStrain == pytest.approx(E_KNOTS[-1], rel=1e-12)
    # past the last point: ruptured, counted, erased, its elastic energy booked
    tensile.drive_strains(s, [E_KNOTS[-1] * 1.01], steps_per_unit_strain=4e4)
    assert O.bodies[s["cylinders"][0]] is None
    assert element_engine().nRuptured == 1
    u_last = 0.5 * (S_KNOTS[-1] * A) ** 2 * 0.1 / (EW * A)
    assert_rel(O.energy["flexRupture"], u_last, 1e-9, "rupture energy = elastic energy at the last point")


def test_unload_reload_cycle_follows_elastic_slope_and_dissipates_the_loop_area(scene):
    L = 0.1
    s = tensile.single_wire(straight_wire(), length=L, radius=R)
    O.trackEnergy = True
    eA = 0.015  # between knots 1 and 2
    e1, f1, _ = tensile.drive_strains(s, [eA], steps_per_unit_strain=2e5)
    fA = f1[-1]
    c = O.bodies[s["cylinders"][0]].shape
    ep = eA - fA / (EW * A)
    assert_rel(c.plasticStrain, ep, 1e-9, "plastic strain after loading")
    # unload to below the plastic strain (slack wire), then reload past eA to the next knot
    e2, f2, _ = tensile.drive_strains(s, [ep - 0.002], steps_per_unit_strain=2e5)
    dissipated_cycle = O.energy["flexBondPlastic"]
    # elastic slope on unloading: two points on the unloading line above zero force
    k1 = next(i for i in range(len(e2)) if e2[i] <= eA - 0.001)
    k2 = next(i for i in range(len(e2)) if e2[i] <= eA - 0.004)
    assert_rel((f2[k1] - f2[k2]) / ((e2[k1] - e2[k2]) * L), EW * A / L, 1e-6, "unloading stiffness EA/L0")
    assert f2[-1] == 0.0, "tension only: no force once the wire is slack"
    e3, f3, _ = tensile.drive_strains(s, [eA], steps_per_unit_strain=2e5)
    assert_rel(f3[-1], fA, 1e-9, "reloading returns to the curve where it left it")
    assert O.energy["flexBondPlastic"] == dissipated_cycle, "elastic reloading dissipates nothing"
    e4, f4, _ = tensile.drive_strains(s, [E_KNOTS[2]], steps_per_unit_strain=2e5)
    assert O.energy["flexBondPlastic"] > dissipated_cycle, "plastic again past the previous maximum"
    assert_rel(f4[-1], S_KNOTS[2] * A, KNOT_TOL, "back on the curve at the next knot")
    # the closed loop 0 -> eA -> (unload) -> slack: its area from the recorded curve
    es = [0.0] + e1 + e2
    fs = [0.0] + f1 + f2
    area = sum(0.5 * (fs[k] + fs[k - 1]) * (es[k] - es[k - 1]) * L for k in range(1, len(es)))
    assert area > 0
    assert_rel(dissipated_cycle, area, CYCLE_ENERGY_TOL, "booked dissipation vs area of the cycle")


def _bent_chain(bending_factor):
    """Two wire links A-B-C along x, A and C clamped; B pushed 2 mm sideways and held there."""
    O.reset()
    mat = wire.wire_material(E_KNOTS, S_KNOTS, slack_scale=0.0, bending_factor=bending_factor)
    nodes, cyls = yf.chain([(0, 0, 0), (0.1, 0, 0)], R, mat, segments=2, fixed=[0, 2])
    O.engines = yf.engines(gravity=(0, 0, 0), damping=0.0)
    O.step()
    mid = O.bodies[nodes[1]]
    mid.state.blockedDOFs = "xyzXYZ"
    mid.state.vel = mid.state.angVel = Vector3(0, 0, 0)
    mid.state.pos = Vector3(0.05, 0.002, 0)
    O.step()
    return nodes, cyls


def test_bar_links_carry_axial_forces_along_the_chords_and_no_moment(scene):
    # bending_factor 0: bar links (axial only, as WirePM's); the knot is a hinge
    nodes, cyls = _bent_chain(0.0)
    x = [O.bodies[i].state.pos for i in nodes]
    n0, n1 = (O.bodies[c].shape.axialForce for c in cyls)
    L = [(x[1] - x[0]).norm(), (x[2] - x[1]).norm()]
    strain = (L[0] - 0.05) / 0.05
    assert strain > 0 and strain < E_KNOTS[0]  # elastic, tension
    assert_rel(n0, EW * A * strain, 1e-9, "axial force = EA x strain")
    # the force on the middle node: the two axial forces along the chords, nothing else
    expected = -n0 * (x[1] - x[0]) / L[0] + n1 * (x[2] - x[1]) / L[1]
    f = O.forces.f(nodes[1])
    assert (f - expected).norm() <= 1e-12 * n0, (f, expected)
    assert sum((O.forces.f(i) for i in nodes), Vector3(0, 0, 0)).norm() <= 1e-12 * n0, "the links' forces balance"
    assert all(O.forces.t(i) == Vector3(0, 0, 0) for i in nodes), "a bar puts no moment on its nodes"
    # the same chain with bending: the beams do load the clamped ends with moments
    nodes, cyls = _bent_chain(1.0)
    assert O.forces.t(nodes[0]).norm() > 0.1, "a bent beam chain carries moments (> 0.1 N m here)"


@pytest.mark.parametrize("strain,stress,message", [
    ([0.01], [1e9], "at least two points"),
    ([0.01, 0.01], [1e9, 1.1e9], "strain must increase strictly"),
    ([0.02, 0.01], [1e9, 1.1e9], "strain must increase strictly"),
    ([-0.01, 0.02], [1e9, 1.1e9], "strain of point 0 must be positive"),
    ([0.01, 0.02], [1e9, -5.0], "stress of point 1 must be positive"),
    ([0.01, 0.02], [1e9], "2 strains but 1 stresses"),
])
def test_bad_curves_raise_value_error_naming_the_problem(scene, strain, stress, message):
    with pytest.raises(ValueError, match=message):
        wire.wire_material(strain, stress)


def test_bad_curve_set_directly_is_rejected_at_attach_and_at_run(scene):
    mat = straight_wire()
    mat.wireStrain = [0.007, 0.006, 0.02, 0.05]
    with pytest.raises(ValueError, match="strain must increase strictly"):
        yf.chain([(0, 0, 0), (0.1, 0, 0)], R, mat, segments=1)
    assert len(O.bodies) == 0, "nothing half-built left in the scene"
    O.reset()
    good = straight_wire()
    yf.chain([(0, 0, 0), (0.1, 0, 0)], R, good, segments=1, fixed=[0, 1])
    O.engines = yf.engines(gravity=(0, 0, 0))
    O.step()
    good.wireStress = [1e9, -1.0, 2.0, 3.0]
    with pytest.raises(Exception, match="stress of point 1 must be positive"):
        O.step()
    with pytest.raises(ValueError, match="leave yieldStress"):
        m = straight_wire()
        m.yieldStress = 1e9
        yf.chain([(1, 0, 0), (1.1, 0, 0)], R, m, segments=1)


def test_distorted_link_follows_the_shifted_curve(scene):
    mat = wire.wire_material(E_KNOTS, S_KNOTS, slack_scale=0.05, force_ratio=0.5, seed=7)
    s = tensile.single_wire(mat, length=0.1, radius=R)
    c = O.bodies[s["cylinders"][0]].shape
    d = c.wireSlack
    assert 0 < d < 0.05
    e, f, _ = tensile.drive_strains(s, [d + 0.5 * E_KNOTS[0]] + [d + x for x in E_KNOTS], steps_per_unit_strain=4e4)
    # end of the soft branch: half the first point's force
    k = min(range(len(e)), key=lambda i: abs(e[i] - (d + 0.5 * E_KNOTS[0])))
    assert_rel(f[k], 0.5 * S_KNOTS[0] * A, KNOT_TOL, "end of the soft initial branch")
    for ek, sk in zip(E_KNOTS, S_KNOTS):
        k = min(range(len(e)), key=lambda i: abs(e[i] - (d + ek)))
        assert_rel(f[k], sk * A, KNOT_TOL, f"shifted knot {ek}")


def _slacks_of_links(n, seed, scale):
    """n independent links (each its own two nodes); their drawn slack strains."""
    O.reset()
    mat = wire.wire_material(E_KNOTS, S_KNOTS, slack_scale=scale, seed=seed)
    out = []
    for k in range(n):
        _, cyls = yf.chain([(0, 0.01 * k, 0), (0.05, 0.01 * k, 0)], R, mat, segments=1)
        out.append(O.bodies[cyls[0]].shape.wireSlack)
    return out


def test_slack_distribution_matches_the_specified_triangular_law(scene):
    n, scale = 2000, 0.08
    xs = sorted(x / scale for x in _slacks_of_links(n, seed=2024, scale=scale))
    cdf = lambda x: 2 * x * x if x <= 0.5 else 1 - 2 * (1 - x) ** 2  # symmetric triangular on [0, 1]
    D = max(max(abs(cdf(x) - k / n), abs(cdf(x) - (k + 1) / n)) for k, x in enumerate(xs))
    assert 0 <= xs[0] and xs[-1] < 1
    assert D < 1.628 / math.sqrt(n), f"Kolmogorov-Smirnov D = {D} (1% critical value {1.628 / math.sqrt(n)})"
    mean = sum(xs) / n
    assert abs(mean - 0.5) < 4 * math.sqrt(1 / 24 / n)
    # the same test rejects a uniform law of the same range (the test can fail)
    Du = max(abs(cdf((k + 0.5) / n) - (k + 0.5) / n) for k in range(n))
    assert Du > 1.628 / math.sqrt(n)


def test_same_seed_same_slack_after_reset_other_seed_other_slack(scene):
    a = _slacks_of_links(50, seed=99, scale=0.1)
    b = _slacks_of_links(50, seed=99, scale=0.1)  # O.reset() in between
    c = _slacks_of_links(50, seed=100, scale=0.1)
    assert a == b
    assert sum(x != y for x, y in zip(a, c)) == 50


def _thread_rows(threads, duration, parallel):
    out = run_yade(os.path.join(HERE, "scripts", "wire_threads_scene.py"), threads=threads, args=[duration, int(parallel)])
    rows = [l.split() for l in out.splitlines() if l.startswith("ROW")]
    assert len(rows) > 50
    return rows


def test_threads_j1_equals_j2_for_a_distorted_mesh_pull():
    # default settings (this small scene runs the element loop serially): bitwise identical,
    # with links carrying hundreds of newtons after a 4% pull (4 m/s for 4.8 ms on 0.5 m)
    r1, r2 = _thread_rows(1, 4.8e-3, False), _thread_rows(2, 4.8e-3, False)
    assert max(float(a[3]) for a in r1) > 100.0
    assert r1 == r2
    # element loop and integrator forced onto two threads: the slack draws are still bitwise
    # identical; forces agree to round-off of the structure's force level over 2.4 ms
    # (per-thread force buffers are summed in another order; the collapsing rhombi later
    # amplify that: 0.5% after 8000 steps at 2 m/s, measured)
    p1, p2 = _thread_rows(1, 2.4e-3, True), _thread_rows(2, 2.4e-3, True)
    assert [a[2] for a in p1] == [b[2] for b in p2] == [a[2] for a in r1]
    fmax = max(abs(float(a[3])) for a in p1)
    assert fmax > 10.0
    for a, b in zip(p1, p2):
        fa, fb = float(a[3]), float(b[3])
        assert abs(fa - fb) <= 1e-9 * fmax, f"link {a[1]}: force -j1 {fa} vs -j2 {fb} (largest link force {fmax} N)"


def test_mesh_impact_energy_balance_closes_with_plastic_links(scene):
    """Steel ball (R = 0.1 m, 5 m/s) into a TECCO panel 0.6 x 0.6 m pinned on its border, no
    damping: the links straighten their slack and yield (flexBondPlastic takes most of the
    energy), and kinetic + elastic + plastic + friction - gravity work stays equal to the
    initial kinetic energy (measured residual 1.3e-4)."""
    from yadeflex import mesh, builders as B
    from yadeflex.harness import scenes
    mat = wire.tecco_wire(seed=5)
    p = mesh.chain_link_panel(0.6, 0.6, mat)
    B.fix(sorted(set(sum(p["edges"].values(), []))), "xyz")
    R, v = 0.1, 5.0
    s = scenes.sphere((p["params"]["width"] / 2, p["params"]["height"] / 2, R + 0.0015 + 1e-4), R, density=7850, young=2e10,
                      velocity=(0, 0, -v))
    O.engines = yf.engines(damping=0.0)
    O.trackEnergy = True
    e0 = 0.5 * O.bodies[s].state.mass * v * v
    worst = 0.0
    while O.time < 0.04:
        scenes.advance(200)
        worst = max(worst, abs(O.energy.total() - e0))
    assert O.energy["flexBondPlastic"] > 0.5 * e0, "the mesh absorbed the impact plastically"
    assert element_engine().nRuptured == 0
    assert worst <= 0.01 * e0, f"energy balance residual {worst / e0:.2e} of the impact energy"


def test_wire_state_and_curve_survive_save_and_load(scene, tmp_path):
    s = tensile.mesh_panel_scene(width=0.4, height=0.4, speed=4.0, seed=3)
    # steps that depend on the collider's bounds would differ after loading (see test_smoke.py)
    next(e for e in O.engines if e.label == "flexDt").skipUnreachable = False
    for _ in range(3000):
        O.step()
    links = s["cylinders"]
    f = str(tmp_path / "wire.yade.gz")
    O.save(f)

    def state():
        return [(O.bodies[c].shape.maxStrain, O.bodies[c].shape.plasticStrain, O.bodies[c].shape.wireSlack, O.bodies[c].shape.axialForce)
                if O.bodies[c] is not None else None for c in links]

    saved = state()
    assert sum(1 for x in saved if x and x[1] > 0) > 10, "links with a plastic memory at the save"
    for _ in range(500):
        O.step()
    a = state()
    O.load(f)
    assert state() == saved, "named wire state restored exactly"
    m = O.bodies[links[0]].material
    assert list(m.wireStrain) == list(wire.TECCO_WIRE_STRAIN) and list(m.wireStress) == list(wire.TECCO_WIRE_STRESS)
    assert m.wireSeed == 3 and m.wireSlackScale == mesh_cal()["slack_scale"]
    for _ in range(500):
        O.step()
    b = state()
    O.load(f)
    for _ in range(500):
        O.step()
    assert state() == b, "two continuations of the same saved scene are bitwise identical"
    # like the uninterrupted run up to round-off (the loaded scene rebuilds its interactions and
    # time step at another moment)
    for x, y in zip(a, b):
        assert (x is None) == (y is None)
        if x is not None:
            assert x[2] == y[2]
            assert all(abs(u - w) <= 1e-9 * max(1e-3, abs(u)) for u, w in zip(x, y)), f"{x} vs {y}"


def mesh_cal():
    from yadeflex.mesh import TECCO_MESH_CALIBRATION
    return TECCO_MESH_CALIBRATION
