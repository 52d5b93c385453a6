"""Joining parts (yadeflex.joins): a closed box surface (each edge shared by two triangles, the
enclosed volume exact, every normal outwards), a bag built from it, lacing wires between panel
edges, an edge rope; their inputs refused with the reason."""
import pytest
from yade import O

import yadeflex as yf
from yadeflex import checks as C


def _signed_volume(points, tris):
    """Divergence theorem: the volume a closed, outward-turned triangle surface encloses."""
    v = 0.0
    for a, b, c in tris:
        (ax, ay, az), (bx, by, bz), (cx, cy, cz) = points[a], points[b], points[c]
        v += (ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)) / 6.0
    return v


@pytest.mark.parametrize("cells", [1, 4, (3, 2, 5)])
def test_a_box_surface_is_closed_and_turned_outwards(cells):
    lo, hi = (0.1, -0.2, 0.0), (0.9, 0.4, 0.5)
    pts, tris = yf.box_surface(lo, hi, cells)
    edges = {}
    for t in tris:
        for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            edges.setdefault(frozenset((a, b)), []).append((a, b))
    # closed and consistently oriented: every edge in two triangles, run once each way
    assert all(len(v) == 2 and v[0] == v[1][::-1] for v in edges.values())
    assert _signed_volume(pts, tris) == pytest.approx(0.8 * 0.6 * 0.5, rel=1e-12)
    assert len(set(pts)) == len(pts)  # every point once: the faces share their edges' points
    if cells == 4:  # cells along the longest side, the others in proportion: 4 x 3 x 2 (rounded)
        assert len(tris) == 2 * 2 * (4 * 3 + 3 * 2 + 4 * 2)


def test_a_bag_holds_its_points_as_shared_nodes(scene):
    bag = yf.bag((0, 0, 0), (0.4, 0.3, 0.2), 4, 0.002, yf.geotextile())
    assert len(bag["facets"]) == 2 * 2 * (4 * 3 + 3 * 2 + 4 * 2)
    assert all(abs(O.bodies[n].state.pos[2]) < 1e-12 for n in bag["bottom"]) and len(bag["bottom"]) == 5 * 4
    with pytest.raises(C.BadValue, match="box hi"):
        yf.bag((0, 0, 0), (0.4, 0.0, 0.2), 4, 0.002, yf.geotextile())


def test_lacing_ties_each_node_of_the_denser_edge_to_its_nearest(scene):
    """Two panels side by side, 2 cm apart: a lacing wire from each node of the edge with more
    nodes to the nearest of the other; each wire as long as the nodes are apart."""
    wire = yf.tecco_wire()
    a = yf.chain_link_panel(0.5, 0.3, wire)
    with yf.placed((a["params"]["width"] + 0.02, 0, 0)):
        b = yf.chain_link_panel(0.5, 0.3, wire)
    ea, eb = a["edges"]["right"], b["edges"]["left"]
    ties = yf.lace(ea, eb, wire, max_gap=0.05)
    assert len(ties) == max(len(ea), len(eb))
    for c in ties:
        n1, n2 = O.bodies[c].shape.node1, O.bodies[c].shape.node2
        p1, p2 = O.bodies[n1].state.pos, O.bodies[n2].state.pos
        assert (p1 - p2).norm() == pytest.approx(0.02, abs=1e-12)  # the same heights: straight across
        assert {n1, n2} <= set(ea) | set(eb)
    with pytest.raises(ValueError, match="more than max_gap"):
        yf.lace(a["edges"]["left"], eb, wire, max_gap=0.05)
    with pytest.raises(ValueError, match="on both edges"):
        yf.lace(ea, ea[:2], wire)


def test_an_edge_rope_runs_through_its_nodes_in_order(scene):
    grid, _ = yf.net(3, 0.1, 0.002, yf.steel(), fix_border=False)
    ring = [grid[0][0], grid[1][0], grid[2][0], grid[2][1], grid[2][2]]
    rope = yf.edge_rope(ring, yf.rope_6x7_8mm(), 0.004, closed=True)
    ends = [(O.bodies[c].shape.node1, O.bodies[c].shape.node2) for c in rope]
    assert ends == list(zip(ring, ring[1:] + ring[:1]))
    with pytest.raises(ValueError, match="each once"):
        yf.edge_rope([grid[0][0], grid[0][0]], yf.rope_6x7_8mm(), 0.004)
