"""Analytic cases, scene and measurement defined once: the tests (tests/yade) assert on them and
the validation report (validation/run.py) grades them. Each function resets O, builds its scene
with the library's builders, runs it and returns a dict with the measured value(s) and the
analytic reference computed from the same parameters."""
import math

from yade import O
from yade.minieigenHP import Vector3

from .. import checks as C
from ..constants import G
from . import scenes as S
from ..materials import steel



def _circle_I(r):
    return math.pi * r ** 4 / 4


def cantilever_deflection(load="tip", segments=10, length=1.0, radius=0.01, force=1.0, rel_tol=1e-7):
    """Steel cantilever (yadeflex.harness.scenes.cantilever) settled under a tip load force [N] ('tip'),
    its own weight ('self') or an axial tip force ('axial'). Returns dict(measured: the tip's
    deflection (-z) or elongation (x) [m], reference: Euler-Bernoulli P L^3 / 3EI, q L^4 / 8EI or
    the bar's P L / EA [m], axial_force of the first element [N] for 'axial')."""
    C.choice("load", load, ("tip", "self", "axial"))
    s = S.cantilever(segments=segments, length=length, radius=radius, load=load, force=force, gravity=G)
    S.settle([s["tip"]], rel_tol=rel_tol)
    E, rho = s["material"].young, s["material"].density
    tip = O.bodies[s["tip"]].state.pos
    out = dict(params=s["params"])
    if load == "tip":
        out.update(measured=-tip[2], reference=force * length ** 3 / (3 * E * _circle_I(radius)))
    elif load == "self":
        q = rho * math.pi * radius ** 2 * G
        out.update(measured=-tip[2], reference=q * length ** 4 / (8 * E * _circle_I(radius)))
    else:
        out.update(measured=tip[0] - length, reference=force * length / (E * math.pi * radius ** 2),
                   axial_force=O.bodies[s["cylinders"][0]].shape.axialForce)
    return out


def first_bending_frequency(segments=10, length=1.0, radius=0.01, window=0.5):
    """The cantilever deflected by a small tip load, settled, released without damping: the
    angular frequency of its free vibration from the upward zero crossings of the tip over
    window [s], against Euler-Bernoulli's first mode 1.875104^2 sqrt(EI / (rho A L^4)).
    Returns dict(measured, reference [rad/s], crossings)."""
    s = S.cantilever(segments=segments, length=length, radius=radius, load="tip", force=1.0, damping=0.0)
    O.engines[-1].damping = 0.8
    S.settle([s["tip"]], rel_tol=1e-6)
    O.engines[-1].damping = 0.0
    O.forces.setPermF(s["tip"], Vector3(0, 0, 0))
    tip = O.bodies[s["tip"]]
    t, z = [], []
    O.step()
    t0 = O.time
    while O.time < t0 + window:
        S.advance(50)  # ~90 samples per period
        t.append(O.time)
        z.append(tip.state.pos[2])
    ups = [t[k - 1] + (t[k] - t[k - 1]) * (-z[k - 1]) / (z[k] - z[k - 1]) for k in range(1, len(z)) if z[k - 1] < 0 <= z[k]]
    mat = s["material"]
    A, I = math.pi * radius ** 2, _circle_I(radius)
    omega1 = 1.875104 ** 2 * math.sqrt(mat.young * I / (mat.density * A * length ** 4))
    period = (ups[-1] - ups[0]) / (len(ups) - 1) if len(ups) >= 2 else math.nan
    return dict(measured=2 * math.pi / period, reference=omega1, crossings=len(ups))


def sphere_wire_impact(friction_deg=0.0, velocity=(0, 0, -3.0), duration=0.03):
    """A steel sphere (R = 30 mm) hitting a clamped steel wire (r = 3 mm, 1 m in 20 segments),
    no numerical damping, energy tracked. Returns dict(e0: the sphere's kinetic energy [J],
    worst: the largest |total energy - e0| over the run [J], touched)."""
    from ..builders import chain
    from ..scene import engines, contacts_on
    O.reset()
    mat = steel(friction_deg=friction_deg)
    chain([(-0.5, 0, 0), (0.5, 0, 0)], 0.003, mat, segments=20, fixed=[0, 20])
    R = 0.03
    s = S.sphere((0.01, 0, R + 0.003 + 1e-4), R, density=7850, young=2e9, friction_deg=friction_deg, velocity=velocity)
    O.engines = engines(damping=0.0)
    O.trackEnergy = True
    m = O.bodies[s].state.mass
    e0 = 0.5 * m * Vector3(*velocity).squaredNorm()
    worst, touched = 0.0, False
    while O.time < duration:
        S.advance(20)
        worst = max(worst, abs(O.energy.total() - e0))
        touched = touched or bool(contacts_on(s))
    return dict(e0=e0, worst=worst, touched=touched, measured=worst / e0, reference=0.0)


