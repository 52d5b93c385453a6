"""Rolling resistance between spheres (Law2_FlexContactGeom_FrictPhys_CundallStrack
.rollingStiffness / .rollingFriction): the capped moment stops a spinning sphere in the time
the constant moment predicts, and the energy it takes is booked ('flexRolling')."""
import math

import pytest
from yade import O
from yade.minieigenHP import Vector3

import yadeflex as yf
import yadeflex.harness.scenes as S


def _pair(eta, beta, omega0=5.0):
    R, delta = 0.05, 1e-4
    a = S.sphere((0, 0, 0), R, young=1e8, friction_deg=0.0)  # frictionless: only the rolling moment acts
    b = S.sphere((0, 0, 2 * R - delta), R, young=1e8, friction_deg=0.0)  # frictionless: only the rolling moment acts
    for i in (a, b):
        O.bodies[i].state.blockedDOFs = "xyz"  # held at their overlap: a constant normal force
    O.bodies[a].state.blockedDOFs = "xyzXYZ"
    O.bodies[b].state.angVel = Vector3(omega0, 0, 0)  # rolling about x, perpendicular to the normal z
    O.engines = yf.engines(gravity=(0, 0, 0), timestep_safety=0.02)  # resolve the stop time to < 0.5%
    law = [e for e in O.engines if e.label == "interactionLoop"][0].lawDispatcher.functors
    flexlaw = [f for f in law if f.label == "flexLaw"][0]
    flexlaw.rollingStiffness, flexlaw.rollingFriction = beta, eta
    O.trackEnergy = True
    return a, b, R, delta


def test_capped_moment_stops_a_spinning_sphere(scene):
    eta, omega0 = 0.2, 5.0
    a, b, R, delta = _pair(eta, 1.0, omega0)
    O.step()
    i = O.interactions[a, b]
    Fn = i.phys.normalForce.norm()
    Reff = R / 2
    M = eta * Reff * Fn  # the cap
    I = O.bodies[b].state.inertia[0]
    kr = 1.0 * i.phys.ks * Reff ** 2
    # elastic ramp until the moment reaches the cap (omega0 cos, theta = omega0/W sin, W^2 = kr/I),
    # then constant deceleration M/I
    W = math.sqrt(kr / I)
    t1 = math.asin(M / (omega0 * math.sqrt(kr * I))) / W
    t_stop = t1 + omega0 * math.cos(W * t1) * I / M
    e0 = 0.5 * I * omega0 ** 2
    total0 = O.energy.total()  # includes the (constant) normal spring energy
    stopped = None
    while O.time < 3 * t_stop:
        O.step()
        if stopped is None and O.bodies[b].state.angVel[0] <= 0:
            stopped = O.time
    assert stopped == pytest.approx(t_stop, rel=0.02)
    e = yf.energy_budget()
    assert e["flexRolling"] > 0.5 * e0  # most of it dissipated by rolling resistance
    assert abs(e["total"] - total0) <= 2e-3 * e0  # kinetic + stored + dissipated = initial


def test_no_rolling_resistance_by_default(scene):
    a, b, R, delta = _pair(0.2, 0.0)
    for _ in range(200):
        O.step()
    assert O.bodies[b].state.angVel[0] == pytest.approx(5.0, rel=1e-12)


@pytest.mark.parametrize("grain_engine", [False, True])
def test_a_rolling_moment_ends_with_its_contact(scene, grain_engine):
    """A contact that separates for one step and touches again starts with no rolling moment, as
    with no shear: the moment's energy was booked as released when it separated ('flexRolling'),
    and a moment brought back would create that energy. Sphere b spins against a (the elastic
    moment builds up), is lifted off for one step and put back at rest: nothing then turns it,
    the contact being frictionless and its normal force through the centres."""
    R, delta, omega0 = 0.05, 1e-4, 5.0
    a = S.sphere((0, 0, 0), R, young=1e8, friction_deg=0.0)
    b = S.sphere((0, 0, 2 * R - delta), R, young=1e8, friction_deg=0.0)
    mat = O.bodies[a].material
    mat.label = "roller"
    O.bodies[b].material = mat
    O.bodies[a].state.blockedDOFs = "xyzXYZ"
    O.bodies[b].state.blockedDOFs = "xyz"
    O.bodies[b].state.angVel = Vector3(omega0, 0, 0)
    O.engines = yf.engines(gravity=(0, 0, 0), rolling_stiffness=1.0, rolling_friction=1.0, grains="roller" if grain_engine else None)
    O.trackEnergy = True
    for _ in range(5):
        O.step()
    assert O.bodies[b].state.angVel[0] < omega0  # the moment slows the spin
    rolling_before = O.energy["flexRolling"] if "flexRolling" in O.energy.keys() else 0.0
    up = O.bodies[b].state.pos
    O.bodies[b].state.pos = up + Vector3(0, 0, 2 * delta)
    O.bodies[b].state.angVel = Vector3(0, 0, 0)
    O.step()  # separated: its moment's energy leaves as released
    assert O.energy["flexRolling"] > rolling_before
    O.bodies[b].state.pos = up
    for _ in range(5):
        O.step()
        assert O.bodies[b].state.angVel == Vector3(0, 0, 0)
    if not grain_engine:
        assert O.interactions[a, b].geom.rollMoment == Vector3(0, 0, 0)
