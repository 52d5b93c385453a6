"""Grains deposited into any container (yadeflex.deposition): a box of YADE walls or facets, a
chain-link panel held at its border, the grain sizes drawn (uniform as the presets, a sieve
curve by mass), and bad input refused by name."""
import math
import random

import pytest
from yade import O, geom, utils
from yade.wrapper import FrictMat

import yadeflex as yf
from yadeflex.checks import BadValue
from yadeflex.deposition import CLEARANCE, SPACING, BoxRegion, CylinderRegion, GrainSizes, deposit, lattice_sites, place_grains
from yadeflex.grains import FILLS, _grain_material
from yadeflex.module.fill import _placement
from yadeflex.mesh import TECCO_G65_DX, TECCO_G65_DY, TECCO_G65_WIRE_RADIUS
from yadeflex.module.params import PLACED_HEIGHT, UNBALANCED_TOL

G = 9.81


def _frictionless():
    """The container's material: rigid enough, frictionless (as the module's filling container)."""
    m = FrictMat(young=1e8, poisson=0.3, density=1000, frictionAngle=0.0, label="container")
    O.materials.append(m)
    return m


def _hcp_count(lo, hi, a, c):
    """Sites of the close-packed lattice of spacing a (rows through the box's middle, layers ABAB)
    with their centres at least c inside the box lo..hi, counted row by row from the ends of each
    row (floor/ceil), not site by site."""
    dz, dy = a * math.sqrt(2 / 3), a * math.sqrt(3) / 2
    ax, ay = 0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])
    n = 0
    for k in range(int((hi[2] - c - (lo[2] + c)) / dz) + 1):
        ox, oy = (0.5 * a, a / (2 * math.sqrt(3))) if k % 2 else (0.0, 0.0)
        for j in range(math.ceil((lo[1] + c - ay - oy) / dy), math.floor((hi[1] - c - ay - oy) / dy) + 1):
            x0 = ax + ox + (0.5 * a if j % 2 else 0.0)
            n += math.floor((hi[0] - c - x0) / a) - math.ceil((lo[0] + c - x0) / a) + 1
    return n


@pytest.mark.parametrize("sides", ["walls", "facets"])
def test_a_box_of_walls_or_facets_fills_densely(scene, sides):
    """Sand (20-30 mm) deposited in a 0.24 m square box of five YADE walls or facets (no lid),
    trimmed to 0.2 m: one grain per lattice site, every grain inside the box, at rest, the core
    as dense as a random packing of spheres."""
    L, H = 0.24, 0.2
    mat = _frictionless()
    if sides == "walls":
        for pos, axis, sense in ((0.0, 2, 1), (0.0, 0, 1), (L, 0, -1), (0.0, 1, 1), (L, 1, -1)):
            O.bodies.append(utils.wall(pos, axis=axis, sense=sense, material=mat))
    else:  # wallMask 31: the floor and four sides
        O.bodies.append(geom.facetBox((L / 2, L / 2, 0.3), (L / 2, L / 2, 0.3), wallMask=31, material=mat))
    region = BoxRegion((0, 0, 0), (L, L, 0.45))
    res = deposit(region, "sand", seed=3, trim_height=H)
    p = FILLS["sand"]
    rmax, dmax = 0.5 * p["grain_max"], p["grain_max"]
    # one grain per site of the lattice (SPACING x the largest radius, CLEARANCE x it from the sides)
    n_sites = _hcp_count(region.lo, region.hi, SPACING * rmax, CLEARANCE * rmax)
    assert len(res.radii) == n_sites == len(lattice_sites(region, SPACING * rmax, CLEARANCE * rmax))
    # at rest: the stopping rule met
    assert res.kinetic_energy < res.ke_tol and res.unbalanced_force < UNBALANCED_TOL, (res.kinetic_energy, res.unbalanced_force)
    # inside the box: no contact carries more than the whole fill's weight W (the sides are
    # frictionless), so no grain sinks into a side or the floor by more than W / kn, kn = E r
    # (Ip2_FrictMat_FrictMat_FrictPhys, equal moduli)
    W = sum(O.bodies[g].state.mass for g in res.grains) * G
    for g in res.grains:
        b = O.bodies[g]
        r, x = b.shape.radius, b.state.pos
        sink = W / (p["young"] * r)
        assert all(r - sink < x[k] < L - r + sink for k in (0, 1)) and x[2] > r - sink, (g, x, r)
        assert x[2] + r <= H
    # random packings of spheres: 0.55 (loose) to 0.64 (dense), a range of sizes a little denser
    # (test_fill.py); core: a largest grain away from the sides and floor, two from the trimmed top
    core = [g for g in res.grains if all(dmax <= O.bodies[g].state.pos[k] <= L - dmax for k in (0, 1))
            and dmax <= O.bodies[g].state.pos[2] <= H - 2 * dmax]
    phi = sum(4 / 3 * math.pi * O.bodies[g].shape.radius ** 3 for g in core) / ((L - 2 * dmax) ** 2 * (H - 3 * dmax))
    assert 0.55 < phi < 0.70, phi
    # the whole box below the top: shells a mean radius rm deep along the four sides, the floor
    # and the trimmed top hold no grain's centre, the rest packs as the core at most
    rm = 0.25 * (p["grain_min"] + p["grain_max"])
    assert phi * (1 - 4 * rm / L - 2 * rm / H) < res.solid_fraction < phi, (res.solid_fraction, phi)
    print(f"{sides}: {len(res.radii)} placed, {len(res.grains)} kept, steps {res.steps}, unbalanced force "
          f"{res.unbalanced_force:.3g}, kinetic energy {res.kinetic_energy:.3g} J (limit {res.ke_tol:.3g}), "
          f"solid fraction core {phi:.3f}, box {res.solid_fraction:.3f}")


