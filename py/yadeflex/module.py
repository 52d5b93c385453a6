"""The damping module: a chain-link mesh cylinder with steel rings, a geotextile lining and a
granular fill on a rigid slab, hit by a boulder. One builder with typed, unit-annotated
parameters, used by the main job (scripts/damping_module.py), the tests and parametric studies.

Stages
  1. fill: grains placed on a close-packed lattice in a rigid, frictionless cylindrical
     container of the lining's radius (grains only: a long time step) settle under gravity,
     first without friction or rolling resistance (so that they pack densely, as a compacted
     fill), then with them; grains above the module's height are removed. (Settled with their
     friction from the start, the grains froze in a loose packing, 0.40 solid fraction and 2.3
     contacts per grain, that kept collapsing during the impact: bench/fill_equilibrium.py);
  2. structure: the mesh, rings and lining are built around the settled fill, the rigid
     container removed, and the whole settled again until it is at rest and in equilibrium
     (unbalanced force too): the fill, released by the container, spreads out onto the lining
     and ends bearing on it. The structure's nodes are made heavier meanwhile (their weight
     kept), so that this quasi-static settle runs at the grains' time step, not the wires';
  3. impact: the boulder is placed just above the fill with the free-fall velocity of its
     drop height, and the run starts without numerical damping unless asked.
Stages 1-2 are cached (O.save) under a key made of every parameter they depend on, so impacts
with other boulders reuse the filled module.

Simplifications (stated, not hidden): the module's base nodes (mesh, rings, lining) are pinned
to the slab (no sliding of the base); the slab is a rigid plane (a YADE Wall) whose reaction is
the force on the wall plus the reactions at the pinned nodes; grains are spheres (the
angularity of gravel is represented by its friction angle and a rolling resistance); a cubic boulder is a
rigid clump of overlapping spheres with the mass and inertia of the solid cube (its edges are
rounded by the member radius).
"""
import dataclasses
import hashlib
import json
import math
import os
import random
import sys
import tempfile

from yade import O
from yade.minieigenHP import Vector3
from yade.wrapper import Body, Sphere, FrictMat, FlexNode, NewtonIntegrator

from . import builders as B
from .constants import G
from . import checks as C
from . import membrane as M
from .materials import FRICTION_DEG
from .mesh import chain_link_cylinder, edge_ring, TECCO_G65_DX, TECCO_G65_DY, TECCO_G65_WIRE_RADIUS as TECCO_WIRE_RADIUS
from .params import param, declared, IMPACT, FILL
from .scene import engines, step_until, CRUSHING_IS50, DAMPING, ROLLING_FRICTION, TIMESTEP_SAFETY as SCENE_TIMESTEP_SAFETY

# a fill counts as settled when its unbalanced force (YADE utils.unbalancedForce) is below this
# as well as its kinetic energy negligible (bench/fill_equilibrium.py)
UNBALANCED_TOL = 0.05
# time step of the filling, x FlexTimeStepper's estimate: the fill settles under heavy local
# damping, so it is not tied to the impact's ModuleParams.timestep_safety, and hitting one fill
# at several steps (convergence checks) loads the same cached fill
FILL_TIMESTEP_SAFETY = 1.0
# largest mass scaling of the structure's nodes while it settles on the fill (_heavier_nodes)
MAX_NODE_MASS_SCALING = 100.0
# the grains are placed on a hexagonal close-packed lattice (spacing 2.05 grain_max: solid
# fraction about 0.33 with the gravel's sizes) up to this x the module's height: about 1.2 x the
# grains a dense fill of the module's height holds, the rest trimmed
PLACED_HEIGHT = 2.4

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


def check_fill(fill):
    """fill if it is a preset of FILLS, else BadValue (a withdrawn preset: with the reason)."""
    allowed = "one of " + ", ".join(C.show(k) for k in sorted(FILLS))
    if isinstance(fill, str) and fill in WITHDRAWN_FILLS:
        raise C.BadValue("fill", fill, f"{allowed} ({fill} is {WITHDRAWN_FILLS[fill]})")
    return C.choice("fill", fill, tuple(sorted(FILLS)))


BOULDER_SHAPES = ("cube", "sphere")
N_MODULES = (1, 3, 7)
# rockfall impact speeds stay below about 40 m/s; faster, the contacts' penalty stiffness
# cannot stop the boulder within a fraction of a grain
MAX_IMPACT_SPEED = 50.0  # [m/s]
BOULDER_MIN_SIZE = 0.05  # [m] a smaller boulder is a grain (its members set a tiny time step)

TIMESTEP_SAFETY = dataclasses.replace(SCENE_TIMESTEP_SAFETY, lo=0.05, lo_open=False, note="x FlexTimeStepper's critical step; "
                                      "the default module is stable to 1.86x (bench/STABILITY.md)")


