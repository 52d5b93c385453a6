"""Analytic element cases: the scenes and measurements of yadeflex.harness.cases (the tests in tests/yade
assert on the same functions), each with its reference, source and tolerance."""
import math

from yadeflex.harness import cases
from yadeflex.harness.verdict import Case, grade

GROUP = "Elements against analytic solutions"
PLOTS = []  # (path under OUT, title), shown under the group's table


def _case(name, quantity, source, tol, justification, kind="relative", reference=math.nan):
    return Case(name=name, group=GROUP, quantity=quantity, reference=reference, source=source, tolerance=tol, kind=kind,
                justification=justification)


def run(full, out):
    res = []

    r = cases.cantilever_deflection("tip", segments=10, length=1.0, radius=0.01, force=1.0)
    c = _case("cantilever_tip_load", "tip deflection [m], steel, L = 1 m, r = 10 mm, P = 1 N, 10 segments",
              "Euler-Bernoulli P L^3 / 3EI", 1e-3,
              "the element is exact for end loads (any segment count); left: the geometric nonlinearity (w/L)^2 = 1e-6 and the settling criterion 1e-7")
    c.reference = r["reference"]
    res.append(grade(c, r["measured"]))

    r = cases.cantilever_deflection("self", segments=10, length=1.0, radius=0.01)
    c = _case("cantilever_self_weight", "tip deflection [m] under its own weight, 10 segments", "Euler-Bernoulli q L^4 / 8EI", 5e-3,
              "lumped nodal loads omit the tip moment q h^2 / 12 of the consistent load: error 1 / (3 N^2) = 3.3e-3 at N = 10")
    c.reference = r["reference"]
    res.append(grade(c, r["measured"]))

    r = cases.cantilever_deflection("axial", segments=5, length=2.0, radius=0.004, force=1000.0)
    c = _case("bar_axial", "elongation [m], steel bar L = 2 m, r = 4 mm, P = 1 kN", "P L / EA", 1e-4,
              "linear bar: exact up to the strain itself (P / EA = 1e-4 of geometric change) and the settling criterion")
    c.reference = r["reference"]
    res.append(grade(c, r["measured"]))

    r = cases.first_bending_frequency(segments=10, length=1.0, radius=0.01)
    c = _case("cantilever_first_frequency", "first bending angular frequency [rad/s], 10 segments",
              "Euler-Bernoulli 1.875104^2 sqrt(EI / rho A L^4)", 0.02,
              "10 segments with lumped masses: a discretisation error of the first mode of order 1/N^2 (1% at N = 10); the period from zero crossings over 0.5 s (7 periods)")
    c.reference = r["reference"]
    res.append(grade(c, r["measured"], crossings=r["crossings"]))

    r = cases.pretensioned_square(n=16 if not full else 32)
    c = _case("membrane_point_load", f"worst relative deflection error [-] a quarter side from a 1 N point load, {16 if not full else 32} cells per side",
              "linear membrane theory T lap w = -P delta, double sine series (yadeflex.harness.membrane_scenes)", 0.015,
              "linear triangles: O(h^2) mesh error, 1.2% measured at 16 cells in the test suite's convergence check; the theory holds while the added strain (< 1e-5) is small against the prestrain 1e-2",
              kind="absolute", reference=0.0)
    res.append(grade(c, r["measured"]))

    r = cases.circular_membrane(rings=12 if not full else 16)
    c = _case("membrane_circular_pressure", "centre deflection [m], clamped circular membrane, 100 Pa", "Foppl-Hencky (numerical solution of the membrane equations)", 0.01,
              "the theory drops terms of order slope^2 (w0/a = 0.09: ~1%) and loads vertically where the model follows the normal")
    c.reference = r["reference"]
    res.append(grade(c, r["measured"]))

    r = cases.sphere_wire_impact(0.0, (0, 0, -3.0))
    c = _case("energy_elastic_impact", "largest energy drift / impact energy [-], undamped frictionless sphere on a clamped wire",
              "conservation of energy (elastic, undamped)", 0.01,
              "leap-frog conserves a shadow energy: the booked total oscillates by O((omega dt)^2) of the contact energy, bounded here at 1%",
              kind="absolute", reference=0.0)
    res.append(grade(c, r["measured"], touched=r["touched"]))

    r = cases.free_fall(height=1.0)
    c = _case("free_fall", "speed [m/s] after a 1 m free fall", "sqrt(2 g h)", 9.81 * r["dt"] / r["reference"],
              "leap-frog: the velocity is exact at the steps, the position leads the exact one by g dt t / 2: the speed at the crossing is off by less than one step's increment g dt (relative g dt / v)")
    c.reference = r["reference"]
    res.append(grade(c, r["measured"], dt=r["dt"]))

    r = cases.sphere_bounce()
    c = _case("contact_duration", "duration [s] of an elastic sphere-sphere contact (R = 50 mm, E = 100 MPa, 1 m/s)",
              "half period of the linear contact spring, pi sqrt(m / kn), kn = E R (the model's contact law is linear, Cundall-Strack, not Hertz)",
              2 * r["dt"] / r["reference"] if math.isfinite(r["reference"]) else math.nan,
              "the contact starts and ends within a step each: the duration is resolved to 2 dt")
    c.reference = r["reference"]
    res.append(grade(c, r["measured"], dt=r["dt"], rebound_over_impact_speed=r["rebound"]))

    r = cases.crushing_bounce()
    c = _case("crushing_restitution", "rebound speed [m/s] of a sphere (R = 20 mm, 2 m/s) off a fixed one (R = 40 mm) whose contact yields at "
              "its crushing load P, 0.3 of the elastic peak force", "elastic-perfectly-plastic contact: the unloading is elastic from P, "
              "rebound speed P / sqrt(m kn)", 2e-3,
              "leap-frog at a twentieth of the critical step: the force reaches and leaves the cap within a step (7e-5 measured)")
    c.reference = r["reference"]
    res.append(grade(c, r["measured"], peak_force_over_crushing_load=r["peak_over_limit"], crushing_energy_over_kinetic_loss=r["crushing_over_loss"]))
    return res
