"""Grains: the fill presets, and the grains' material, bodies and engines while they settle (any
deposition, yadeflex.deposition, the damping module's fill among them)."""
import math

from yade import O
from yade.minieigenHP import Vector3
from yade.wrapper import Body, Sphere, FrictMat

from . import checks as C
from .scene import engines

# a packing counts as settled when its unbalanced force (yadeflex.deposition.unbalanced_force) is
# below this as well as its kinetic energy negligible (bench/fill_equilibrium.py)
UNBALANCED_TOL = 0.05
# time step of grains settling alone, x FlexTimeStepper's estimate: they settle under heavy local
# damping, so it is not tied to an impact's time-step safety (and hitting one fill at several
# steps, convergence checks, loads the same cached fill)
FILL_TIMESTEP_SAFETY = 1.0
SETTLE_DAMPING = 0.7  # local damping while grains settle (the module's default settle_damping)
# grain friction while a fill is densified: 0 the densest, up to the fill's own angle a looser one
DEPOSITION_FRICTION = C.Range(0.0, 45.0, "deg", note="at most the fill's friction angle")

# Fill presets: grain size range [m] (the simulated size; real sand is far too fine for a
# sphere-per-grain model and is represented by coarser grains with its bulk properties),
# solid density [kg/m3], friction angle [deg], contact modulus [Pa], rolling friction [-]
# (rolling resistance of angular grains on spheres, kr = ks R^2; assumed values in the range
# used for crushed rock in DEM, not calibrated here).
FILLS = {
    "gravel": dict(grain_min=0.032, grain_max=0.063, density=2650.0, friction_deg=38.0, young=1e8, rolling_friction=0.1),
    "sand": dict(grain_min=0.020, grain_max=0.030, density=2650.0, friction_deg=33.0, young=1e8, rolling_friction=0.05),
}
# Presets withdrawn until the model represents what they depend on: name -> why (the refusal says it)
WITHDRAWN_FILLS = {
    "cellular_glass": "withdrawn: foam-glass granulate absorbs an impact by crushing its porous grains, and the fill's grains are elastic "
                      "spheres that do not crush (as such they gave a higher peak force than gravel and a rebound; grain_crushing_is50 "
                      "stands in for crushing rock, not foam glass)",
}
PRESET_KEYS = ("grain_min", "grain_max", "density", "friction_deg", "young", "rolling_friction")


def check_fill(fill):
    """fill if it is a preset of FILLS, else BadValue (a withdrawn preset: with the reason)."""
    allowed = "one of " + ", ".join(C.show(k) for k in sorted(FILLS))
    if isinstance(fill, str) and fill in WITHDRAWN_FILLS:
        raise C.BadValue("fill", fill, f"{allowed} ({fill} is {WITHDRAWN_FILLS[fill]})")
    return C.choice("fill", fill, tuple(sorted(FILLS)))


def fill_preset(p):
    """The fill preset (a dict of PRESET_KEYS) of p: the name of a preset of FILLS, a preset
    dict (checked for its keys), or parameters with a preset() (a ModuleParams: its preset with
    its overrides)."""
    if isinstance(p, str):
        return dict(FILLS[check_fill(p)])
    if isinstance(p, dict):
        missing = [k for k in PRESET_KEYS if k not in p]
        if missing:
            raise C.BadValue("fill preset", p, f"a dict with the keys {', '.join(PRESET_KEYS)} (missing {', '.join(missing)})")
        return p
    if callable(getattr(p, "preset", None)):
        return p.preset()
    raise C.BadValue("fill preset", p, "a ModuleParams, the name of a preset (" + ", ".join(sorted(FILLS)) + ") or a preset dict")


def _grain_material(p, seedless_label="fill"):
    """The grains' FrictMat of preset dict p (modulus, density, friction), appended to O.materials."""
    m = FrictMat(young=p["young"], poisson=0.3, density=p["density"], frictionAngle=math.radians(p["friction_deg"]), label=seedless_label)
    O.materials.append(m)
    return m


def _sphere_body(center, radius, mat):
    """A sphere of radius [m] at center [m] of material mat, its mass and inertia from mat's density; returns its id."""
    b = Body()
    b.shape = Sphere(radius=radius)
    b.material = mat
    b.state.pos = center
    m = mat.density * 4 / 3 * math.pi * radius ** 3
    b.state.mass = m
    b.state.inertia = Vector3(1, 1, 1) * 0.4 * m * radius * radius
    return O.bodies.append(b)


def fill_engines(p, damping, friction=True, timestep_safety=FILL_TIMESTEP_SAFETY):
    """yadeflex.engines() for grains of preset p (fill_preset: ModuleParams, preset name or dict)
    settling at the filling's step (timestep_safety): with p's rolling resistance, or (friction
    False) with none."""
    p = fill_preset(p)
    rf = p["rolling_friction"] if friction else 0.0
    return engines(damping=damping, timestep_safety=timestep_safety, rolling_stiffness=1.0 if rf > 0 else 0.0, rolling_friction=rf)