@dataclasses.dataclass
class ModuleParams:
    """Parameters of a damping-module impact (SI units), each declared once (yadeflex.params):
    unit, allowed values, meaning, stage (fill: the filled module depends on it; impact: the
    cached fill is hit with it) and its value in the reduced module (small())."""
    diameter: float = param(1.0, unit="m", meaning="mesh cylinder diameter", small=0.4,
                            allowed=C.Range(0.2, math.inf, "m", note="at least three cells around; at most the body budget allows"))
    height: float = param(0.6, unit="m", meaning="mesh cylinder height", small=0.3, row="diameter",
                          allowed=C.Range(0.1, math.inf, "m", note="at least two half-cells; at most the body budget allows"))
    ring_bar_diameter: float = param(0.010, unit="m", meaning="bar of the steel rings at top and bottom", row="diameter",
                                     allowed=C.Range(0.004, 0.03, "m"))
    lining: bool = param(True, "boolean", meaning="geotextile lining inside the mesh")
    lining_thickness: float = param(0.002, unit="m", meaning="its thickness", row="lining",
                                    allowed=C.Range(0.0005, 0.01, "m", note="geotextiles are 1-10 mm thick"))
    lining_gap: float = param(0.01, unit="m", meaning="its clearance from the mesh at rest", row="lining",
                              allowed=C.Range(0.0, math.inf, "m", note="below diameter/4"))
    fill: str = param("gravel", "choice", allowed=tuple(sorted(FILLS)), checker=lambda name, v: check_fill(v),
                      meaning="fill preset (presets in --help; no crushable fill: `cellular_glass` is refused)")
    grain_min: float = param(None, unit="m", meaning="smallest grain diameter", default_text="the preset's", small=0.06, row="fill",
                             allowed=C.Range(0.0, math.inf, "m", lo_open=True, note="grain_max/10 to grain_max"))
    grain_max: float = param(None, unit="m", meaning="largest grain diameter (gravel 0.032-0.063)", default_text="the preset's", small=0.08,
                             row="fill", allowed=C.Range(0.0, math.inf, "m", lo_open=True,
                                                         note="at most diameter/4 and height/2; at least the body budget allows"))
    fill_friction_deg: float = param(None, unit="deg", meaning="grain friction angle", default_text="the preset's", allowed=FRICTION_DEG)
    rolling_friction: float = param(None, unit="-", meaning="rolling resistance of the grains (0: none)", default_text="the preset's",
                                    row="fill_friction_deg", allowed=ROLLING_FRICTION)
    fill_young: float = param(None, unit="Pa", meaning="contact modulus of the grains", default_text="the preset's", row="fill_friction_deg",
                              allowed=C.Range(1e6, 1e11, "Pa", note="softer grains sink into each other, stiffer ones shorten the step"))
    grain_crushing_is50: float = param(None, unit="Pa", stage=IMPACT, default_text="none (grains do not crush)", row="fill_friction_deg",
                                       meaning="point-load index Is(50) of the grains' rock: their contacts yield at its failure load during the impact",
                                       allowed=CRUSHING_IS50)
    fill_deposition_friction_deg: float = param(0.0, unit="deg", allowed=C.Range(0.0, 45.0, "deg", note="at most the fill's friction angle"),
                                                meaning="grain friction while the fill is densified: 0 the densest fill, up to the fill's own angle a looser one")
    boulder_mass: float = param(800.0, unit="kg", stage=IMPACT, meaning="boulder mass", small=100.0, allowed=C.Range(
        0.0, math.inf, "kg", lo_open=True, note=f"a boulder (cube side, sphere diameter) of {BOULDER_MIN_SIZE} m to 3 x the diameter"))
    boulder_shape: str = param("cube", "choice", stage=IMPACT, allowed=BOULDER_SHAPES, row="boulder_mass",
                               meaning="its shape: a cube (a rigid clump of 64 spheres with the cube's mass and inertia) or a sphere")
    boulder_density: float = param(2400.0, unit="kg/m3", stage=IMPACT, meaning="its density (concrete)", row="boulder_mass",
                                   allowed=C.Range(500.0, 2e4, "kg/m3"))
    drop_height: float = param(2.0, unit="m", stage=IMPACT, meaning="free fall of the boulder's lowest point onto the fill top", small=1.0,
                               allowed=C.Range(0.0, MAX_IMPACT_SPEED ** 2 / (2 * G), "m", lo_open=True,
                                               note=f"an impact speed up to {MAX_IMPACT_SPEED:g} m/s"))
    impact_velocity: float = param(None, unit="m/s", stage=IMPACT, meaning="or the impact speed", default_text="from --drop-height",
                                   row="drop_height", allowed=C.Range(0.0, MAX_IMPACT_SPEED, "m/s", lo_open=True))
    impact_offset: tuple = param((0.0, 0.0), "pair", unit="m", stage=IMPACT, meaning="horizontal offset of the impact from the axis, within the module's radius")
    damping: float = param(0.0, unit="-", stage=IMPACT, meaning="numerical (local) damping from the boulder's first contact (the free fall is undamped)",
                           allowed=dataclasses.replace(DAMPING, note="local damping"))
    settle_damping: float = param(0.7, unit="-", meaning="local damping while the fill settles (not part of the impact)",
                                  allowed=C.Range(0.1, 1.0, hi_open=True, note="the fill settles under heavy damping"))
    timestep_safety: float = param(1.0, unit="-", stage=IMPACT, meaning="impact time step as a fraction of the estimated critical step "
                                   "(the fill settles at its own, FILL_TIMESTEP_SAFETY)", allowed=TIMESTEP_SAFETY)
    steel_contact_young: float = param(2e10, unit="Pa", meaning="contact modulus of wires and rings (their elements keep 200 GPa)",
                                       allowed=C.Range(1e8, 2e11, "Pa", note="up to steel's E"))
    lining_node_mass: float = param(0.02, unit="kg", stage=IMPACT, allowed=C.Range(0.0, 0.2, "kg"),
                                    meaning="least mass of a lining node during the impact (mass scaling for the time step; "
                                    "0: its own, about 1 g; the mass added is reported as lining_mass_added)")
    seed: int = param(1, "integer", unit="-", meaning="grain sizes and wire slack draws", allowed=(0, 2 ** 31 - 1))
    n_modules: int = param(1, "choice", unit="-", allowed=N_MODULES, meaning="modules: 1, 3 in a row or 7 in a hexagonal cluster")
    module_gap: float = param(0.02, unit="m", meaning="clear gap between neighbouring modules", row="n_modules",
                              allowed=C.Range(0.0, math.inf, "m", note="below the diameter"))
    rope: bool = param(None, "boolean", meaning="boundary rope (6x7 FC, 8 mm) around all modules at mid-height", row="n_modules",
                       default_text="with --n-modules above 1")

    @classmethod
    def small(cls, **kw):
        """The reduced module (`scripts/run OUT --small`, the tests): 0.4 m x 0.3 m, 60-80 mm
        grains, a 100 kg cube dropped 1 m; keyword arguments override."""
        return cls(**dict(SMALL, **kw))

    def preset(self):
        """The fill preset with this module's overrides (grain sizes, friction, modulus)."""
        check_fill(self.fill)
        p = dict(FILLS[self.fill])
        for k in ("grain_min", "grain_max"):
            if getattr(self, k) is not None:
                p[k] = getattr(self, k)
        if self.fill_friction_deg is not None:
            p["friction_deg"] = self.fill_friction_deg
        if self.rolling_friction is not None:
            p["rolling_friction"] = self.rolling_friction
        if self.fill_young is not None:
            p["young"] = self.fill_young
        return p

    def engines(self, damping, timestep_safety=None, crushing=True):
        """yadeflex.engines() with this module's rolling resistance and, unless crushing is
        False (the fill), its grain crushing (time step: timestep_safety, default this module's)."""
        rf = self.preset()["rolling_friction"]
        ts = self.timestep_safety if timestep_safety is None else timestep_safety
        return engines(damping=damping, timestep_safety=ts, rolling_stiffness=1.0 if rf > 0 else 0.0, rolling_friction=rf,
                       crushing_is50=self.grain_crushing_is50 if crushing else None)

    def validate(self):
        """Raise BadValue (a ValueError) naming the first bad parameter, its value and the values
        allowed, before anything is built (each field's declaration, FILLS, the bounds that
        depend on other parameters, the body budget MAX_BODIES)."""
        for k, (_, p) in PARAMS.items():
            if not (k == "drop_height" and self.impact_velocity is not None):
                p.check(k, getattr(self, k))
        C.number("fill_deposition_friction_deg", self.fill_deposition_friction_deg,
                 dataclasses.replace(LIMITS["fill_deposition_friction_deg"], hi=min(45.0, self.preset()["friction_deg"])))
        D, H = self.diameter, self.height
        C.number("lining_gap", self.lining_gap, C.Range(0.0, 0.25 * D, "m", hi_open=True, note="below diameter/4"))
        C.number("module_gap", self.module_gap, C.Range(0.0, D, "m", hi_open=True, note="below the diameter"))
        p = self.preset()
        gmax = C.number("grain_max", p["grain_max"], C.Range(0.0, min(0.25 * D, 0.5 * H), "m", lo_open=True,
                                                            note="at most diameter/4 and height/2"))
        C.number("grain_min", p["grain_min"], C.Range(0.1 * gmax, gmax, "m", note="grain_max/10 to grain_max: the smallest grain sets the time step"))
        n = self.body_estimate()
        if n > C.MAX_BODIES:
            raise self._too_many_bodies(n)
        if math.hypot(*self.impact_offset) > 0.5 * D:
            raise C.BadValue("impact_offset", self.impact_offset, f"(x, y) within the module's radius, {0.5 * D:g} m")
        vol = (lambda s: s ** 3) if self.boulder_shape == "cube" else (lambda s: math.pi / 6 * s ** 3)
        m_lo, m_hi = (self.boulder_density * vol(s) for s in (BOULDER_MIN_SIZE, 3 * D))
        C.number("boulder_mass", self.boulder_mass, C.Range(m_lo, m_hi, "kg", note=f"a {self.boulder_shape} of "
                 f"{BOULDER_MIN_SIZE:g} m to 3 x the diameter at {self.boulder_density:g} kg/m3"))

    def body_estimate(self):
        """Bodies of the filled module, estimated from its geometry without building it (an upper
        bound: the grains placed on their lattice before they settle, the mesh, rings, lining and
        rope, the boulder); float, for any size."""
        p = self.preset()
        a = 1.025 * p["grain_max"]  # lattice spacing of settle_fill
        r_lin, r_in = fill_radii(self)
        side = 2 * max(0.0, r_in - 0.5 * p["grain_max"]) / a + 1
        grains = PLACED_HEIGHT * math.sqrt(2.0) * self.height / a * side * side  # the close-packed lattice: sqrt(2) x a cubic one's count
        up, around = self.height / (0.5 * TECCO_G65_DX) + 1, math.pi * self.diameter / (0.5 * TECCO_G65_DY) + 1
        mesh = 1.5 * up * around + 2 * around  # nodes, legs, rings
        cells = (2 * math.pi * max(r_lin, 0.0) / 0.08 + 1) * (self.height / 0.08 + 2)
        rope = 2 * (math.pi * self.diameter + 6 * (self.diameter + self.module_gap)) / 0.1 if self.with_rope() else 0.0
        container = 100  # the filling's rigid container (48 x 2 facets) and the slab
        return self.n_modules * (grains + mesh + 3 * cells + container) + rope + 65  # 65: the cube's clump and 64 members

    def _too_many_bodies(self, n):
        """BadValue for a module over MAX_BODIES, naming the size that departs most from the
        default module in its share of the body count (D^2 H / grain_max^3), with the bound that
        keeps the module within the budget at the other sizes."""
        ref = dict(diameter=(ModuleParams.diameter, 2), height=(ModuleParams.height, 1), grain_max=(FILLS[self.fill]["grain_max"], -3))
        value = lambda k: self.preset()[k] if k == "grain_max" else getattr(self, k)
        name = max(ref, key=lambda k: ref[k][1] * math.log(value(k) / ref[k][0]))
        others = ", ".join(f"{k} {value(k):g} m" for k in ref if k != name) + f", {self.n_modules} module(s)"
        budget = f"the module would need about {n:.3g} bodies, more than yadeflex.checks.MAX_BODIES = {C.MAX_BODIES}"
        ok, bad = ref[name][0], value(name)
        if dataclasses.replace(self, **{name: ok}).body_estimate() > C.MAX_BODIES:
            return C.BadValue(name, value(name), f"a smaller module ({others} are large too): {budget}")
        for _ in range(100):  # bisection in log space between a value within the budget and this one
            mid = math.sqrt(ok * bad)
            if dataclasses.replace(self, **{name: mid}).body_estimate() <= C.MAX_BODIES:
                ok = mid
            else:
                bad = mid
        return C.BadValue(name, value(name), f"{'>=' if name == 'grain_max' else '<='} {ok:.3g} m with {others}: {budget}")

    def resolved(self):
        """The values a run uses: the parameters with the fill preset's values in place of None
        (grain sizes, friction, rolling friction, modulus) and the fill's density, the rope,
        the impact speed and the boulder's size."""
        p = self.preset()
        d = dataclasses.asdict(self)
        d.update(grain_min=p["grain_min"], grain_max=p["grain_max"], fill_friction_deg=p["friction_deg"], rolling_friction=p["rolling_friction"],
                 fill_young=p["young"], fill_density=p["density"], rope=self.with_rope(), impact_velocity=self.impact_speed(),
                 boulder_size=self.boulder_size())
        return d

    def centers(self):
        """Module centres (x, y) [m]: the first is the one the boulder hits."""
        d = self.diameter + self.module_gap
        if self.n_modules == 1:
            return [(0.0, 0.0)]
        if self.n_modules == 3:
            return [(0.0, 0.0), (-d, 0.0), (d, 0.0)]
        return [(0.0, 0.0)] + [(d * math.cos(k * math.pi / 3), d * math.sin(k * math.pi / 3)) for k in range(6)]

    def with_rope(self):
        return self.n_modules > 1 if self.rope is None else bool(self.rope)

    def fill_key(self):
        """Hash of what the filled module depends on (the cache key): the fields declared for the
        fill stage, the fill preset, the radii the lining gap gives and the fill's time step."""
        d = {k: v for k, v in dataclasses.asdict(self).items() if PARAMS[k][1].stage == FILL}
        if d["fill_deposition_friction_deg"] == 0:  # (the default is left out of the key)
            d.pop("fill_deposition_friction_deg")
        else:  # (20 and 20.0: one fill)
            d["fill_deposition_friction_deg"] = float(d["fill_deposition_friction_deg"])
        # the clearance between mesh and lining acts only through the lining's radius, which the
        # rings may set instead (the small module): the radii, not the option, in the key
        d.pop("lining_gap")
        d["_fill_radii"] = [repr(float(x)) for x in fill_radii(self)]
        d["_fill_timestep_safety"] = FILL_TIMESTEP_SAFETY
        d["_preset"] = self.preset()
        d["_version"] = 20  # raised whenever the code fills the same parameters differently (why: git log -S_version)
        if self.with_rope():
            d["_rope_version"] = 2  # the same for the rope
        return hashlib.sha256(json.dumps(d, sort_keys=True).encode()).hexdigest()[:16]

    def boulder_size(self):
        """Cube side or sphere diameter [m] of the boulder."""
        v = self.boulder_mass / self.boulder_density
        return v ** (1 / 3) if self.boulder_shape == "cube" else (6 * v / math.pi) ** (1 / 3)

    def impact_speed(self):
        return self.impact_velocity if self.impact_velocity is not None else math.sqrt(2 * G * self.drop_height)