def test_grains_rest_on_a_chain_link_panel_and_none_falls_through(scene):
    """A TECCO G65/3 panel fixed at its border, four frictionless YADE walls as the sides, grains
    of 90-110 mm: larger than any opening (a rhombus of side s passes at most a sphere of
    s - 2 r_wire, a square's, 79.7 mm here, whatever the mesh's distortion), so none falls
    through; the grains come to rest on the sagging mesh (the stopping rule: kinetic energy and
    the unbalanced force, the border's reactions left out)."""
    side = 0.5 * math.hypot(TECCO_G65_DX, TECCO_G65_DY)
    d_min, d_max = 0.09, 0.11
    assert d_min > side - 2 * TECCO_G65_WIRE_RADIUS
    panel = yf.chain_link_panel(0.5, 0.5, yf.tecco_wire())
    W, Hp = panel["params"]["width"], panel["params"]["height"]
    border = sorted({n for e in panel["edges"].values() for n in e})
    yf.fix(border, "xyz")
    mat = _frictionless()
    for pos, axis, sense in ((0.0, 0, 1), (W, 0, -1), (0.0, 1, 1), (Hp, 1, -1)):
        O.bodies.append(utils.wall(pos, axis=axis, sense=sense, material=mat))
    res = deposit(BoxRegion((0, 0, 0.01), (W, Hp, 0.6)), "gravel", seed=2, sizes=GrainSizes.uniform(d_min, d_max))
    assert res.kinetic_energy < res.ke_tol and res.unbalanced_force < UNBALANCED_TOL, (res.kinetic_energy, res.unbalanced_force)
    assert len(res.grains) == len(res.radii)
    nodes = sorted(panel["nodes"].values())
    lowest = min(O.bodies[n].state.pos[2] for n in nodes)
    sag = -lowest
    assert sag > 0  # the mesh carries the grains
    for g in res.grains:
        x = O.bodies[g].state.pos
        assert x[2] > lowest and 0 < x[0] < W and 0 < x[1] < Hp, (g, x)
    print(f"panel: {len(res.grains)} grains, steps {res.steps}, unbalanced force {res.unbalanced_force:.3g}, kinetic energy "
          f"{res.kinetic_energy:.3g} J (limit {res.ke_tol:.3g}), sag {sag * 1e3:.1f} mm")


def _mass_passing(diameters, d):
    """Fraction by mass of the grains finer than d, and its standard error from the sample (the
    ratio estimator's: sqrt(sum (m_i (I_i - F))^2) / sum m_i, mass ~ d^3)."""
    m = [x ** 3 for x in diameters]
    total = sum(m)
    f = sum(mi for mi, x in zip(m, diameters) if x <= d) / total
    se = math.sqrt(sum((mi * ((x <= d) - f)) ** 2 for mi, x in zip(m, diameters))) / total
    return f, se


