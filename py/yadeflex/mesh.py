"""Chain-link (TECCO-type) wire mesh: planar panels and cylinders, rings on its edges.

Geometry. A chain-link mesh is a row of spiral wires, each a flattened zigzag along its axis,
every bend hooked into the bend of the neighbouring spiral. In the plane (x across the spirals,
y along them) the bends sit on the lattice points (i a, k h) with i + k even, where a = Dx/2
and h = Dy/2 are half the rhombus diagonals (TECCO G65/3: Dx = 83 mm, Dy = 143 mm). Spiral s
(s = 0 .. nx-1) runs through the columns s and s+1: at row k it is in column
s + ((s + k) mod 2). Cells are rhombi with diagonals Dx (along x) and Dy (along y); each leg (a
cylinder) is sqrt(a^2 + h^2) long.

Directions. Along the spirals (y) each spiral is one continuous wire: a section y = const cuts
2/Dx legs per metre, an upper bound of 2/Dx fu A = 301 kN/m for TECCO G65/3. Across the spirals
(x) the load passes from spiral to spiral through the knots, and the rhombi open and close as
a mechanism. We take the datasheet's longitudinal direction, 150 kN/m, to be along the
spirals. In the model, across the spirals the panel is a mechanism: 35 kN/m at 73% elongation,
measured with scripts/tensile_mesh.py. That is incompatible with a direction rated 150 kN/m.
This is a judgement: the datasheet does not say which way the spirals run.

Knot models (chain_link_panel's knots option):
- knots=False (default; the only one of chain_link_cylinder): the two hooked bends of
  neighbouring spirals share ONE node. It transmits force both ways and costs nothing to
  detect; the legs that meet there are bonded neighbours that never touch. The node also
  carries moments between the two spirals (beam links), which a real hook does not. The play
  of the hook is the links' stochastic slack (TECCO_MESH_CALIBRATION).
- knots=True or 'beam' (planar panels): each inner knot is the two bends as they lie in the
  mesh, their apexes crossed one wire diameter d apart in the plane and one d apart across it
  (the wires lie on each other: the hook's out-of-plane eccentricity), joined by a knot link (a
  beam of the wire's section, 200 GPa). The knot is then an eccentric joint; its play stays the
  links' slack (TECCO_MESH_CALIBRATION). A plain hinged link would let the two bends swing
  through each other (most knots of a panel pulled to rupture do), which the wires wrapped
  around each other cannot do.
- knots='hook' (planar panels): the same two apexes joined by a hinged bar (axial only) with a
  stop (FlexCylinder.hookLegs, pkg/kernel/Hook.hpp): the bends turn about each other freely,
  but pulled apart the left bend bears on the right one along the way it opens (from its legs'
  midpoint to its apex) and cannot pass it. Knots of the top and bottom rows (one leg per bend)
  keep a plain hinged link.
Nothing in either knot model is fitted to the mesh datasheet: d, the wire section and E are
the wire's. Their time step is many times shorter (the short knot links; FlexTimeStepper
bounds each bond with its own mass).
"""
import math

from yade import O
from yade.minieigenHP import Vector3
from yade.wrapper import FlexNode

from . import builders as B
from . import placement
from . import checks as C

TECCO_G65_DX = 0.083  # [m] rhombus diagonal across the spirals (longitudinal direction)
TECCO_G65_DY = 0.143  # [m] rhombus diagonal along the spirals (transverse direction)
TECCO_G65_WIRE_RADIUS = 0.0015  # [m] d = 3 mm
TECCO_G65_STRENGTH = 150e3  # [N/m] mesh tensile strength, longitudinal (Geobrugg datasheet; docs/model.md)

# Distortion of the mesh links (Thoeni et al. 2013 "type 2"), NOT fitted to the mesh datasheet:
# the slack of a link is at most the play of a knot, one wire diameter over a leg,
# d / sqrt(a^2 + h^2) = 3 / 82.7 = 0.036, reached through one soft segment (force ratio 1, as
# WirePM's default). The datasheet's 150 kN/m is then only a check (validation/README.md); the
# free side edges make the per-metre strength depend on the specimen width.
TECCO_MESH_CALIBRATION = dict(slack_scale=0.036, force_ratio=1.0)


def _lattice(nx, ny):
    """Lattice points (i, k), i + k even, of a mesh with nx spirals and ny rows of legs."""
    return [(i, k) for k in range(ny + 1) for i in range(nx + 1) if (i + k) % 2 == 0]


def _spiral_column(s, k):
    return s + ((s + k) % 2)


