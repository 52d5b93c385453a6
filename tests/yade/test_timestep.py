"""Critical time step from bonds and contacts: matches analytic values, keeps runs stable."""
import math

import pytest
from yade import O
from yade.minieigenHP import Vector3

import yadeflex as yf
from yadeflex import scenes
from yadeflex.scenes import sphere
from tol import assert_rel


def test_axial_chain_bound_is_exact_for_a_single_bar(scene):
    # one free steel bar with negligible bending (bending_factor tiny): the highest mode is the
    # axial one, omega^2 = 2 k / m_h, k = EA/L, m_h = rho A L / 2
    E, rho, r, L = 200e9, 7850.0, 0.002, 0.1
    mat = yf.steel(bending_factor=1e-9)
    yf.chain([(0, 0, 0), (L, 0, 0)], r, mat)
    A = math.pi * r * r
    k, mh = E * A / L, rho * A * L / 2
    assert_rel(yf.critical_timestep(), 2 / math.sqrt(2 * k / mh), 1e-9, "critical step of a bar")


def test_contact_stiffness_lowers_the_step(scene):
    mat = yf.steel()
    nodes, cyls = yf.chain([(-0.2, 0, 0), (0.2, 0, 0)], 0.003, mat, segments=4, fixed=[0, 4])
    O.engines = yf.engines()
    dt_bonds = yf.critical_timestep()
    s = sphere((0.0, 0, 0.003 + 0.01 - 1e-5), 0.01, density=7850, young=1e12)  # very stiff contact
    O.engines = yf.engines()
    O.dt = 1e-12
    O.step()
    assert yf.contacts_on(s)
    assert yf.critical_timestep() < 0.5 * dt_bonds
    # the stepper names what sets the step: a node under the stiff contact (the light side)
    assert O.engines[-2].stiffestBody in set(nodes[1:-1])


def test_the_stepper_names_the_stiffest_element(scene):
    mat = yf.steel()
    nodes, cyls = yf.chain([(0, 0, 0), (0.3, 0, 0)], 0.003, mat, segments=3, fixed=[0])
    O.bodies[nodes[2]].state.mass *= 0.01  # the element(s) at this light node have the highest omega^2
    O.engines = yf.engines()
    O.step()
    st = O.engines[-2]
    assert st.stiffestBody in {cyls[1], cyls[2]}
    assert O.bodies[st.stiffestBody].shape.node1 == nodes[2] or O.bodies[st.stiffestBody].shape.node2 == nodes[2]


@pytest.mark.parametrize("safety", [1.0])
def test_run_at_the_estimated_step_is_stable(scene, safety):
    """An undamped net hit by a stiff, heavy ball at exactly the estimated critical step: the
    energy stays bounded by what was put in (no blow-up)."""
    scenes.net_impact(n=8, spacing=0.05, wire_radius=0.002, sphere_radius=0.06, speed=10.0)
    O.engines[-2].safety = safety
    O.engines[-2].interval = 1
    O.trackEnergy = True
    O.step()
    e0 = O.energy["kinetic"]
    emax = 0.0
    for _ in range(60):
        scenes.advance(50)
        emax = max(emax, O.energy["kinetic"] + O.energy["flexBondElastic"] + O.energy.get("flexContactElastic", 0.0) if hasattr(O.energy, "get") else O.energy["kinetic"])
    assert any(yf.contacts_on(b.id) for b in O.bodies if b is not None and type(b.shape).__name__ == "Sphere") or emax > 0
    assert math.isfinite(emax) and emax < 2 * e0 + 1.0, f"energy grew from {e0} J to {emax} J"


