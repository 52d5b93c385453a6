"""Elements against YADE's rigid surfaces: a net of wires and a geotextile sheet on a Wall, on a
floor of two Facets and on a Box (yadeflex.harness.scenes.drop_on_surface, as a user builds it). Each
node meets the surface once (pkg/kernel/Surface.hpp); asserted against the analytic bounce of a
linear spring, the statics of a structure at rest, and the energy balance."""
import math

import pytest
from yade import O
from yade.wrapper import InteractionLoop, FlexInteractionLoop

import yadeflex as yf
from yadeflex.harness import scenes

CASES = [(st, su) for st in scenes.STRUCTURES for su in scenes.SURFACES]
IDS = [f"{st}-{su}" for st, su in CASES]


def _floor_contacts(s):
    """{node id: [its active contacts with the floor]}."""
    out = {n: [] for n in s["nodes"]}
    for i in O.interactions:
        if not i.isReal or not i.geom.active:
            continue
        if i.id1 in s["floor"] and i.id2 in out:
            out[i.id2].append(i)
    return out


def _in_contact(s):
    return any(_floor_contacts(s).values())


# Dropped on its face, every node of the structure lands on its own linear spring: the contact
# lasts (pi + 2 atan(g / (w v))) / w with w = sqrt(kn / m) and v the landing speed, and the
# structure leaves with the energy it landed with (no damping: O.energy.total() in flight, a few
# steps after the contact, past the crossing correction's two steps, against its value before).
# A net of one cell: four nodes of equal mass land together (a sheet's nodes differ in mass and
# part at different times, coupled by the fabric; its balance is the next test's).
@pytest.mark.parametrize("surface", scenes.SURFACES)
def test_landing_is_the_bounce_of_a_linear_spring(scene, surface):
    structure = "net"
    s = scenes.drop_on_surface(structure, surface, drop=0.001, cells=1, velocity=(0, 0, -0.5), friction_deg=0.0)
    O.trackEnergy = True
    n = s["nodes"][0]
    g = 9.81
    st = O.bodies[n].state
    before = None
    while True:
        yf.step_until(math.inf, 1)
        if _in_contact(s):
            break
        before, e_before = 0.5 * st.vel.squaredNorm() + g * st.pos[2], O.energy.total()
        assert O.time < 0.05, "the structure never reached the floor"
    landing = math.sqrt(2 * (before - g * st.pos[2]))  # the speed at the first overlap
    t0, steps, kn = O.time - O.dt, 0, None
    while any(_floor_contacts(s)[m] for m in s["nodes"]):
        if _floor_contacts(s)[n]:
            (c,) = _floor_contacts(s)[n]
            kn, t1 = c.phys.kn, O.time
        assert min(O.bodies[m].state.pos[2] for m in s["nodes"]) > 0, "a node passed through the floor"
        yf.step_until(math.inf, 1)
        steps += 1
        assert steps < 100000, "the structure never left the floor"
    lasted = t1 - t0
    yf.step_until(math.inf, 4)
    w = math.sqrt(kn / st.mass)
    expected = (math.pi + 2 * math.atan(g / (w * landing))) / w
    assert abs(lasted - expected) <= 2 * O.dt + 0.01 * expected, f"contact lasted {lasted:.3e} s, a linear spring {expected:.3e} s"
    ke = 0.5 * sum(O.bodies[m].state.mass for m in s["nodes"]) * landing ** 2
    assert O.energy.total() == pytest.approx(e_before, abs=0.01 * ke), f"the structure landed with {ke:.3e} J"


