"""The hooked knot (FlexCylinder.hookAxis, pkg/kernel/Hook.hpp): two hooked wire bends joined by a
hinged bar turn about each other but do not pass through each other."""
import math

import pytest
from yade import O
from yade.minieigenHP import Vector3

import yadeflex as yf
from yadeflex.mesh import chain_link_panel, knot_bar

D = 0.003  # wire diameter [m]
R = D / 2


def _knot(hook=True):
    """The knot of yadeflex.mesh (knots='hook'): left bend at (d/2, 0, -d/2), right bend at
    (-d/2, 0, d/2), a hinged steel bar between them; returns (left, right, link)."""
    mat = knot_bar("knot", bending_factor=0.0)
    left = yf.node((0.5 * D, 0, -0.5 * D), R, mat)
    right = yf.node((-0.5 * D, 0, 0.5 * D), R, mat)
    link = yf.cylinder(left, right, R, mat, hook_axis=(1, 0, 0) if hook else None)
    return left, right, link


def test_the_stop_pushes_back_with_its_stiffness_and_moment(scene):
    """The left bend turned about the right one (bar at its rest length, 20 degrees into the
    stop): force k (c - g) along the axis, moment f (n x r) on the left bend, nothing else."""
    left, right, link = _knot()
    O.engines = yf.engines(gravity=(0, 0, 0))
    c = O.bodies[link].shape
    ell = c.L0
    assert c.hookGap == pytest.approx(D, rel=1e-12) and ell == pytest.approx(D * math.sqrt(2), rel=1e-12)
    k = 200e9 * math.pi * R * R / ell
    assert c.hookStiffness == pytest.approx(k, rel=1e-12)
    th = math.radians(25.0)  # the bar at 25 degrees from -z: g = l sin(th) < d (45 degrees at rest)
    O.bodies[left].state.pos = O.bodies[right].state.pos + Vector3(ell * math.sin(th), 0, -ell * math.cos(th))
    yf.fix([left, right], "xyzXYZ")  # forces read after one step, nothing moves
    O.step()
    f = k * (D - ell * math.sin(th))
    assert c.hookForce == pytest.approx(f, rel=1e-9)
    assert c.axialForce == pytest.approx(0, abs=1e-6 * f)  # the bar at its rest length
    fl, fr = O.forces.f(left), O.forces.f(right)
    assert (fl - Vector3(f, 0, 0)).norm() <= 1e-6 * f and (fr + fl).norm() <= 1e-9 * f
    assert (O.forces.t(left) - Vector3(0, f * ell * math.cos(th), 0)).norm() <= 1e-6 * f * ell
    assert O.forces.t(right).norm() == 0


def test_the_stop_adds_its_modes_to_the_time_step_bound(scene):
    left, right, link = _knot(hook=False)
    plain = O.bodies[link].shape.omega2
    O.reset()
    left, right, link = _knot()
    c = O.bodies[link].shape
    k, m, inertia = c.hookStiffness, c.massShare, c.inertiaShare
    assert c.omega2 - plain == pytest.approx(k * (2 / m + c.L0 ** 2 / inertia), rel=1e-12)


@pytest.mark.parametrize("hook", [True, False])
def test_hooked_bends_turn_but_do_not_pass(scene, hook):
    """The left bend thrown at 1 m/s towards -x (pulled out of the hook), its rotation held (as its
    legs hold it in a mesh; the axis turns with it). With the stop it comes back and stays on the
    right bend's +x side, and the booked energy stays the kinetic energy it started with; a
    plain hinged bar lets it swing through to the other side."""
    from yade.wrapper import FlexTimeStepper
    left, right, link = _knot(hook)
    yf.fix([right], "xyzXYZ")
    yf.fix([left], "XYZ")
    s = O.bodies[left].state
    s.vel = Vector3(-1.0, 0, 0)
    O.engines = yf.engines(gravity=(0, 0, 0), timestep_safety=0.05)
    O.trackEnergy = True
    e0 = 0.5 * s.mass * 1.0 ** 2
    xs, drift, bound = [], 0.0, 0.0
    # the bounce step by step at a tenth of the usual step. YADE books the kinetic energy from the
    # velocity half a step away from the positions the elastic energy is read at: the booked total
    # is off by about |F . v| dt / 2 (first order in dt), which bounds the drift with a factor 2
    for _ in range(3000):
        O.step()
        xs.append((s.pos - O.bodies[right].state.pos)[0])
        drift = max(drift, abs(O.energy.total() - e0))
        bound = max(bound, abs(O.forces.f(left).dot(s.vel)) * O.dt)
    if hook:
        assert max(x for x in xs) > D and s.vel[0] > 0, "the stop did not send the bend back"
        assert drift <= bound, f"energy drift {drift:.3e} J above the booking's {bound:.3e} J (e0 {e0:.3e} J)"
    # then at the usual step for 10 ms: a hinged bend circles its partner at the 0.7 m/s of its
    # velocity across the bar, through the 45 degrees to the plane x = 0 in 4.7 ms
    next(e for e in O.engines if isinstance(e, FlexTimeStepper)).safety = 0.5
    t0 = O.time
    while O.time - t0 < 10e-3:
        O.run(400, True)
        xs.append((s.pos - O.bodies[right].state.pos)[0])
    if hook:
        assert min(xs) > 0.99 * D, f"the bends passed: smallest x-separation {min(xs)} m"
    else:
        assert min(xs) < 0, "a hinged bar without the stop is expected to let the bends swing through"


@pytest.mark.parametrize("axis", [(0, 0, 0), (math.nan, 0, 1)])
def test_bad_hook_axis_is_refused(scene, axis):
    mat = knot_bar("knot", bending_factor=0.0)
    a, b = yf.node((0, 0, 0), R, mat), yf.node((D, 0, 0), R, mat)
    n = len(O.bodies)
    with pytest.raises(ValueError, match="hook axis"):
        yf.cylinder(a, b, R, mat, hook_axis=axis)
    assert len(O.bodies) == n


def test_panel_with_hooked_knots(scene):
    p = chain_link_panel(0.25, 0.3, yf.tecco_wire(), knots="hook")
    assert p["params"]["knots"] == "hook" and p["knot_links"]
    for i in p["knot_links"]:
        c = O.bodies[i].shape
        assert c.hookStiffness > 0 and c.hookGap == pytest.approx(D, rel=1e-9)
        assert O.bodies[i].material.bendingFactor == 0
    with pytest.raises(ValueError, match="knots"):
        chain_link_panel(0.25, 0.3, yf.tecco_wire(), knots="rope")