def _mesh_budget(nx, ny, blame):
    """Refuse a mesh of nx x ny legs that passes the body budget, naming blame = (name, value)."""
    C.body_budget(*blame, nx * ny + (nx + 1) * (ny + 1) // 2)


def _build(nx, ny, position, material, wire_radius, wrap=""):
    """Nodes at position(i, k); spirals as chains of cylinders. wrap 'x': column nx is column 0
    (the last spiral hooks into the first); 'y': row ny is row 0 (each spiral closes on itself)."""
    r = B._section("wire radius", wire_radius)
    mat = B._material(material)
    ids = {}
    for (i, k) in _lattice(nx, ny):
        if (wrap == "x" and i == nx) or (wrap == "y" and k == ny):
            continue
        ids[(i, k)] = B.node(position(i, k), r, mat)
    key = lambda i, k: (i % nx if wrap == "x" else i, k % ny if wrap == "y" else k)
    return ids, _spirals(nx, ny, lambda s, i, k: ids[key(i, k)], r, mat)


def _spirals(nx, ny, node_of, r, mat):
    """Legs of every spiral s as cylinders between node_of(s, i, k) at its consecutive bends."""
    spirals = []
    for s in range(nx):
        legs = []
        for k in range(ny):
            a = node_of(s, _spiral_column(s, k), k)
            b = node_of(s, _spiral_column(s, k + 1), k + 1)
            legs.append(B.cylinder(a, b, r, mat))
        spirals.append(legs)
    return spirals


def knot_bar(label="tecco_knot", young=200e9, bending_factor=1.0):
    """Material of the knot links (see _build_knotted): a linear-elastic steel link of the
    wire's E = 200 GPa; bending_factor 1: a beam (the two bends cannot turn about each other),
    0: a hinged bar (the hooked knot: the stop keeps them from passing). Never ruptures (a knot
    fails by the wire breaking at its bend, which the legs' wire law carries)."""
    from .materials import flex_material
    return flex_material(young=young, density=7850.0, bending_factor=bending_factor, label=label)


KNOT_MODELS = ("shared", "beam", "hook")


def knot_model(knots):
    """The knot model's name from chain_link_panel's knots argument: False/'shared', True/'beam', 'hook'."""
    if isinstance(knots, str) and knots.strip().lower() in KNOT_MODELS:
        return knots.strip().lower()
    try:
        return "beam" if C.boolean("knots", knots) else "shared"
    except C.BadValue:
        raise C.BadValue("knots", knots, "one of False ('shared'), True ('beam') or 'hook'") from None


def _build_knotted(nx, ny, a, h, origin, material, wire_radius, knot_material, hook=False):
    """Planar panel whose knots are two hooked bends (knots=True of chain_link_panel).

    At an inner knot (i, k) the bend of the spiral on the left (s = i - 1) is wrapped around
    the wire of the spiral on the right (s = i) and the other way round: the two bends' apexes
    are crossed, one wire diameter d = 2 r apart along x (each apex lies on the far side of the
    other wire) and one diameter apart across the plane (the wires lie on each other: the
    out-of-plane eccentricity of the hook). One node per apex; a knot link (a bar of the
    wire's section, knot_material) joins them, of length d sqrt(2). Pulling the spirals apart
    presses the two bends together: the link carries it, and its tilt turns part of it out of
    the plane. Each spiral's bends alternate above and below the plane along k
    (its legs cross the plane), as the flattened helix of a real spiral does. Edge bends (columns 0 and nx) have no
    partner: one node in the plane."""
    r = B._section("wire radius", wire_radius)
    d = 2 * r
    mat = B._material(material)
    kmat = B._material(knot_material)
    apex = {}  # (s, i, k) -> node id
    links, pairs = [], []
    for (i, k) in _lattice(nx, ny):
        p = origin + Vector3(i * a, k * h, 0)
        here = [s for s in (i - 1, i) if 0 <= s < nx and _spiral_column(s, k) == i]
        if len(here) == 1:
            apex[(here[0], i, k)] = B.node(p, r, mat)
            continue
        # spiral i-1's bend wraps around spiral i's wire and lies under it; each spiral is the
        # left one at every other bend, so its bends alternate under and over the plane
        left = B.node(p + Vector3(0.5 * d, 0, -0.5 * d), r, mat)
        right = B.node(p + Vector3(-0.5 * d, 0, 0.5 * d), r, mat)
        apex[(i - 1, i, k)], apex[(i, i, k)] = left, right
        pairs.append((i, k, left, right))
    for i, k, left, right in pairs:
        # hook: the left bend (spiral i-1's, its legs going to column i-1 at rows k -+ 1) stays on
        # the right one's far side along the way it opens: pulled apart, its wire bears on the
        # other's; pushed together, the two slide freely. At the top and bottom rows the bends
        # have one leg each: a plain hinged link there
        legs = (apex.get((i - 1, i - 1, k - 1)), apex.get((i - 1, i - 1, k + 1)))
        links.append(B.cylinder(left, right, r, kmat, hook_legs=legs if hook and None not in legs else None))
    spirals = _spirals(nx, ny, lambda s, i, k: apex[(s, i, k)], r, mat)
    at = {}
    for (s, i, k), n in apex.items():
        at.setdefault((i, k), []).append(n)
    return at, spirals, links


def _counts(length, pitch, what, even=False):
    n = int(round(B._positive(what, length) / pitch))
    if even and n % 2:
        n += 1
    if n < 2:
        raise ValueError(f"{what} {length!r} m is shorter than two half-cells ({2 * pitch} m)")
    return n


def panel_counts(width, height, dx=TECCO_G65_DX, dy=TECCO_G65_DY):
    """(a, h, nx, ny) of a chain-link panel: half-diagonals [m] and legs across and along the
    spirals; BadValue for sizes that are not positive or a panel over the body budget."""
    a, h = 0.5 * B._positive("dx", dx), 0.5 * B._positive("dy", dy)
    nx, ny = _counts(width, a, "panel width"), _counts(height, h, "panel height")
    _mesh_budget(nx, ny, ("panel width", width) if nx > ny else ("panel height", height))
    return a, h, nx, ny


def chain_link_panel(width, height, material, dx=TECCO_G65_DX, dy=TECCO_G65_DY, wire_radius=TECCO_G65_WIRE_RADIUS,
                     origin=(0, 0, 0), knots=False, knot_material=None):
    """Planar chain-link panel in the plane z = origin.z: x across the spirals (longitudinal,
    width [m]), y along them (height [m]); rhombus diagonals dx, dy [m]. The sizes are rounded
    to whole half-diagonals (the returned params give the built ones).
    knots: False or 'shared' (default), each knot one node shared by the two spirals; True or
    'beam', each inner knot two crossed bend apexes with the hook's eccentricity joined by a knot
    link of knot_material (None: knot_bar(), a beam); 'hook', the same apexes joined by a hinged
    bar (knot_material None: knot_bar(bending_factor=0)) with a stop that keeps the two bends from
    passing through each other (FlexCylinder.hookLegs); see _build_knotted.
    Returns dict(nodes={(i, k): id, or [ids] with knots}, cylinders (the legs), spirals, edges,
    knot_links, params)."""
    o = B.check_finite("panel origin", origin)
    a, h, nx, ny = panel_counts(width, height, dx, dy)
    links = []
    model = knot_model(knots)
    if model != "shared":
        hook = model == "hook"
        kmat = knot_material if knot_material is not None else knot_bar(*(("tecco_knot_hook", 200e9, 0.0) if hook else ()))
        ids, spirals, links = _build_knotted(nx, ny, a, h, o, material, wire_radius, kmat, hook=hook)
        flat = lambda p: ids[p]
    else:
        ids, spirals = _build(nx, ny, lambda i, k: o + Vector3(i * a, k * h, 0), material, wire_radius)
        flat = lambda p: [ids[p]]
    edge = lambda test: [n for p in sorted(ids) if test(p) for n in flat(p)]
    edges = dict(left=edge(lambda p: p[0] == 0), right=edge(lambda p: p[0] == nx),
                 bottom=edge(lambda p: p[1] == 0), top=edge(lambda p: p[1] == ny))
    return dict(nodes=ids, cylinders=[c for sp in spirals for c in sp], spirals=spirals, edges=edges, knot_links=links,
                params=dict(width=nx * a, height=ny * h, dx=2 * a, dy=2 * h, nx=nx, ny=ny, wire_radius=wire_radius, knots=model))


def chain_link_cylinder(diameter, height, material, dx=TECCO_G65_DX, dy=TECCO_G65_DY, wire_radius=TECCO_G65_WIRE_RADIUS,
                        center=(0, 0, 0), spirals="around"):
    """Chain-link mesh rolled into a vertical cylinder (axis z, bottom at center.z) of the
    given diameter and height [m].

    spirals='around': the spirals run around the module (each closes on itself, the strong
    direction carries the hoop force of the fill); the seam is where each spiral's two ends
    are joined, here by a shared node (as strong as the wire). spirals='vertical': the spirals
    run up the module and the seam is the last spiral hooked into the first, like every other
    knot. The lattice needs an even number of half-cells around, and the cell is stretched so
    that the diameter is exact: params give the built dx, dy.
    Returns the dict of chain_link_panel, edges bottom/top and seam (node ids of the seam)."""
    c = B.check_finite("cylinder center", center)
    D = B._positive("diameter", diameter)
    C.choice("spirals", spirals, ("around", "vertical"))
    a, h = 0.5 * B._positive("dx", dx), 0.5 * B._positive("dy", dy)
    R = 0.5 * D
    if spirals == "vertical":  # x (across the spirals) around, y up
        nx, ny = _counts(math.pi * D, a, "circumference", even=True), _counts(height, h, "mesh height")
        a = math.pi * D / nx
        angle_height = lambda i, k: (2 * math.pi * i / nx, k * h)
        wrap, seam_of = "x", lambda p: p[0] == 0
        level = lambda p: p[1]
    else:  # y (along the spirals) around, x up
        nx, ny = _counts(height, a, "mesh height"), _counts(math.pi * D, h, "circumference", even=True)
        h = math.pi * D / ny
        angle_height = lambda i, k: (2 * math.pi * k / ny, i * a)
        wrap, seam_of = "y", lambda p: p[1] == 0
        level = lambda p: p[0]

    def pos(i, k):
        phi, z = angle_height(i, k)
        return c + Vector3(R * math.cos(phi), R * math.sin(phi), z)

    around, up = (nx, ny) if spirals == "vertical" else (ny, nx)
    _mesh_budget(nx, ny, ("diameter", diameter) if around > up else ("height", height))
    ids, sp = _build(nx, ny, pos, material, wire_radius, wrap=wrap)
    top = max(level(p) for p in ids)
    edges = dict(bottom=[ids[p] for p in sorted(ids) if level(p) == 0], top=[ids[p] for p in sorted(ids) if level(p) == top],
                 seam=[ids[p] for p in sorted(ids) if seam_of(p)])
    return dict(nodes=ids, cylinders=[cy for s_ in sp for cy in s_], spirals=sp, edges=edges,
                params=dict(diameter=D, height=(nx * a if spirals == "around" else ny * h), dx=2 * a, dy=2 * h, nx=nx, ny=ny,
                            wire_radius=wire_radius, spirals=spirals))


def _sorted_around(node_ids):
    """Node ids sorted by angle around their centroid (an edge of a cylindrical mesh), in the
    frame of the current placement (yadeflex.placement: a tilted module's edge as an upright one's)."""
    pl = placement.current()
    ps = [O.bodies[i].state.pos if pl.is_identity() else pl.local(O.bodies[i].state.pos) for i in node_ids]
    cx = sum(p[0] for p in ps) / len(ps)
    cy = sum(p[1] for p in ps) / len(ps)
    return [i for _, i in sorted((math.atan2(p[1] - cy, p[0] - cx), i) for i, p in zip(node_ids, ps))]


def edge_ring(edge_nodes, bar_radius, material, closed=True):
    """A steel ring (or bar, closed=False) through the mesh edge nodes: the mesh wires wrap
    around it, modelled as shared nodes (the ring's cylinders and the mesh legs meet at the
    edge nodes). bar_radius [m] (TECCO module rings: 5 mm). Returns the ring's cylinder ids."""
    closed = C.boolean("closed", closed)
    edge_nodes = B._body_ids("edge_nodes", edge_nodes)
    if len(edge_nodes) < (3 if closed else 2):
        raise ValueError(f"a ring needs at least {3 if closed else 2} edge nodes, got {len(edge_nodes)}")
    if len(set(edge_nodes)) != len(edge_nodes) or not all(isinstance(O.bodies[i].shape, FlexNode) for i in edge_nodes):
        raise C.BadValue("edge_nodes", edge_nodes, "distinct ids of FlexNode bodies")
    B._section("bar_radius", bar_radius)
    B._material(material)
    C.body_budget("edge_nodes", f"{len(edge_nodes)} nodes", len(edge_nodes))
    nodes = _sorted_around(edge_nodes) if closed else list(edge_nodes)
    cyls = [B.cylinder(nodes[k], nodes[k + 1], bar_radius, material) for k in range(len(nodes) - 1)]
    if closed:
        cyls.append(B.cylinder(nodes[-1], nodes[0], bar_radius, material))
    return cyls
