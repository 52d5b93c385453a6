"""Contacts on deformable cylinders: one contact at shared nodes, continuous force, exact
kinematics, balance, no NaN, detection following both nodes."""
import math

import pytest
from yade import O
from yade.minieigenHP import Vector3

import yadeflex as yf
from yadeflex.harness import scenes
from yadeflex.harness.scenes import sphere
from tol import assert_rel


def _clamped_chain(points, r, mat):
    nodes, cyls = yf.chain(points, r, mat)
    yf.fix(nodes)
    return nodes, cyls


def _active(body):
    return yf.contacts_on(body)


def _prescribe(body, vel=(0, 0, 0), angvel=(0, 0, 0)):
    s = O.bodies[body].state
    s.blockedDOFs = "xyzXYZ"
    s.vel = Vector3(*vel)
    s.angVel = Vector3(*angvel)


@pytest.mark.parametrize("friction_deg", [0.0, 30.0])
def test_sphere_sliding_across_shared_node_one_contact_continuous_force(scene, friction_deg):
    r, R, delta, v = 0.005, 0.02, 1e-4, 0.5
    mat = yf.steel(friction_deg=friction_deg)
    _clamped_chain([(-0.2, 0, 0), (0, 0, 0), (0.2, 0, 0)], r, mat)
    s = sphere((-0.01, 0, R + r - delta), R, young=1e9, friction_deg=friction_deg)
    _prescribe(s, vel=(v, 0, 0))
    O.engines = yf.engines(gravity=(0, 0, 0))
    forces, counts = [], []
    while O.bodies[s].state.pos[0] < 0.01:
        O.step()
        counts.append(len(_active(s)))
        forces.append(Vector3(O.forces.f(s)))
    assert set(counts) == {1}, "exactly one contact at every step, also at the shared node"
    steady = forces[len(forces) // 4:]  # after the shear spring has reached its limit
    scale = max(f.norm() for f in steady)
    jump = max((steady[k] - steady[k - 1]).norm() for k in range(1, len(steady)))
    assert jump < 0.01 * scale, f"force jump {jump / scale:.2e} of the force"
    # crossed the node: both segments carried the contact
    fn = steady[-1][2]
    assert fn > 0
    if friction_deg:
        assert_rel(-steady[-1][0], math.tan(math.radians(friction_deg)) * fn, 1e-6, "Coulomb sliding force")


@pytest.mark.parametrize("x_cross", [0.0, 0.1])
def test_cylinder_crossing_chain_at_node_gets_same_force_as_midspan(scene, x_cross):
    r, delta = 0.005, 2e-4
    mat = yf.steel(friction_deg=0)
    _clamped_chain([(-0.2, 0, 0), (0, 0, 0), (0.2, 0, 0)], r, mat)
    bn, bc = _clamped_chain([(x_cross, -0.1, 2 * r - delta), (x_cross, 0.1, 2 * r - delta)], r, mat)
    O.engines = yf.engines(gravity=(0, 0, 0))
    O.dt = 1e-8
    O.step()
    contacts = _active(bc[0])
    assert len(contacts) == 1
    kn = contacts[0].phys.kn
    fz = sum(O.forces.f(n)[2] for n in bn)
    assert_rel(fz, kn * delta, 1e-9, f"contact force crossing at x={x_cross}")


@pytest.mark.parametrize("L", [0.1, 1.0, 10.0])
def test_rigid_rotation_with_sphere_riding_gives_zero_slip(scene, L):
    r, R, delta = 0.01, 0.05, 1e-4
    mat = yf.steel()
    nodes, cyls = yf.chain([(0, 0, 0), (L, 0, 0)], r, mat)
    s = sphere((0.3 * L, 0, r + R - delta), R)
    w, c = Vector3(0.3, -0.2, 1.0), Vector3(0.1 * L, 0.2, -0.1)
    for b in nodes + [s]:
        st = O.bodies[b].state
        st.vel = w.cross(st.pos - c)
        st.angVel = w
    O.engines = yf.engines(gravity=(0, 0, 0))
    O.dt = 1e-9
    O.step()
    i = _active(s)[0]
    assert i.geom.relVel.norm() < 1e-12 * w.norm() * L, f"slip velocity {i.geom.relVel.norm()} m/s under rigid rotation"


def _two_cylinders(a0, a1, b0, b1, r=0.005):
    mat = yf.steel(friction_deg=0)
    an, ac = _clamped_chain([a0, a1], r, mat)
    bn, bc = _clamped_chain([b0, b1], r, mat)
    O.engines = yf.engines(gravity=(0, 0, 0))
    O.dt = 1e-8
    O.step()
    return an, ac, bn, bc


def test_parallel_cylinders_contact_mid_overlap(scene):
    r, delta = 0.005, 1e-4
    an, ac, bn, bc = _two_cylinders((0, 0, 0), (1, 0, 0), (0.5, 2 * r - delta, 0), (1.5, 2 * r - delta, 0), r)
    (i,) = _active(ac[0])
    assert i.geom.contactPoint[0] == pytest.approx(0.75, abs=1e-12)  # middle of the overlap [0.5, 1]
    assert abs(abs(i.geom.normal[1]) - 1) < 1e-12
    assert_rel(sum(O.forces.f(n)[1] for n in bn), i.phys.kn * delta, 1e-9, "parallel contact force")


def test_intersecting_axes_give_finite_normal_and_force(scene):
    r = 0.005
    an, ac, bn, bc = _two_cylinders((-0.1, 0, 0), (0.1, 0, 0), (0, -0.1, 0), (0, 0.1, 0), r)
    (i,) = _active(ac[0])
    n = i.geom.normal
    assert all(math.isfinite(x) for x in n) and abs(abs(n[2]) - 1) < 1e-12  # perpendicular to both axes
    f = sum((O.forces.f(k) for k in bn), Vector3(0, 0, 0))
    assert all(math.isfinite(x) for x in f)
    assert_rel(f.norm(), i.phys.kn * 2 * r, 1e-9, "full overlap force")


def test_sphere_centre_on_axis_is_finite(scene):
    mat = yf.steel()
    _clamped_chain([(0, 0, 0), (1, 0, 0)], 0.01, mat)
    s = sphere((0.5, 0, 0), 0.02)
    _prescribe(s)
    O.engines = yf.engines(gravity=(0, 0, 0))
    O.dt = 1e-8
    O.step()
    (i,) = _active(s)
    assert all(math.isfinite(x) for x in i.geom.normal) and abs(i.geom.normal[0]) < 1e-12
    assert all(math.isfinite(x) for x in O.forces.f(s))


def test_swinging_cylinder_cannot_pass_through_sphere(scene):
    L, r, R = 1.0, 0.01, 0.03
    mat = yf.steel()
    nodes, cyls = yf.chain([(0, 0, 0), (L, 0, 0)], r, mat)
    yf.fix([nodes[0]])
    wz = 20.0  # rad/s about the fixed node: the far end moves at 20 m/s
    O.bodies[nodes[1]].state.vel = Vector3(0, wz * L, 0)
    O.bodies[nodes[1]].state.angVel = Vector3(0, 0, wz)
    th = 0.3
    s = sphere((0.9 * L * math.cos(th), 0.9 * L * math.sin(th), 0), R)
    O.engines = yf.engines(gravity=(0, 0, 0))
    hit = False
    while O.time < 0.05:  # the tip reaches the sphere after ~0.015 s
        O.step()
        hit = hit or bool(_active(s))
    assert hit, "the sphere was never touched"
    sv = O.bodies[s].state.vel
    assert sv.norm() > 1.0, "the sphere was not pushed"
    assert sv.dot(Vector3(-math.sin(th), math.cos(th), 0)) > 0  # pushed along the swing


def test_force_and_moment_balance_whole_scene(scene):
    """Newton's third law: bonds and contacts together put zero net force and moment."""
    import random
    rnd = random.Random(3)
    mat = yf.steel(friction_deg=30)
    grid, cyls = yf.net(4, 0.05, 0.003, mat, fix_border=False)
    bn, bc = yf.chain([(0.02, -0.05, 0.0055), (0.08, 0.2, 0.0058)], 0.003, mat)
    s = sphere((0.075, 0.075, 0.0285), 0.026, young=1e9)
    ids = [n for row in grid for n in row] + bn + [s]
    for i in ids:
        O.bodies[i].state.vel = Vector3(rnd.uniform(-1, 1), rnd.uniform(-1, 1), rnd.uniform(-1, 1)) * 0.05
        O.bodies[i].state.angVel = Vector3(rnd.uniform(-1, 1), rnd.uniform(-1, 1), rnd.uniform(-1, 1))
    O.engines = yf.engines(gravity=(0, 0, 0))
    n_contacts = 0
    for _ in range(50):
        x = {i: Vector3(O.bodies[i].state.pos) for i in ids}  # forces are computed at these positions
        O.step()
        F = sum((O.forces.f(i) for i in ids), Vector3(0, 0, 0))
        M = sum((x[i].cross(O.forces.f(i)) + O.forces.t(i) for i in ids), Vector3(0, 0, 0))
        scale = max(O.forces.f(i).norm() for i in ids)
        assert F.norm() <= 1e-12 * scale and M.norm() <= 1e-12 * scale, (F, M, scale)
        n_contacts = max(n_contacts, len([i for i in O.interactions if i.isReal]))
    assert n_contacts >= 2  # the sphere and the crossing cylinder touched the net


def test_bonded_neighbours_never_become_contacts(scene):
    # zig-zag with 60 degree bends: neighbouring capsules overlap near every node
    mat = yf.steel()
    pts = [(0.02 * k, 0.01 * (k % 2), 0) for k in range(12)]
    nodes, cyls = yf.chain(pts, 0.004, mat)
    O.engines = yf.engines(gravity=(0, 0, -9.81))
    for _ in range(100):
        O.step()
    assert len([i for i in O.interactions if i.isReal]) == 0
    # and they cost nothing per step: their collider pairs are gone, not merely skipped
    assert len(O.interactions) == 0


def _hairpin(delta, r=0.002):
    """A chain A-B-Q-R folded back over itself at B: P = A-B along x, X = B-Q back over P, S =
    Q-R along P at height 2r - delta (its end Q overlaps P by delta; S shares no node with P).
    All nodes held. Returns (P, X, S) cylinder ids and S's nodes."""
    mat = yf.steel(friction_deg=0)
    nodes, cyls = yf.chain([(-0.1, 0, 0), (0, 0, 0), (-0.01, 0, 2 * r - delta), (-0.05, 0, 2 * r + 0.0025)], r, mat)
    yf.fix(nodes)
    return cyls, nodes[2:]


@pytest.mark.parametrize("delta", [1e-4, 5e-4])
def test_contact_is_not_suppressed_by_a_wire_bonded_to_the_partner(scene, delta):
    # X is bonded to both P (node B) and S (node Q) and lies closer to P's closest point than S
    # does: as a member of S's cluster it used to beat S, although X can never touch P (bonded
    # neighbours), so no element carried the S-P contact and S sank into P with no force; the
    # contact then started at its full depth, 1/2 kn delta^2 from nothing (the fast small-module
    # impacts of bench/STABILITY.md, finding 5: wires sinking 6 mm into the rings)
    (p, x, s), s_nodes = _hairpin(delta)
    O.engines = yf.engines(gravity=(0, 0, 0))
    O.dt = 1e-8
    O.step()
    on_s = _active(s)
    assert [(min(i.id1, i.id2), max(i.id1, i.id2)) for i in on_s] == [(p, s)], "exactly one contact, S on P"
    assert not _active(x), "X is bonded to P and S: no contact"
    kn = on_s[0].phys.kn
    fz = sum(O.forces.f(n)[2] for n in s_nodes)
    assert_rel(fz, kn * delta, 1e-6, "S pushed off P by kn x overlap")


def _sphere_placed_into_a_wire(r, R, delta):
    """A sphere of radius R held still, placed delta deep into a clamped wire of radius r, after
    one step: (sphere id, the contact law, the contact)."""
    _clamped_chain([(-0.2, 0, 0), (0.2, 0, 0)], r, yf.steel(friction_deg=0))
    s = sphere((0.03, 0, R + r - delta), R, young=1e9, friction_deg=0)
    _prescribe(s)
    O.engines = yf.engines(gravity=(0, 0, 0))
    O.dt = 1e-8
    O.step()
    (c,) = _active(s)
    return s, yf.contact_law(), c


def test_contact_starting_overlapped_is_counted_with_its_spring_energy(scene):
    # a sphere placed into a wire: its contact starts at the full overlap, 1/2 kn delta^2 from nothing
    r, R, delta = 0.005, 0.02, 2e-4
    s, law, c = _sphere_placed_into_a_wire(r, R, delta)
    assert law.deepOnsets == 1
    assert_rel(law.deepOnsetEnergy, 0.5 * c.phys.kn * delta ** 2, 1e-9, "onset energy")
    assert_rel(c.geom.onsetDepth, delta, 1e-9, "onset depth")
    for _ in range(10):
        O.step()
    assert (law.deepOnsets, law.deepEndings) == (1, 0), "a lasting contact is counted once"


@pytest.mark.parametrize("target", ["midspan", "node"])
def test_contacts_reached_by_motion_start_within_one_step_and_hand_overs_cancel(scene, target):
    # a sphere flying at 3 m/s onto a wire chain, at mid-span or onto the shared node, starts its
    # contact within one step of approach (no deep onset); then sliding along the wire across the
    # node, its contact passes from one segment to the other: one deep ending and one deep onset
    # with the same overlap, so the same spring energy
    r, R, v = 0.005, 0.02, 3.0
    mat = yf.steel(friction_deg=0)
    _, cyls = _clamped_chain([(-0.2, 0, 0), (0, 0, 0), (0.2, 0, 0)], r, mat)
    x0 = -0.03 if target == "midspan" else 0.0
    s = sphere((x0, 0, R + r + 0.002), R, young=1e9, friction_deg=0)
    _prescribe(s, vel=(0, 0, -v))
    O.engines = yf.engines(gravity=(0, 0, 0))
    O.trackEnergy = True
    O.step()
    while not _active(s):
        O.step()
    law = yf.contact_law()
    assert (law.deepOnsets, law.deepEndings) == (0, 0)
    O.bodies[s].state.vel = Vector3(2 * v, 0, 0)  # now slide along the wire, across the node
    owners = []
    while O.bodies[s].state.pos[0] < x0 + 0.05:
        O.step()
        (c,) = _active(s)
        owners.append(c.id1 + c.id2 - s)
    assert owners[0] == cyls[0] and owners[-1] == cyls[1], "the contact passed from one segment to the other"
    assert (law.deepOnsets, law.deepEndings) == (1, 1)
    # the same overlap up to its change in one step (here none: sliding along a straight wire)
    assert_rel(law.deepOnsetEnergy, law.deepEndingEnergy, 1e-4, "a hand-over passes on its spring energy")
    # booked as it happens: the ending books its spring as lost, the onset books it back
    assert abs(O.energy["flexHandover"]) <= 1e-4 * law.deepEndingEnergy, (O.energy["flexHandover"], law.deepEndingEnergy)


def test_the_law_keeps_the_largest_overlap_ratio_of_any_step(scene):
    # a sphere placed into a wire: the largest overlap / reach (R + r) is the placed overlap, with
    # the two bodies; set to 0 it starts again from the current step
    r, R, delta = 0.005, 0.02, 2e-4
    s, law, c = _sphere_placed_into_a_wire(r, R, delta)
    assert_rel(law.maxOverlapRatio, delta / (R + r), 1e-9, "largest overlap ratio")
    assert_rel(law.maxOverlapRatio, c.geom.penetrationDepth / (c.geom.refR1 + c.geom.refR2), 1e-12, "the contact's own")
    assert sorted(law.maxOverlapIds) == sorted((c.id1, c.id2))
    O.bodies[s].state.pos = O.bodies[s].state.pos + Vector3(0, 0, 0.5 * delta)  # half the overlap
    law.maxOverlapRatio = 0.0
    O.step()
    assert_rel(law.maxOverlapRatio, 0.5 * delta / (R + r), 1e-6, "after a reset: this step's")
