"""Grains deposited into any container: placed on a close-packed lattice inside a region, settled
under gravity (-z) inside whatever bodies the scene already holds (YADE walls, facets, boxes,
yade-flex meshes and membranes), first frictionless, then with their own friction, until at rest.
The damping module's fill (yadeflex.module.fill.settle_grains) is this deposition in a cylinder.

A region is where the grains are first placed, in global coordinates [m]: a BoxRegion, a CylinderRegion, or
any object with the same three methods:

    bounds()                      -> ((x, y, z) lowest corner, (x, y, z) highest corner) [m]
    contains(x, y, z, clearance)  -> True if the point is inside, at least clearance [m] from
                                     its boundary
    volume(top)                   -> its volume below the height top [m3] (top = inf: all of it)

and optionally `anchor`, the horizontal point (x, y) [m] a row of the lattice passes through
(default: the middle of its bounds). The region must be clear of the container's bodies.
"""
import bisect
import dataclasses
import math
import random

from yade import O
from yade.minieigenHP import Vector3
from yade.wrapper import NewtonIntegrator

from . import checks as C
from .constants import G
from .grains import (DEPOSITION_FRICTION, FILL_TIMESTEP_SAFETY, SETTLE_DAMPING, UNBALANCED_TOL, _grain_material, _sphere_body, fill_engines,
                     fill_preset)
from .mass_scaling import _heavier_nodes, _restore_nodes
from .scene import DAMPING, DEFAULT_TIMESTEP_SAFETY, grain_engine, step_until

# clearance of the lattice's centres from the region's boundary, x the largest radius (a grain
# placed there does not touch the boundary), and the lattice's spacing, x the largest radius
CLEARANCE = 1.05
SPACING = 2.05


@dataclasses.dataclass
class BoxRegion:
    """Axis-aligned box from the corner lo to the corner hi, each (x, y, z) [m]."""
    lo: tuple
    hi: tuple

    def __post_init__(self):
        self.lo, self.hi = C.vector("BoxRegion lo", self.lo, 3), C.vector("BoxRegion hi", self.hi, 3)
        for k, axis in enumerate("xyz"):
            if not self.hi[k] > self.lo[k]:
                raise C.BadValue("BoxRegion hi", self.hi, f"above lo = {C.show(self.lo)} in x, y and z (a box of positive size; {axis} is not)")

    @property
    def anchor(self):
        return 0.5 * (self.lo[0] + self.hi[0]), 0.5 * (self.lo[1] + self.hi[1])

    def bounds(self):
        return self.lo, self.hi

    def contains(self, x, y, z, clearance=0.0):
        (x0, y0, z0), (x1, y1, z1) = self.lo, self.hi
        return x0 + clearance <= x <= x1 - clearance and y0 + clearance <= y <= y1 - clearance and z0 + clearance <= z <= z1 - clearance

    def volume(self, top=math.inf):
        """Volume below the height top [m3]."""
        return (self.hi[0] - self.lo[0]) * (self.hi[1] - self.lo[1]) * max(0.0, min(top, self.hi[2]) - self.lo[2])


@dataclasses.dataclass
class CylinderRegion:
    """Vertical cylinder of the given radius [m] about the axis through center = (x, y) [m],
    from the height z0 up to z1 [m]."""
    center: tuple
    radius: float
    z0: float
    z1: float

    def __post_init__(self):
        self.center = C.vector("CylinderRegion center", self.center, 2)
        self.radius = C.positive("CylinderRegion radius", self.radius, "m")
        self.z0 = C.number("CylinderRegion z0", self.z0, C.Range(unit="m"))
        self.z1 = C.number("CylinderRegion z1", self.z1, C.Range(self.z0, math.inf, "m", lo_open=True, note="above z0"))

    @property
    def anchor(self):
        return self.center

    def bounds(self):
        (x, y), r = self.center, self.radius
        return (x - r, y - r, self.z0), (x + r, y + r, self.z1)

    def contains(self, x, y, z, clearance=0.0):
        return self.z0 + clearance <= z <= self.z1 - clearance and math.hypot(x - self.center[0], y - self.center[1]) <= self.radius - clearance

    def volume(self, top=math.inf):
        """Volume below the height top [m3]."""
        return math.pi * self.radius ** 2 * max(0.0, min(top, self.z1) - self.z0)