PARAMS = declared(ModuleParams)  # {name: (field, Param)}
LIMITS = {k: p.allowed for k, (_, p) in PARAMS.items() if p.kind == "number"}  # the numbers' allowed values
SMALL = {k: p.small for k, (_, p) in PARAMS.items() if p.small is not None}  # the reduced module (ModuleParams.small)


def _grain_material(p, seedless_label="fill"):
    m = FrictMat(young=p["young"], poisson=0.3, density=p["density"], frictionAngle=math.radians(p["friction_deg"]), label=seedless_label)
    O.materials.append(m)
    return m


def _sphere_body(center, radius, mat):
    b = Body()
    b.shape = Sphere(radius=radius)
    b.material = mat
    b.state.pos = center
    m = mat.density * 4 / 3 * math.pi * radius ** 3
    b.state.mass = m
    b.state.inertia = Vector3(1, 1, 1) * 0.4 * m * radius * radius
    return O.bodies.append(b)


def _placement(r, z0, z1, a):
    """Centres of a hexagonal close-packed lattice of spacing a (layers ABAB) inside the
    vertical cylinder of radius r about the axis, from z0 up to z1."""
    dz, dy = a * math.sqrt(2.0 / 3.0), a * math.sqrt(3.0) / 2
    m = int(r / a) + 2
    out = []
    for k in range(int((z1 - z0) / dz) + 1):
        ox, oy = (0.5 * a, a / (2 * math.sqrt(3.0))) if k % 2 else (0.0, 0.0)
        for j in range(-m, m + 1):
            for i in range(-m, m + 1):
                x, y = i * a + (0.5 * a if j % 2 else 0.0) + ox, j * dy + oy
                if math.hypot(x, y) <= r:
                    out.append((x, y, z0 + k * dz))
    return out