# At rest on the floor, each node touches it through exactly one contact, whichever facet of the
# floor it lies on (the nodes on the floor's diagonal lie on both facets' shared edge), and the
# floor carries the structure's weight; a node of the sheet (no bending stiffness) carries its
# own weight (the net's bars bend a little as nodes of different mass sink differently).
@pytest.mark.parametrize("structure,surface", CASES, ids=IDS)
def test_resting_structure_carries_each_node_once(scene, structure, surface):
    s = scenes.drop_on_surface(structure, surface, drop=0.002, damping=0.6)
    yf.step_until(0.3, 10 ** 6)
    speed = max(O.bodies[n].state.vel.norm() for n in s["nodes"])
    assert speed < 1e-3, f"not at rest: {speed:.2e} m/s"
    per_node = _floor_contacts(s)
    counts = {n: len(c) for n, c in per_node.items()}
    assert set(counts.values()) == {1}, f"contacts per node: {sorted(set(counts.values()))}"
    if surface == "facets":
        on_diagonal = [n for n in s["nodes"] if abs(O.bodies[n].state.pos[0] - O.bodies[n].state.pos[1]) < 1e-9]
        assert len(on_diagonal) >= 2, "no node lies on the facets' shared edge"
    total = sum(O.bodies[n].state.mass for n in s["nodes"]) * 9.81
    assert sum(c.phys.normalForce.norm() for (c,) in per_node.values()) == pytest.approx(total, rel=0.01)
    if structure == "sheet":
        for n, (c,) in per_node.items():
            assert c.phys.normalForce.norm() == pytest.approx(O.bodies[n].state.mass * 9.81, rel=0.01), f"node {n}"
    assert sum(O.forces.f(f)[2] for f in s["floor"]) == pytest.approx(-total, rel=0.01)
    assert min(O.bodies[n].state.pos[2] for n in s["nodes"]) > 0


# No damping: what the structure gains or loses over its bounces, compared when it is in flight
# (no contact at either end of a step), stays within 1% of the energy of the drop; also with a
# floor as stiff as steel on steel (the time step counts the node contacts).
@pytest.mark.parametrize("structure,surface,young", [c + (1e8,) for c in CASES] + [("net", "wall", 2e11)],
                         ids=IDS + ["net-wall-steel"])
def test_bounces_close_the_energy(scene, structure, surface, young):
    s = scenes.drop_on_surface(structure, surface, drop=0.01, contact_young=young)
    O.trackEnergy = True
    yf.step_until(math.inf, 1)
    tot0 = O.energy.total()
    drop = sum(O.bodies[n].state.mass for n in s["nodes"]) * 9.81 * 0.01
    worst, landings, was = 0.0, 0, False
    while O.time < 0.15:
        yf.step_until(math.inf, 1)
        now = _in_contact(s)
        if now and not was:
            landings += 1
        if not now and not was:
            worst = max(worst, abs(O.energy.total() - tot0))
        was = now
        assert min(O.bodies[n].state.pos[2] for n in s["nodes"]) > 0, "a node passed through the floor"
    assert landings >= 2, f"{landings} landings"
    assert worst <= 0.01 * drop, f"residual in flight {worst:.2e} J = {100 * worst / drop:.2f}% of the drop's {drop:.2e} J"


def test_engines_carry_the_surface_functors(scene):
    names = {type(f).__name__ for f in yf.engines()[2].geomDispatcher.functors}
    assert {"Ig2_Wall_FlexNode_FlexContactGeom", "Ig2_Box_FlexNode_FlexContactGeom", "Ig2_Facet_FlexNode_FlexContactGeom",
            "Ig2_Box_FlexCylinder_FlexContactGeom", "Ig2_Facet_FlexCylinder_FlexContactGeom",
            "Ig2_Box_FlexFacet_FlexContactGeom", "Ig2_Facet_FlexFacet_FlexContactGeom"} <= names


# Elements and a surface the interaction loop cannot make them touch: refused at the first step,
# naming the functor, instead of falling through without a word.
@pytest.mark.parametrize("structure,surface,functor", [("net", "wall", "Ig2_Wall_FlexNode_FlexContactGeom"), ("net", "facets", "Ig2_Facet_FlexNode_FlexContactGeom"),
                                                       ("net", "box", "Ig2_Box_FlexNode_FlexContactGeom"),
                                                       ("sheet", "facets", "Ig2_Facet_FlexFacet_FlexContactGeom"),
                                                       ("sheet", "box", "Ig2_Box_FlexFacet_FlexContactGeom")])