def _regions(region):
    """region (one, or a sequence of disjoint ones) as a list, each checked for the protocol."""
    out = list(region) if isinstance(region, (list, tuple)) else [region]
    for r in out:
        if not all(callable(getattr(r, m, None)) for m in ("bounds", "contains", "volume")):
            raise C.BadValue("region", r, "a BoxRegion, a CylinderRegion or an object with bounds(), contains(x, y, z, clearance) and volume(top)")
    if not out:
        raise C.BadValue("region", region, "a region or a sequence of regions")
    return out


class GrainSizes:
    """A rule drawing the grains' radii [m]: uniform() or sieve(); d_min, d_max the smallest and
    largest diameters [m] it draws, radius(rnd) one radius drawn with the random.Random rnd."""

    def __init__(self, d_min, d_max, curve=None):
        self.d_min, self.d_max, self.curve = d_min, d_max, curve
        if curve is not None:
            # each segment's share of the grains by number (sieve())
            w = [(p1 - p0) / math.log(d1 / d0) * (d0 ** -3 - d1 ** -3) / 3 for (d0, p0), (d1, p1) in zip(curve, curve[1:])]
            self._cum = [sum(w[:k + 1]) / sum(w) for k in range(len(w))]

    @classmethod
    def uniform(cls, d_min, d_max):
        """Diameters uniform in d_min..d_max [m] (the fill presets' rule: radius =
        0.5 x rnd.uniform(d_min, d_max))."""
        d_max = C.positive("d_max", d_max, "m")
        return cls(C.number("d_min", d_min, C.Range(0.0, d_max, "m", lo_open=True, note="up to d_max")), d_max)

    @classmethod
    def sieve(cls, curve):
        """A grading curve as sieve analyses give it: [(sieve size d [m], percent passing by mass),
        ...], sizes rising, percentages rising (or level) from 0 at the smallest size to 100 at the
        largest. The mass passing is taken as linear in log d between sieves (as grading curves
        are drawn): within a segment the mass per unit diameter goes as 1/d, the number of grains
        per unit diameter as d^-4 (a grain's mass ~ d^3). Each grain: a segment drawn with its
        share of the grains by number, (P1 - P0) / ln(d1/d0) x (d0^-3 - d1^-3) / 3, then its
        diameter from the d^-4 law inverted, d = (d0^-3 - u (d0^-3 - d1^-3))^(-1/3), u uniform
        in [0, 1); two rnd.random() calls. The sample's mass passing each sieve is the curve's
        within the scatter of a finite sample."""
        try:
            pts = [(C.positive("sieve size", d, "m"), C.number("percent passing", p, C.Range(0.0, 100.0, "%"))) for d, p in curve]
        except (TypeError, ValueError) as e:
            if isinstance(e, C.BadValue):
                raise
            raise C.BadValue("sieve curve", curve, "a sequence of (sieve size [m], percent passing) pairs") from None
        allowed = "sizes rising, percent passing rising or level, from 0 at the smallest size to 100 at the largest"
        if len(pts) < 2 or pts[0][1] != 0.0 or pts[-1][1] != 100.0:
            raise C.BadValue("sieve curve", curve, allowed + " (at least two sieves)")
        for (d0, p0), (d1, p1) in zip(pts, pts[1:]):
            if not (d1 > d0 and p1 >= p0):
                raise C.BadValue("sieve curve", curve, f"{allowed} ({d0:g} m, {p0:g} % is followed by {d1:g} m, {p1:g} %)")
        return cls(pts[0][0], pts[-1][0], pts)

    @classmethod
    def of(cls, preset):
        """The uniform sizes grain_min..grain_max of a fill preset (fill.fill_preset)."""
        p = fill_preset(preset)
        return cls.uniform(p["grain_min"], p["grain_max"])

    def passing(self, d):
        """Percent by mass of the grains drawn (in the mean) passing the size d [m]: uniform sizes
        (by number) pass 100 (d^4 - d_min^4) / (d_max^4 - d_min^4), a sieve curve its own."""
        if self.curve is None:
            d = min(max(d, self.d_min), self.d_max)
            return 100.0 * (d ** 4 - self.d_min ** 4) / (self.d_max ** 4 - self.d_min ** 4) if self.d_max > self.d_min else 100.0 * (d >= self.d_max)
        ds = [q[0] for q in self.curve]
        k = min(max(bisect.bisect_right(ds, d) - 1, 0), len(ds) - 2)
        (d0, p0), (d1, p1) = self.curve[k], self.curve[k + 1]
        return p0 + (p1 - p0) * min(1.0, max(0.0, math.log(d / d0) / math.log(d1 / d0)))

    def radius(self, rnd):
        """One radius [m] drawn with rnd."""
        if self.curve is None:
            return 0.5 * rnd.uniform(self.d_min, self.d_max)
        k = bisect.bisect_right(self._cum, rnd.random())
        k = min(k, len(self._cum) - 1)
        (d0, _), (d1, _) = self.curve[k], self.curve[k + 1]
        return 0.5 * (d0 ** -3 - rnd.random() * (d0 ** -3 - d1 ** -3)) ** (-1.0 / 3.0)

    def __repr__(self):
        return f"GrainSizes.sieve({self.curve!r})" if self.curve else f"GrainSizes.uniform({self.d_min!r}, {self.d_max!r})"


