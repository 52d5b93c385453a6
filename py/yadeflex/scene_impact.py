"""A boulder onto any structure: yadeflex.boulder_impact(out, Boulder(...), parts=..., reactions=...).

The scene in O is the structure (built with the builders, placed, filled); the runner adds the
boulder, runs the impact to the rebound (yadeflex.runner) and writes into `out`:
params.json, timeseries.csv (boulder, force, penetration, the reaction of each group of
supports, broken elements by part), energy.csv, summary.json, impact.png, energy.png and
vtk/flex.pvd, with the exit status of the main job (yadeflex.runner.EXIT).
"""
import dataclasses
import math
import os
import time

from yade import O
from yade.minieigenHP import Vector3

from . import checks as C
from . import parts as P
from . import runner as R
from .boulder import boulder_material, make_boulder
from .drop import lower_onto
from .files import write_json
from .force_filter import CUTOFF_HZ, describe
from .scene import contact_law

PROG = "impact"
RESULT_FILES = ("params.json", "timeseries.csv", "energy.csv", "summary.json", "impact.png", "energy.png")
SHAPES = ("sphere", "cube")


@dataclasses.dataclass
class Boulder:
    """The boulder of an impact.

    mass [kg]; shape: 'sphere', 'cube' (a clump of 4 x 4 x 4 spheres) or a clump file (lines
    'x y z r' [m]: its member spheres about its centre); density [kg/m3] (sets the size of a
    sphere or cube). Where: at=(x, y, z), its centre [m]; or above=(x, y): centred there, its
    lowest point `gap` [m] above the highest body under it. How fast: speed [m/s] at the start,
    or drop_height [m] (the speed of a fall from that height, sqrt(2 g h), reached at the
    structure: the gap's fall is taken off). direction: its direction of travel (default down).
    Or body: the id of a sphere or clump already in the scene (resting under a drapery, say),
    set moving at `speed` along `direction`; its mass is its own."""
    mass: float = None
    shape: str = "sphere"
    density: float = 2650.0
    at: tuple = None
    above: tuple = None
    speed: float = None
    drop_height: float = None
    direction: tuple = (0.0, 0.0, -1.0)
    gap: float = 0.005
    body: int = None

    def __post_init__(self):
        if self.body is not None:
            if not (isinstance(self.body, int) and 0 <= self.body < len(O.bodies) and O.bodies[self.body] is not None
                    and (O.bodies[self.body].isClump or type(O.bodies[self.body].shape).__name__ == "Sphere")):
                raise C.BadValue("Boulder.body", self.body, "the id of a sphere or clump of the scene")
            if self.at is not None or self.above is not None or self.drop_height is not None:
                raise ValueError("Boulder: body= is already placed: give its speed (and direction), not at, above or drop_height")
            self.mass = O.bodies[self.body].state.mass
            if self.speed is None:
                raise ValueError("Boulder: give body= its speed [m/s] (the impact energy the balance is measured against)")
            self.speed = C.number("Boulder.speed", self.speed, C.Range(0.0, 100.0, "m/s", lo_open=True))
            self.shape = f"body #{self.body}"
            self.direction = tuple(self._unit(self.direction))
            return
        self.mass = C.positive("Boulder.mass", self.mass, "kg")
        self.density = C.positive("Boulder.density", self.density, "kg/m3")
        if isinstance(self.shape, str) and self.shape not in SHAPES:
            if not os.path.isfile(self.shape):
                raise C.BadValue("Boulder.shape", self.shape, "'sphere', 'cube' or the path of a clump file (lines 'x y z r' in metres)")
            self.shape = read_clump(self.shape)
        elif not isinstance(self.shape, str):
            self.shape = [tuple(C.vector("Boulder.shape member", m, 4)) for m in self.shape]
        if (self.at is None) == (self.above is None):
            raise ValueError("Boulder: give either at=(x, y, z), its centre, or above=(x, y), the point it falls onto")
        if self.at is not None:
            self.at = tuple(C.vector("Boulder.at", self.at))
        if self.above is not None:
            self.above = tuple(C.vector("Boulder.above", self.above, 2))
        if (self.speed is None) == (self.drop_height is None):
            raise ValueError("Boulder: give either speed [m/s] or drop_height [m]")
        if self.speed is not None:
            self.speed = C.number("Boulder.speed", self.speed, C.Range(0.0, 100.0, "m/s", lo_open=True))
        if self.drop_height is not None:
            self.drop_height = C.number("Boulder.drop_height", self.drop_height, C.Range(0.0, 500.0, "m", lo_open=True))
        self.direction = tuple(self._unit(self.direction))
        self.gap = C.number("Boulder.gap", self.gap, C.Range(0.0, 1.0, "m"))

    @staticmethod
    def _unit(direction):
        d = Vector3(*C.vector("Boulder.direction", direction))
        if d.norm() == 0:
            raise C.BadValue("Boulder.direction", direction, "a non-zero vector")
        return d / d.norm()

    def size(self):
        """Sphere diameter or cube side [m] (None for a clump file's shape or a given body)."""
        if self.body is not None:
            return None
        v = self.mass / self.density
        if self.shape == "sphere":
            return (6 * v / math.pi) ** (1 / 3)
        if self.shape == "cube":
            return v ** (1 / 3)
        return None

    def half_height(self):
        """Its half extent along z [m]."""
        if isinstance(self.shape, str):
            return 0.5 * self.size()
        return 0.5 * (max(m[2] + m[3] for m in self.shape) - min(m[2] - m[3] for m in self.shape))

    def half_width(self):
        """Its largest half extent across z [m]."""
        if isinstance(self.shape, str):
            return 0.5 * self.size() * (1.0 if self.shape == "sphere" else math.sqrt(2.0))
        return max(math.hypot(m[0], m[1]) + m[3] for m in self.shape)

    def speed_at_contact(self, g):
        """Its speed when it reaches the structure [m/s]."""
        return self.speed if self.speed is not None else math.sqrt(2 * g * self.drop_height)

    def add(self, g):
        """The boulder into O (gravity g [m/s2]), or the given body set moving; returns its body id."""
        if self.body is not None:
            O.bodies[self.body].state.vel = Vector3(*self.direction) * self.speed
            return self.body
        if self.at is not None:
            x, y, z = self.at
            bottom = z - self.half_height()
        else:
            x, y = self.above
            bottom = surface_under(x, y, self.half_width()) + self.gap
        v = self.speed_at_contact(g)
        if self.drop_height is not None and self.above is not None:
            v = math.sqrt(max(0.0, v * v - 2 * g * self.gap))  # (the gap is fallen before the contact)
        mat = boulder_material(self.density)
        shape = self.shape
        bid = make_boulder(shape, self.size(), self.mass, mat, x, y, bottom, Vector3(*self.direction) * v)
        if self.above is not None:  # (its first touch after a fall of exactly the gap)
            lower_onto(bid, self.gap)
        return bid


