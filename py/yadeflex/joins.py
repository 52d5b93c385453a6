"""Joining parts into structures: panels laced along their edges (a gabion from six panels), a
rope along an edge, a closed membrane box (a bag).

- lace(edge_a, edge_b, material, radius): each node of edge_a tied to the nearest node of edge_b
  by a lacing wire (a cylinder), as gabion panels are laced.
- edge_rope(nodes, material, radius, closed): a rope through the given nodes in their order.
- box_surface(lo, hi, cells): the points and triangles of a closed box surface (no YADE);
  bag(lo, hi, cells, thickness, material): that surface as a membrane, every node shared.
"""
import math

from yade import O

from . import builders as B
from . import checks as C


def lace(edge_a, edge_b, material, radius=0.0011, max_gap=None):
    """Lacing wires between two edges: each node of the edge with more nodes tied by a cylinder of
    `radius` [m] (default: a 2.2 mm lacing wire) and `material` to the nearest node of the other
    (edges of different pitch, a chain-link panel's two directions, are laced too). max_gap [m]:
    a pair farther apart raises ValueError naming it (default: no limit). Nodes that coincide
    cannot be laced (a cylinder needs a length): place the panels a wire's gap apart. Returns the
    cylinder ids."""
    a, b = B._body_ids("edge_a", edge_a), B._body_ids("edge_b", edge_b)
    if not a or not b:
        raise ValueError("lace: both edges need nodes")
    if set(a) & set(b):
        raise ValueError(f"lace: node #{sorted(set(a) & set(b))[0]} is on both edges")
    if max_gap is not None:
        max_gap = C.positive("max_gap", max_gap, "m")
    if len(b) > len(a):
        a, b = b, a
    pairs = []
    for n in a:
        p = O.bodies[n].state.pos
        m = min(b, key=lambda k: (O.bodies[k].state.pos - p).norm())
        d = (O.bodies[m].state.pos - p).norm()
        if max_gap is not None and d > max_gap:
            raise ValueError(f"lace: node #{n} is {d:.4g} m from the nearest node of the other edge (#{m}), more than max_gap = {max_gap:g} m")
        if d == 0:
            raise ValueError(f"lace: nodes #{n} and #{m} coincide: place the panels apart by a gap for the lacing wire")
        pairs.append((n, m))
    return [B.cylinder(n, m, radius, material) for n, m in pairs]


def edge_rope(nodes, material, radius, closed=False):
    """A rope of `material` and `radius` [m] through nodes in their order (closed: back to the
    first), one cylinder per pair of neighbours; the nodes keep their other elements. Returns
    the cylinder ids."""
    ids = B._body_ids("rope nodes", nodes)
    if len(ids) < 2 or len(set(ids)) != len(ids):
        raise ValueError(f"edge_rope: at least two different nodes, each once (got {len(ids)}, {len(set(ids))} different)")
    ends = list(zip(ids, ids[1:] + (ids[:1] if closed else [])))
    return [B.cylinder(p, q, radius, material) for p, q in ends]


def box_surface(lo, hi, cells):
    """(points, triangles) of the closed surface of the box lo-hi [m], (nx, ny, nz) cells along
    its sides (an int: that many along the longest side, the others in proportion), each cell
    split into two triangles, every point shared by the faces that meet there; the triangles
    turn outwards."""
    lo, hi = C.vector("box lo", lo, 3), C.vector("box hi", hi, 3)
    size = [hi[k] - lo[k] for k in range(3)]
    if not all(s > 0 for s in size):
        raise C.BadValue("box hi", hi, "above lo in x, y and z")
    if isinstance(cells, int) and not isinstance(cells, bool):
        n = C.integer("cells", cells, 1, 1000)
        cells = [max(1, round(n * s / max(size))) for s in size]
    cells = [C.integer("cells", c, 1, 1000) for c in cells]
    index, points = {}, []

    def point(i, j, k):
        key = (i, j, k)
        if key not in index:
            index[key] = len(points)
            points.append(tuple(lo[a] + size[a] * key[a] / cells[a] for a in range(3)))
        return index[key]

    tris = []
    for axis in range(3):
        u, v = [a for a in range(3) if a != axis]
        for side in (0, cells[axis]):
            for p in range(cells[u]):
                for q in range(cells[v]):
                    def at(du, dv):
                        key = [0, 0, 0]
                        key[axis], key[u], key[v] = side, p + du, q + dv
                        return point(*key)
                    c = (at(0, 0), at(1, 0), at(1, 1), at(0, 1))
                    # outward: (u, v, axis) right-handed on the far side, reversed on the near side
                    right = (u, v, axis) in ((0, 1, 2), (1, 2, 0), (2, 0, 1))
                    if (side > 0) != right:
                        c = c[::-1]
                    tris += [(c[0], c[1], c[2]), (c[0], c[2], c[3])]
    return points, tris


def bag(lo, hi, cells, thickness, material):
    """A closed membrane box (a bag before it is filled: box_surface as yadeflex.triangle_mesh)
    from lo to hi [m]. Returns dict(nodes, facets, bottom (the nodes of the face z = lo.z))."""
    points, tris = box_surface(lo, hi, cells)
    from .membrane import triangle_mesh
    nodes, facets = triangle_mesh(points, tris, material, thickness)
    z0 = C.vector("box lo", lo, 3)[2]
    bottom = [n for n, p in zip(nodes, points) if math.isclose(p[2], z0, abs_tol=1e-12)]
    return dict(nodes=nodes, facets=facets, bottom=bottom)