def lattice_sites(region, spacing, clearance, top=None):
    """Centres (x, y, z) [m] of a hexagonal close-packed lattice of spacing [m] (layers ABAB, rows
    through the region's anchor) inside the region at least clearance [m] from its boundary, the
    lowest layer at clearance above its floor, the highest at most at the height top [m] (None:
    the region's top), in the order layer by layer, row by row (y), along each row (x)."""
    (x0, y0, zlo), (x1, y1, zhi) = region.bounds()
    cx, cy = getattr(region, "anchor", (0.5 * (x0 + x1), 0.5 * (y0 + y1)))
    a = spacing
    dz, dy = a * math.sqrt(2.0 / 3.0), a * math.sqrt(3.0) / 2
    mi, mj = int(max(cx - x0, x1 - cx) / a) + 2, int(max(cy - y0, y1 - cy) / dy) + 2
    z_first = zlo + clearance
    top = zhi - clearance if top is None else top
    out = []
    for k in range(int((top - z_first) / dz) + 1 if top >= z_first else 0):
        ox, oy = (0.5 * a, a / (2 * math.sqrt(3.0))) if k % 2 else (0.0, 0.0)
        z = z_first + k * dz
        for j in range(-mj, mj + 1):
            for i in range(-mi, mi + 1):
                x, y = cx + (i * a + (0.5 * a if j % 2 else 0.0) + ox), cy + (j * dy + oy)
                if region.contains(x, y, z, clearance):
                    out.append((x, y, z))
    return out


def _sites(regions, sizes, spacing, top):
    """The lattice sites of each region, checked (none empty, the body budget), before any body
    is added: (a list of sites per region)."""
    if not isinstance(sizes, GrainSizes):
        raise C.BadValue("sizes", sizes, "a GrainSizes (GrainSizes.uniform, .sieve or .of)")
    rmax = 0.5 * sizes.d_max
    a = SPACING * rmax if spacing is None else C.number("spacing", spacing, C.Range(sizes.d_max, math.inf, "m", note="at least the largest diameter"))
    if top is not None:
        top = C.number("top", top, C.Range(unit="m"))
    clearance = CLEARANCE * rmax
    out = []
    for r in regions:
        C.body_budget("region", r, math.sqrt(2.0) * r.volume(math.inf if top is None else top + clearance) / a ** 3)
        out.append(lattice_sites(r, a, clearance, top))
        if not out[-1]:
            raise C.BadValue("region", r, f"a region that holds a grain: no site of the lattice of spacing {a:g} m lies "
                             f"{clearance:g} m ({CLEARANCE:g} x the largest radius) inside it" + (f" up to {top:g} m" if top is not None else ""))
    return out