def test_local_damping_shortens_the_step_and_keeps_a_fine_cantilever_stable(scene):
    """Cundall damping c scales accelerations by up to 1 + c: the step must shrink by
    sqrt(1 + c). Without that, a 20-element cantilever with c = 0.8 spins nodes at 1e4 rad/s
    (measured) instead of settling at the Euler-Bernoulli deflection."""
    s = scenes.cantilever(segments=20, length=1.0, radius=0.01, load="tip", force=1.0, damping=0.0)
    dt0 = yf.critical_timestep()
    O.engines[-1].damping = 0.8
    assert_rel(yf.critical_timestep(), dt0 / math.sqrt(1.8), 1e-12, "damped critical step")
    scenes.settle([s["tip"]], rel_tol=1e-7)
    assert max(O.bodies[i].state.angVel.norm() for i in s["nodes"]) < 1.0
    I = math.pi * 0.01 ** 4 / 4
    assert_rel(-O.bodies[s["tip"]].state.pos[2], 1.0 / (3 * 200e9 * I), 1e-3, "20-element cantilever")


def _gershgorin_spheres():
    """The contact bound of FlexTimeStepper.omega2Contacts for a scene of spheres, written out
    independently: each contact (real: its kn, ks; potential: the stiffness Ip2_FrictMat gives,
    kn = 2 k1 k2 / (k1 + k2) with k = E r, ks likewise with E nu r) adds k m_a^-1/2 (m_a^-1/2 +
    m_b^-1/2) to the translational row of a and 2 ks l^2 / I_a to its rotational row."""
    row, rot = {}, {}

    def inv_sqrt_mass(b):
        return 0.0 if (not b.dynamic or b.state.mass <= 0) else 1 / math.sqrt(b.state.mass)

    for i in O.interactions.all(False):
        b = [O.bodies[i.id1], O.bodies[i.id2]]
        if i.isReal:
            if not i.geom.active:
                continue
            k, ks, lever = max(i.phys.kn, i.phys.ks), i.phys.ks, [i.geom.refR1, i.geom.refR2]
        else:
            kk = [x.material.young * x.shape.radius for x in b]
            ss = [x.material.young * x.material.poisson * x.shape.radius for x in b]
            kn, ks = 2 * kk[0] * kk[1] / (kk[0] + kk[1]), 2 * ss[0] * ss[1] / (ss[0] + ss[1])
            k, lever = max(kn, ks), [x.shape.radius for x in b]
        w = [inv_sqrt_mass(x) for x in b]
        for s in (0, 1):
            if w[s] == 0:
                continue
            row[b[s].id] = row.get(b[s].id, 0.0) + k * w[s] * (w[0] + w[1])
            rot[b[s].id] = rot.get(b[s].id, 0.0) + 2 * ks * lever[s] ** 2 / min(b[s].state.inertia)
    return max(list(row.values()) + list(rot.values()), default=0.0)


def test_contact_bound_of_a_granular_pack_matches_an_independent_sum(scene):
    """A loose pack of spheres of two sizes and two materials, falling onto a fixed sphere
    layer: real and potential (bounds overlap only) contacts. The C++ bound (which gathers
    body data in a table once per estimate) equals the independent sum to round-off."""
    import random
    rng = random.Random(3)
    for ix in range(7):
        for iy in range(7):
            O.bodies[sphere((0.035 * ix, 0.035 * iy, 0.0), 0.025, young=1e9)].dynamic = False  # fixed floor
    for k in range(64):  # 4 layers of 4 x 4, no initial overlap, jittered
        r = rng.choice([0.01, 0.016])
        x, y, z = 0.025 + 0.05 * (k % 4), 0.025 + 0.05 * (k // 4 % 4), 0.06 + 0.04 * (k // 16)
        sphere((x + rng.uniform(-0.005, 0.005), y + rng.uniform(-0.005, 0.005), z), r,
               young=rng.choice([1e8, 3e8]), density=rng.choice([2000.0, 2650.0]))
    O.engines = yf.engines(verlet=0.004)
    n_real = n_potential = 0
    for _ in range(40):
        scenes.advance(400)
        n_real = max(n_real, sum(1 for i in O.interactions.all(False) if i.isReal))
        n_potential = max(n_potential, sum(1 for i in O.interactions.all(False) if not i.isReal))
        ref, got = _gershgorin_spheres(), O.engines[-2].omega2Contacts()
        if ref == 0:  # no contact with a moving sphere yet
            assert got == 0
        else:
            assert_rel(got, ref, 1e-12, "sphere contact bound")
    assert n_real > 20 and n_potential > 20, (n_real, n_potential)