def test_a_loop_without_the_surface_functor_is_refused(scene, structure, surface, functor):
    scenes.drop_on_surface(structure, surface)
    loop = O.engines[2]
    kept = [f for f in loop.geomDispatcher.functors if type(f).__name__ != functor]
    O.engines = O.engines[:2] + [FlexInteractionLoop(kept, loop.physDispatcher.functors, loop.lawDispatcher.functors)] + O.engines[3:]
    with pytest.raises(ValueError, match=functor):
        O.step()
    scenes.drop_on_surface(structure, surface)
    O.engines = O.engines[:2] + [InteractionLoop(kept, loop.physDispatcher.functors, loop.lawDispatcher.functors)] + O.engines[3:]
    with pytest.raises(ValueError, match=functor):
        O.step()


def test_a_shape_elements_cannot_touch_is_refused(scene):
    from yade import wrapper
    scenes.drop_on_surface("net", "wall")
    other = next(getattr(wrapper, c) for c in ("Tetra", "Polyhedra", "PFacet") if hasattr(wrapper, c))
    b = wrapper.Body()
    b.shape = other()
    b.material = O.materials[0]
    b.state.blockedDOFs = "xyzXYZ"
    O.bodies.append(b)
    with pytest.raises(ValueError, match=f"is a {other.__name__}, which yade-flex elements cannot touch"):
        O.step()


# A block smaller than a cell of the net meets the wires between their nodes, at its edges: it is
# caught and thrown back (no damping), with the energy balance closed to 1% of its impact energy
# at every step; a clump of two boxes as well (its members' forces go to the clump).
@pytest.mark.parametrize("clump", [False, True], ids=["box", "clump"])
def test_block_smaller_than_a_cell_is_caught_by_the_wires(scene, clump):
    s = scenes.block_on_net(clump=clump)
    st = O.bodies[s["block"]].state
    O.trackEnergy = True
    yf.step_until(math.inf, 1)
    tot0, ke = O.energy.total(), 0.5 * st.mass * st.vel.squaredNorm()
    worst, lowest, edges = 0.0, math.inf, 0
    while st.vel[2] <= 0:
        yf.step_until(math.inf, 1)
        worst = max(worst, abs(O.energy.total() - tot0))
        lowest = min(lowest, st.pos[2])
        edges = max(edges, sum(1 for i in O.interactions if i.geom.active and i.id1 in s["members"] and i.id2 in s["cylinders"]))
        assert O.time < 0.1, f"the block passed the net (centre at z = {st.pos[2]:.3f} m)"
    assert edges >= 2, "the wires did not meet the block at its edges"
    assert lowest - 0.03 > -0.01, f"the block's underside reached z = {lowest - 0.03:.4f} m"
    assert worst <= 0.01 * ke, f"energy residual {worst:.2e} J = {100 * worst / ke:.2f}% of the impact energy {ke:.3f} J"



def _block_rebound(clump):
    """The block's velocity [m/s] 0.03 s after it starts 7 mm above the net, and the most active
    contacts that any one point carries twice (two members' contacts with one element at one point)."""
    s = scenes.block_on_net(clump=clump)
    st = O.bodies[s["block"]].state
    doubled = 0
    while O.time < 0.03:
        yf.step_until(math.inf, 1)
        seen = {}
        for i in O.interactions:
            if i.isReal and i.geom.active and i.id1 in s["members"]:
                seen.setdefault(i.id2, []).append(i.geom.contactPoint)
        doubled = max(doubled, sum(1 for pts in seen.values() for k, p in enumerate(pts) for q in pts[k + 1:] if (p - q).norm() < 1e-9))
    return st.vel, doubled