def place_grains(region, sizes, rnd, material, spacing=None, top=None):
    """Spheres of `material` on lattice_sites of each region (one, or a sequence of disjoint ones,
    in turn) at the spacing [m] (default SPACING x the largest radius), clearance CLEARANCE x the
    largest radius, up to the height top [m]; each radius drawn in turn by sizes (GrainSizes)
    with rnd. Returns (grain ids, their radii [m])."""
    ids, radii = [], []
    for sites in _sites(_regions(region), sizes, spacing, top):
        for x, y, z in sites:
            rad = sizes.radius(rnd)
            radii.append(rad)
            ids.append(_sphere_body(Vector3(x, y, z), rad, material))
    return ids, radii


def _fell_through(grains, rmax):
    """A check, after each chunk of steps, that no grain has fallen more than two of the largest
    radii below every other body's bounding box (it would fall for ever: the container has no
    floor, or a hole larger than the grains): RuntimeError naming it."""
    gs = set(grains)

    def check():
        floor = min((b.bound.min[2] for b in O.bodies if b is not None and b.id not in gs and b.bound is not None), default=-math.inf)
        low = min(grains, key=lambda g: O.bodies[g].state.pos[2])
        z = O.bodies[low].state.pos[2]
        if z < floor - 2 * rmax:
            raise RuntimeError(f"grain #{low} fell through the container (z = {z:.4g} m, below its lowest body, {floor:.4g} m): "
                               "a floor is missing or has a hole larger than the grains")
    return check


def unbalanced_force():
    """YADE's unbalanced force (utils.unbalancedForce: the mean over the dynamic bodies of the
    resultant of their forces and weight, over the mean contact force) [-], the supports left
    out: YADE counts the reaction on a body whose translations are blocked (a mesh's fixed
    border) as unbalanced, a force its support balances. Here a body with x, y and z blocked is
    left out, one with some blocked counts along the others. Without such bodies, YADE's call."""
    from yade import utils
    bodies = [b for b in O.bodies if b is not None and b.dynamic and not b.isClumpMember]
    ge = grain_engine()  # (its contacts are not in O.interactions, where YADE's call looks)
    if ge is None and not any(set(b.state.blockedDOFs) & set("xyz") for b in bodies):
        return utils.unbalancedForce()
    g = next(e for e in O.engines if isinstance(e, NewtonIntegrator)).gravity
    free = [(b, [k for k, ax in enumerate("xyz") if ax not in b.state.blockedDOFs]) for b in bodies]
    res = [math.sqrt(sum((O.forces.f(b.id) + b.state.mass * g)[k] ** 2 for k in ks)) for b, ks in free if ks]
    contacts = [(i.phys.normalForce + i.phys.shearForce).norm() for i in O.interactions if i.isReal]
    contacts += [(fn + fs).norm() for _, _, fn, fs in (ge.contactList() if ge else ())]
    return (sum(res) / len(res)) / (sum(contacts) / len(contacts)) if res and contacts else math.nan


def _until_at_rest(grains, ke_tol, max_steps, report, t_min=-math.inf, balanced=False, chunk=500):
    """Steps in chunks until, from the time t_min [s] on, the grains' kinetic energy is below
    ke_tol [J] and (balanced) unbalanced_force() below UNBALANCED_TOL: yadeflex.module.fill._settle's rule, with
    the time a fall needs and the supports' reactions left out. report(steps, kinetic energy,
    ke_tol) after each chunk. Returns the steps taken; RuntimeError after max_steps."""
    steps, ubf = 0, math.nan
    while steps < max_steps:
        step_until(math.inf, chunk)
        steps += chunk
        ke = sum(0.5 * O.bodies[g].state.mass * O.bodies[g].state.vel.squaredNorm() for g in grains)
        report(steps, ke, ke_tol)
        if O.time >= t_min and ke < ke_tol:
            if not balanced:
                return steps
            ubf = unbalanced_force()
            if ubf < UNBALANCED_TOL:
                return steps
    raise RuntimeError(f"the fill did not settle in {max_steps} steps (kinetic energy {ke:.3g} J, limit {ke_tol:.3g} J"
                       + (f"; unbalanced force {ubf:.3g}, limit {UNBALANCED_TOL:.3g})" if balanced else ")"))


