"""Deformable cylinders as beams: analytic cantilever, bar, frequency; objectivity; ropes; rupture."""
import math

import pytest
from yade import O
from yade.minieigenHP import Vector3

from yadeflex.harness import scenes

from yadeflex.harness import cases
import yadeflex as yf
from tol import assert_rel, circle_I, STEEL_E, STEEL_RHO, G


def _elements():
    """The scene's FlexElementEngine (by label: the engine list may start with a FlexGuard)."""
    return next(e for e in O.engines if e.label == "flexElements")


def test_cantilever_tip_load_matches_PL3_over_3EI(scene):
    # small load: geometric nonlinearity ~ (delta/L)^2 ~ 1e-7
    r = cases.cantilever_deflection("tip", segments=10, length=1.0, radius=0.01, force=1.0)
    assert r["reference"] == pytest.approx(1.0 / (3 * STEEL_E * circle_I(0.01)), rel=1e-12)
    assert_rel(r["measured"], r["reference"], 1e-3, "tip deflection, 10 segments")


def test_cantilever_self_weight_matches_qL4_over_8EI(scene):
    r = cases.cantilever_deflection("self", segments=10, length=1.0, radius=0.01)
    q = STEEL_RHO * math.pi * 0.01 ** 2 * G
    assert r["reference"] == pytest.approx(q / (8 * STEEL_E * circle_I(0.01)), rel=1e-12)
    # lumped loads omit only the tip moment q h^2/12 of the consistent load: error 1/(3 N^2)
    assert_rel(r["measured"], r["reference"], 5e-3, "self-weight tip deflection, 10 segments")


def test_axial_bar_stiffness_EA_over_L(scene):
    L, rad, P = 2.0, 0.004, 1000.0
    r = cases.cantilever_deflection("axial", segments=5, length=L, radius=rad, force=P)
    assert r["reference"] == pytest.approx(P * L / (STEEL_E * math.pi * rad ** 2), rel=1e-12)
    assert_rel(r["measured"], r["reference"], 1e-4, "bar elongation")
    assert_rel(r["axial_force"], P, 1e-4, "axial force")


def test_first_bending_frequency(scene):
    # static deflection under the tip load, then release: free vibration, mostly mode 1
    L, rad = 1.0, 0.01
    r = cases.first_bending_frequency(segments=10, length=L, radius=rad)
    A, I = math.pi * rad ** 2, circle_I(rad)
    assert r["reference"] == pytest.approx(1.875104 ** 2 * math.sqrt(STEEL_E * I / (STEEL_RHO * A * L ** 4)), rel=1e-12)
    assert r["crossings"] >= 4
    assert_rel(r["measured"], r["reference"], 0.02, "first bending frequency")


def test_finite_rigid_rotation_creates_no_force(scene):
    # a bent, twisted structure: a ring and a helix, rotated by 1.1 rad as a whole
    mat = yf.steel()
    rn, rc = yf.ring((0, 0, 0), 0.2, 0.004, mat, segments=12)
    hn, hc = yf.helix(30, 0.05, 0.02, 0.002, mat, center=(1, 0, 0), fixed=())
    O.engines = yf.engines(gravity=(0, 0, 0))
    O.dt = 1e-7
    O.run(1, True)
    scenes.rotate_rigidly(rn + hn, axis=(1, 2, 3), angle=1.1, center=(0.3, -0.2, 0.1))
    O.run(1, True)
    fmax = max(O.forces.f(i).norm() for i in rn + hn)
    mmax = max(O.forces.t(i).norm() for i in rn + hn)
    # a 1e-6 strain in these bars would give ~ EA*1e-6 = 10 N: the forces must be round-off only
    assert fmax < 1e-6, f"max node force after rigid rotation {fmax} N"
    assert mmax < 1e-8, f"max node moment after rigid rotation {mmax} N m"


def test_rope_carries_no_compression(scene):
    rope = yf.rope_6x7_8mm()
    s = scenes.cantilever(segments=4, length=1.0, radius=0.004, load="axial", force=-500.0, material=rope)
    scenes.advance(200)
    assert all(O.bodies[c].shape.axialForce == 0.0 for c in s["cylinders"])
    assert O.bodies[s["cylinders"][-1]].shape.strain < -1e-4  # the pushed segment did shorten


