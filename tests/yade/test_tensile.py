"""Tensile tests of the damping-module steel parts: rope (EA, breaking force), ring (curved-beam
theory), chain-link mesh geometry (panel, cylinder, seam, edge ring) and the TECCO G65/3 panel
(free side edges, and its modellers' setup with held side edges) against its datasheet."""
import math
from collections import Counter

import pytest
from yade import O

import yadeflex as yf
from yadeflex import mesh, wire
from yadeflex.harness import tensile
from tol import assert_rel

ROPE_EA = 96e9 * 24.32e-6  # [N] datasheet E x metallic area (docs/model.md)
ROPE_MBF = 37.6e3  # [N] minimum breaking force


@pytest.mark.parametrize("segments,damping,rate", [(1, 0.0, 2e5), (10, 0.3, 2e6)])
def test_rope_axial_stiffness_and_breaking_force(scene, segments, damping, rate):
    r = tensile.rope_tensile_test(length=1.0, segments=segments, damping=damping, steps_per_unit_strain=rate)
    assert_rel(r["EA"], ROPE_EA, 1e-2, "rope EA")  # issue 4: within 1%
    assert_rel(r["rupture_force"], ROPE_MBF, 2e-2, "rope breaking force")  # issue 4: within 2%
    last = r["force"][-1]  # after rupture: the element is gone (1 segment) or carries nothing
    assert r["ruptured"] >= 1 and (last is None or abs(last) < 1.0)


def test_ring_under_diametral_point_loads_matches_curved_beam_theory(scene):
    # A polygon of N straight beams converges to the circle with an error ~ c / N^2 (measured
    # c = 8.0): 0.35% at 48 segments; the tolerance 0.5% holds that and no more.
    g24 = tensile.ring_point_loads(ring_radius=0.3, bar_radius=0.005, segments=24)
    g48 = tensile.ring_point_loads(ring_radius=0.3, bar_radius=0.005, segments=48)
    assert_rel(g48["delta"], g48["theory"], 5e-3, "ring deflection, 48 segments")
    e24, e48 = g24["delta"] / g24["theory"] - 1, g48["delta"] / g48["theory"] - 1
    assert 3.5 < e24 / e48 < 4.5, f"second-order convergence expected, errors {e24:.3e}, {e48:.3e}"
    # the hoop-deformation correction of Roark is tiny for a thin ring (alpha = I/(A R^2))
    assert abs(g48["theory"] / g48["theory_thin"] - 1) < 1e-3


def _legs_at(cyls):
    n = Counter()
    for c in cyls:
        n[O.bodies[c].shape.node1] += 1
        n[O.bodies[c].shape.node2] += 1
    return n


def test_chain_link_panel_geometry(scene):
    mat = wire.tecco_wire()
    p = mesh.chain_link_panel(1.0, 1.0, mat)
    a, h = mesh.TECCO_G65_DX / 2, mesh.TECCO_G65_DY / 2
    nx, ny = p["params"]["nx"], p["params"]["ny"]
    assert (nx, ny) == (24, 14)
    assert len(p["cylinders"]) == nx * ny and len(p["spirals"]) == nx
    leg = math.hypot(a, h)
    for c in p["cylinders"]:
        assert O.bodies[c].shape.L0 == pytest.approx(leg, rel=1e-12)
    legs = _legs_at(p["cylinders"])
    inner = [i for (ij, i) in p["nodes"].items() if 0 < ij[0] < nx and 0 < ij[1] < ny]
    assert inner and all(legs[i] == 4 for i in inner), "a knot joins two legs of each of two spirals"
    # each spiral is one continuous zigzag wire along y
    for sp in p["spirals"]:
        for c1, c2 in zip(sp, sp[1:]):
            assert O.bodies[c1].shape.node2 == O.bodies[c2].shape.node1


@pytest.mark.parametrize("spirals", ["around", "vertical"])
def test_chain_link_cylinder_is_closed_with_its_seam_and_takes_edge_rings(scene, spirals):
    D, H = 1.0, 0.6
    m = mesh.chain_link_cylinder(D, H, wire.tecco_wire(), spirals=spirals)
    for i in m["nodes"].values():
        p = O.bodies[i].state.pos
        assert math.hypot(p[0], p[1]) == pytest.approx(D / 2, rel=1e-12)
    legs = _legs_at(m["cylinders"])
    edge = set(m["edges"]["bottom"]) | set(m["edges"]["top"])
    assert all(legs[i] == 4 for i in m["nodes"].values() if i not in edge), "no free edge: the seam is closed"
    assert m["edges"]["seam"] and abs(m["params"]["height"] - H) <= max(m["params"]["dx"], m["params"]["dy"]) / 2
    # rings (bar d = 10 mm) through the top and bottom edge knots
    steel = yf.steel()
    n_before = len(m["cylinders"])
    for side in ("bottom", "top"):
        ring = mesh.edge_ring(m["edges"][side], 0.005, steel)
        assert len(ring) == len(m["edges"][side])
        for c in ring:
            s = O.bodies[c].shape
            assert s.radius == 0.005 and s.node1 in m["edges"][side] and s.node2 in m["edges"][side]
    assert n_before == len(m["cylinders"])