def _container(radius, height, n=48, center=(0.0, 0.0)):
    """Rigid frictionless cylinder of YADE facets (only while the grains settle)."""
    from yade import geom
    mat = FrictMat(young=1e8, poisson=0.3, density=1000, frictionAngle=0.0, label="container")
    O.materials.append(mat)
    fs = geom.facetCylinder((center[0], center[1], height / 2), radius, height, segmentsNumber=n, wallMask=4, material=mat)
    return O.bodies.append(fs)


def _settle(ke_tol, max_steps, chunk=500, progress=None, unbalanced_tol=None):
    """Run until the kinetic energy of the spheres falls below ke_tol [J] and, if unbalanced_tol
    is given, YADE's unbalanced force (mean resultant on the dynamic bodies over the mean contact
    force) below it too: a packing at rest, not one creeping slowly under heavy damping (a loose
    fill met the kinetic-energy test while still compacting at an unbalanced force of 0.19).
    progress(steps, kinetic energy, ke_tol) after every chunk."""
    from yade import utils
    steps = 0
    ubf = float("nan")
    while steps < max_steps:
        step_until(math.inf, chunk)
        steps += chunk
        ke = sum(0.5 * b.state.mass * b.state.vel.squaredNorm() for b in O.bodies if b is not None and isinstance(b.shape, Sphere))
        if progress:
            progress(steps, ke, ke_tol)
        if ke < ke_tol:
            if unbalanced_tol is None:
                return steps
            ubf = utils.unbalancedForce()
            if ubf < unbalanced_tol:
                return steps
    raise RuntimeError(f"the fill did not settle in {max_steps} steps (kinetic energy {ke:.3g} J, limit {ke_tol:.3g} J"
                       + (f"; unbalanced force {ubf:.3g}, limit {unbalanced_tol:.3g})" if unbalanced_tol is not None else ")"))


def _relayout():
    """Save O to memory and load it back: the bodies and interactions, created in the order the
    grains met while they fell, come back side by side in memory, in the order the loops visit
    them (the steps that follow wait less on memory)."""
    O.saveTmp("yadeflex_fill")
    O.loadTmp("yadeflex_fill")


def _heavier_nodes(factor):
    """Mass scaling for a quasi-static settle: the dynamic FlexNodes' mass and rotational inertia
    x factor (>= 1), their weight held at m g by a permanent force (factor - 1) m g upwards. The
    static equilibrium is the same; FlexTimeStepper's step for the elements grows as
    sqrt(factor). Returns what _restore_nodes needs."""
    if factor <= 1.0:
        return []
    g = next(e for e in O.engines if isinstance(e, NewtonIntegrator)).gravity
    out = []
    for b in O.bodies:
        if b is not None and isinstance(b.shape, FlexNode) and b.dynamic:
            m, inertia = b.state.mass, Vector3(b.state.inertia)
            out.append((b.id, m, inertia))
            b.state.mass = m * factor
            b.state.inertia = inertia * factor
            O.forces.setPermF(b.id, -(factor - 1.0) * m * g)
    return out


