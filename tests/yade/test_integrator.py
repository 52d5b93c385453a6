"""FlexNewtonIntegrator: the same motion as YADE's NewtonIntegrator, bit for bit, while it
skips element bodies; it triggers the collider from element nodes."""
import pytest
from yade import O
from yade.wrapper import NewtonIntegrator, FlexNewtonIntegrator

import yadeflex as yf
from yadeflex.harness import scenes


def _run(cls, steps=1500, **kw):
    scenes.net_impact(n=10, spacing=0.05, wire_radius=0.002, sphere_radius=0.06, speed=6.0, damping=0.2)
    old = O.engines[-1]
    # a fixed step: the time stepper also updates when the collider runs, and the two
    # integrators trigger the collider at different steps (that is the point of the Flex one)
    O.dt = 0.5 * yf.critical_timestep()
    O.engines = [e for e in O.engines[:-1] if e.label != "flexDt"] + [cls(gravity=old.gravity, damping=old.damping, **kw)]
    O.trackEnergy = True
    for _ in range(steps):
        O.step()
    dofs = [(tuple(b.state.pos), tuple(b.state.vel), tuple(b.state.angVel), tuple(b.state.ori)) for b in O.bodies
            if b is not None and type(b.shape).__name__ != "FlexCylinder"]
    return dofs, {k: O.energy[k] for k in O.energy.keys()}, O.engines[-1]


def _spheres():
    return [k for k, b in enumerate(b for b in O.bodies if b is not None and type(b.shape).__name__ != "FlexCylinder")
            if type(b.shape).__name__ == "Sphere"]


def _same_energy(ea, eb):
    """Same terms; the integrator's terms (kinetic, gravWork, nonviscDamp) equal to the round-off
    of the order of summation: FlexNewtonIntegrator sums its bodies' terms and books the sum once
    per step, NewtonIntegrator books body by body (a relative 1e-12 is ~1e3 x that round-off)."""
    assert set(ea) == set(eb)
    for k in ea:
        assert eb[k] == pytest.approx(ea[k], rel=1e-12, abs=1e-12 * max(abs(v) for v in ea.values())), k


def test_same_motion_and_energy_as_newton_integrator(scene):
    a, ea, _ = _run(NewtonIntegrator)
    b, eb, e = _run(FlexNewtonIntegrator, sphereOrientation=True)
    assert e.usedFastPath
    assert a == b
    _same_energy(ea, eb)


def test_spheres_keep_their_orientation_and_move_the_same(scene):
    """By default the fast path leaves a sphere's orientation alone (no force depends on it):
    every other DOF, and the nodes' orientations, as NewtonIntegrator's, bit for bit."""
    a, ea, _ = _run(NewtonIntegrator)
    spheres = _spheres()
    b, eb, e = _run(FlexNewtonIntegrator)
    assert e.usedFastPath and not e.sphereOrientation and spheres
    for k, (da, db) in enumerate(zip(a, b)):
        assert da[:3] == db[:3], k
        if k in spheres:
            assert db[3] == (0.0, 0.0, 0.0, 1.0) and da[3] != db[3], k  # NewtonIntegrator's turned
        else:
            assert da[3] == db[3], k
    _same_energy(ea, eb)
    assert ea["nonviscDamp"] > 0 and ea["flexFriction"] > 0


def test_falls_back_for_aspherical_bodies(scene):
    from yade.wrapper import Body, Box, FrictMat
    from yade.minieigenHP import Vector3
    mat = yf.steel()
    yf.chain([(0, 0, 0), (1, 0, 0)], 0.01, mat, segments=2, fixed=[0])
    b = Body()
    b.shape = Box(extents=Vector3(0.1, 0.1, 0.1))
    b.material = FrictMat(density=1000)
    b.state.mass, b.state.inertia = 8.0, Vector3(1, 1, 1)
    b.state.pos = Vector3(0, 0, 2)
    b.aspherical = True
    O.bodies.append(b)
    O.engines = yf.engines()
    O.step()
    O.step()
    assert not O.engines[-1].usedFastPath
    assert O.bodies[b.id].state.vel[2] < 0  # still integrated (by NewtonIntegrator's loop)


