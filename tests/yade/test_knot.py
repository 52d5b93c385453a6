"""The hooked knot (FlexCylinder.hookLegs, pkg/kernel/Hook.hpp): two hooked wire bends joined by a
hinged bar turn about each other but do not pass through each other."""
import math

import pytest
from yade import O
from yade.minieigenHP import Vector3

import yadeflex as yf
from yadeflex.mesh import chain_link_panel, knot_bar

D = 0.003  # wire diameter [m]
R = D / 2
A, H = 0.0415, 0.0715  # TECCO G65/3 half diagonals [m]


def _knot(hook=True):
    """A knot of yadeflex.mesh (knots='hook'): the left bend at (d/2, 0, -d/2) with its legs' far
    nodes at (-a, -+h, 0), the right bend at (-d/2, 0, d/2), a hinged steel bar between the two
    bends; returns (left, right, link, legs)."""
    mat = knot_bar("knot", bending_factor=0.0)
    left = yf.node((0.5 * D, 0, -0.5 * D), R, mat)
    right = yf.node((-0.5 * D, 0, 0.5 * D), R, mat)
    legs = [yf.node((-A, -H, 0), R, mat), yf.node((-A, H, 0), R, mat)]
    link = yf.cylinder(left, right, R, mat, hook_legs=legs if hook else None)
    return left, right, link, legs


def test_the_stop_pushes_back_with_its_stiffness(scene):
    """The left bend turned about the right one (the bar at its rest length, 25 degrees from -z
    instead of 45: 1.3 mm into the stop): the stop's force k (c - g) along the way the bend opens,
    equal and opposite on the right bend, the rest on the legs' far nodes; no moments."""
    left, right, link, legs = _knot()
    yf.fix([left, right] + legs, "xyzXYZ")  # forces read after one step, nothing moves
    O.engines = yf.engines(gravity=(0, 0, 0))
    c = O.bodies[link].shape
    ell = c.L0
    k = 200e9 * math.pi * R * R / ell
    assert c.hookStiffness == pytest.approx(k, rel=1e-12)
    m0 = O.bodies[left].state.pos - 0.5 * (O.bodies[legs[0]].state.pos + O.bodies[legs[1]].state.pos)
    assert c.hookGap == pytest.approx((O.bodies[left].state.pos - O.bodies[right].state.pos).dot(m0.normalized()), rel=1e-12)
    th = math.radians(25.0)
    xi = O.bodies[right].state.pos + Vector3(ell * math.sin(th), 0, -ell * math.cos(th))
    O.bodies[left].state.pos = xi
    O.step()
    n = (xi - 0.5 * (O.bodies[legs[0]].state.pos + O.bodies[legs[1]].state.pos)).normalized()
    f = k * (c.hookGap - (xi - O.bodies[right].state.pos).dot(n))
    assert f > 0 and c.hookForce == pytest.approx(f, rel=1e-9)
    assert c.axialForce == pytest.approx(0, abs=1e-6 * f)  # the bar at its rest length
    fr = O.forces.f(right)
    assert (fr + f * n).norm() <= 1e-9 * f
    total = sum((O.forces.f(i) for i in [left, right] + legs), Vector3(0, 0, 0))
    assert total.norm() <= 1e-9 * f
    moment = sum((O.bodies[i].state.pos.cross(O.forces.f(i)) for i in [left, right] + legs), Vector3(0, 0, 0))
    assert moment.norm() <= 1e-9 * f * A
    assert all(O.forces.t(i).norm() == 0 for i in [left, right] + legs)


def test_the_stop_adds_its_mode_to_the_time_step_bound(scene):
    left, right, link, _ = _knot(hook=False)
    plain = O.bodies[link].shape.omega2
    O.reset()
    left, right, link, _ = _knot()
    c = O.bodies[link].shape
    assert c.omega2 - plain == pytest.approx(3.5 * c.hookStiffness / c.massShare, rel=1e-12)


@pytest.mark.parametrize("hook", [True, False])
def test_hooked_bends_turn_but_do_not_pass(scene, hook):
    """The left bend thrown at 1 m/s towards -x (pulled out of the hook), the legs' far nodes
    held. With the stop it comes back and stays on the right bend's +x side, and the booked energy
    stays the kinetic energy it started with; a plain hinged bar lets it swing through to the
    other side."""
    from yade.wrapper import FlexTimeStepper
    left, right, link, legs = _knot(hook)
    yf.fix([right] + legs, "xyzXYZ")
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
        assert max(xs) > D and s.vel[0] > 0, "the stop did not send the bend back"
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


@pytest.mark.parametrize("legs", [(0, 1), (5, 5), (99, 100), "ab", (0,)])
def test_bad_hook_legs_are_refused(scene, legs):
    """Not two distinct nodes other than the link's ends, or a straight bend: a ValueError naming
    the hook's legs; nothing added."""
    mat = knot_bar("knot", bending_factor=0.0)
    a, b = yf.node((0, 0, 0), R, mat), yf.node((D, 0, 0), R, mat)
    yf.node((-A, -H, 0), R, mat), yf.node((-A, H, 0), R, mat), yf.node((2 * A, 0, 0), R, mat), yf.node((D, 0.1, 0), R, mat)
    live = lambda: sum(1 for b in O.bodies if b is not None)
    n = live()
    with pytest.raises(ValueError, match="hook ?[lL]egs"):
        yf.cylinder(a, b, R, mat, hook_legs=legs)
    assert live() == n


def test_a_straight_bend_cannot_hook(scene):
    mat = knot_bar("knot", bending_factor=0.0)
    a, b = yf.node((0, 0, 0), R, mat), yf.node((D, 0, 0), R, mat)
    legs = [yf.node((-0.1, 0.001, 0), R, mat), yf.node((0.1, -0.001, 0), R, mat)]  # a's legs in line
    with pytest.raises(ValueError, match="straight"):
        yf.cylinder(a, b, R, mat, hook_legs=legs)


def test_panel_with_hooked_knots(scene):
    """Inner-row knots carry the stop, their legs' far nodes the left bend's neighbours on its
    own spiral; the top and bottom rows' knots (one leg per bend) a plain hinged link."""
    p = chain_link_panel(0.25, 0.43, yf.tecco_wire(), knots="hook")
    ny = p["params"]["ny"]
    assert p["params"]["knots"] == "hook" and p["knot_links"]
    hooked = 0
    for (i, k), ids in p["nodes"].items():
        if len(ids) != 2:
            continue
        link = next(c for c in p["knot_links"] if O.bodies[c].shape.node1 == ids[0])
        c = O.bodies[link].shape
        assert O.bodies[link].material.bendingFactor == 0
        if 0 < k < ny:
            assert c.hookStiffness > 0 and set(c.hookLegs) == {p["nodes"][(i - 1, k - 1)][-1], p["nodes"][(i - 1, k + 1)][-1]}
            hooked += 1
        else:
            assert c.hookStiffness == 0
    assert hooked > 0
    with pytest.raises(ValueError, match="knots"):
        chain_link_panel(0.25, 0.3, yf.tecco_wire(), knots="rope")