def test_knotted_chain_link_panel_geometry(scene):
    """knots=True: every inner knot is two crossed bend apexes, one wire diameter apart in the
    plane and across it, joined by one knot link (a beam); each spiral stays one continuous
    wire, its bends alternating under and over the plane."""
    p = mesh.chain_link_panel(1.0, 1.0, wire.tecco_wire(), knots=True)
    nx, ny = p["params"]["nx"], p["params"]["ny"]
    d = 2 * mesh.TECCO_G65_WIRE_RADIUS
    inner = [ij for ij in p["nodes"] if 0 < ij[0] < nx]
    assert len(p["knot_links"]) == len(inner) and all(len(p["nodes"][ij]) == 2 for ij in inner)
    assert all(len(p["nodes"][ij]) == 1 for ij in p["nodes"] if ij[0] in (0, nx))
    for c in p["knot_links"]:
        sh = O.bodies[c].shape
        a, b = O.bodies[sh.node1].state.pos, O.bodies[sh.node2].state.pos
        assert (a[0] - b[0], abs(a[1] - b[1]), b[2] - a[2]) == (pytest.approx(d, rel=1e-9), pytest.approx(0, abs=1e-12),
                                                                pytest.approx(d, rel=1e-9))
        assert O.bodies[c].material.bendingFactor == 1
    legs = _legs_at(p["cylinders"])
    assert all(legs[i] == 2 for ij in inner if 0 < ij[1] < ny for i in p["nodes"][ij])
    for sp in p["spirals"]:
        for c1, c2 in zip(sp, sp[1:]):
            assert O.bodies[c1].shape.node2 == O.bodies[c2].shape.node1
        zs = [O.bodies[O.bodies[c].shape.node1].state.pos[2] for c in sp]
        assert all(z1 == -z2 for z1, z2 in zip(zs, zs[1:]) if z1 and z2)  # edge bends lie in the plane


@pytest.mark.parametrize("knots", ["beam", "hook"])
def test_knotted_panel_keeps_its_knots_hooked(scene, knots):
    """A 0.5 x 0.5 m knotted panel (eccentric or hooked knots) pulled along the spirals to
    rupture: no two bends whose legs are whole pass through each other (the crossed apexes keep
    their order in the plane), the test is quasi-static, and the peak stays below every wire
    crossing a section at its breaking force."""
    s = tensile.mesh_panel_scene(width=0.5, height=0.5, direction="longitudinal", speed=1.0, knots=knots)
    r = tensile.mesh_tensile_test(s, chunk=400, max_elongation=0.3)
    assert r["ruptured"] > 0
    assert r["unbalance_at_peak"] < 0.01, "quasi-static: both clamped edges carry the same force"
    assert r["peak"] < 2 / mesh.TECCO_G65_DX * wire.TECCO_WIRE_STRESS[-1] * math.pi * 0.0015 ** 2
    # hooked: the knots whose bends kept both legs (a bend that lost one lets go); eccentric: all
    whole = (lambda n: len(O.bodies[n].shape.elements) == 3) if knots == "hook" else (lambda n: True)
    order = [O.bodies[O.bodies[c].shape.node1].state.pos[0] - O.bodies[O.bodies[c].shape.node2].state.pos[0]
             for c in s["knot_links"] if O.bodies[c] is not None and whole(O.bodies[c].shape.node1) and whole(O.bodies[c].shape.node2)]
    assert len(order) > len(s["knot_links"]) // 2 and min(order) > 0, "a bend passed through the wire it is hooked around"
    if knots == "hook":  # a bend that lost a leg has let go
        lost = [c for c in s["knot_links"] if O.bodies[c] is not None and O.bodies[c].shape.hookNodes[0] >= 0
                and not whole(O.bodies[c].shape.node1)]
        assert lost and all(O.bodies[c].shape.hookStiffness == 0 for c in lost)


def _tecco_panel_runs():
    runs = {}
    for speed in (1.0, 2.0):
        s = tensile.mesh_panel_scene(width=1.0, height=1.0, direction="longitudinal", speed=speed)
        runs[speed] = tensile.mesh_tensile_test(s, chunk=400, max_elongation=0.3)
    return runs


def test_tecco_panel_is_quasi_static_and_below_the_wire_bound(scene):
    """1 x 1 m panel (the module's mesh: shared-node knots), clamped edges, pulled along the
    spirals: speed-independent peak, balanced edges, bounded by the wires."""
    runs = _tecco_panel_runs()
    r = runs[1.0]
    assert r["ruptured"] > 0
    assert r["unbalance_at_peak"] < 0.01, "quasi-static: both clamped edges carry the same force"
    assert_rel(runs[2.0]["peak"], r["peak"], 0.01, "peak independent of the pulling speed")
    assert r["peak"] < 2 / mesh.TECCO_G65_DX * wire.TECCO_WIRE_STRESS[-1] * math.pi * 0.0015 ** 2
    assert 0.005 < r["elongation_at_peak"] < 0.2
    assert r["quasi_static_peak"] == r["peak"]  # its peak is balanced: the quasi-static one