def _restore_nodes(heavier):
    """Undo _heavier_nodes: the nodes' own mass and inertia, no permanent force, everything at rest."""
    for bid, m, inertia in heavier:
        b = O.bodies[bid]
        b.state.mass, b.state.inertia = m, inertia
    if heavier:
        O.forces.reset()
    for b in O.bodies:
        if b is not None and b.dynamic:
            b.state.vel = Vector3(0, 0, 0)
            b.state.angVel = Vector3(0, 0, 0)


def lining_cells_around(r_lin):
    """Facets around the lining (cells of about 8 cm)."""
    return max(12, int(round(2 * math.pi * r_lin / 0.08)))


def fill_radii(params):
    """(lining midplane radius, radius the grains may reach) [m]: the lining inside the wires,
    and inside the rings (a ring is a polygon through the mesh edge nodes, about pi D / dy of
    them, whose chords cut inwards by R (1 - cos(dy/D))). The lining is a polygon too, its nodes
    on r_lin: the grains stay inside the middles of its flat facets, r_lin cos(pi / n), less half
    its thickness (settled against r_lin itself they started the structure stage overlapping
    the lining by up to its sagitta, 1.7 mm on the default module, and pushed its 1 g nodes
    with kilonewtons at the first step)."""
    from .mesh import TECCO_G65_DY
    R = 0.5 * params.diameter
    r_lin = min(R - params.lining_gap - 0.5 * params.lining_thickness - 0.0015,
                R * math.cos(TECCO_G65_DY / params.diameter) - 0.5 * params.ring_bar_diameter - 0.5 * params.lining_thickness - 0.002)
    return r_lin, r_lin * math.cos(math.pi / lining_cells_around(r_lin)) - 0.5 * params.lining_thickness


def settle_fill(params, r_in, rnd, progress=None):
    """Stage 1 on an empty O: the module's grains settled in their container of radius r_in
    (settle_grains with the module's preset, height, centres and settle damping), the container
    removed. Returns (wall id, grain ids, the kinetic-energy tolerance used)."""
    wall, grains, ke_tol, _ = settle_grains(params.preset(), params.height, r_in, rnd, centers=params.centers(),
                                            damping=params.settle_damping, progress=progress,
                                            deposition_friction_deg=params.fill_deposition_friction_deg)
    return wall, grains, ke_tol


def fill_engines(p, damping, friction=True):
    """yadeflex.engines() for grains of preset p settling at the filling's step: with p's rolling
    resistance, or (friction False) with none."""
    rf = p["rolling_friction"] if friction else 0.0
    return engines(damping=damping, timestep_safety=FILL_TIMESTEP_SAFETY, rolling_stiffness=1.0 if rf > 0 else 0.0, rolling_friction=rf)


def _floor_grains(radius, r_floor, mat):
    """A fixed monolayer of spheres of radius r_floor on a square lattice of spacing 2 r_floor,
    touching z = 0, out to `radius` about the axis: a floor as rough as the largest grains."""
    n = int(radius / (2 * r_floor))
    out = []
    for i in range(-n, n + 1):
        for j in range(-n, n + 1):
            x, y = 2 * r_floor * i, 2 * r_floor * j
            if math.hypot(x, y) <= radius:
                bid = _sphere_body(Vector3(x, y, r_floor), r_floor, mat)
                O.bodies[bid].state.blockedDOFs = "xyzXYZ"
                O.bodies[bid].dynamic = False
                out.append(bid)
    return out


def settle_grains(p, H, r_in, rnd, centers=((0.0, 0.0),), damping=ModuleParams.settle_damping, rough_floor=0.0, keep_container=False, progress=None,
                  deposition_friction_deg=0.0):
    """Grains of fill preset p settled as the module's fill is, on an empty O: placed on a
    close-packed lattice up to PLACED_HEIGHT x H (solid fraction about 0.33: enough for a dense
    fill above H) in a rigid frictionless container of radius r_in about each centre, on a wall
    at z = 0, settled without rolling resistance and frictionless (or at deposition_friction_deg
    [deg]: a looser fill), then with the fill's friction and rolling resistance (until at rest:
    kinetic energy and unbalanced force, local damping `damping`), and trimmed to the height H.
    rough_floor > 0: a fixed monolayer of the largest grains covers the floor out to that
    radius, and the fill starts on it. keep_container: the container stays (else removed).
    Returns (wall id, grain ids, the kinetic-energy tolerance used, the container's facet ids)."""
    gmat = _grain_material(p)
    from yade import utils
    wall = O.bodies.append(utils.wall(0, axis=2, sense=1, material=gmat))
    rmax = 0.5 * p["grain_max"]
    z0 = rmax * 1.05
    if rough_floor > 0:
        r_floor = rmax
        _floor_grains(rough_floor, r_floor, gmat)
        z0 += 2 * r_floor
    a = 2.05 * rmax
    grains, container = [], []
    for cx, cy in centers:
        container += _container(r_in, 3.6 * H, center=(cx, cy))
        for pos in _placement(r_in - 1.05 * rmax, z0, PLACED_HEIGHT * H, a):
            rad = 0.5 * rnd.uniform(p["grain_min"], p["grain_max"])
            grains.append(_sphere_body(Vector3(cx + pos[0], cy + pos[1], pos[2]), rad, gmat))
    # densification: no friction, no rolling resistance (a standard DEM filling procedure); a
    # deposition friction above 0 leaves the grains less dense
    dep = C.number("deposition friction", deposition_friction_deg,
                   dataclasses.replace(LIMITS["fill_deposition_friction_deg"], hi=min(45.0, p["friction_deg"])))
    phi = gmat.frictionAngle
    gmat.frictionAngle = math.radians(dep)
    O.engines = fill_engines(p, damping, friction=False)
    O.dt = 1e-5
    ke_tol = 1e-4 * sum(O.bodies[g].state.mass for g in grains) * G * H
    stage = f"fill, deposited at {dep:g} deg" if dep else "fill, dense"
    if progress:  # the count of grains sets the time a step takes
        progress(f"{stage} ({len(grains)} grains placed)", 0, float("nan"), ke_tol)
    _settle(ke_tol, 400000, progress=progress and (lambda s, ke, tol: progress(stage, s, ke, tol)))
    # then the fill's own friction and rolling resistance, on the existing contacts too (as
    # Ip2_FrictMat_FrictMat_FrictPhys sets it: the smaller angle of the two materials, so the
    # container stays frictionless)
    gmat.frictionAngle = phi
    for i in O.interactions:
        if i.isReal and hasattr(i.phys, "tangensOfFrictionAngle"):
            angles = [getattr(O.bodies[k].material, "frictionAngle", 0.0) for k in (i.id1, i.id2)]
            i.phys.tangensOfFrictionAngle = math.tan(min(angles))
    O.engines = fill_engines(p, damping)
    if progress:
        progress("fill, with friction", 0, float("nan"), ke_tol)
    _settle(ke_tol, 400000, progress=progress and (lambda s, ke, tol: progress("fill, with friction", s, ke, tol)), unbalanced_tol=UNBALANCED_TOL)
    # trim: keep the grains wholly below the height
    for g in list(grains):
        b = O.bodies[g]
        if b.state.pos[2] + b.shape.radius > H:
            O.bodies.erase(g)
            grains.remove(g)
    if not keep_container:
        for f in container:
            O.bodies.erase(f)
        container = []
    for g in grains:
        O.bodies[g].state.vel = Vector3(0, 0, 0)
        O.bodies[g].state.angVel = Vector3(0, 0, 0)
    return wall, grains, ke_tol, container