def _run_clump(cls, steps=1500, rotate=True):
    """net_impact with its ball replaced by a tumbling cube clump of 3 x 3 x 3 spheres (isotropic
    inertia, not aspherical: the spherical rotation update is exact for it)."""
    from yade.wrapper import Body, Sphere
    from yade.minieigenHP import Vector3
    s = scenes.net_impact(n=10, spacing=0.05, wire_radius=0.002, sphere_radius=0.06, speed=6.0, damping=0.2)
    ball = O.bodies[s["sphere"]]
    c, v, mat = Vector3(ball.state.pos), Vector3(ball.state.vel), ball.material
    O.bodies.erase(s["sphere"])
    r = 0.02
    members = []
    for i in range(3):
        for j in range(3):
            for k in range(3):
                b = Body()
                b.shape = Sphere(radius=r)
                b.material = mat
                b.state.pos = c + Vector3(2 * r * (i - 1), 2 * r * (j - 1), 2 * r * (k - 1) + 0.01)
                members.append(b)
    cid = O.bodies.appendClumped(members)[0]
    cl = O.bodies[cid]
    cl.state.mass = 5.0
    cl.state.inertia = Vector3(1, 1, 1) * 5.0 * (6 * r) ** 2 / 6
    cl.aspherical = False
    cl.state.vel = v
    if rotate:
        cl.state.angVel = Vector3(3.0, -2.0, 1.0)
    old = O.engines[-1]
    O.dt = 0.5 * yf.critical_timestep()
    O.engines = [e for e in O.engines[:-1] if e.label != "flexDt"] + [cls(gravity=old.gravity, damping=old.damping)]
    O.trackEnergy = True
    z0 = cl.state.pos[2]
    for _ in range(steps):
        O.step()
    dofs = [(tuple(b.state.pos), tuple(b.state.vel), tuple(b.state.angVel), tuple(b.state.ori)) for b in O.bodies
            if b is not None and type(b.shape).__name__ != "FlexCylinder"]
    return dofs, {k: O.energy[k] for k in O.energy.keys()}, O.engines[-1], z0 - cl.state.pos[2]


def test_clumps_take_the_fast_path_with_the_same_motion_and_energy(scene):
    a, ea, _, _ = _run_clump(NewtonIntegrator)
    b, eb, e, drop = _run_clump(FlexNewtonIntegrator)
    assert e.usedFastPath
    assert drop > 0.02  # the clump fell onto the net and pushed it down
    assert a == b
    _same_energy(ea, eb)
    assert ea["nonviscDamp"] > 0 and ea["flexFriction"] > 0


def _damped_sphere(blocked, vel, gravity, steps=200, integrator=FlexNewtonIntegrator, aspherical=False):
    from yade import utils
    from yade.minieigenHP import Vector3
    O.reset()
    b = utils.sphere((0, 0, 0), 0.05, material=yf.steel())
    b.aspherical = aspherical  # an aspherical body sends FlexNewtonIntegrator to NewtonIntegrator's loop
    b.state.blockedDOFs = blocked
    b.state.vel = Vector3(*vel)
    O.bodies.append(b)
    O.engines = [integrator(gravity=gravity, damping=0.3)]
    O.dt = 1e-4
    O.trackEnergy = True
    for _ in range(steps):
        O.step()
    return O.energy["nonviscDamp"] if "nonviscDamp" in O.energy.keys() else 0.0, b


def test_damping_is_booked_on_free_dofs_only(scene):
    """Local damping acts on free DOFs only, so only they book nonviscDamp. A sphere driven
    along x (blocked, gravity along x pushing against the driver) books nothing;
    NewtonIntegrator books c |v||m g| dt per step there (shown here, it is what we differ
    from). Blocked in x and free in z, it books exactly what the same sphere falling freely
    along z books."""
    g = (-9.81, 0, 0)
    e_flex, b = _damped_sphere("xyzXYZ", (1, 0, 0), g)
    assert e_flex == 0.0 and b.state.pos[0] == pytest.approx(200 * 1e-4)
    e_newton, _ = _damped_sphere("xyzXYZ", (1, 0, 0), g, integrator=NewtonIntegrator)
    assert e_newton == pytest.approx(0.3 * b.state.mass * 9.81 * 1.0 * 1e-4 * 200, rel=1e-9)
    e_part, bp = _damped_sphere("x", (1, 0, 0), (-9.81, 0, -9.81))
    e_free, bf = _damped_sphere("", (0, 0, 0), (0, 0, -9.81))
    assert bp.state.pos[2] == bf.state.pos[2] < 0 and bp.state.vel[0] == 1.0
    assert e_free > 0 and e_part == e_free


def test_fallback_path_books_damping_on_free_dofs_only(scene):
    """On NewtonIntegrator's loop (the fallback, here for an aspherical body) the same holds:
    a driven sphere books no damping, and blocked in x, free in z, it books what the free fall
    books, while NewtonIntegrator itself books c |v||m g| dt on the driven DOF."""
    g = (-9.81, 0, 0)
    e_flex, b = _damped_sphere("xyzXYZ", (1, 0, 0), g, aspherical=True)
    assert not O.engines[-1].usedFastPath
    assert e_flex == 0.0 and b.state.pos[0] == pytest.approx(200 * 1e-4)
    e_newton, _ = _damped_sphere("xyzXYZ", (1, 0, 0), g, integrator=NewtonIntegrator, aspherical=True)
    assert e_newton == pytest.approx(0.3 * b.state.mass * 9.81 * 1.0 * 1e-4 * 200, rel=1e-9)
    e_part, bp = _damped_sphere("x", (1, 0, 0), (-9.81, 0, -9.81), aspherical=True)
    assert not O.engines[-1].usedFastPath
    e_free, bf = _damped_sphere("", (0, 0, 0), (0, 0, -9.81), aspherical=True)
    assert bp.state.pos[2] == bf.state.pos[2] < 0 and bp.state.vel[0] == 1.0
    assert e_free > 0 and e_part == pytest.approx(e_free, rel=1e-12)
