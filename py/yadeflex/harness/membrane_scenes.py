"""Membrane scenes defined once, reused by the tests and the benchmarks.

Each builder resets O, builds the scene and returns a dict with the ids that matter and the
parameters used.
"""
import math

from yade import O
from yade.minieigenHP import Vector3

from .. import checks as C
from .. import membrane as M
from ..constants import G
from ..builders import fix, _positive, _section
from ..materials import FRICTION_DEG, _density
from ..scene import DEFAULT_TIMESTEP_SAFETY, engines, engine_args
from .scenes import sphere


def _check_square(n, size, damping=0.0, gravity=G, timestep_safety=DEFAULT_TIMESTEP_SAFETY):
    """Arguments shared by the square scenes, checked before O.reset: n x n cells, size [m]."""
    n = C.integer("n", n, 1, C.MAX_BODIES)
    C.body_budget("n", n, 3.0 * (n + 1) * (n + 1) + 1)
    _positive("size", size)
    engine_args((0, 0, gravity), damping, timestep_safety)


def _check_membrane(stiffness, poisson):
    M.membrane_material(stiffness, 0.3, poisson=poisson, tension_only=False)


def _check_sphere(radius, density, friction_deg, drop):
    _positive("sphere_radius", radius)
    _density("sphere_density", density)
    C.number("friction_deg", friction_deg, FRICTION_DEG)
    C.number("drop", drop, C.Range(0.0, unit="m"))