def build_filled(params, progress=None):
    """Stages 1-2 on a fresh O. Returns the dict of ids (also stored in O.tags['yadeflex_module'])."""
    params.validate()
    rnd = random.Random(params.seed)
    O.reset()
    H = params.height
    r_lin, r_in = fill_radii(params)
    wall, grains, ke_tol = settle_fill(params, r_in, rnd, progress)
    # --- stage 2: the structure around the fill
    from .wire import TECCO_WIRE_YOUNG, tecco_wire
    wire = tecco_wire(seed=params.seed, young=params.steel_contact_young, element_young=TECCO_WIRE_YOUNG)
    O.materials.append(wire)
    from .materials import STEEL_YOUNG, steel
    ring_mat = steel(label="ring_steel", friction_deg=30.0, young=params.steel_contact_young, element_young=STEEL_YOUNG)
    # contact modulus 3e9 Pa: kn = E r = 3e6 N/m for the 1 mm half thickness, so that the
    # lining pressed by grains against the wires and rings stays out of them (at 1e9 three modules
    # closed their energy balance to 35% only; 1e10 costs 2.4x in time step)
    gtx = M.geotextile(friction_deg=30.0, young=3e9) if params.lining else None
    per = []
    for cx, cy in params.centers():
        mesh = chain_link_cylinder(params.diameter, H, wire, center=(cx, cy, 0))
        rings = dict(bottom=edge_ring(mesh["edges"]["bottom"], 0.5 * params.ring_bar_diameter, ring_mat),
                     top=edge_ring(mesh["edges"]["top"], 0.5 * params.ring_bar_diameter, ring_mat))
        lin = None
        if params.lining:
            n_around = lining_cells_around(r_lin)
            n_height = max(2, int(round(H / 0.08)))
            lin = M.lining(r_lin, H, n_around, n_height, params.lining_thickness, gtx, center=(cx, cy, 0.5 * params.lining_thickness),
                           fix_bottom=True)
        B.fix(mesh["edges"]["bottom"], "xyz")
        per.append(dict(center=(cx, cy), mesh_nodes=sorted(mesh["nodes"].values()), mesh_cylinders=mesh["cylinders"],
                        ring_bottom=rings["bottom"], ring_top=rings["top"], lining=(lin["facets"] if lin else []),
                        lining_nodes=(sorted({n for row in lin["rings"] for n in row}) if lin else []),
                        base_nodes=sorted(set(mesh["edges"]["bottom"]) | set(lin["bottom"] if lin else [])), mesh_params=mesh["params"]))
    rope = dict(nodes=[], cylinders=[])
    if params.with_rope():
        from .materials import ROPE_6X7_YOUNG, rope_6x7_8mm
        from .rope import rope_around
        rn, rc = rope_around(params.centers(), 0.5 * params.diameter + TECCO_WIRE_RADIUS, 0.5 * H, rope_6x7_8mm(young=params.steel_contact_young, element_young=ROPE_6X7_YOUNG))
        rope = dict(nodes=rn, cylinders=rc)
    O.engines = params.engines(params.settle_damping, FILL_TIMESTEP_SAFETY, crushing=False)
    # the structure settles onto the fill: the mesh takes up its slack, a creep that local
    # damping slows down; 1e-3 of the fill's potential energy scale is "negligible" here. The
    # kinetic energy alone is not enough: the grains released by the container stand just clear
    # of the lining (they settled inside its flat facets) and creep out onto it, slowly, under
    # this damping; stopped on the kinetic energy the cached fill had no grain touching the
    # lining and sank once released without damping (bench/fill_equilibrium.py). The
    # unbalanced force holds it until the fill bears on the lining.
    if progress:
        progress("structure (mesh, rings, lining) on the fill", 0, float("nan"), 10 * ke_tol)
    _relayout()
    # the grains alone ran at dt_fill; the structure's light nodes shorten the step: heavier
    # nodes (their weight kept) settle to the same equilibrium at the grains' step
    dt_fill = O.dt
    # every bound swept by the collider's full distance: at the grains' step, the adaptive sweep
    # of slow bodies (InsertionSortCollider.targetInterv) re-ran the collider on many steps
    next(e for e in O.engines if e.label == "collider").targetInterv = -1
    O.step()
    heavier = _heavier_nodes(min(MAX_NODE_MASS_SCALING, (dt_fill / O.dt) ** 2))
    _settle(10 * ke_tol, 300000, progress=progress and (lambda s, ke, tol: progress("structure", s, ke, tol)), unbalanced_tol=UNBALANCED_TOL)
    _restore_nodes(heavier)
    ids = dict(per[0], wall=wall, grains=grains, modules=per, rope=rope["cylinders"], rope_nodes=rope["nodes"],
               base_nodes=sorted({n for m in per for n in m["base_nodes"]}))
    O.tags["yadeflex_module"] = json.dumps(ids)
    return ids