def read_clump(path):
    """The member spheres (x, y, z, r) [m] of a clump file: one sphere per line, '#' comments."""
    out = []
    with open(path) as fh:
        for k, line in enumerate(fh, 1):
            line = line.split("#")[0].strip()
            if not line:
                continue
            try:
                x, y, z, r = (float(v) for v in line.replace(",", " ").split())
            except ValueError:
                raise ValueError(f"{path}, line {k}: a clump file line is 'x y z r' (metres), got {line!r}") from None
            if not (all(math.isfinite(v) for v in (x, y, z, r)) and r > 0):
                raise ValueError(f"{path}, line {k}: finite coordinates and a radius > 0, got {line!r}")
            out.append((x, y, z, r))
    if not out:
        raise ValueError(f"{path}: no member sphere in the clump file")
    return out


def surface_under(x, y, half_width):
    """The top [m] of the highest body under the disc of radius half_width about (x, y): spheres
    by their radius; yade-flex cylinders and facets by their nodes plus their own radius (a
    segment or a flat triangle is nowhere higher than its highest node; a wire thicker than its
    nodes' display radius reaches higher than they do); YADE facets by their vertices, boxes by
    their extents, walls normal to z by their plane; ValueError if nothing is."""
    from yade.wrapper import Box, Facet, FlexCylinder, FlexFacet, FlexNode, Sphere, Wall
    top = -math.inf
    for b in O.bodies:
        if b is None or b.isClump:
            continue
        sh, pos = b.shape, b.state.pos
        if isinstance(sh, Wall):
            if sh.axis == 2:
                top = max(top, pos[2])
            continue
        if isinstance(sh, (Sphere, FlexNode)):
            if math.hypot(pos[0] - x, pos[1] - y) <= half_width + sh.radius:
                top = max(top, pos[2] + sh.radius)
            continue
        reach = 0.0
        if isinstance(sh, (FlexCylinder, FlexFacet)):
            ends = (sh.node1, sh.node2) if isinstance(sh, FlexCylinder) else (sh.node1, sh.node2, sh.node3)
            if any(i < 0 or i >= len(O.bodies) or O.bodies[i] is None for i in ends):
                continue
            pts = [O.bodies[i].state.pos for i in ends]
            reach = sh.radius
        elif isinstance(sh, Facet):
            pts = [pos + b.state.ori * v for v in sh.vertices]
        elif isinstance(sh, Box):
            e = sh.extents
            pts = [pos + b.state.ori * Vector3(i * e[0], j * e[1], k * e[2]) for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)]
        else:
            continue
        # (by the rectangle around its corners, widened by its radius)
        w = half_width + reach
        if (min(p[0] for p in pts) - w <= x <= max(p[0] for p in pts) + w
                and min(p[1] for p in pts) - w <= y <= max(p[1] for p in pts) + w):
            top = max(top, max(p[2] for p in pts) + reach)
    if top == -math.inf:
        raise ValueError(f"Boulder.above=({x:g}, {y:g}): no body under that point to fall onto")
    return top