def pretensioned_square(n=16, size=1.0, prestrain=0.01, load=1.0, stiffness=20e3, poisson=0.3, damping=0.8):
    """Square membrane (n x n cells, side `size` [m] at rest, clamped border), stretched
    uniformly by (1 + prestrain) in both directions, with a point load `load` [N] (-z) on
    its centre node. Prestress per unit current width: T = Et/(1-nu) ((1+e)^2 - 1)/2."""
    if C.integer("n", n, 2, C.MAX_BODIES) % 2:
        raise C.BadValue("n", n, "an even number (a centre node)")
    _check_square(n, size, damping)
    C.number("prestrain", prestrain, C.Range(0.0, 1.0, note="the sheet is stretched by 1 + prestrain"))
    C.number("load", load, C.Range(unit="N"))
    _check_membrane(stiffness, poisson)
    O.reset()
    mat = M.membrane_material(stiffness, 0.3, poisson=poisson, tension_only=False)
    sh = M.sheet(n, n, (size, size), 0.002, mat, origin=(-size / 2, -size / 2, 0))
    lam = 1 + prestrain
    for row in sh["grid"]:
        for i in row:
            O.bodies[i].state.pos = O.bodies[i].state.pos * lam
    centre = sh["grid"][n // 2][n // 2]
    O.engines = engines(gravity=(0, 0, 0), damping=damping)
    O.forces.setPermF(centre, Vector3(0, 0, -load))
    T = stiffness / (1 - poisson) * (lam * lam - 1) / 2
    return dict(sheet=sh, centre=centre, side=size * lam, tension=T,
                params=dict(n=n, size=size, prestrain=prestrain, load=load, stiffness=stiffness, poisson=poisson))


def square_membrane_deflection(x, y, x0, y0, load, tension, side, terms=400):
    """Linear membrane theory (T lap w = -P delta): deflection at (x, y) of a square membrane
    (side a, uniform tension T [N/m], edges fixed) under a point load P at (x0, y0); all
    coordinates from one corner. Double sine series, summed to `terms` per direction."""
    a = side
    s = 0.0
    for m in range(1, terms + 1):
        sm = math.sin(m * math.pi * x0 / a) * math.sin(m * math.pi * x / a)
        if sm == 0:
            continue
        for k in range(1, terms + 1):
            sk = math.sin(k * math.pi * y0 / a) * math.sin(k * math.pi * y / a)
            s += sm * sk / ((m * math.pi / a) ** 2 + (k * math.pi / a) ** 2)
    return 4 * load / (tension * a * a) * s


def circular_membrane(rings=12, radius=0.5, pressure=100.0, stiffness=20e3, poisson=0.3, damping=0.8):
    """Circular membrane (radius [m], `rings` rings of nodes, about 6k nodes on ring k, clamped
    edge), no prestress, under a uniform pressure [Pa] (+z, follower). Hencky's solution
    for nu = 0.3: centre deflection w0 = 0.662 a (p a / (E t))^(1/3)."""
    rings = C.integer("rings", rings, 1, C.MAX_BODIES)
    C.body_budget("rings", rings, 9.0 * rings * (rings + 1) + 1)
    _check_square(1, radius, damping)
    C.number("pressure", pressure, C.Range(unit="Pa"))
    _check_membrane(stiffness, poisson)
    O.reset()
    mat = M.membrane_material(stiffness, 0.3, poisson=poisson, tension_only=False)
    pts = [(0.0, 0.0, 0.0)]
    ring_start = [0]
    for k in range(1, rings + 1):
        ring_start.append(len(pts))
        nk = 6 * k
        for i in range(nk):
            a = 2 * math.pi * i / nk
            pts.append((radius * k / rings * math.cos(a), radius * k / rings * math.sin(a), 0.0))
    tris = []
    for k in range(1, rings + 1):
        inner = list(range(ring_start[k - 1], ring_start[k - 1] + max(1, 6 * (k - 1))))
        outer = list(range(ring_start[k], ring_start[k] + 6 * k))
        no = len(outer)
        if k == 1:  # the fan around the centre
            tris += [(0, outer[j], outer[(j + 1) % no]) for j in range(no)]
            continue
        # walk both rings by angle and triangulate the strip between them
        ni, i, j = len(inner), 0, 0
        while i < ni or j < no:
            if j < no and (i >= ni or (j + 1) / no <= (i + 1) / ni):
                tris.append((inner[i % ni], outer[j], outer[(j + 1) % no]))
                j += 1
            else:
                tris.append((inner[i % ni], outer[j % no], inner[(i + 1) % ni]))
                i += 1
    edge = list(range(ring_start[rings], len(pts)))
    nodes, facets = M.triangle_mesh(pts, tris, mat, 0.002, fixed=edge)
    for f in facets:
        O.bodies[f].shape.pressure = pressure
    O.engines = engines(gravity=(0, 0, 0), damping=damping)
    return dict(nodes=nodes, facets=facets, centre=nodes[0],
                params=dict(rings=rings, radius=radius, pressure=pressure, stiffness=stiffness, poisson=poisson))


def sheet_impact(n=16, size=1.0, thickness=0.002, stiffness=250e3, areal_density=0.3, tension_only=True,
                 sphere_radius=0.1, sphere_density=2000.0, drop=0.01, friction_deg=30.0, damping=0.0,
                 timestep_safety=DEFAULT_TIMESTEP_SAFETY, gravity=G):
    """Square sheet (n x n cells, clamped border, geotextile-like) and a sphere released
    `drop` [m] above it at its centre, under gravity."""
    _check_square(n, size, damping, gravity, timestep_safety)
    _section("thickness", thickness)
    M.membrane_material(stiffness, areal_density, tension_only=tension_only, friction_deg=friction_deg)
    _check_sphere(sphere_radius, sphere_density, friction_deg, drop)
    O.reset()
    mat = M.membrane_material(stiffness, areal_density, tension_only=tension_only, friction_deg=friction_deg)
    sh = M.sheet(n, n, (size, size), thickness, mat)
    s = sphere((size / 2, size / 2, thickness / 2 + sphere_radius + drop), sphere_radius, density=sphere_density, young=1e8,
               friction_deg=friction_deg)
    O.engines = engines(gravity=(0, 0, -gravity), damping=damping, timestep_safety=timestep_safety)
    return dict(sheet=sh, sphere=s, params=dict(n=n, size=size, thickness=thickness, stiffness=stiffness, areal_density=areal_density,
                                                tension_only=tension_only, sphere_radius=sphere_radius, drop=drop))


def bumpy_surface(n=20, size=1.0, amplitude=0.02, waves=3, sphere_radius=0.05, speed=1.0, friction_deg=20.0):
    """A sphere rolling/sliding over a fixed bumpy surface of facets z = A sin(k x) sin(k y)
    (n x n cells, crossed diagonals), launched along x at `speed` [m/s] under gravity."""
    _check_square(n, size)
    C.number("amplitude", amplitude, C.Range(0.0, 0.1 * size, "m", note="at most size/10"))
    C.number("waves", waves, C.Range(0.0, n / 4, note="at most n/4: four cells a wave"))
    _check_sphere(sphere_radius, 2500.0, friction_deg, 0.0)
    C.number("speed", speed, C.Range(unit="m/s"))
    O.reset()
    mat = M.membrane_material(250e3, 0.3, tension_only=False, friction_deg=friction_deg)
    k = 2 * math.pi * waves / size
    pts = [(size * i / n, size * j / n, amplitude * math.sin(k * size * i / n) * math.sin(k * size * j / n))
           for i in range(n + 1) for j in range(n + 1)]
    idx = lambda i, j: i * (n + 1) + j
    tris = []
    for i in range(n):
        for j in range(n):
            a, b, c, d = idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)
            tris += [(a, b, c), (a, c, d)] if (i + j) % 2 == 0 else [(a, b, d), (b, c, d)]
    nodes, facets = M.triangle_mesh(pts, tris, mat, 0.002, fixed=list(range(len(pts))))
    s = sphere((0.1 * size, 0.37 * size, amplitude + 0.001 + sphere_radius + 0.002), sphere_radius, density=2500.0, young=1e8,
               friction_deg=friction_deg, velocity=(speed, 0, 0))
    O.engines = engines(damping=0.0)
    return dict(nodes=nodes, facets=facets, sphere=s, params=dict(n=n, size=size, amplitude=amplitude, waves=waves,
                                                                   sphere_radius=sphere_radius, speed=speed))