CONTAINER_NODE_SCALING = 100.0  # a yade-flex container's node masses x this while grains settle in it (settle_deposit)


def settle_deposit(grains, material, preset, height, damping=SETTLE_DAMPING, deposition_friction_deg=0.0, progress=None,
                   max_steps=400000, node_mass_scaling=None):
    """Settle the placed grains (ids; their material `material`, of fill preset `preset`) under
    gravity: without rolling resistance and frictionless (or at deposition_friction_deg [deg]:
    a looser packing), then with the preset's friction and rolling resistance, each stage until
    the grains' kinetic energy is below 1e-4 x their weight x height [m] and, in the second,
    unbalanced_force() below UNBALANCED_TOL; the first not before the grains had the time to fall
    from the lattice's top to its bottom at (1 - damping) g (with a short step, the first steps'
    kinetic energy is below the tolerance); local damping `damping`; at most max_steps steps a
    stage (else RuntimeError; also when a grain falls through the container). progress(stage,
    steps, kinetic energy [J], its tolerance [J]) as the steps go (steps 0: a stage starts).
    A container of yade-flex elements settles at the engines' default time-step safety, its
    nodes' masses x node_mass_scaling (default CONTAINER_NODE_SCALING; their weight held at m g,
    restored at the end: the same equilibrium at a step sqrt(node_mass_scaling) longer, as the
    damping module's structure settles). Returns ((steps of each stage), the kinetic-energy
    tolerance [J], (the grains' kinetic energy [J], unbalanced_force()) at rest)."""
    p = fill_preset(preset)
    dep = C.number("deposition_friction_deg", deposition_friction_deg,
                   dataclasses.replace(DEPOSITION_FRICTION, hi=min(45.0, p["friction_deg"])))
    max_steps = C.integer("max_steps", max_steps, 1)
    rmax = max(O.bodies[g].shape.radius for g in grains)
    check = _fell_through(grains, rmax)

    def chunk(stage):
        def report(s, ke, tol):
            check()
            if progress:
                progress(stage, s, ke, tol)
        return report
    # densification: no friction, no rolling resistance (a standard DEM filling procedure); a
    # deposition friction above 0 leaves the grains less dense
    phi = material.frictionAngle
    material.frictionAngle = math.radians(dep)
    # the grains alone settle at the filling's step; a container of yade-flex elements (light
    # nodes under stiff contacts) at the engines' default safety
    from yade.wrapper import FlexNode
    flex = any(b is not None and isinstance(b.shape, FlexNode) for b in O.bodies)
    safety = DEFAULT_TIMESTEP_SAFETY if flex else FILL_TIMESTEP_SAFETY
    scaling = C.number("node_mass_scaling", CONTAINER_NODE_SCALING if node_mass_scaling is None else node_mass_scaling, C.Range(1.0, 1e4))
    O.engines = fill_engines(p, damping, friction=False, timestep_safety=safety)
    heavier = _heavier_nodes(scaling) if flex else []
    O.dt = 1e-5
    ke_tol = 1e-4 * sum(O.bodies[g].state.mass for g in grains) * G * height
    stage = f"fill, deposited at {dep:g} deg" if dep else "fill, dense"
    if progress:  # the count of grains sets the time a step takes
        progress(f"{stage} ({len(grains)} grains placed)", 0, float("nan"), ke_tol)
    zs = [O.bodies[g].state.pos[2] for g in grains]
    t_fall = math.sqrt(2 * (max(zs) - min(zs) + 2 * rmax) / ((1 - damping) * G))
    s1 = _until_at_rest(grains, ke_tol, max_steps, chunk(stage), t_min=O.time + t_fall)
    # then the fill's own friction and rolling resistance, on the existing contacts too (as
    # Ip2_FrictMat_FrictMat_FrictPhys sets it: the smaller angle of the two materials, so a
    # frictionless container stays frictionless)
    material.frictionAngle = phi
    for i in O.interactions:
        if i.isReal and hasattr(i.phys, "tangensOfFrictionAngle"):
            angles = [getattr(O.bodies[k].material, "frictionAngle", 0.0) for k in (i.id1, i.id2)]
            i.phys.tangensOfFrictionAngle = math.tan(min(angles))
    O.engines = fill_engines(p, damping, timestep_safety=safety)
    if progress:
        progress("fill, with friction", 0, float("nan"), ke_tol)
    s2 = _until_at_rest(grains, ke_tol, max_steps, chunk("fill, with friction"), balanced=True)
    # (at rest: measured before the container's own masses come back)
    rest = (sum(0.5 * O.bodies[g].state.mass * O.bodies[g].state.vel.squaredNorm() for g in grains), unbalanced_force())
    if heavier:
        _restore_nodes(heavier)
    return (s1, s2), ke_tol, rest


