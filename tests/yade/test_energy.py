"""Energy: every mechanism booked in O.energy, the balance closes."""
import math

from yade import O
from yade.minieigenHP import Vector3

import yadeflex as yf
from yadeflex.harness import scenes
from yadeflex.harness import cases


def _impact(friction_deg, vel):
    r = cases.sphere_wire_impact(friction_deg, vel)
    return r["e0"], r["worst"], r["touched"]


def test_undamped_elastic_sphere_wire_impact_conserves_energy(scene):
    e0, worst, touched = _impact(0.0, (0, 0, -3.0))
    assert touched
    assert O.energy["flexBondElastic"] >= 0 and "flexContactElastic" in O.energy.keys()
    assert worst <= 0.01 * e0, f"energy drift {worst / e0:.2e} of the impact energy"


def test_frictional_impact_balance_closes(scene):
    e0, worst, touched = _impact(30.0, (2.0, 0.5, -3.0))
    assert touched
    assert O.energy["flexFriction"] > 0.001 * e0  # it slid: friction took a measurable share
    assert worst <= 0.01 * e0, f"energy balance residual {worst / e0:.2e} of the impact energy"


def test_plastic_bar_books_plastic_work_equal_to_external_work(scene):
    """Bar pulled past yield by a slowly ramped force: plastic strain and plastic work match the
    1D theory, and elastic + plastic + damping + kinetic energy equals the work of the force."""
    E, r, L, sy, h = 200e9, 0.002, 0.5, 300e6, 0.05
    mat = yf.steel(yield_stress=sy, hardening=h)
    s = scenes.cantilever(segments=2, length=L, radius=r, load="axial", force=0.0, material=mat, damping=0.5)
    A = math.pi * r * r
    P = 1.1 * sy * A
    O.trackEnergy = True
    tip = O.bodies[s["tip"]].state
    work, u_prev, f_prev = 0.0, 0.0, 0.0
    ramp = 40000
    for k in range(1, ramp + 1):  # smooth quasi-static ramp ending at zero rate: no overshoot
        f = P * 0.5 * (1 - math.cos(math.pi * k / ramp))
        O.forces.setPermF(s["tip"], Vector3(f, 0, 0))
        O.step()
        u = tip.pos[0] - L
        work += f * (u - u_prev)  # the force f acted while the tip moved from u_prev to u
        u_prev = u
    scenes.settle([s["tip"]], rel_tol=1e-9)
    u = tip.pos[0] - L
    work += P * (u - u_prev)
    # 1D theory: eps_p = (P - Ny) / (h E A) (linear isotropic hardening, H = h EA)
    eps_p = (P - sy * A) / (h * E * A)
    plastic_theory = (sy * A + 0.5 * h * E * A * eps_p) * eps_p * L
    assert abs(O.bodies[s["cylinders"][0]].shape.plasticStrain - eps_p) <= 2e-3 * eps_p
    assert abs(O.energy["flexBondPlastic"] - plastic_theory) <= 2e-3 * plastic_theory
    booked = O.energy["flexBondElastic"] + O.energy["flexBondPlastic"] + O.energy["nonviscDamp"] + O.energy["kinetic"]
    assert abs(booked - work) <= 0.01 * work, f"booked {booked} J vs work of the load {work} J"