def _is_element(b):
    """Whether body b is a yade-flex element (a cylinder or facet: its forces act on its nodes)."""
    return type(b.shape).__name__ in ("FlexCylinder", "FlexFacet")


class Reactions:
    """The reaction of each named group of supports: for each body of the group, the force its
    supports exert, -(force on it + its weight) on each blocked translation (all three on a body
    that is not dynamic: a wall, a YADE facet or box); summed over the group [N]. Elements
    (cylinders, facets) are left out: their nodes carry their forces."""

    def __init__(self, groups, gravity):
        self.gravity = gravity
        self.groups = {}
        for name, ids in groups.items():
            rows = []
            for i in sorted(set(P._flatten(ids))):
                b = O.bodies[i]
                if _is_element(b):
                    continue
                blocked = "xyz" if not b.dynamic else "".join(c for c in "xyz" if c in b.state.blockedDOFs)
                if blocked:
                    rows.append((i, tuple(k for k, c in enumerate("xyz") if c in blocked)))
            if not rows:
                raise ValueError(f"reactions[{name!r}]: none of its {len(set(P._flatten(ids)))} bodies is supported (no blocked x, y or z, "
                                 "and dynamic): a reaction is the force on a support")
            self.groups[name] = rows

    def __call__(self):
        """dict name -> reaction (Vector3) now."""
        out = {}
        for name, rows in self.groups.items():
            r = Vector3(0, 0, 0)
            for i, axes in rows:
                b = O.bodies[i]
                if b is None:
                    continue
                f = O.forces.f(i) + b.state.mass * self.gravity
                for k in axes:
                    r[k] -= f[k]
            out[name] = r
        return out


def default_supports(names):
    """Groups of supports when none are given: per named part, its supported bodies (blocked or
    not dynamic), else one group 'supports' of every such body; the boulder's left out."""
    groups = {}
    table = P.scene_parts()
    for b in O.bodies:
        if b is None or b.isClump or b.isClumpMember or _is_element(b):
            continue
        if b.dynamic and not any(c in b.state.blockedDOFs for c in "xyz"):
            continue
        k = table.get(b.id)
        name = names[k] if k is not None and k >= len(P.PARTS) else "supports"
        groups.setdefault(name, []).append(b.id)
    return groups