def foppl_hencky_centre_deflection(pressure, radius, stiffness, poisson, steps=4000):
    """Centre deflection [m] of a clamped circular membrane (no prestress) under a uniform
    lateral pressure, from Foppl's axisymmetric membrane equations (small strain, moderate
    rotation: the theory behind Hencky's series, w0 ~ 0.65 a (p a/Et)^(1/3) for nu = 0.3),
    solved numerically here by shooting on the centre membrane force.
    Equations, y = r N_r: vertical equilibrium N_r w' = -p r/2; in-plane equilibrium
    N_t = y'; compatibility r^2 y'' + r y' - y = -Et p^2 r^5 / (8 y^2); u(a) = 0."""
    a, q, Et, nu = radius, pressure, stiffness, poisson

    def shoot(N0):
        r = a * 1e-4
        c = -Et * q * q / (64 * N0 * N0)
        y, yp = N0 * r + c * r ** 3, N0 + 3 * c * r * r
        h = (a - r) / steps
        w_int = 0.5 * q * r * r / (2 * N0)  # int_0^r q r/(2 N_r) dr

        def f(r, y, yp):
            return yp, (-Et * q * q * r ** 5 / (8 * y * y) - r * yp + y) / (r * r)

        for _ in range(steps):
            k1 = f(r, y, yp)
            k2 = f(r + h / 2, y + h / 2 * k1[0], yp + h / 2 * k1[1])
            k3 = f(r + h / 2, y + h / 2 * k2[0], yp + h / 2 * k2[1])
            k4 = f(r + h, y + h * k3[0], yp + h * k3[1])
            # slope integral by Simpson on the same step
            w_int += h / 6 * (q * r * r / (2 * y) + 4 * q * (r + h / 2) ** 2 / (2 * (y + h / 2 * k1[0] + h * h / 8 * k1[1]))
                               + q * (r + h) ** 2 / (2 * (y + h * k1[0] + h * h / 2 * k1[1])))
            y += h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
            yp += h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
            r += h
        return a * yp - nu * y, w_int

    lo, hi = 1e-6 * Et, Et  # N0 bracket [N/m]
    flo = shoot(lo)[0]
    for _ in range(200):
        mid = math.sqrt(lo * hi)
        fm, w = shoot(mid)
        if (fm > 0) == (flo > 0):
            lo, flo = mid, fm
        else:
            hi = mid
        if hi / lo - 1 < 1e-12:
            break
    return w


def hanging_fabric(n=8, size=0.5, thickness=0.002):
    """A square of geotextile (yadeflex.geotextile: tension-only, 40 kN/m strength), n x n cells
    of size [m], held along one edge (y = 0) and released flat (horizontal, z = 0) under gravity:
    it swings down, folds over and wrinkles while it carries only its own weight (tens of N/m at
    most). No damping."""
    C.integer("n", n, 1, 200)
    _positive("size", size)
    _section("thickness", thickness)
    O.reset()
    mat = M.geotextile()
    sh = M.sheet(n, n, (size, size), thickness, mat, fix_border=False)
    held = [col[0] for col in sh["grid"]]
    fix(held)
    O.engines = engines(damping=0.0)
    return dict(sheet=sh, held=held, params=dict(n=n, size=size, thickness=thickness))


def driven_indenter(n=8, size=0.8, speed=0.3, radius=0.1, thickness=0.002):
    """A rigid sphere of radius [m] held in every degree of freedom and driven down at speed
    [m/s] (a prescribed motion: an indenter or plate) into the centre of a square geotextile
    sheet (n x n cells of size [m], border clamped), from just above it. The drive's work is
    O.energy['driveWork'] (minus the work put in)."""
    C.integer("n", n, 1, 200)
    _positive("size", size)
    _positive("radius", radius)
    _section("thickness", thickness)
    C.number("speed", speed, C.Range(0.0, 100.0, "m/s"))
    O.reset()
    sh = M.sheet(n, n, (size, size), thickness, M.geotextile())
    s = sphere((0.5 * size, 0.5 * size, radius + 0.5 * thickness + 1e-4), radius, density=7850.0, young=1e8)
    fix([s])
    O.bodies[s].state.vel = Vector3(0, 0, -speed)  # held in every DOF, moved at this speed
    O.engines = engines(damping=0.0)
    return dict(sheet=sh, indenter=s, params=dict(n=n, size=size, speed=speed, radius=radius, thickness=thickness))
