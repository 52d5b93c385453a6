"""Placement of a structure (yadeflex.placement): builders inside `placed(...)` build the same
structure moved rigidly, and it behaves as the unplaced one moved alike."""
import math

import pytest
from yade import O
from yade.minieigenHP import Quaternion, Vector3

import yadeflex as yf
from yadeflex.checks import BadValue
from yadeflex.mesh import chain_link_cylinder, chain_link_panel, edge_ring


def _positions(ids):
    return [Vector3(O.bodies[i].state.pos) for i in ids]


def _rotation(axis, angle_deg):
    a = Vector3(*axis)
    return Quaternion(a / a.norm(), math.radians(angle_deg))


def test_a_panel_placed_on_a_slope_is_the_flat_panel_moved(scene):
    """A TECCO panel built flat, then on a 65 degree slope (about x, origin moved): each node is
    at origin + R p, oriented R, and every wire has its length."""
    mat = yf.tecco_wire()
    flat = chain_link_panel(0.5, 0.5, mat)
    ids = sorted(flat["nodes"].values())
    p0 = _positions(ids)
    l0 = [(O.bodies[c].shape.node1, O.bodies[c].shape.node2) for c in flat["cylinders"]]
    len0 = [(O.bodies[a].state.pos - O.bodies[b].state.pos).norm() for a, b in l0]
    O.reset()
    origin, R = Vector3(1.0, -2.0, 3.0), _rotation((1, 0, 0), 65.0)
    with yf.placed(origin=origin, axis=(1, 0, 0), angle=65.0):
        slope = chain_link_panel(0.5, 0.5, yf.tecco_wire())
    assert sorted(slope["nodes"].values()) == ids and slope["cylinders"] == flat["cylinders"]
    for i, p in zip(ids, p0):
        assert (O.bodies[i].state.pos - (origin + R * p)).norm() < 1e-12
        ori = O.bodies[i].state.ori
        for e in (Vector3(1, 0, 0), Vector3(0, 1, 0)):  # the same rotation: the same image of two axes
            assert (ori * e - R * e).norm() < 1e-12
    for (a, b), L in zip(l0, len0):
        assert (O.bodies[a].state.pos - O.bodies[b].state.pos).norm() == pytest.approx(L, rel=1e-12)
    # outside the block, builders are not placed
    n = yf.node((0, 0, 0), 0.001)
    assert O.bodies[n].state.pos == Vector3(0, 0, 0)


def test_a_wire_turned_about_gravity_sags_as_the_unturned_one(scene):
    """A wire clamped at one end sagging under gravity for 300 steps, built plain and turned 40
    degrees about the vertical and moved: the same motion, turned (gravity is along the axis, so
    the physics is the same; only round-off differs)."""
    def run(place):
        O.reset()
        if place:
            with yf.placed(origin=(0.3, 0.1, 0.2), axis=(0, 0, 1), angle=40.0):
                nodes, _ = yf.chain([(0, 0, 0), (0.3, 0, 0)], 0.002, yf.steel(), segments=6, fixed=[0])
        else:
            nodes, _ = yf.chain([(0, 0, 0), (0.3, 0, 0)], 0.002, yf.steel(), segments=6, fixed=[0])
        O.engines = yf.engines(gravity=(0, 0, -9.81))
        O.run(300, True)
        return _positions(nodes), nodes
    plain, _ = run(False)
    turned, _ = run(True)
    R, o = _rotation((0, 0, 1), 40.0), Vector3(0.3, 0.1, 0.2)
    assert max(abs(p[2]) for p in plain) > 1e-5  # it sagged
    for p, q in zip(plain, turned):
        assert (q - (o + R * p)).norm() < 1e-9


def test_a_tilted_module_gets_the_rings_of_the_upright_one(scene):
    """A chain-link cylinder with its edge rings, upright and tilted 80 degrees: the rings join the
    same edge nodes in the same order (the edge is sorted in the placement's frame)."""
    def build():
        c = chain_link_cylinder(0.6, 0.3, yf.tecco_wire())
        ring = edge_ring(c["edges"]["bottom"], 0.005, yf.steel())
        return [(O.bodies[r].shape.node1, O.bodies[r].shape.node2) for r in ring]
    upright = build()
    O.reset()
    with yf.placed(axis=(1, 1, 0), angle=80.0):
        tilted = build()
    assert tilted == upright


def test_placements_nest_and_bad_ones_are_refused(scene):
    with yf.placed(origin=(1, 0, 0)):
        with yf.placed(origin=(0, 2, 0), axis=(0, 0, 1), angle=90.0):
            n = yf.node((1, 0, 0), 0.001)
    # inner first: (1, 0, 0) turned 90 deg about z -> (0, 1, 0), + (0, 2, 0), then + (1, 0, 0)
    assert (O.bodies[n].state.pos - Vector3(1, 3, 0)).norm() < 1e-12
    with pytest.raises(BadValue, match="axis"):
        with yf.placed(axis=(0, 0, 0)):
            pass
    with pytest.raises(BadValue, match="angle"):
        with yf.placed(angle=float("nan")):
            pass
    with pytest.raises(BadValue, match="origin"):
        with yf.placed(origin=(0, float("inf"), 0)):
            pass
