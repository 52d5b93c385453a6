"""Builders: nodes, deformable cylinders, chains (wires, ropes), rings, helices, nets.

Every builder validates its input and raises ValueError naming the problem before anything
is added to the scene.
"""
import math

from yade import O
from yade.wrapper import Body, FlexNode, FlexCylinder, FlexMat
from yade.minieigenHP import Vector2i, Vector3

from . import checks as C
from . import placement


def _positive(name, v):
    return C.positive(name, v)


# the radius of a wire, bar or rope, or a membrane's thickness: from a micrometre to a metre (a
# thinner one gives its nodes a mass that underflows to 0 or a step below any use; a thicker one is
# no longer a wire or a membrane)
SECTION = C.Range(1e-6, 1.0, "m")


def _section(name, v):
    return C.number(name, v, SECTION)


check_finite = C.point  # Vector3 from 3 finite numbers (the public name of checks.point)


def lookup_material(material, cls, check=None, append=True):
    """A material of class cls given as an instance (added to O.materials if it is not there
    yet, unless append is False) or as the label of one in O.materials; ValueError naming the
    problem otherwise. check(m) may return an error text for an instance that is not usable."""
    if isinstance(material, str):
        for m in O.materials:
            if m.label == material:
                if not isinstance(m, cls):
                    raise ValueError(f"material '{material}' is a {type(m).__name__}, not a {cls.__name__}")
                material = m
                break
        else:
            raise ValueError(f"unknown material '{material}' (labels in O.materials: {[m.label for m in O.materials]})")
    if not isinstance(material, cls):
        raise ValueError(f"material must be a {cls.__name__} or the label of one, got {material!r}")
    err = check(material) if check else ""
    if err:
        raise ValueError(f"material '{material.label}': {err}")
    if material.id < 0 and append:
        O.materials.append(material)
    return material


def _material(material, append=True):
    return lookup_material(material, FlexMat, check=lambda m: m.wireError(), append=append)


def _body_ids(name, ids):
    """ids as a list after checking that each is the id of an existing body."""
    try:
        items = list(ids)
    except TypeError:
        raise C.BadValue(name, ids, "a sequence of body ids") from None
    for i in items:
        if isinstance(i, bool) or not isinstance(i, int) or not 0 <= i < len(O.bodies) or O.bodies[i] is None:
            raise C.BadValue(name, ids, f"ids of existing bodies (0 to {len(O.bodies) - 1})")
    return items


def fix(ids, dofs="xyzXYZ"):
    """Block degrees of freedom of nodes (default: clamp); dofs: letters of 'xyzXYZ'."""
    if not (isinstance(dofs, str) and set(dofs) <= set("xyzXYZ")):
        raise C.BadValue("dofs", dofs, "a string of the letters xyzXYZ")
    for i in _body_ids("ids", ids):
        O.bodies[i].state.blockedDOFs = dofs
        O.bodies[i].state.vel = Vector3(0, 0, 0)
        O.bodies[i].state.angVel = Vector3(0, 0, 0)


def _place(b, pos):
    """Body b at pos [m], both placed by the current placement (yadeflex.placement)."""
    pl = placement.current()
    if pl.is_identity():
        b.state.pos = pos
    else:
        b.state.pos = pl.point(pos)
        b.state.ori = pl.orientation(b.state.ori)


def node(pos, radius, material=None, fixed=False):
    """A FlexNode at pos [m] (placed: yadeflex.placement); radius [m] for display. Mass and
    inertia come from the cylinders attached to it. Returns the body id."""
    p = check_finite("node position", pos)
    r = _positive("node radius", radius)
    fixed = C.boolean("fixed", fixed)
    mat = _material(material) if material is not None else None
    C.body_budget("node", pos, 1)
    b = Body()
    b.shape = FlexNode(radius=r)
    _place(b, p)
    b.bounded = False  # contacts are detected on the elements
    if mat is not None:
        b.material = mat
    elif len(O.materials):
        b.material = O.materials[0]
    i = O.bodies.append(b)
    if fixed:
        fix([i])
    return i


def cylinder(node1, node2, radius, material, hook_legs=None):
    """A deformable cylinder (capsule, bond) between two FlexNode bodies. Returns its id.
    hook_legs: (a, b), the far nodes of node1's two legs: the link is a hooked knot whose node1
    stays on its side of node2 along the way its bend opens (FlexCylinder.hookLegs); None: none."""
    r = _section("cylinder radius", radius)
    mat = _material(material)
    for n in (node1, node2):
        if isinstance(n, bool) or not isinstance(n, int) or n < 0 or n >= len(O.bodies) or O.bodies[n] is None:
            raise ValueError(f"cylinder end {n!r} is not the id of an existing body")
        if not isinstance(O.bodies[n].shape, FlexNode):
            raise ValueError(f"cylinder end #{n} is a {type(O.bodies[n].shape).__name__}, not a FlexNode")
    if node1 == node2:
        raise C.BadValue("cylinder ends", (node1, node2), "two different nodes (both ends are the same node)")
    C.body_budget("cylinder", (node1, node2), 1)
    b = Body()
    b.shape = FlexCylinder(node1=node1, node2=node2, radius=r)
    if hook_legs is not None:
        legs = tuple(hook_legs) if isinstance(hook_legs, (tuple, list)) else ()
        if len(legs) != 2 or not all(isinstance(n, int) and not isinstance(n, bool) and 0 <= n < len(O.bodies) for n in legs):
            raise C.BadValue("hook legs", hook_legs, "two ids of existing nodes, the far ends of node1's legs")
        b.shape.hookLegs = Vector2i(*legs)
    b.material = mat
    b.state.pos = 0.5 * (O.bodies[node1].state.pos + O.bodies[node2].state.pos)
    i = O.bodies.append(b)
    try:
        b.shape.attach(i)
    except Exception:
        O.bodies.erase(i)
        raise
    return i


