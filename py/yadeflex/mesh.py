"""Chain-link (TECCO-type) wire mesh: planar panels and cylinders, rings on its edges.

Geometry. A chain-link mesh is a row of spiral wires, each a flattened zigzag along its axis,
every bend hooked into the bend of the neighbouring spiral. In the plane (x across the spirals,
y along them) the bends sit on the lattice points (i a, k h) with i + k even, where a = Dx/2
and h = Dy/2 are half the rhombus diagonals (TECCO G65/3: Dx = 83 mm, Dy = 143 mm). Spiral s
(s = 0 .. nx-1) runs through the columns s and s+1: at row k it is in column
s + ((s + k) mod 2). Cells are rhombi with diagonals Dx (along x) and Dy (along y); each leg (a
cylinder) is sqrt(a^2 + h^2) long. The longitudinal direction of the product (roll length,
the datasheet's 150 kN/m) is across the spirals, x: a section x = const cuts 2/Dy legs per metre,
which with the wire's breaking force gives an upper bound of 2/Dy x fu A (175 kN/m for TECCO).

Knot model: the two hooked bends of neighbouring spirals share ONE node. It transmits force
both ways, as the hook does in tension, and it costs nothing to detect. The legs that meet at
a knot are bonded neighbours, so they never contact each other. The price: the node also
carries moments between the two spirals, which a real hook does not, so the knot is a rigid
joint rather than a hinge. The moments are elastic bending of a 3 mm wire (about 4EI/L = 38 N m
per radian per leg end), which is small against the axial forces (kN).

One cylinder per leg (knot to knot), so each leg is one link of the wire law, with its own
stochastic slack (see yadeflex.wire).
"""
import math

from yade import O
from yade.minieigenHP import Vector3

from . import builders as B

TECCO_G65_DX = 0.083  # [m] rhombus diagonal across the spirals (longitudinal direction)
TECCO_G65_DY = 0.143  # [m] rhombus diagonal along the spirals (transverse direction)
TECCO_G65_WIRE_RADIUS = 0.0015  # [m] d = 3 mm
TECCO_G65_STRENGTH = 150e3  # [N/m] mesh tensile strength, longitudinal (Geobrugg datasheet; DESIGN.md)

# Distortion of the mesh links (Thoeni et al. 2013 "type 2"). Chosen by the calibration in
# scripts/tensile_mesh.py (see README: calibration on the longitudinal strength).
TECCO_MESH_CALIBRATION = dict(slack_scale=0.04, force_ratio=0.5)


def _lattice(nx, ny):
    """Lattice points (i, k), i + k even, of a mesh with nx spirals and ny rows of legs."""
    return [(i, k) for k in range(ny + 1) for i in range(nx + 1) if (i + k) % 2 == 0]


def _spiral_column(s, k):
    return s + ((s + k) % 2)


def _build(nx, ny, position, material, wire_radius, wrap):
    """Nodes at position(i, k); spirals as chains of cylinders. wrap: column nx is column 0."""
    r = B._positive("wire radius", wire_radius)
    mat = B._material(material)
    ids = {}
    for (i, k) in _lattice(nx, ny):
        if wrap and i == nx:
            continue
        ids[(i, k)] = B.node(position(i, k), r, mat)
    col = (lambda i: i % nx) if wrap else (lambda i: i)
    spirals = []
    for s in range(nx):
        legs = []
        for k in range(ny):
            a = ids[(col(_spiral_column(s, k)), k)]
            b = ids[(col(_spiral_column(s, k + 1)), k + 1)]
            legs.append(B.cylinder(a, b, r, mat))
        spirals.append(legs)
    return ids, spirals


def _counts(length, pitch, what, even=False):
    n = int(round(B._positive(what, length) / pitch))
    if even and n % 2:
        n += 1
    if n < 2:
        raise ValueError(f"{what} {length!r} m is shorter than two half-cells ({2 * pitch} m)")
    return n