class PartBreaks:
    """Broken elements (FlexElementEngine.rupturedIds) counted by part name."""

    def __init__(self, names, table):
        self.names, self.table = names, table

    def counts(self, ruptured_ids):
        c = {}
        for i in ruptured_ids:
            k = self.table.get(i)
            name = self.names[k] if k is not None else "other"
            c[f"broken_{name}"] = c.get(f"broken_{name}", 0) + 1
        c["broken_elements_total"] = len(ruptured_ids)
        return c


class SceneImpact(R.ImpactRun):
    """The runner's ImpactRun on the scene in O: the boulder added, its force, penetration, the
    supports' reactions and the broken elements by part recorded."""
    PROG = PROG
    RELEASE = 0.02  # [s] the boulder passed through or left: no force on it for this long ends the run

    def __init__(self, boulder, parts, reactions, damping, cutoff_hz, folder, signals, settings, progress=True):
        self.spec, self.parts_given, self.reactions_given, self.damping, self.cutoff_hz = boulder, parts, reactions, damping, cutoff_hz
        super().__init__(folder, signals, settings, progress)

    def units(self):
        known = dict(self.UNITS, dt="s")
        return lambda k: known.get(k) or ("N" if k.startswith("reaction_") else "-" if k.startswith("broken_") else None)

    def prepare(self):
        if self.parts_given:
            P.name_parts(self.parts_given)
        if not O.engines:
            from .scene import engines
            O.engines = engines(damping=self.damping)
        missing = [lab for lab in ("newton", "flexElements", "flexDt") if R.engine(lab) is None]
        if missing:
            raise ValueError(f"the scene's engines lack {', '.join(repr(m) for m in missing)}: use yadeflex.engines() (or leave O.engines "
                             "empty: the runner sets them)")
        contact_law()  # (ValueError naming it if the engines have none)
        self.gravity = Vector3(R.engine("newton").gravity)
        g = self.gravity.norm()
        if len(O.bodies) == 0:
            raise ValueError("the scene is empty: build the structure before the impact")
        bid = self.spec.add(g)
        groups = P.named_groups()
        if not O.bodies[bid].isClump and not any(bid in ids for ids in groups.values()):
            P.name_parts(dict(groups, boulder=[bid]))  # (a clump and its members are the boulder already)
        self.names = P.part_names()
        table = P.scene_parts()
        self.name_of = {i: self.names[k] for i, k in table.items()}
        self.boulder = O.bodies[bid]
        self.mass = self.boulder.state.mass
        self.direction = Vector3(*self.spec.direction)
        v = self.spec.speed_at_contact(g)
        self.e_impact = 0.5 * self.mass * v * v
        self.boulder.state.isDamped = False
        O.trackEnergy = True
        O.energy.clear()
        O.timingEnabled = True
        groups = self.reactions_given if self.reactions_given is not None else default_supports(self.names)
        self.reactions = Reactions(groups, self.gravity) if groups else None
        self.broken = PartBreaks(self.names, table)
        self.broken_parts = sorted({self.names[table[i]] for i in table if O.bodies[i] is not None
                                    and type(O.bodies[i].shape).__name__ in ("FlexCylinder", "FlexFacet")})
        self.reaction_names = list(self.reactions.groups) if self.reactions else []
        write_json(self.folder.file("params.json"), dict(
            boulder=dict(dataclasses.asdict(self.spec), shape=self.spec.shape if isinstance(self.spec.shape, str) else "clump",
                         mass_used=self.mass, size=self.spec.size(), speed_at_contact=v),
            parts={n: sum(1 for k in table.values() if self.names[k] == n) for n in self.names if any(self.names[k] == n for k in table.values())},
            reactions={n: [i for i, _ in rows] for n, rows in (self.reactions.groups.items() if self.reactions else [])},
            numerical_damping=R.engine("newton").damping, force_filter=describe(self.cutoff_hz), gravity=list(self.gravity),
            engines=[e.label or type(e).__name__ for e in O.engines]))
        print(f"impact: {self.mass:.4g} kg {self.spec.shape if isinstance(self.spec.shape, str) else 'clump'} at {v:.2f} m/s "
              f"({self.e_impact / 1e3:.3g} kJ) onto {len(O.bodies) - 1} bodies; parts {', '.join(n for n in self.names if n in self.name_of.values()) or 'none named'}; "
              f"reactions of {', '.join(self.reaction_names) or 'no support'}; {O.numThreads} thread(s)", flush=True)

    def scene_row(self):
        row = {}
        if self.reactions:
            for n, r in self.reactions().items():
                row.update({f"reaction_{n}": r.norm(), f"reaction_{n}_x": r[0], f"reaction_{n}_y": r[1], f"reaction_{n}_z": r[2]})
        c = self.broken.counts(self.el.rupturedIds)
        for n in self.broken_parts:
            row[f"broken_{n}"] = c.get(f"broken_{n}", 0)
        return row

    def part_name(self, bid):
        if bid is not None and bid in self.name_of and O.bodies[bid] is not None:
            return f"{self.name_of[bid]} #{bid}"
        return super().part_name(bid)

    def vtk_parts(self):
        return P.scene_parts()

    def head_results(self):
        g = self.gravity.norm() if hasattr(self, "gravity") else None
        return dict(boulder_mass=self.spec.mass, impact_speed_expected=self.spec.speed_at_contact(g) if g else None,
                    threads=O.numThreads, run_time_s=time.time() - self.t_wall)

    def scene_results(self):
        rows = self.rows.rows
        out = {}
        for n in self.reaction_names:
            if rows:
                best = max(rows, key=lambda r: r[f"reaction_{n}"])
                out[f"reaction_{n}_max"] = best[f"reaction_{n}"]
                out[f"reaction_{n}_at_max"] = [best[f"reaction_{n}_{c}"] for c in "xyz"]
        return out

    def broken_results(self):
        return self.broken.counts(self.el.rupturedIds)

    def plots(self, folder, rows, erows, keys):
        from .impact_plots import write_energy_plot, write_scene_plots
        write_scene_plots(folder, rows, (getattr(self, "filtered", None) or {}).get("impact_force"), describe(self.cutoff_hz), self.reaction_names)
        write_energy_plot(folder, erows, keys)


