"""yadeflex.drop: how far a boulder falls before its first touch, against exact geometry, and the
boulders placed with it touching after a fall of exactly their gap."""
import math

import pytest
from yade import O
from yade.wrapper import Facet, Wall
from yade import utils

import yadeflex as yf
import yadeflex.harness.scenes as S
from yadeflex.drop import first_touch

R = 0.1  # the falling sphere's radius [m]
Z = 1.0  # its centre's height [m]


@pytest.mark.parametrize("rho", [0.0, 0.05, 0.12])
def test_onto_a_sphere_beside_its_path(scene, rho):
    r = 0.03
    S.sphere((rho, 0, 0.5), r)
    assert first_touch([((0, 0, Z), R)]) == pytest.approx(Z - (0.5 + math.sqrt((R + r) ** 2 - rho ** 2)), abs=1e-9)


def test_past_a_sphere_out_of_reach(scene):
    S.sphere((R + 0.03 + 1e-3, 0, 0.5), 0.03)
    assert first_touch([((0, 0, Z), R)]) == math.inf


@pytest.mark.parametrize("rho", [0.0, 0.07])
def test_onto_a_wire_across_its_path(scene, rho):
    """A capsule of radius 5 mm between nodes of 1 mm, 2 m long, at horizontal distance rho."""
    re = 0.005
    a, b = yf.node((-1.0, rho, 0.4), 0.001), yf.node((1.0, rho, 0.4), 0.001)
    yf.cylinder(a, b, re, yf.steel())
    assert first_touch([((0, 0, Z), R)]) == pytest.approx(Z - (0.4 + math.sqrt((R + re) ** 2 - rho ** 2)), abs=1e-9)


def test_onto_a_membrane_and_a_facet_and_a_wall(scene):
    """A thick triangle (half thickness 2 mm) under the sphere's lowest point, a YADE facet lower,
    the floor lower still: the first touch is the membrane's top."""
    n = [yf.node(p, 0.0005) for p in ((-0.5, -0.5, 0.3), (0.5, -0.5, 0.3), (0, 0.5, 0.3))]
    yf.facet(*n, yf.geotextile(), thickness=0.004)
    O.bodies.append(utils.facet([(-1, -1, 0.2), (1, -1, 0.2), (0, 1, 0.2)]))
    O.bodies.append(utils.wall(0.0, axis=2))
    assert first_touch([((0, 0, Z), R)]) == pytest.approx(Z - R - 0.302, abs=1e-9)
    # without the membrane, the facet; without both, the wall
    for i in [b.id for b in O.bodies if type(b.shape).__name__ == "FlexFacet"]:
        O.bodies.erase(i)
    assert first_touch([((0, 0, Z), R)]) == pytest.approx(Z - R - 0.2, abs=1e-9)
    O.bodies.erase([b.id for b in O.bodies if isinstance(b.shape, Facet)][0])
    assert first_touch([((0, 0, Z), R)]) == pytest.approx(Z - R, abs=1e-9)
    assert isinstance([b for b in O.bodies if b is not None][-1].shape, Wall)


@pytest.mark.parametrize("shape", ["sphere", "cube"])
def test_a_boulder_above_touches_after_its_gap(scene, shape):
    """Boulder(above=...) onto a net of 5 mm wires on 1 mm nodes, with a grain on it off the
    boulder's axis: whatever it meets first, it meets it after a fall of its gap."""
    m = yf.steel()
    nodes = {}
    for i in range(7):
        for j in range(7):
            nodes[i, j] = yf.node((-0.3 + 0.1 * i, -0.3 + 0.1 * j, 0.0), 0.001)
    for i in range(7):
        for j in range(7):
            if i < 6:
                yf.cylinder(nodes[i, j], nodes[i + 1, j], 0.005, m)
            if j < 6:
                yf.cylinder(nodes[i, j], nodes[i, j + 1], 0.005, m)
    S.sphere((0.13, 0.07, 0.035), 0.03)
    b = yf.Boulder(mass=20.0, shape=shape, above=(0.01, 0.02), drop_height=0.5)
    bid = b.add(9.81)
    ids = [bid] + (list(O.bodies[bid].shape.members.keys()) if O.bodies[bid].isClump else [])
    spheres = [(O.bodies[i].state.pos, O.bodies[i].shape.radius) for i in ids if not O.bodies[i].isClump]
    assert first_touch(spheres, skip=ids) == pytest.approx(b.gap, abs=1e-9)