def _modellers_runs(direction):
    """The modellers' setup (1.079 x 1.001 m, side edges held across the pull), the module's mesh,
    at 1 and 2 m/s."""
    return {v: tensile.tecco_modellers_test(direction, speed=v)[1] for v in (1.0, 2.0)}


@pytest.mark.parametrize("direction", ["longitudinal", "transverse"])
def test_tecco_panel_in_the_modellers_setup(scene, direction):
    """The TECCO G65/3 specimen of the mesh's modellers, its side edges held across the pull and
    out of the plane (shared-node knots): the driven and held edges' reactions balance within 1%
    at the peak, the peak does not depend on the pulling speed (1%), and, held at its sides, the
    specimen stretches uniformly: every leg crossing a section reaches the wire's breaking force,
    the peak within 3% (the wire curve's last rise, 1720 to 1770 N/mm2) of the wires' bound at
    the legs' angle of that uniform stretch. Longitudinally, held side edges carry more than free ones."""
    runs = _modellers_runs(direction)
    r = runs[1.0]
    assert r["ruptured"] > 0
    k = r["force_per_m"].index(r["peak"])
    assert abs(r["driven_per_m"][k] - r["held_per_m"][k]) <= 0.01 * r["driven_per_m"][k], "reactions balance"
    assert_rel(runs[2.0]["peak"], r["peak"], 0.01, "peak independent of the pulling speed")
    assert r["quasi_static_peak"] == r["peak"]
    assert_rel(r["peak"], tensile.wire_bound_per_m(direction, r["elongation_at_peak"]), 0.03, "every leg at its breaking force")
    assert r["peak"] < tensile.wire_bound_per_m(direction)
    assert r["side_per_m_at_peak"] > 0, "the held sides keep the specimen from contracting"
    if direction == "longitudinal":
        free = tensile.mesh_tensile_test(tensile.mesh_panel_scene(width=tensile.MODELLERS_WIDTH, height=tensile.MODELLERS_LENGTH, speed=1.0),
                                         chunk=400, max_elongation=0.3)
        assert free["peak"] < r["peak"], (free["peak"], r["peak"])


@pytest.mark.xfail(strict=True, reason="issue 58: held side edges (the modellers' setup) give 262 kN/m, free ones 124 kN/m: "
                   "the datasheet's edge conditions lie between (validation/README.md)")
def test_tecco_panel_longitudinal_strength_vs_datasheet(scene):
    """The datasheet's 150 kN/m within issue 36's 5% (one value, no scatter given), in the
    modellers' setup with the module's mesh. No parameter is fitted to the mesh, so this is a
    prediction; strict: passing would flag the change."""
    _, r, _ = tensile.tecco_modellers_test("longitudinal", speed=1.0)
    assert_rel(r["peak"], mesh.TECCO_G65_STRENGTH, 0.05, "peak resistance per metre vs TECCO G65/3 datasheet")


def test_rope_closed_around_two_modules_has_the_hull_length(scene):
    R, r, d = 0.5, 0.004, 1.2  # module radius, rope radius, distance between module centres [m]
    nodes, cyls = yf.rope_around([(0, 0), (d, 0)], R, 0.3, yf.rope_6x7_8mm(), rope_radius=r, segment_length=0.05)
    length = sum(O.bodies[c].shape.L0 for c in cyls)
    exact = 2 * math.pi * (R + r) + 2 * d  # two half circles and two tangents
    # chords of ~5 cm on a 0.5 m radius touching the circles at their middles: the polygon is
    # longer than the arcs by ~ (h/R)^2/12 ~ 8e-4 of their length
    assert_rel(length, exact, 1e-3, "rope length around two modules")
    pos = [O.bodies[i].state.pos for i in nodes]
    centres = [(0.0, 0.0), (d, 0.0)]
    gaps = []
    for k in range(len(pos)):
        a, b = pos[k], pos[(k + 1) % len(pos)]
        for c in centres:  # closest point of the chord to the module axis
            t = max(0.0, min(1.0, ((c[0] - a[0]) * (b[0] - a[0]) + (c[1] - a[1]) * (b[1] - a[1])) / ((b - a).squaredNorm())))
            gaps.append(math.hypot(a[0] + t * (b[0] - a[0]) - c[0], a[1] + t * (b[1] - a[1]) - c[1]) - (R + r))
    # no chord cuts into a module (their sagitta, ~0.6 mm here, was 6 mm for the main job's
    # three small modules: 100 kN on the mesh at the first step), and they touch (snug, no slack)
    assert min(gaps) >= -1e-9 * R
    assert min(gaps) <= 1e-6