def boulder_impact(out, boulder, parts=None, reactions=None, damping=0.0, cutoff_hz=CUTOFF_HZ, progress=True, **settings):
    """A boulder (Boulder) onto the structure in O, recorded into the folder `out`.

    parts: dict name -> body ids (yadeflex.parts.name_parts): the names of the VTK part field,
    the 3D view, the broken-element counts and the messages. reactions: dict name -> ids of
    supported bodies (fixed nodes, walls, facets): the force their supports exert, per group, in
    timeseries.csv and summary.json; default: each named part's supported bodies, else all of
    them as 'supports'. damping: the engines' numerical damping if the runner sets them (O.engines
    empty); the boulder's free fall is never damped. cutoff_hz: the low-pass filter of the
    reported peak force (yadeflex.force_filter; the raw force is kept beside it). settings:
    yadeflex.runner.RunSettings' fields (duration, record_every, vtk_every, no_vtk,
    min_dt_fraction, max_residual). Returns the summary (summary.json's), with its exit_status."""
    if not isinstance(boulder, Boulder):
        raise TypeError(f"boulder: a yadeflex.Boulder, got {type(boulder).__name__}")
    C.number("damping", damping, C.Range(0.0, 1.0, hi_open=True))
    C.number("cutoff_hz", cutoff_hz, C.Range(0.0, 1e5, "Hz", lo_open=True))
    s = R.RunSettings(**settings)
    return R.run_into(out, RESULT_FILES, PROG, lambda folder, signals: SceneImpact(boulder, parts, reactions, damping, cutoff_hz, folder, signals, s,
                                                                                   progress))
