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