# A clump of two boxes with the outline of one box (its seam, where the members touch, right over
# a wire): its members' edges on the seam lie inside the clump's face, and the wire under the seam
# touches both members' bottom edges at one point: one contact (kernel/Surface.hpp, ownsOnUnion).
# The clump bounces off the net as the box does: the same velocity 0.03 s on, to 0.1% (before, the
# seam's two contacts pushed twice and the clump left 2.8% slower).
def test_a_clump_of_boxes_bounces_as_the_box_of_its_outline(scene):
    v_box, _ = _block_rebound(False)
    v_clump, doubled = _block_rebound(True)
    assert doubled == 0, f"{doubled} points carried twice by the clump's members"
    assert v_box[2] > 0.5, f"the box did not bounce: {v_box}"
    assert (v_clump - v_box).norm() <= 1e-3 * v_box.norm(), f"clump {v_clump} against box {v_box}"

def _below_ridge(s):
    """How far the axis of a wire crossing the ridge (x = 0.5 m, z = 0) passes below it [m] (0:
    none does), at the crossing."""
    worst = 0.0
    for e in s["elements"]:
        a, b = (O.bodies[n].state.pos for n in (O.bodies[e].shape.node1, O.bodies[e].shape.node2))
        if (a[0] - 0.5) * (b[0] - 0.5) < 0:
            t = (0.5 - a[0]) / (b[0] - a[0])
            worst = max(worst, -(a[2] + t * (b[2] - a[2])))
    return worst


def _ridge_contacts(s):
    cyl = set(s["elements"])
    return [i for i in O.interactions if i.isReal and i.geom.active and i.id1 in s["roof"] and i.id2 in cyl]


# A net dropped on the sharp ridge of a roof of facets that runs between two columns of its nodes:
# the wires crossing the ridge meet it between their nodes, one contact each (the ridge is an edge
# of two facets), and hold the net on it (node contacts alone let the ridge pass through the net:
# its nodes first touch the slopes 29 mm below the ridge). Undamped, the energy balance closes to
# 1% of the gravity work done on the net at every step; damped, the net comes to rest on the ridge
# and the roof carries its weight.
def test_wires_meet_a_ridge_of_facets_between_their_nodes(scene):
    s = scenes.net_on_ridge(drop=0.005)
    O.trackEnergy = True
    yf.step_until(math.inf, 1)
    tot0 = O.energy.total()
    crossing = 6  # (cells + 1) wires cross the ridge
    worst, deepest, most = 0.0, 0.0, 0
    while O.time < 0.08:
        yf.step_until(math.inf, 1)
        worst = max(worst, abs(O.energy.total() - tot0))
        deepest = max(deepest, _below_ridge(s))
        on = _ridge_contacts(s)
        most = max(most, len(on))
        assert len({i.id2 for i in on}) == len(on), "a wire carries two contacts with the ridge"
    work = -O.energy["gravWork"]
    assert most == crossing, f"{most} wires met the ridge, {crossing} cross it"
    assert deepest < 0.003, f"a wire's axis passed {1000 * deepest:.1f} mm below the ridge (wire radius 3 mm)"
    assert work > 0 and worst <= 0.01 * work, f"energy residual {worst:.2e} J = {100 * worst / work:.2f}% of the gravity work {work:.2e} J"


def test_a_net_rests_on_a_ridge_of_facets(scene):
    s = scenes.net_on_ridge(drop=0.002, damping=0.6)
    yf.step_until(0.4, 10 ** 6)
    speed = max(O.bodies[n].state.vel.norm() for n in s["nodes"])
    assert speed < 1e-3, f"not at rest: {speed:.2e} m/s"
    weight = sum(O.bodies[n].state.mass for n in s["nodes"]) * 9.81
    assert sum(O.forces.f(f)[2] for f in s["roof"]) == pytest.approx(-weight, rel=0.01)
    assert len(_ridge_contacts(s)) == 6
    assert _below_ridge(s) < 0.003