def _segments(name, n, lo=1):
    """A count of segments (or cells) that the scene has room for: 2 bodies each at most."""
    n = C.integer(name, n, lo, C.MAX_BODIES)
    C.body_budget(name, n, 2 * n + 1)
    return n


def _subdivide(points, segments, closed):
    if segments is not None:
        _segments("segments", segments)
    try:
        pts = [check_finite(f"point {k}", p) for k, p in enumerate(points)]
    except TypeError:
        raise C.BadValue("points", points, "a sequence of 3D points") from None
    if len(pts) < 2:
        raise ValueError(f"a chain needs at least 2 points, got {len(pts)}")
    if segments is None:
        return pts
    if len(pts) != 2 or closed:
        raise ValueError("segments= subdivides a straight chain between exactly 2 points")
    a, b = pts
    return [a + (b - a) * (k / segments) for k in range(segments + 1)]


def chain(points, radius, material, segments=None, closed=False, fixed=()):
    """Chain of cylinders through points (a wire, bar or rope).

    points: sequence of 3D points [m] (or two end points with segments=N); closed: join the
    last point to the first (a ring); fixed: indices of points to clamp.
    Returns (node_ids, cylinder_ids)."""
    closed = C.boolean("closed", closed)
    pts = _subdivide(points, segments, closed)
    r = _section("chain radius", radius)
    mat = _material(material)
    fixed = C.indices("fixed", fixed, len(pts))
    C.body_budget("points", f"{len(pts)} points", 2 * len(pts))
    for k in range(len(pts) - (0 if closed else 1)):
        if (pts[(k + 1) % len(pts)] - pts[k]).norm() <= 1e-9 * r:
            raise ValueError(f"points {k} and {(k + 1) % len(pts)} coincide: zero-length segment")
    nodes = [node(p, r, mat) for p in pts]
    cyls = [cylinder(nodes[k], nodes[k + 1], r, mat) for k in range(len(nodes) - 1)]
    if closed:
        cyls.append(cylinder(nodes[-1], nodes[0], r, mat))
    fix([nodes[k] for k in fixed])
    return nodes, cyls


def ring(center, ring_radius, bar_radius, material, segments=24, axis=(0, 0, 1)):
    """Closed ring of `segments` cylinders, radius ring_radius [m], bar radius [m], in the
    plane normal to axis. Returns (node_ids, cylinder_ids)."""
    c = check_finite("ring center", center)
    R = _positive("ring radius", ring_radius)
    segments = _segments("segments", segments, 3)
    ax = check_finite("ring axis", axis)
    if ax.norm() == 0:
        raise C.BadValue("ring axis", axis, "a non-zero vector")
    ax = ax / ax.norm()
    e1 = ax.cross(Vector3(1, 0, 0) if abs(ax[0]) < 0.9 else Vector3(0, 1, 0))
    e1 = e1 / e1.norm()
    e2 = ax.cross(e1)
    pts = [c + R * (math.cos(2 * math.pi * k / segments) * e1 + math.sin(2 * math.pi * k / segments) * e2) for k in range(segments)]
    return chain(pts, bar_radius, material, closed=True)


def helix(segments, coil_radius, pitch, wire_radius, material, turns=None, center=(0, 0, 0), fixed=(0,)):
    """Helix along z: `segments` cylinders over `turns` turns (default: segments/20), rising
    pitch [m] per turn. Returns (node_ids, cylinder_ids)."""
    segments = _segments("segments", segments)
    Rc = _positive("coil radius", coil_radius)
    pitch = C.number("pitch", pitch, C.Range(unit="m"))
    turns = segments / 20.0 if turns is None else _positive("turns", turns)
    c = check_finite("helix center", center)
    pts = []
    for k in range(segments + 1):
        a = 2 * math.pi * turns * k / segments
        pts.append(c + Vector3(Rc * math.cos(a), Rc * math.sin(a), pitch * turns * k / segments))
    return chain(pts, wire_radius, material, fixed=fixed)


def net(n, spacing, wire_radius, material, origin=(0, 0, 0), fix_border=True):
    """Square net of n x n nodes in the plane z = origin.z, joined by cylinders along x and
    y. Border nodes are clamped if fix_border. Returns (node_grid[i][j], cylinder_ids)."""
    n = C.integer("n", n, 2, C.MAX_BODIES)
    C.body_budget("n", n, 3.0 * n * n)
    h = _positive("spacing", spacing)
    r = _section("wire radius", wire_radius)
    o = check_finite("net origin", origin)
    fix_border = C.boolean("fix_border", fix_border)
    mat = _material(material)
    grid = [[node(o + Vector3(i * h, j * h, 0), r, mat) for j in range(n)] for i in range(n)]
    cyls = []
    for i in range(n):
        for j in range(n):
            if i + 1 < n:
                cyls.append(cylinder(grid[i][j], grid[i + 1][j], r, mat))
            if j + 1 < n:
                cyls.append(cylinder(grid[i][j], grid[i][j + 1], r, mat))
    if fix_border:
        fix([grid[i][j] for i in range(n) for j in range(n) if i in (0, n - 1) or j in (0, n - 1)])
    return grid, cyls