def pretensioned_square(n=16):
    """Square membrane (yadeflex.harness.membrane_scenes.pretensioned_square), 1 N at its centre,
    settled; the deflection at three nodes a quarter side from the load against the double sine
    series of linear membrane theory. Returns dict(measured: the worst relative error, reference 0)."""
    from . import membrane_scenes as MS
    sc = MS.pretensioned_square(n=n, load=1.0)
    S.settle([sc["centre"]], rel_tol=1e-7, chunk=1000)
    g, L = sc["sheet"]["grid"], sc["side"]
    worst = 0.0
    for (i, j) in [(n // 4, n // 2), (n // 4, n // 4), (n // 2, n // 4)]:
        p = O.bodies[g[i][j]].state.pos
        w = MS.square_membrane_deflection(p[0] + L / 2, p[1] + L / 2, L / 2, L / 2, 1.0, sc["tension"], L, terms=200)
        worst = max(worst, abs(-p[2] / w - 1))
    return dict(measured=worst, reference=0.0)


def circular_membrane(rings=12, pressure=100.0, radius=0.5, stiffness=20e3, poisson=0.3):
    """Clamped circular membrane under uniform pressure [Pa], settled: its centre deflection [m]
    against Foppl-Hencky (yadeflex.harness.membrane_scenes.foppl_hencky_centre_deflection)."""
    from . import membrane_scenes as MS
    ref = MS.foppl_hencky_centre_deflection(pressure, radius, stiffness, poisson)
    sc = MS.circular_membrane(rings=rings, radius=radius, pressure=pressure, stiffness=stiffness, poisson=poisson)
    S.settle([sc["centre"]], rel_tol=1e-7, chunk=1000)
    return dict(measured=O.bodies[sc["centre"]].state.pos[2], reference=ref)


def free_fall(height=1.0, radius=0.05):
    """A sphere released from rest under gravity, no contact: its speed when it has fallen
    height [m] (interpolated within the step that crosses it) against sqrt(2 g h)."""
    from ..scene import engines
    C.positive("height", height, "m")
    O.reset()
    s = S.sphere((0, 0, 0), radius)
    O.engines = engines(gravity=(0, 0, -G), damping=0.0)
    O.dt = 1e-4
    b = O.bodies[s].state
    z_prev, v_prev = 0.0, 0.0
    while -b.pos[2] < height:
        z_prev, v_prev = -b.pos[2], -b.vel[2]
        O.step()
    f = (height - z_prev) / (-b.pos[2] - z_prev)
    return dict(measured=v_prev + f * (-b.vel[2] - v_prev), reference=math.sqrt(2 * G * height), dt=O.dt)


def sphere_bounce(radius=0.05, density=2500.0, young=1e8, speed=1.0, timestep_safety=0.02):
    """A sphere dropped at speed [m/s] onto a fixed sphere of the same material (linear contact,
    no damping, no gravity): the duration of the contact against half the period of the contact
    spring, pi sqrt(m / kn), kn = E R (two equal spheres, YADE's Ip2_FrictMat_FrictMat_FrictPhys),
    and the rebound speed against the impact speed (elastic: restitution 1). timestep_safety:
    the fraction of the critical step (the default resolves the contact in ~90 steps)."""
    from ..scene import engines
    O.reset()
    a = S.sphere((0, 0, 0), radius, density=density, young=young, friction_deg=0.0)
    b = S.sphere((0, 0, 2 * radius + 1e-6), radius, density=density, young=young, friction_deg=0.0, velocity=(0, 0, -speed))
    O.bodies[a].state.blockedDOFs = "xyzXYZ"
    O.engines = engines(gravity=(0, 0, 0), damping=0.0, timestep_safety=timestep_safety)
    st = O.bodies[b].state
    t_on = t_off = None
    while t_off is None and O.time < 1.0:
        O.step()
        f = O.forces.f(b).norm()
        if f > 0 and t_on is None:
            t_on = O.time - O.dt  # the force acts over the step that has just run
        elif f == 0 and t_on is not None:
            t_off = O.time - O.dt
    m = st.mass
    kn = young * radius  # 2 E1 R1 E2 R2 / (E1 R1 + E2 R2) for equal spheres
    return dict(measured=(t_off - t_on) if t_off is not None else math.nan, reference=math.pi * math.sqrt(m / kn), dt=O.dt,
                rebound=st.vel[2] / speed)


def crushing_bounce(small=0.02, large=0.04, density=2500.0, young=1e8, speed=2.0, cap_share=0.3, timestep_safety=0.05):
    """A sphere of radius small [m] hits a fixed sphere of radius large [m] (frictionless, no
    gravity) with grain crushing on (engines' crushing_is50), its point-load index chosen so that
    the smaller sphere's failure load P is cap_share of the elastic impact's peak force
    speed sqrt(m kn). The contact force stops at P and unloads elastically, so the rebound speed
    is P / sqrt(m kn) (elastic-perfectly-plastic restitution) and the rest of the impact energy is
    booked as 'flexCrushing'. Returns the rebound speed (measured, reference), the largest normal
    force over P and the crushing energy over the kinetic energy lost."""
    from ..crushing import failure_load
    from ..scene import engines, step_until
    O.reset()
    a = S.sphere((0, 0, 0), large, density=density, young=young, friction_deg=0.0)
    b = S.sphere((0, 0, large + small + 1e-4), small, density=density, young=young, friction_deg=0.0, velocity=(0, 0, -speed))
    O.bodies[a].state.blockedDOFs = "xyzXYZ"
    m, kn = O.bodies[b].state.mass, young * 2 * large * small / (large + small)  # FrictPhys: 2 E1 R1 E2 R2 / (E1 R1 + E2 R2)
    limit = cap_share * speed * math.sqrt(m * kn)
    O.engines = engines(gravity=(0, 0, 0), timestep_safety=timestep_safety, crushing_is50=limit / failure_load(2 * small, 1.0))
    O.trackEnergy = True
    peak = 0.0
    while O.time < 1.0 and not (O.bodies[b].state.vel[2] > 0 and not O.interactions.has(a, b)):
        step_until(math.inf, 1)
        if O.interactions.has(a, b) and O.interactions[a, b].isReal:
            peak = max(peak, O.interactions[a, b].phys.normalForce.norm())
    v = O.bodies[b].state.vel[2]
    crushed = O.energy["flexCrushing"] if "flexCrushing" in O.energy.keys() else 0.0
    return dict(measured=v, reference=limit / math.sqrt(m * kn), peak_over_limit=peak / limit,
                crushing_over_loss=crushed / (0.5 * m * (speed ** 2 - v ** 2)), dt=O.dt)