def test_sizes_follow_the_sieve_curve_by_mass_and_the_uniform_rule_is_the_presets(scene):
    """20,000 diameters drawn from a grading curve: the mass passing each sieve is the curve's
    within 4 standard errors of the sample (the bound a sample's scatter allows; 1 in 16,000 per
    sieve by chance), none in the size band the curve holds level; the uniform sizes are the
    presets' call, draw for draw, and their mass passing (d^4 - d_min^4) / (d_max^4 - d_min^4)."""
    curve = [(0.016, 0.0), (0.02, 10.0), (0.03, 35.0), (0.04, 35.0), (0.063, 100.0)]
    sizes = GrainSizes.sieve(curve)
    rnd = random.Random(7)
    ds = [2 * sizes.radius(rnd) for _ in range(20000)]
    assert 0.016 <= min(ds) and max(ds) <= 0.063
    assert not any(0.03 < d < 0.04 for d in ds)  # no mass between these sieves
    for d, pct in curve[1:-1]:
        f, se = _mass_passing(ds, d)
        assert sizes.passing(d) == pct
        assert abs(100 * f - pct) < 4 * 100 * se, (d, 100 * f, pct, 100 * se)
        print(f"sieve {d * 1e3:g} mm: {100 * f:.2f} % passing (curve {pct:g} %, standard error {100 * se:.2f} %)")
    # the presets' rule: radius = 0.5 x rnd.uniform(grain_min, grain_max), the same draws
    p = FILLS["gravel"]
    a, b = random.Random(11), random.Random(11)
    u = GrainSizes.of("gravel")
    assert [u.radius(a) for _ in range(1000)] == [0.5 * b.uniform(p["grain_min"], p["grain_max"]) for _ in range(1000)]
    ds = [2 * u.radius(rnd) for _ in range(20000)]
    for d in (0.04, 0.05, 0.06):
        f, se = _mass_passing(ds, d)
        assert abs(100 * f - u.passing(d)) < 4 * 100 * se, (d, 100 * f, u.passing(d))
        print(f"uniform, {d * 1e3:g} mm: {100 * f:.2f} % passing (expected {u.passing(d):.2f} %, standard error {100 * se:.2f} %)")


def test_a_cylinder_region_is_the_module_lattice_and_any_region_object_is_taken(scene):
    """A CylinderRegion gives the module's lattice (fill._placement about each centre), site for
    site; a region of the user's (an annulus, with the protocol's three methods) gets grains only
    inside it, at the clearance."""
    rmax = 0.5 * FILLS["gravel"]["grain_max"]
    a, c, H = SPACING * rmax, CLEARANCE * rmax, 0.35
    for cx, cy in ((0.0, 0.0), (0.62, -0.31)):
        sites = lattice_sites(CylinderRegion((cx, cy), 0.27, 0.0, 3.6 * H), a, c, top=PLACED_HEIGHT * H)
        assert sites == [(cx + x, cy + y, z) for x, y, z in _placement(0.27 - c, c, PLACED_HEIGHT * H, a)]

    class Annulus:
        def __init__(self, r0, r1, h):
            self.r0, self.r1, self.h = r0, r1, h

        def bounds(self):
            return (-self.r1, -self.r1, 0.0), (self.r1, self.r1, self.h)

        def contains(self, x, y, z, clearance):
            return self.r0 + clearance <= math.hypot(x, y) <= self.r1 - clearance and clearance <= z <= self.h - clearance

        def volume(self, top):
            return math.pi * (self.r1 ** 2 - self.r0 ** 2) * max(0.0, min(top, self.h))
    ring = Annulus(0.15, 0.35, 0.2)
    ids, radii = place_grains(ring, GrainSizes.of("gravel"), random.Random(1), _grain_material(FILLS["gravel"]))
    assert len(ids) == len(radii) > 50
    for g in ids:
        x = O.bodies[g].state.pos
        assert ring.contains(x[0], x[1], x[2], c)
        assert 0.15 + O.bodies[g].shape.radius < math.hypot(x[0], x[1]) < 0.35 - O.bodies[g].shape.radius