def chain_link_panel(width, height, material, dx=TECCO_G65_DX, dy=TECCO_G65_DY, wire_radius=TECCO_G65_WIRE_RADIUS,
                     origin=(0, 0, 0)):
    """Planar chain-link panel in the plane z = origin.z: x across the spirals (longitudinal,
    width [m]), y along them (height [m]); rhombus diagonals dx, dy [m]. The sizes are rounded
    to whole half-diagonals (the returned params give the built ones).
    Returns dict(nodes={(i, k): id}, cylinders, spirals, edges, params)."""
    o = B.check_finite("panel origin", origin)
    a, h = 0.5 * B._positive("dx", dx), 0.5 * B._positive("dy", dy)
    nx, ny = _counts(width, a, "panel width"), _counts(height, h, "panel height")
    ids, spirals = _build(nx, ny, lambda i, k: o + Vector3(i * a, k * h, 0), material, wire_radius, wrap=False)
    edges = dict(left=[ids[p] for p in sorted(ids) if p[0] == 0], right=[ids[p] for p in sorted(ids) if p[0] == nx],
                 bottom=[ids[p] for p in sorted(ids) if p[1] == 0], top=[ids[p] for p in sorted(ids) if p[1] == ny])
    return dict(nodes=ids, cylinders=[c for sp in spirals for c in sp], spirals=spirals, edges=edges,
                params=dict(width=nx * a, height=ny * h, dx=2 * a, dy=2 * h, nx=nx, ny=ny, wire_radius=wire_radius))


def chain_link_cylinder(diameter, height, material, dx=TECCO_G65_DX, dy=TECCO_G65_DY, wire_radius=TECCO_G65_WIRE_RADIUS,
                        center=(0, 0, 0)):
    """Chain-link mesh rolled into a vertical cylinder (axis z, bottom at center.z) of the
    given diameter and height [m]: spirals vertical, the longitudinal direction around.

    The seam: the mesh is closed by hooking the last spiral into the first, like every other
    knot (the first column's nodes are shared), so the seam is as strong as the mesh. The
    number of spirals around is even (lattice parity) and the cell width is adjusted so that
    the diameter is exact: params give the built dx. Returns the dict of chain_link_panel with
    edges bottom/top and seam (node ids of the seam column)."""
    c = B.check_finite("cylinder center", center)
    D = B._positive("diameter", diameter)
    a0, h = 0.5 * B._positive("dx", dx), 0.5 * B._positive("dy", dy)
    nx = _counts(math.pi * D, a0, "circumference", even=True)
    ny = _counts(height, h, "mesh height")
    R = 0.5 * D

    def pos(i, k):
        phi = 2 * math.pi * i / nx
        return c + Vector3(R * math.cos(phi), R * math.sin(phi), k * h)

    ids, spirals = _build(nx, ny, pos, material, wire_radius, wrap=True)
    edges = dict(bottom=[ids[p] for p in sorted(ids) if p[1] == 0], top=[ids[p] for p in sorted(ids) if p[1] == ny],
                 seam=[ids[p] for p in sorted(ids) if p[0] == 0])
    return dict(nodes=ids, cylinders=[cy for sp in spirals for cy in sp], spirals=spirals, edges=edges,
                params=dict(diameter=D, height=ny * h, dx=2 * math.pi * R / nx * 2, dy=2 * h, nx=nx, ny=ny, wire_radius=wire_radius))


def _sorted_around(node_ids):
    """Node ids sorted by angle around their centroid (an edge of a cylindrical mesh)."""
    ps = [O.bodies[i].state.pos for i in node_ids]
    cx = sum(p[0] for p in ps) / len(ps)
    cy = sum(p[1] for p in ps) / len(ps)
    return [i for _, i in sorted((math.atan2(p[1] - cy, p[0] - cx), i) for i, p in zip(node_ids, ps))]


def edge_ring(edge_nodes, bar_radius, material, closed=True):
    """A steel ring (or bar, closed=False) through the mesh edge nodes: the mesh wires wrap
    around it, modelled as shared nodes (the ring's cylinders and the mesh legs meet at the
    edge nodes). bar_radius [m] (TECCO module rings: 5 mm). Returns the ring's cylinder ids."""
    if len(edge_nodes) < (3 if closed else 2):
        raise ValueError(f"a ring needs at least {3 if closed else 2} edge nodes, got {len(edge_nodes)}")
    nodes = _sorted_around(edge_nodes) if closed else list(edge_nodes)
    cyls = [B.cylinder(nodes[k], nodes[k + 1], bar_radius, material) for k in range(len(nodes) - 1)]
    if closed:
        cyls.append(B.cylinder(nodes[-1], nodes[0], bar_radius, material))
    return cyls
