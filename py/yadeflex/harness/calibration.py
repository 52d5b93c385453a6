"""Laboratory tests of a fill preset (yadeflex.module.FILLS): what a fill of the preset's spheres
does in bulk, to compare with documented values of the real material.

- repose_test: the angle of repose. A column of grains, filled as the module's fill is, stands
  in a frictionless cylinder on a floor of fixed grains (the largest size); the cylinder is lifted slowly and the
  grains flow out into a heap, whose flank angle is measured (heap_angle).
- oedometer_test: confined compression. The module's fill procedure in a rigid frictionless
  cylinder; a frictionless plate pushes down at a slow, constant speed. Measured: the vertical
  stress on the plate and on the floor, the radial stress on the cylinder, hence the
  constrained modulus M = d(sigma_v)/d(epsilon) over stress ranges, the earth-pressure ratio
  K0 = d(sigma_h)/d(sigma_v), and the isotropic elastic moduli these give (lambda = K0 M,
  nu = K0 / (1 + K0), E = M (1 + nu)(1 - 2 nu) / (1 - nu)), among them the Lame constant and
  the plate-load modulus of the cushion formulas (yadeflex.module.cushion).
- plate_load_test: the plate-load modulus M_E of the cushion formulas, measured as they define
  it: a rigid circular plate pressed into the surface of a fill layer filled as the module's
  fill is, M_E = D dp/ds (D the plate's diameter, p its mean pressure, s its settlement).
- bulk density: the solid fraction of the settled fill times the grains' density.
The tests start from an empty O (O.reset()). validation/fill_calibration.py runs them on the
presets and writes the report."""
import math
import random

import numpy as np

from yade import O
from yade.minieigenHP import Vector3
from yade.wrapper import FrictMat, Sphere

from .. import checks as C
from ..scene import step_until
from ..constants import G
from ..module import FILLS, LIMITS, UNBALANCED_TOL, check_fill, settle_grains, fill_engines, _settle

# the heap's flank: the part of the surface profile between these fractions of its height
# (the crest is rounded by the last grains to stop, the toe by the grains that rolled out)
FLANK = (0.2, 0.8)


def preset(fill="gravel", friction_deg=None, rolling_friction=None, young=None):
    """The preset's parameters with the given overrides, each checked as the main job checks it."""
    p = dict(FILLS[check_fill(fill)])
    for key, name, v in (("friction_deg", "fill_friction_deg", friction_deg), ("rolling_friction", "rolling_friction", rolling_friction),
                         ("young", "fill_young", young)):
        if v is not None:
            p[key] = LIMITS[name].check(name, v)
    return p