def test_bad_input_is_refused_by_name(scene):
    nan = float("nan")
    with pytest.raises(BadValue, match="BoxRegion hi.*positive size; y is not"):
        BoxRegion((0, 0, 0), (1, 0, 1))
    with pytest.raises(BadValue, match="BoxRegion hi.*positive size; z is not"):
        BoxRegion((0, 0, 1), (1, 1, 0.5))
    with pytest.raises(BadValue, match="BoxRegion lo"):
        BoxRegion((0, nan, 0), (1, 1, 1))
    for r in (0.0, -0.1, nan):
        with pytest.raises(BadValue, match="CylinderRegion radius"):
            CylinderRegion((0, 0), r, 0.0, 1.0)
    with pytest.raises(BadValue, match="CylinderRegion z1.*above z0"):
        CylinderRegion((0, 0), 0.3, 1.0, 1.0)
    with pytest.raises(BadValue, match="CylinderRegion center"):
        CylinderRegion((0, nan), 0.3, 0.0, 1.0)
    for lo, hi, name in ((0.0, 0.03, "d_min"), (-0.01, 0.03, "d_min"), (0.04, 0.03, "d_min"), (0.01, nan, "d_max"), (0.01, -0.02, "d_max")):
        with pytest.raises(BadValue, match=name):
            GrainSizes.uniform(lo, hi)
    with pytest.raises(BadValue, match="sieve curve.*sizes rising.*0.02 m, 50 % is followed by 0.01 m, 60 %"):
        GrainSizes.sieve([(0.01, 0), (0.02, 50), (0.01, 60), (0.03, 100)])
    with pytest.raises(BadValue, match="sieve curve.*30 % is followed by .* 20 %"):
        GrainSizes.sieve([(0.01, 0), (0.02, 30), (0.025, 20), (0.03, 100)])
    with pytest.raises(BadValue, match="sieve curve.*from 0 at the smallest size to 100"):
        GrainSizes.sieve([(0.01, 5), (0.03, 100)])
    with pytest.raises(BadValue, match="percent passing"):
        GrainSizes.sieve([(0.01, 0), (0.03, 120)])
    with pytest.raises(BadValue, match="sieve size"):
        GrainSizes.sieve([(-0.01, 0), (0.03, 100)])
    with pytest.raises(BadValue, match="sieve size"):
        GrainSizes.sieve([(nan, 0), (0.03, 100)])
    with pytest.raises(BadValue, match="sieve curve.*pairs"):
        GrainSizes.sieve([0.01, 0.03])
    # deposits: refused before anything is added to the scene
    O.bodies.append(utils.wall(0.0, axis=2, sense=1))
    n_bodies, n_mats = len(O.bodies), len(O.materials)
    with pytest.raises(BadValue, match="region.*no site of the lattice"):
        deposit(BoxRegion((0, 0, 0), (0.05, 0.05, 0.05)), "gravel")  # narrower than a largest grain and its clearance
    with pytest.raises(BadValue, match="region.*no site of the lattice"):
        deposit(BoxRegion((0, 0, 0), (1, 1, 1)), "gravel", top=-0.5)
    with pytest.raises(BadValue, match="region: got 'box'"):
        deposit("box", "gravel")
    with pytest.raises(BadValue, match="spacing.*at least the largest diameter"):
        deposit(BoxRegion((0, 0, 0), (1, 1, 1)), "gravel", spacing=0.05)
    with pytest.raises(BadValue, match="deposition_friction_deg"):
        deposit(BoxRegion((0, 0, 0), (1, 1, 1)), "gravel", deposition_friction_deg=40.0)  # above gravel's 38 deg
    with pytest.raises(BadValue, match="sizes"):
        deposit(BoxRegion((0, 0, 0), (1, 1, 1)), "gravel", sizes=(0.03, 0.06))
    with pytest.raises(ValueError, match="top or height_fraction"):
        deposit(BoxRegion((0, 0, 0), (1, 1, 1)), "gravel", top=0.5, height_fraction=0.5)
    with pytest.raises(BadValue, match="height_fraction"):
        deposit(BoxRegion((0, 0, 0), (1, 1, 1)), "gravel", height_fraction=0.0)
    with pytest.raises(BadValue, match="damping"):
        deposit(BoxRegion((0, 0, 0), (1, 1, 1)), "gravel", damping=1.0)
    assert (len(O.bodies), len(O.materials)) == (n_bodies, n_mats)
    O.reset()
    with pytest.raises(ValueError, match="no container"):
        deposit(BoxRegion((0, 0, 0), (1, 1, 1)), "gravel")


def test_a_floor_missing_is_named(scene):
    """Grains with nothing under them (the only other body a small box beside them): deposit
    stops at the first grain that falls below every other body, instead of running to max_steps."""
    O.bodies.append(utils.box((0, 0, -0.3), (0.02, 0.02, 0.02), fixed=True, material=_frictionless()))
    with pytest.raises(RuntimeError, match="fell through the container"):
        deposit(BoxRegion((0.1, 0.1, 0.0), (0.3, 0.3, 0.2)), "gravel")