CACHE_FORMAT = "yadeflex filled module"


def cache_files(params, cache_dir):
    """(scene file, its metadata file, lock file) of params' filled module in cache_dir."""
    stem = os.path.join(cache_dir, f"module-{params.fill_key()}")
    return stem + ".yade.gz", stem + ".json", stem + ".lock"


def save_compressed(path):
    """O.save into path, a '.yade.gz', without YADE's gzip writer: that writer loops for ever in its
    close when the disk fills (and returns normally having written nothing or a part when the
    folder is gone). The scene goes to an uncompressed file next to path (whose writer raises on a
    failed write), which Python's gzip then compresses into path (OSError on a full disk); the
    uncompressed file is removed whatever happens, path when it could not be written whole.
    Raises OSError naming the file."""
    import gzip
    import shutil
    raw = path[:-len(".gz")] + ".raw.yade" if path.endswith(".gz") else path + ".raw.yade"
    try:
        try:
            O.save(raw)
        except RuntimeError as e:  # ("output stream error": the disk is full)
            raise OSError(f"saving {raw} failed: {e} (disk full, or the folder gone?)") from None
        check_written(raw)
        try:
            with open(raw, "rb") as src, gzip.open(path, "wb", compresslevel=6) as dst:
                shutil.copyfileobj(src, dst, 1 << 20)
        except OSError as e:
            if os.path.exists(path):
                os.unlink(path)
            raise OSError(f"saving {path} failed: {e.strerror or e} (disk full, or the folder gone?)") from None
    finally:
        if os.path.exists(raw):
            os.unlink(raw)
    check_saved(path)


def check_written(path):
    """Raises OSError naming path unless it exists and is not empty."""
    if not os.path.exists(path) or os.path.getsize(path) == 0:
        raise OSError(f"saving {path} failed: nothing was written (disk full, or the folder gone?)")


def check_saved(path):
    """Raises OSError naming path unless it holds a whole gzip stream, as O.save writes a
    '.yade.gz' (YADE's O.save returns normally having written nothing or a part when the disk is
    full or the folder is gone)."""
    import gzip
    import zlib
    try:
        if os.path.getsize(path) == 0:
            raise OSError("nothing was written")
        with gzip.open(path, "rb") as fh:
            while fh.read(1 << 20):
                pass
    except (OSError, EOFError, zlib.error) as e:
        raise OSError(f"saving {path} failed: {e} (disk full, or the folder gone?)") from None


def _sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def cache_problem(params, cache_dir):
    """Why the cached module of params in cache_dir cannot be loaded, checked before YADE reads
    the file (a damaged or foreign archive can crash YADE's reader or make it allocate without
    bound): None if it can, "missing" if there is none, else a sentence. The metadata file
    written with the scene names the format and the key and holds the scene's size and SHA-256:
    a file of another module under this key, another YADE scene, a partial or damaged file, or
    one saved by a yade-flex without metadata are all refused."""
    f, meta_file, _ = cache_files(params, cache_dir)
    if not os.path.exists(f):
        return "missing"
    try:
        with open(meta_file) as fh:
            meta = json.load(fh)
    except FileNotFoundError:
        return f"has no metadata file {os.path.basename(meta_file)} (saved by an older yade-flex, or its save was cut short)"
    except (OSError, ValueError) as e:
        return f"has an unreadable metadata file {os.path.basename(meta_file)} ({e})"
    if not isinstance(meta, dict) or meta.get("format") != CACHE_FORMAT:
        return f"has a metadata file {os.path.basename(meta_file)} that does not describe a filled module"
    if meta.get("key") != params.fill_key():
        return f"is described as the filled module {meta.get('key')!r}, not {params.fill_key()!r}"
    if meta.get("bytes") != os.path.getsize(f) or meta.get("sha256") != _sha256(f):
        return "is not the file its metadata describes (other size or checksum: damaged, cut short, or replaced)"
    return None


def _remove_stale_temps(f, keep):
    """The temporary files of cache file f that a run killed while saving left (only a run holding
    f's lock saves f, and the caller holds it: every other one is stale); keep: the caller's own."""
    import glob
    folder, base = os.path.split(f)
    for t in glob.glob(os.path.join(glob.escape(folder), f".{glob.escape(base)}.*")):
        if os.path.abspath(t) != os.path.abspath(keep):
            try:
                os.unlink(t)
            except OSError:
                pass


def filled_module(params, cache_dir=None, progress=None):
    """The settled module on O: loaded from the cache when it holds this key (with
    params.engines(params.damping) set), else built and saved there. A cache file that
    cache_problem() refuses, or that this build cannot read (classes changed since it was
    saved), is filled again, with a message. progress(stage, steps, kinetic energy [J], its
    target [J]) is called while filling (steps 0: a stage starts). Returns (ids, cache_file,
    from_cache).

    Runs sharing a cache folder: the module is looked up and filled under a lock on its own
    lock file, so a second run asking for a module another run is filling waits for it and
    loads it; the scene and its metadata are each written to a temporary file and renamed into
    place, so a run stopped while saving leaves the old cache or none, never a part. A cache
    folder that cannot be written is refused before the fill."""
    params.validate()
    cache_dir = cache_dir or os.path.join(os.path.expanduser("~"), ".cache", "yadeflex", "modules")
    f, meta_file, lock = cache_files(params, cache_dir)
    key = params.fill_key()
    from .files import locked, write_json
    try:
        os.makedirs(cache_dir, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=cache_dir, prefix=f".{os.path.basename(f)}.", suffix=".yade.gz")  # where a fill is saved
        os.close(fd)
    except OSError as e:
        raise ValueError(f"the module cache folder {cache_dir} cannot be written: {e.strerror or e}") from None
    try:
        with locked(lock, waiting=lambda: print(f"yadeflex: waiting for another run that fills the module {f}", flush=True)):
            _remove_stale_temps(f, keep=tmp)
            problem = cache_problem(params, cache_dir)
            if problem is None:
                try:
                    O.load(f)
                    stored = O.tags["yadeflex_module_key"] if "yadeflex_module_key" in O.tags.keys() else None
                except Exception as e:  # saved by a build whose classes have other attributes
                    stored, problem = None, f"cannot be read by this build ({type(e).__name__}: {e})"
                else:
                    if stored == key:
                        # (outside the try: an error here is not the cache file's, and filling again would not mend it)
                        O.engines = params.engines(params.damping)
                        return json.loads(O.tags["yadeflex_module"]), f, True
                    problem = f"holds the module {stored!r}, not {key!r}"
                O.reset()
            if problem != "missing":
                print(f"yadeflex: the cached module {f} {problem}; filling it again", file=sys.stderr, flush=True)
            build_filled(params, progress=progress)
            O.tags["yadeflex_module_key"] = key
            # without engines: an engine's attributes change more often than the bodies', and a
            # cache must stay readable (the impact sets its own engines anyway)
            engines_ = O.engines
            O.engines = []
            try:
                save_compressed(tmp)
            finally:
                O.engines = engines_
            meta = dict(format=CACHE_FORMAT, key=key, bytes=os.path.getsize(tmp), sha256=_sha256(tmp))
            os.chmod(tmp, 0o644)  # mkstemp makes it 0600
            os.replace(tmp, f)
            write_json(meta_file, meta)
            # go on from the file, as every later run will: the same state to the last bit, and
            # the bodies and interactions in order in memory
            O.load(f)
            O.engines = params.engines(params.damping)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return json.loads(O.tags["yadeflex_module"]), f, False


