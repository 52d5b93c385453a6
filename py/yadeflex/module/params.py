"""The damping module's parameters: ModuleParams (each option declared once, yadeflex.params;
the fill presets are yadeflex.grains'), and the geometry the cache key needs (the lining's and
the grains' radii)."""
import dataclasses
import hashlib
import json
import math


from ..constants import G
from .. import checks as C
from ..materials import FRICTION_DEG
from ..mesh import TECCO_G65_DX, TECCO_G65_DY
from ..params import param, declared, IMPACT, FILL
from ..scene import engines, CRUSHING_IS50, DAMPING, ROLLING_FRICTION, TIMESTEP_SAFETY as SCENE_TIMESTEP_SAFETY
from ..grains import (FILL_TIMESTEP_SAFETY, FILLS, UNBALANCED_TOL, WITHDRAWN_FILLS, DEPOSITION_FRICTION, SETTLE_DAMPING,  # noqa: F401
                      check_fill)


# largest mass scaling of the structure's nodes while it settles on the fill (_heavier_nodes)
MAX_NODE_MASS_SCALING = 100.0
# the grains are placed on a hexagonal close-packed lattice (spacing 2.05 grain_max: solid
# fraction about 0.33 with the gravel's sizes) up to this x the module's height: about 1.2 x the
# grains a dense fill of the module's height holds, the rest trimmed
PLACED_HEIGHT = 2.4

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
    fill_deposition_friction_deg: float = param(0.0, unit="deg", allowed=DEPOSITION_FRICTION,
                                                meaning="grain friction while the fill is densified: 0 the densest fill, up to the fill's own angle a looser one")
    boulder_mass: float = param(800.0, unit="kg", stage=IMPACT, meaning="boulder mass", small=100.0, allowed=C.Range(
        0.0, math.inf, "kg", lo_open=True, note=f"a boulder (cube side, sphere diameter) of {BOULDER_MIN_SIZE} m to 3 x the diameter"))
    boulder_shape: str = param("cube", "choice", stage=IMPACT, allowed=BOULDER_SHAPES, row="boulder_mass",
                               meaning="its shape: a cube (a rigid clump of 64 spheres with the cube's mass and inertia) or a sphere")
    boulder_density: float = param(2400.0, unit="kg/m3", stage=IMPACT, meaning="its density (concrete)", row="boulder_mass",
                                   allowed=C.Range(500.0, 2e4, "kg/m3"))
    drop_height: float = param(2.0, unit="m", stage=IMPACT, meaning="free fall of the boulder to its first touch of the module (fill, rings, wires or lining)", small=1.0,
                               allowed=C.Range(0.0, MAX_IMPACT_SPEED ** 2 / (2 * G), "m", lo_open=True,
                                               note=f"an impact speed up to {MAX_IMPACT_SPEED:g} m/s"))
    impact_velocity: float = param(None, unit="m/s", stage=IMPACT, meaning="or the impact speed", default_text="from --drop-height",
                                   row="drop_height", allowed=C.Range(0.0, MAX_IMPACT_SPEED, "m/s", lo_open=True))
    impact_offset: tuple = param((0.0, 0.0), "pair", unit="m", stage=IMPACT, meaning="horizontal offset of the impact from the axis, within the module's radius")
    damping: float = param(0.0, unit="-", stage=IMPACT, meaning="numerical (local) damping from the boulder's first contact (the free fall is undamped)",
                           allowed=dataclasses.replace(DAMPING, note="local damping"))
    settle_damping: float = param(SETTLE_DAMPING, unit="-", meaning="local damping while the fill settles (not part of the impact)",
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

    def engines(self, damping, timestep_safety=None, crushing=True, grain_engine=None):
        """yadeflex.engines() with this module's rolling resistance and, unless crushing is
        False (the fill), its grain crushing (time step: timestep_safety, default this module's).
        grain_engine: the grain-grain contacts in a FlexGrainEngine (yadeflex.engines(grains="fill"));
        None: for the impact (crushing True) unless the grains crush, not for the fill (its
        cached states were built with the interaction loop)."""
        rf = self.preset()["rolling_friction"]
        ts = self.timestep_safety if timestep_safety is None else timestep_safety
        return engines(damping=damping, timestep_safety=ts, rolling_stiffness=1.0 if rf > 0 else 0.0, rolling_friction=rf,
                       crushing_is50=self.grain_crushing_is50 if crushing else None,
                       grains="fill" if (crushing and not self.grain_crushing_is50 if grain_engine is None else grain_engine) else None)

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
        d["_version"] = 22  # raised whenever the code fills the same parameters differently (why: git log -S_version)
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
    from ..mesh import TECCO_G65_DY
    R = 0.5 * params.diameter
    r_lin = min(R - params.lining_gap - 0.5 * params.lining_thickness - 0.0015,
                R * math.cos(TECCO_G65_DY / params.diameter) - 0.5 * params.ring_bar_diameter - 0.5 * params.lining_thickness - 0.002)
    return r_lin, r_lin * math.cos(math.pi / lining_cells_around(r_lin)) - 0.5 * params.lining_thickness