def heap_angle(centers, radii, z_floor=0.0, axis=None, bin_width=None, flank=FLANK):
    """Angle of repose [deg] of a heap of spheres: the surface profile (per ring of width
    bin_width about the vertical axis through `axis` (x, y), default the grains' centroid: the
    highest sphere top), and a straight line fitted to it where it lies between flank[0] and
    flank[1] of the heap's height above z_floor. Returns dict(angle_deg, r, top (the profile),
    fit (r0, r1), n_fit, height)."""
    xyz = np.asarray(centers, dtype=float).reshape(-1, 3)
    rad = np.asarray(radii, dtype=float).reshape(-1)
    if len(xyz) < 10 or len(rad) != len(xyz):
        raise ValueError(f"heap_angle needs at least 10 spheres with one radius each, got {len(xyz)} centres and {len(rad)} radii")
    if not (np.isfinite(xyz).all() and np.isfinite(rad).all()):
        raise ValueError("heap_angle: non-finite sphere centre or radius")
    cx, cy = (xyz[:, 0].mean(), xyz[:, 1].mean()) if axis is None else axis
    w = float(bin_width) if bin_width is not None else 2 * float(rad.mean())
    r = np.hypot(xyz[:, 0] - cx, xyz[:, 1] - cy)
    top = xyz[:, 2] + rad
    k = (r // w).astype(int)
    prof = np.full(k.max() + 1, -np.inf)
    np.maximum.at(prof, k, top)
    rc = (np.arange(len(prof)) + 0.5) * w
    have = np.isfinite(prof)
    rc, prof = rc[have], prof[have]
    h = prof.max() - z_floor
    sel = (prof >= z_floor + flank[0] * h) & (prof <= z_floor + flank[1] * h)
    if sel.sum() < 3:
        return dict(angle_deg=math.nan, r=rc, top=prof, fit=(math.nan, math.nan), n_fit=int(sel.sum()), height=h)
    slope, icpt = np.polyfit(rc[sel], prof[sel], 1)
    return dict(angle_deg=math.degrees(math.atan(-slope)), r=rc, top=prof, fit=(float(rc[sel].min()), float(rc[sel].max())),
                n_fit=int(sel.sum()), height=float(h), intercept=float(icpt))


def _grain_ids():
    return [b.id for b in O.bodies if b is not None and isinstance(b.shape, Sphere) and b.dynamic]


def repose_test(fill="gravel", friction_deg=None, rolling_friction=None, young=None, radius=0.25, height=0.5, lift_speed=0.025, damping=0.2,
                seed=1, progress=None):
    """Angle of repose of the preset's grains (overrides as in preset()): a column of radius
    `radius` and height `height` [m], filled as the module's fill is (settle_grains) on a floor
    of the largest grains fixed side by side, then the frictionless cylinder lifted at
    lift_speed [m/s] and the grains left to come to rest (kinetic energy and unbalanced force,
    local damping `damping`). The slower the lift, the steeper the heap: the grains that run out
    last arrive slower and stop on a steeper flank (validation/calibration shows by how much). Returns dict(angle_deg, heap (heap_angle's dict), grains,
    params, steps, seconds simulated)."""
    p = preset(fill, friction_deg, rolling_friction, young)
    radius = C.number("radius", radius, C.Range(2 * p["grain_max"], 2.0, "m", note="at least two of the largest grains"))
    height = C.number("height", height, C.Range(2 * p["grain_max"], 4.0, "m", note="at least two of the largest grains"))
    lift_speed = C.number("lift_speed", lift_speed, C.Range(0.0, 1.0, "m/s", lo_open=True))
    damping = C.number("damping", damping, LIMITS["damping"])
    O.reset()
    # the floor reaches as far as a cone of the column's volume with a flank of 20 degrees
    floor = (3 * radius * radius * height / math.tan(math.radians(20.0))) ** (1 / 3) + p["grain_max"]
    _, grains, ke_tol, container = settle_grains(p, height, radius, random.Random(seed), rough_floor=floor, keep_container=True,
                                                 progress=progress)
    O.engines = fill_engines(p, damping)
    t0, it0 = O.time, O.iter
    for f in container:
        O.bodies[f].state.vel = Vector3(0, 0, lift_speed)
    lift = height + 0.05
    while O.time - t0 < lift / lift_speed:
        step_until(math.inf, 200)
        if progress:
            progress("lifting the cylinder", O.iter - it0, O.time - t0, lift / lift_speed)
    for f in container:
        O.bodies.erase(f)
    _settle(ke_tol, 400000, progress=progress and (lambda s, ke, tol: progress("heap", s, ke, tol)), unbalanced_tol=UNBALANCED_TOL)
    ids = _grain_ids()
    heap = heap_angle([tuple(O.bodies[i].state.pos) for i in ids], [O.bodies[i].shape.radius for i in ids], z_floor=p["grain_max"])
    return dict(angle_deg=heap["angle_deg"], heap=heap, grains=len(ids), params=p, steps=O.iter - it0, seconds=O.time - t0)


def solid_fraction(centers, radii, radius, z0, z1, voxel=0.004):
    """Fraction of the cylinder of `radius` about the z axis between z0 and z1 [m] that the
    spheres fill, counted on a grid of voxel-sized cells (their centres inside a sphere)."""
    xyz = np.asarray(centers, dtype=float).reshape(-1, 3)
    rad = np.asarray(radii, dtype=float).reshape(-1)
    n = int(math.ceil(2 * radius / voxel))
    nz = int(math.ceil((z1 - z0) / voxel))
    g = (np.arange(n) + 0.5) * (2 * radius / n) - radius
    gz = z0 + (np.arange(nz) + 0.5) * ((z1 - z0) / nz)
    full = np.zeros((n, n, nz), dtype=bool)
    dx, dz = 2 * radius / n, (z1 - z0) / nz
    for (x, y, z), r in zip(xyz, rad):
        i0, i1 = max(0, int((x - r + radius) / dx)), min(n, int((x + r + radius) / dx) + 1)
        j0, j1 = max(0, int((y - r + radius) / dx)), min(n, int((y + r + radius) / dx) + 1)
        k0, k1 = max(0, int((z - r - z0) / dz)), min(nz, int((z + r - z0) / dz) + 1)
        if i0 >= i1 or j0 >= j1 or k0 >= k1:
            continue
        X, Y, Z = np.meshgrid(g[i0:i1] - x, g[j0:j1] - y, gz[k0:k1] - z, indexing="ij")
        full[i0:i1, j0:j1, k0:k1] |= X * X + Y * Y + Z * Z <= r * r
    X, Y = np.meshgrid(g, g, indexing="ij")
    inside = (X * X + Y * Y <= radius * radius)[:, :, None]
    return float((full & inside).sum() / (inside.sum() * nz))


def first_crossing(x, y, level):
    """x where the curve y(x) first reaches `level`, interpolated linearly; nan if it never does."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    k = np.nonzero(y >= level)[0]
    if len(k) == 0:
        return math.nan
    j = k[0]
    if j == 0:
        return float(x[0])
    return float(x[j - 1] + (level - y[j - 1]) * (x[j] - x[j - 1]) / (y[j] - y[j - 1]))


def secant(x, y, y0, y1):
    """(y1 - y0) / (x(y1) - x(y0)) along a curve y(x) rising through y0 and y1 (first
    crossings); nan if the curve does not reach y1."""
    xa, xb = first_crossing(x, y, y0), first_crossing(x, y, y1)
    return (y1 - y0) / (xb - xa) if math.isfinite(xa) and math.isfinite(xb) and xb > xa else math.nan


def elastic_from_oedometer(M, K0):
    """Isotropic linear elastic moduli from a constrained modulus M [Pa] and the ratio K0 of
    radial to vertical stress increments: dict(lame, nu, young, shear, plate_load), plate_load
    being the modulus of a plate-load test, M_E = p D / s = 4 E / (pi (1 - nu^2)) (a rigid
    circular plate on an elastic half-space)."""
    nu = K0 / (1 + K0)
    E = M * (1 + nu) * (1 - 2 * nu) / (1 - nu)
    return dict(lame=K0 * M, nu=nu, young=E, shear=0.5 * M * (1 - K0), plate_load=4 * E / (math.pi * (1 - nu * nu)))


def oedometer_test(fill="gravel", friction_deg=None, rolling_friction=None, young=None, radius=0.3, height=0.3, max_stress=400e3,
                   strain_rate=0.05, damping=0.2, seed=1, ranges=((10e3, 50e3), (50e3, 100e3), (100e3, 200e3), (200e3, 400e3)),
                   every=20, progress=None):
    """Confined compression of the preset's fill (overrides as in preset()): the module's fill
    procedure (settle_grains) in a frictionless cylinder of `radius` and `height` [m], then a
    frictionless plate lowered onto it at strain_rate [1/s] (quasi-static: inertial number
    about strain_rate d sqrt(rho / sigma) < 1e-3) until the vertical stress reaches max_stress
    [Pa], sampled every `every` steps. Returns dict with the curve (strain, sigma_top,
    sigma_bottom, sigma_v (their mean), sigma_h) [Pa], the solid fraction and bulk density
    (whole sample and its core, a grain away from floor, cylinder and top), and per stress
    range (lo, hi) [Pa] the secant constrained modulus M, the ratio K0 of the stress increments
    and elastic_from_oedometer's moduli."""
    p = preset(fill, friction_deg, rolling_friction, young)
    radius = C.number("radius", radius, C.Range(4 * p["grain_max"], 2.0, "m", note="at least four of the largest grains"))
    height = C.number("height", height, C.Range(4 * p["grain_max"], 4.0, "m", note="at least four of the largest grains"))
    max_stress = C.number("max_stress", max_stress, C.Range(1e3, 1e8, "Pa"))
    strain_rate = C.number("strain_rate", strain_rate, C.Range(0.0, 1.0, "1/s", lo_open=True))
    damping = C.number("damping", damping, LIMITS["damping"])
    every = C.integer("every", every, 1)
    O.reset()
    floor, grains, _, container = settle_grains(p, height, radius, random.Random(seed), keep_container=True, progress=progress)
    from yade import utils
    z_top = max(O.bodies[g].state.pos[2] + O.bodies[g].shape.radius for g in grains)
    smooth = FrictMat(young=p["young"], poisson=0.3, density=1000, frictionAngle=0.0, label="plate")
    O.materials.append(smooth)
    plate = O.bodies.append(utils.wall(z_top, axis=2, sense=-1, material=smooth))
    mass = sum(O.bodies[g].state.mass for g in grains)
    area = math.pi * radius * radius
    dmean = 0.5 * (p["grain_min"] + p["grain_max"])
    cs, rs = [tuple(O.bodies[g].state.pos) for g in grains], [O.bodies[g].shape.radius for g in grains]
    out = dict(params=p, grains=len(grains), height=z_top, radius=radius, mass=mass,
               solid_fraction=solid_fraction(cs, rs, radius, 0.0, z_top),
               core_solid_fraction=solid_fraction(cs, rs, radius - dmean, dmean, z_top - dmean))
    out["bulk_density"] = out["solid_fraction"] * p["density"]
    out["core_bulk_density"] = out["core_solid_fraction"] * p["density"]
    O.engines = fill_engines(p, damping)
    speed = strain_rate * z_top
    O.bodies[plate].state.vel = Vector3(0, 0, -speed)
    curve = dict(strain=[], sigma_top=[], sigma_bottom=[], sigma_h=[])
    it0 = O.iter
    while True:
        step_until(math.inf, every)
        zp = O.bodies[plate].state.pos[2]
        radial = 0.0
        for f in container:
            fv = O.forces.f(f)
            c = O.bodies[f].state.pos
            n = math.hypot(c[0], c[1])
            radial += (fv[0] * c[0] + fv[1] * c[1]) / n if n > 0 else 0.0
        curve["strain"].append((z_top - zp) / z_top)
        curve["sigma_top"].append(O.forces.f(plate)[2] / area)
        curve["sigma_bottom"].append(O.forces.f(floor)[2] * -1.0 / area)
        curve["sigma_h"].append(radial / (2 * math.pi * radius * zp))
        if progress:
            progress("compression", O.iter - it0, curve["sigma_top"][-1], max_stress)
        if curve["sigma_top"][-1] >= max_stress:
            break
        if (z_top - zp) > 0.2 * z_top:
            raise RuntimeError(f"the oedometer plate went down 20% of the sample without reaching {max_stress:g} Pa "
                               f"({curve['sigma_top'][-1]:.4g} Pa)")
    curve = {k: np.asarray(v) for k, v in curve.items()}
    curve["sigma_v"] = 0.5 * (curve["sigma_top"] + curve["sigma_bottom"])
    out["curve"] = curve
    out["weight_stress"] = mass * G / area
    out["steps"] = O.iter - it0
    rows = []
    for lo, hi in ranges:
        M = secant(curve["strain"], curve["sigma_v"], lo, hi)
        K0 = (first_crossing(curve["sigma_h"], curve["sigma_v"], hi) - first_crossing(curve["sigma_h"], curve["sigma_v"], lo)) / (hi - lo)
        row = dict(lo=lo, hi=hi, M=M, K0=K0)
        if math.isfinite(M) and math.isfinite(K0):
            row.update(elastic_from_oedometer(M, K0))
        rows.append(row)
    out["ranges"] = rows
    return out


def _disk(z, radius, n, mat):
    """A rigid horizontal disk of n triangular facets (a fan about the axis) at height z."""
    from yade import utils
    ids = []
    for k in range(n):
        t0, t1 = 2 * math.pi * k / n, 2 * math.pi * (k + 1) / n
        v = [Vector3(0, 0, z), Vector3(radius * math.cos(t0), radius * math.sin(t0), z), Vector3(radius * math.cos(t1), radius * math.sin(t1), z)]
        ids.append(O.bodies.append(utils.facet(v, material=mat, fixed=True)))
    return ids


def plate_load_test(fill="gravel", friction_deg=None, rolling_friction=None, young=None, plate_diameter=0.3, radius=0.3, height=0.6,
                    max_stress=200e3, max_settlement=0.06, speed=0.005, damping=0.2, seed=1, ranges=((10e3, 50e3), (50e3, 100e3), (100e3, 200e3)),
                    every=20, progress=None):
    """Plate-load test of the preset's fill (overrides as in preset()): the module's fill
    procedure (settle_grains) in a rigid frictionless cylinder of `radius` and `height` [m] on a
    rigid floor (a layer on a slab, as a cushion is), then a rigid circular plate of
    `plate_diameter` [m] (a polygon of 36 sides inscribed in that circle), as rough as the grains, pressed into the middle of its surface at a
    constant `speed` [m/s] until its mean pressure reaches max_stress [Pa] or it has sunk
    max_settlement [m] (a fill that gives way under the plate: then `reached` is False and the
    ranges above the last pressure have no modulus), sampled every `every` steps. The plate
    starts on the highest grain under it. Returns dict with the curve
    (settlement s [m], pressure p [Pa] on the plate, sigma_bottom [Pa]: the floor's mean vertical
    stress), the sample's solid fraction and weight, and per pressure range (lo, hi) [Pa] the
    secant plate-load modulus M_E = D (hi - lo) / (s(hi) - s(lo)) [Pa] (first crossings), and
    `imbalance`: the mean of |floor load - weight - plate load| / plate load above 10 kPa (zero
    when quasi-static)."""
    p = preset(fill, friction_deg, rolling_friction, young)
    plate_diameter = C.number("plate_diameter", plate_diameter, C.Range(4 * p["grain_max"], 2.0, "m", note="at least four of the largest grains"))
    radius = C.number("radius", radius, C.Range(plate_diameter, 4.0, "m", note="at least the plate's diameter: the container at half a plate from its edge"))
    height = C.number("height", height, C.Range(plate_diameter, 4.0, "m", note="at least the plate's diameter"))
    max_stress = C.number("max_stress", max_stress, C.Range(1e3, 1e8, "Pa"))
    max_settlement = C.number("max_settlement", max_settlement, C.Range(0.0, 0.5 * plate_diameter, "m", lo_open=True, note="at most half the plate's diameter"))
    speed = C.number("speed", speed, C.Range(0.0, 1.0, "m/s", lo_open=True))
    damping = C.number("damping", damping, LIMITS["damping"])
    every = C.integer("every", every, 1)
    O.reset()
    floor, grains, _, container = settle_grains(p, height, radius, random.Random(seed), keep_container=True, progress=progress)
    R = 0.5 * plate_diameter
    under = [g for g in grains if math.hypot(O.bodies[g].state.pos[0], O.bodies[g].state.pos[1]) < R + O.bodies[g].shape.radius]
    z0 = max(O.bodies[g].state.pos[2] + O.bodies[g].shape.radius for g in under)
    gmat = O.bodies[grains[0]].material
    n_facets = 36
    plate = _disk(z0, R, n_facets, gmat)
    mass = sum(O.bodies[g].state.mass for g in grains)
    area = 0.5 * n_facets * R * R * math.sin(2 * math.pi / n_facets)  # the plate's polygon
    floor_area = math.pi * radius * radius
    cs, rs = [tuple(O.bodies[g].state.pos) for g in grains], [O.bodies[g].shape.radius for g in grains]
    out = dict(params=p, grains=len(grains), plate_diameter=plate_diameter, plate_area=area, radius=radius, height=height, mass=mass,
               solid_fraction=solid_fraction(cs, rs, radius, 0.0, height), weight_stress=mass * G / floor_area)
    O.engines = fill_engines(p, damping)
    for f in plate:
        O.bodies[f].state.vel = Vector3(0, 0, -speed)
    curve = dict(s=[], p=[], sigma_bottom=[])
    it0 = O.iter
    while True:
        step_until(math.inf, every)
        curve["s"].append(z0 - O.bodies[plate[0]].state.pos[2])
        curve["p"].append(sum(O.forces.f(f)[2] for f in plate) / area)
        curve["sigma_bottom"].append(-O.forces.f(floor)[2] / floor_area)
        if progress:
            progress("plate load", O.iter - it0, curve["p"][-1], max_stress)
        if curve["p"][-1] >= max_stress or curve["s"][-1] >= max_settlement:
            break
    out["reached"] = bool(curve["p"][-1] >= max_stress)
    curve = {k: np.asarray(v) for k, v in curve.items()}
    # quasi-static: the frictionless container carries no vertical load, so the floor carries the
    # plate's load and the weight; the mean imbalance relative to the plate's load above 10 kPa
    on = curve["p"] > 10e3
    F = curve["p"][on] * area
    out["imbalance"] = float(np.mean(np.abs(curve["sigma_bottom"][on] * floor_area - mass * G - F) / F)) if on.any() else math.nan
    out["curve"] = curve
    out["steps"] = O.iter - it0
    out["ranges"] = [dict(lo=lo, hi=hi, M_E=plate_diameter * secant(curve["s"], curve["p"], lo, hi)) for lo, hi in ranges]
    return out