def test_rope_axial_stiffness_and_rupture_force(scene):
    rope = yf.rope_6x7_8mm()
    s = scenes.cantilever(segments=4, length=1.0, radius=0.004, load="axial", force=10e3, material=rope)
    scenes.settle([s["tip"]], rel_tol=1e-7)
    du = O.bodies[s["tip"]].state.pos[0] - 1.0
    assert_rel(10e3 * 1.0 / du, 96e9 * 24.32e-6, 0.01, "rope EA from datasheet")
    # displacement-controlled pull at 1 cm/s (quasi-static): the bond breaks at 37.6 kN
    O.forces.setPermF(s["tip"], Vector3(0, 0, 0))
    tip = O.bodies[s["tip"]].state
    tip.blockedDOFs = "xyzXYZ"
    tip.vel = Vector3(0.01, 0, 0)
    fmax, steps = 0.0, 0
    while _elements().nRuptured == 0 and steps < 200000:
        fmax = max([fmax] + [O.bodies[c].shape.axialForce for c in s["cylinders"] if O.bodies[c] is not None])
        O.step()
        steps += 1
    assert _elements().nRuptured == 1
    assert_rel(fmax, 37.6e3, 0.02, "rope breaking force")


def test_rupture_removes_element_and_counts(scene):
    mat = yf.steel(tensile_strength=400e6)
    s = scenes.cantilever(segments=3, length=0.3, radius=0.002, load="axial", force=0.0, material=mat)
    O.forces.setPermF(s["tip"], Vector3(1.2 * 400e6 * math.pi * 0.002 ** 2, 0, 0))
    mass_before = sum(O.bodies[n].state.mass for n in s["nodes"])
    O.trackEnergy = True
    for _ in range(1000):
        scenes.advance(20)
        if _elements().nRuptured:
            break
    broken = _elements().rupturedIds
    assert _elements().nRuptured == 1 and len(broken) == 1
    assert O.bodies[broken[0]] is None  # the element is gone, not a ghost
    assert all(broken[0] not in O.bodies[n].shape.elements for n in s["nodes"])
    assert len([i for i in O.interactions if broken[0] in (i.id1, i.id2)]) == 0
    assert sum(O.bodies[n].state.mass for n in s["nodes"]) == pytest.approx(mass_before, rel=1e-15)
    assert O.energy["flexRupture"] > 0


def test_rupture_step_books_the_broken_elements_energy_once(scene):
    # at the step an element breaks, its stored energy goes to flexRupture and leaves the
    # elements' elastic term: counted in both, the balance showed it twice for that step
    mat = yf.steel(tensile_strength=400e6)
    s = scenes.cantilever(segments=3, length=0.3, radius=0.002, load="axial", force=0.0, material=mat)
    O.forces.setPermF(s["tip"], Vector3(1.2 * 400e6 * math.pi * 0.002 ** 2, 0, 0))
    O.trackEnergy = True
    for _ in range(20000):
        O.step()
        if _elements().nRuptured:
            break
    assert _elements().nRuptured == 1
    left = [O.bodies[c].shape.elasticEnergy for c in s["cylinders"] if O.bodies[c] is not None]
    assert O.energy["flexRupture"] > 0
    assert O.energy["flexBondElastic"] == pytest.approx(sum(left), rel=1e-12, abs=1e-12 * O.energy["flexRupture"])


@pytest.mark.parametrize("bending_factor", [1.0, 0.0])
def test_element_loop_follows_states_and_materials_replaced_from_python(scene, bending_factor):
    """FlexElementEngine keeps, per cylinder, pointers to its shape, material and nodes' states,
    checked against the bodies at each step: a node state or a material replaced from Python is
    used from the next step on (EA dL/L0 with the new position, then with the new modulus)."""
    from yade.wrapper import State
    r, E = 0.01, 200e9
    nodes, cyls = yf.chain([(0, 0, 0), (1, 0, 0)], r, yf.steel(bending_factor=bending_factor), fixed=[0])
    O.engines = yf.engines(gravity=(0, 0, 0))
    EA = E * math.pi * r ** 2

    def pull(x):
        st = State()
        st.pos, st.mass, st.blockedDOFs = Vector3(x, 0, 0), 1.0, "xyzXYZ"
        O.bodies[nodes[1]].state = st  # a new State object
        O.step()
        return O.bodies[cyls[0]].shape.axialForce

    assert_rel(pull(1.001), EA * 1e-3, 1e-9, "axial force after the node's state was replaced")
    assert_rel(pull(1.002), EA * 2e-3, 1e-9, "after a second replacement")
    O.bodies[cyls[0]].material = yf.steel(young=E / 2, bending_factor=bending_factor, label="soft")
    O.step()
    assert_rel(O.bodies[cyls[0]].shape.axialForce, EA / 2 * 2e-3, 1e-9, "after the material was replaced")