def trim_grains(grains, height):
    """Erase the grains not wholly below the height [m]; returns the ids kept."""
    kept = []
    for g in grains:
        b = O.bodies[g]
        if b.state.pos[2] + b.shape.radius > height:
            O.bodies.erase(g)
        else:
            kept.append(g)
    return kept


@dataclasses.dataclass
class DepositResult:
    """What deposit() left: the grains' ids, the steps of its two stages, the kinetic energy [J]
    (and its tolerance) and the unbalanced force [-] (unbalanced_force()) when they came to rest (before the trim),
    the fill's top (highest grain surface [m]), the solid fraction of the regions below it (the
    grains centred in them; the looser layers along the walls, the floor and the top included),
    the radii drawn [m] (every grain placed, the trimmed ones too, in placement order)."""
    grains: list
    steps: tuple
    kinetic_energy: float
    ke_tol: float
    unbalanced_force: float
    top: float
    solid_fraction: float
    radii: list


def deposit(region, preset="gravel", seed=1, sizes=None, spacing=None, top=None, height_fraction=None, deposition_friction_deg=0.0,
            damping=SETTLE_DAMPING, trim_height=None, progress=None, max_steps=400000, node_mass_scaling=None):
    """Grains of the fill preset `preset` (a name of FILLS, a preset dict or a ModuleParams: their
    density, friction, modulus, rolling resistance) deposited into the scene's container: placed
    on a close-packed lattice in `region` (a BoxRegion, a CylinderRegion or a sequence of them, see the
    module's docstring) up to the height top [m] (or height_fraction of the region's height;
    default: all of it), their radii drawn by sizes (GrainSizes; default the preset's uniform
    sizes) with seed (an int or a random.Random), then settled in the bodies the scene holds
    (settle_deposit, local damping `damping`), and trimmed to the grains wholly below trim_height
    [m] if given. The kinetic-energy tolerance's height is trim_height (else the region's top,
    or top) above the region's floor. progress(stage, steps, kinetic energy [J], its tolerance [J])
    while settling; max_steps, node_mass_scaling: settle_deposit's. Returns a DepositResult."""
    regions = _regions(region)
    p = fill_preset(preset)
    sizes = GrainSizes.of(p) if sizes is None else sizes
    rnd = seed if isinstance(seed, random.Random) else random.Random(C.integer("seed", seed, 0, 2 ** 63 - 1))
    damping = C.number("damping", damping, DAMPING)
    C.number("deposition_friction_deg", deposition_friction_deg, dataclasses.replace(DEPOSITION_FRICTION, hi=min(45.0, p["friction_deg"])))
    zlo, zhi = min(r.bounds()[0][2] for r in regions), max(r.bounds()[1][2] for r in regions)
    if top is not None and height_fraction is not None:
        raise ValueError("deposit: give top or height_fraction, not both")
    if height_fraction is not None:
        top = zlo + C.number("height_fraction", height_fraction, C.Range(0.0, 1.0, lo_open=True)) * (zhi - zlo)
    if trim_height is not None:
        trim_height = C.number("trim_height", trim_height, C.Range(zlo, math.inf, "m", lo_open=True, note="above the region's floor"))
    if not any(b is not None for b in O.bodies):
        raise ValueError("deposit: the scene holds no container (add its floor and sides first: YADE walls, facets or boxes, "
                         "yade-flex meshes or membranes)")
    _sites(regions, sizes, spacing, top)  # (its checks before anything is added)
    mat = _grain_material(p)
    grains, radii = place_grains(regions, sizes, rnd, mat, spacing, top)
    height = (trim_height if trim_height is not None else (zhi if top is None else min(top, zhi))) - zlo
    steps, ke_tol, (ke, ubf) = settle_deposit(grains, mat, p, height, damping, deposition_friction_deg, progress, max_steps, node_mass_scaling)
    if trim_height is not None:
        grains = trim_grains(grains, trim_height)
    for g in grains:
        O.bodies[g].state.vel = Vector3(0, 0, 0)
        O.bodies[g].state.angVel = Vector3(0, 0, 0)
    fill_top = max(O.bodies[g].state.pos[2] + O.bodies[g].shape.radius for g in grains) if grains else zlo
    at = lambda g: O.bodies[g].state.pos
    inside = [g for g in grains if any(r.contains(at(g)[0], at(g)[1], at(g)[2], 0.0) for r in regions)]
    solid = sum(4 / 3 * math.pi * O.bodies[g].shape.radius ** 3 for g in inside)
    vol = sum(r.volume(fill_top) for r in regions)
    return DepositResult(grains=grains, steps=steps, kinetic_energy=ke, ke_tol=ke_tol, unbalanced_force=ubf, top=fill_top,
                         solid_fraction=solid / vol if vol > 0 else 0.0, radii=radii)