def fill_contacts(ids):
    """The filled module's active contacts: dict of grain_grain (count), grain_lining (count) and
    grain_lining_force (their total normal force [N])."""
    gs, lining = set(g for g in ids["grains"] if O.bodies[g] is not None), set(ids["lining"])
    out = dict(grain_grain=0, grain_lining=0, grain_lining_force=0.0)
    for i in O.interactions:
        if not i.isReal or (hasattr(i.geom, "active") and not i.geom.active):
            continue
        if i.id1 in gs and i.id2 in gs:
            out["grain_grain"] += 1
        elif (i.id1 in gs and i.id2 in lining) or (i.id2 in gs and i.id1 in lining):
            out["grain_lining"] += 1
            out["grain_lining_force"] += i.phys.normalForce.norm()
    return out


def fill_top(ids):
    """Height of the highest grain surface [m]."""
    return max(O.bodies[g].state.pos[2] + O.bodies[g].shape.radius for g in ids["grains"] if O.bodies[g] is not None)


def add_boulder(params, ids, gap=0.005):
    """The boulder, its lowest point `gap` [m] above the highest point of the module (fill,
    top ring), moving down with the free-fall speed of params (drop height reduced by the
    gap, so that it reaches the fill top at sqrt(2 g h)). Returns its body id."""
    params.validate()
    top = max(fill_top(ids), max(O.bodies[n].state.pos[2] for n in ids["mesh_nodes"]) + 0.5 * params.ring_bar_diameter)
    s = params.boulder_size()
    v_top = params.impact_speed()
    v0 = math.sqrt(max(0.0, v_top * v_top - 2 * G * gap))
    mat = FrictMat(young=3e9, poisson=0.2, density=params.boulder_density, frictionAngle=math.radians(35), label="boulder")
    O.materials.append(mat)
    ox, oy = params.impact_offset
    if params.boulder_shape == "sphere":
        r = 0.5 * s
        bid = _sphere_body(Vector3(ox, oy, top + gap + r), r, mat)
        O.bodies[bid].state.vel = Vector3(0, 0, -v0)
        return bid
    n = 4  # member spheres per side: radius s/(2n), centres on a grid inset by that radius
    r = s / (2 * n)
    members = []
    for i in range(n):
        for j in range(n):
            for k in range(n):
                c = Vector3(ox - s / 2 + r + 2 * r * i, oy - s / 2 + r + 2 * r * j, top + gap + r + 2 * r * k)
                b = Body()
                b.shape = Sphere(radius=r * 1.0)
                b.material = mat
                b.state.pos = c
                members.append(b)
    cid = O.bodies.appendClumped(members)[0]
    cl = O.bodies[cid]
    cl.state.mass = params.boulder_mass
    cl.state.inertia = Vector3(1, 1, 1) * params.boulder_mass * s * s / 6
    cl.aspherical = False  # isotropic inertia (a solid cube): the spherical rotation update is exact
    cl.state.vel = Vector3(0, 0, -v0)
    return cid


def touches(bid):
    """Whether body bid (a clump: one of its members) has a real interaction."""
    b = O.bodies[bid]
    return any(i.isReal for m in (list(b.shape.members.keys()) if b.isClump else [bid]) for i in O.interactions.withBody(m))


def scale_lining_nodes(ids, m_min):
    """Mass scaling of the lining for the impact: every dynamic lining node gets at least the mass
    m_min [kg], its rotational inertia scaled by the same factor. The geotextile's own nodes weigh
    about a gram; pressed between grains and wires they would set the time step of the whole
    impact (FlexTimeStepper's stiffest body), while their inertia is small beside the grains that
    press on them. The mass added weighs too (gravity acts on it). Returns (mass added, the
    lining's own mass) [kg]; m_min = 0 changes nothing."""
    added = own = 0.0
    for m in ids["modules"]:
        for n in m.get("lining_nodes", []):
            b = O.bodies[n]
            if b is None or not b.dynamic:
                continue
            own += b.state.mass
            if b.state.mass < m_min:
                f = m_min / b.state.mass
                added += m_min - b.state.mass
                b.state.mass = m_min
                b.state.inertia = Vector3(b.state.inertia) * f
    return added, own


def impact_start(params, cache_dir=None, max_fall=0.5):
    """The main job's impact up to the boulder's first contact: loads (or fills) the module,
    adds the boulder and the impact engines, and steps until the boulder touches something (for
    benchmarks and diagnostics that look at the impact itself). Returns (ids, boulder id, the
    boulder's member body ids), with the lining's nodes scaled as the main job scales them
    (scale_lining_nodes). Raises RuntimeError if no contact within max_fall [s]."""
    ids, _, _ = filled_module(params, cache_dir=cache_dir)
    scale_lining_nodes(ids, params.lining_node_mass)
    bid = add_boulder(params, ids)
    O.engines = params.engines(params.damping)
    boulder = O.bodies[bid]
    members = set(boulder.shape.members.keys()) if boulder.isClump else {bid}
    t0 = O.time
    while not touches(bid):
        if O.time - t0 > max_fall:
            raise RuntimeError("the boulder never touched the module")
        step_until(math.inf, 50)
    return ids, bid, members