def _sheet_height_at(s, x, y):
    """Height of the sheet's midplane over (x, y) [m] (the facet over it; None: none)."""
    for f in s["elements"]:
        sh = O.bodies[f].shape
        p = [O.bodies[n].state.pos for n in (sh.node1, sh.node2, sh.node3)]
        d = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1])
        u = ((x - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (y - p[0][1])) / d
        v = ((p[1][0] - p[0][0]) * (y - p[0][1]) - (x - p[0][0]) * (p[1][1] - p[0][1])) / d
        if u >= 0 and v >= 0 and u + v <= 1:
            return p[0][2] + u * (p[1][2] - p[0][2]) + v * (p[2][2] - p[0][2])
    return None


# A sheet dropped onto a box corner that points up under the middle of one of its cells (on the
# diagonal two facets share): the corner meets the fabric between its nodes
# (Ig2_Box_FlexFacet_FlexContactGeom) and throws it back; the corner never reaches the sheet's
# midplane (before, it passed through the fabric without a contact, its nodes far from the corner),
# and undamped the energy balance closes to 1% of the gravity work done on the sheet at every step.
def test_a_sheet_meets_a_box_corner_between_its_nodes(scene):
    s = scenes.sheet_on_corner(drop=0.005)
    O.trackEnergy = True
    yf.step_until(math.inf, 1)
    tot0 = O.energy.total()
    worst, lowest, touched = 0.0, math.inf, 0
    while O.time < 0.1:
        yf.step_until(math.inf, 1)
        worst = max(worst, abs(O.energy.total() - tot0))
        z = _sheet_height_at(s, 0.5, 0.5)
        if z is not None:
            lowest = min(lowest, z)
        touched += any(i.isReal and i.geom.active and i.id1 == s["box"] and i.id2 in s["elements"] for i in O.interactions.withBody(s["box"]))
    work = -O.energy["gravWork"]
    assert touched > 0, "the corner never touched the sheet's facets"
    assert lowest > 0, f"the corner passed {1000 * -lowest:.2f} mm through the sheet's midplane"
    assert work > 0 and worst <= 0.01 * work, f"energy residual {worst:.2e} J = {100 * worst / work:.2f}% of the gravity work {work:.2e} J"


def _ridge_sheet_depth(s):
    """How far the ridge (x = 0.5 m, z = 0) rises above the sheet's midplane [m] (negative: it does
    not reach it), along the ridge under the sheet."""
    return max(-z for z in (_sheet_height_at(s, 0.5, 0.25 + 0.01 * k) for k in range(1, 50)) if z is not None)


# A sheet dropped across a ridge of facets (the net's scene with a geotextile sheet): the ridge
# meets the fabric between its nodes (Ig2_Facet_FlexFacet_FlexContactGeom, before: no contact
# until its nodes reached the slopes 29 mm below the ridge) and never reaches the midplane. The
# ridge lies along the sheet, a line contact carried at the point of each facet nearest the ridge:
# as the sheet drapes those points merge at the facets' shared edges and part again, and a
# merging contact's spring goes with it (README, current limits). That energy is booked as it
# goes ('flexHandover': lost, never made), so undamped the balance closes to 1% of the gravity
# work done on the sheet at every step.
def test_a_sheet_meets_a_ridge_of_facets_between_its_nodes(scene):
    s = scenes.net_on_ridge(drop=0.005, structure="sheet")
    O.trackEnergy = True
    yf.step_until(math.inf, 1)
    tot0 = O.energy.total()
    worst, made, deepest = 0.0, 0.0, -math.inf
    while O.time < 0.08:
        yf.step_until(math.inf, 1)
        worst = max(worst, abs(O.energy.total() - tot0))
        made = max(made, -O.energy["flexHandover"] if "flexHandover" in O.energy.keys() else 0.0)
        deepest = max(deepest, _ridge_sheet_depth(s))
    work = -O.energy["gravWork"]
    assert deepest < 0, f"the ridge passed {1000 * deepest:.2f} mm through the sheet's midplane"
    assert work > 0 and worst <= 0.01 * work, f"energy residual {worst:.2e} J = {100 * worst / work:.2f}% of the gravity work {work:.2e} J"
    assert made <= 1e-3 * work, f"contact hand-overs made {made:.2e} J = {100 * made / work:.2f}% of the gravity work"