def settle(damping=0.3, ke_tol=None, node_mass_scaling=1.0, max_steps=1_000_000, progress=None):
    """The whole scene brought to rest (a structure on its fill, a panel hanging on its anchors)
    before a load: numerical damping `damping` on the engines (O.engines, set by
    yadeflex.engines() if empty), the yade-flex nodes' mass x node_mass_scaling (>= 1; their
    weight held at m g: the same equilibrium at a longer time step), until the dynamic bodies'
    kinetic energy is below ke_tol [J] (default 1e-5 x their weight x the scene's height) and
    unbalanced_force() below UNBALANCED_TOL. Then the masses are restored, every body is at
    rest and the damping is back to its value. progress(steps, kinetic energy, ke_tol) after
    each chunk. Returns the steps taken; RuntimeError if not at rest after max_steps."""
    from .scene import engines
    damping = C.number("damping", damping, DAMPING)
    node_mass_scaling = C.number("node_mass_scaling", node_mass_scaling, C.Range(1.0, 1e4))
    if not O.engines:
        O.engines = engines()
    newton = next(e for e in O.engines if isinstance(e, NewtonIntegrator))
    bodies = [b.id for b in O.bodies if b is not None and b.dynamic and not b.isClumpMember]
    if not bodies:
        raise ValueError("settle: the scene has no dynamic body")
    if ke_tol is None:
        zs = [O.bodies[i].state.pos[2] for i in bodies]
        ke_tol = 1e-5 * sum(O.bodies[i].state.mass for i in bodies) * newton.gravity.norm() * max(max(zs) - min(zs), 0.1)
    ke_tol = C.positive("ke_tol", ke_tol, "J")
    own = newton.damping
    newton.damping = damping
    heavier = _heavier_nodes(node_mass_scaling)
    try:
        return _until_at_rest(bodies, ke_tol, max_steps, progress or (lambda *a: None), balanced=True)
    finally:
        _restore_nodes(heavier)
        newton.damping = own
