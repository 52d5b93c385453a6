"""The damping-module impact: run_impact, the main job's run (scripts/damping_module.py), and its
bookkeeping; one use of the generic runner (yadeflex.runner).

- run_impact(params, out, ...): the filled module, the boulder and the impact into a results
  folder, row by row; returns the summary, with the exit status. fill_only: the filled module
  into the cache, nothing else (the main job's --fill-only). ImpactRun: one such run (the
  runner's ImpactRun with the module's hooks); RunSettings, EXIT: as yadeflex.runner's.
- BrokenElements: what broke, by kind.
- fill_progress: the progress lines of the fill.
"""
import dataclasses
import math
import os
import sys
import time
import traceback

from yade import O
from yade.minieigenHP import Vector3

from .. import runner as R
from ..runner import EXIT, RunSettings
from ..files import write_json
from .impact_plots import write_plots
from ..constants import G
from ..module import filled_module, add_boulder, fill_top, scale_lining_nodes, UNBALANCED_TOL
from .ids import BROKEN_KINDS, ModuleIds

PROG = "damping_module"  # the main job: its name starts the lines it writes to stderr
RESULT_FILES = ("params.json", "timeseries.csv", "energy.csv", "summary.json", "impact.png", "energy.png")

# unit of each column of timeseries.csv (its header reads NAME[UNIT])
TIMESERIES_UNITS = dict(t="s", boulder_z="m", boulder_vz="m/s", boulder_az="m/s2", impact_force="N", penetration="m", slab_force="N",
                        bulge_max="m", bulge_mean="m", ring_top_force="N", ring_bottom_force="N", rope_force="N", broken_wires="-",
                        broken_ring_segments="-", broken_rope_segments="-", broken_lining_facets="-", dt="s")
class BrokenElements:
    """Counts of ruptured elements by kind (FlexElementEngine.rupturedIds: every element it
    erased, of any kind): the BROKEN_KINDS keys (yadeflex.module.ids), broken_other_elements (an
    element of none of those kinds) and broken_elements_total, their sum."""

    def __init__(self, ids):
        self.kind = ModuleIds.of(ids).broken_kinds()

    def counts(self, ruptured_ids):
        c = dict.fromkeys(list(BROKEN_KINDS) + ["broken_other_elements"], 0)
        for i in ruptured_ids:
            c[self.kind.get(i, "broken_other_elements")] += 1
        c["broken_elements_total"] = len(ruptured_ids)
        return c


def fill_progress(t_wall):
    """progress(stage, steps, kinetic energy, target) for filled_module: a line at the start of
    each stage, then every 10,000 steps and at least every 30 s, with the time left in the stage."""
    last = {}  # stage -> (wall time, kinetic energy) at its last report
    printed = dict(at=t_wall, stages=0)  # wall time of the last line, stages started

    def prog(stage, steps, ke, target):
        now = time.time()
        if steps == 0:
            note = " (filled once, then cached)" if printed["stages"] == 0 else ""
            print(f"  {stage}: settles until the kinetic energy is below {target:.3g} J{note}, {now - t_wall:.0f} s", flush=True)
            printed.update(at=now, stages=printed["stages"] + 1)
            return
        # every 10,000 steps, and at least every 30 s (a fill of seven modules takes 40 s or more per 10,000)
        if steps % 10000 and now - printed["at"] < 30:
            return
        printed["at"] = now
        # time left in this stage, from the exponential decay of the kinetic energy since the
        # last report (the stages that also wait for the unbalanced force may take longer)
        eta = ""
        if stage in last and 0 < ke < last[stage][1] and ke > target:
            rate = math.log(last[stage][1] / ke) / (now - last[stage][0])
            eta = f", ~{math.log(ke / target) / rate:.0f} s left in this stage at the current decay"
        elif ke <= target:  # (only the stages that also wait for the unbalanced force go on)
            eta = f", below its target: waiting for the unbalanced force to fall below {UNBALANCED_TOL}"
        last[stage] = (now, ke)
        print(f"  {stage}: {steps} steps, kinetic energy {ke:.3g} J, {now - t_wall:.0f} s{eta}", flush=True)
    return prog


class ImpactRun(R.ImpactRun):
    """The main job's run (yadeflex.runner.ImpactRun with the module's hooks): the filled module
    (loaded from the cache or filled), its lining's mass scaling, the boulder dropped onto it; the
    module's columns (slab force, bulging, ring and rope forces, broken elements by kind), its
    summary numbers and plots."""
    PROG = PROG
    UNITS = TIMESERIES_UNITS

    def __init__(self, p, folder, signals, settings, cache_dir=None, progress=True):
        self.p, self.cache_dir = p, cache_dir
        self.t_fill = self.cached = self.cache_file = None
        super().__init__(folder, signals, settings, progress)
        self.stage = "fill"
        write_json(folder.file("summary.json"), dict(status="running", stage=self.stage, pid=os.getpid()))

    def prepare(self):
        p = self.p
        print(f"damping module: {p.n_modules} x {p.diameter} m x {p.height} m{' with a boundary rope' if p.with_rope() else ''}, {p.fill} fill, {p.boulder_mass} kg {p.boulder_shape} at {p.impact_speed():.2f} m/s, {O.numThreads} thread(s)")
        ids, self.cache_file, self.cached = filled_module(p, cache_dir=self.cache_dir, progress=fill_progress(self.t_wall) if self.show_progress else None)
        self.t_fill = self.t_prepare = time.time() - self.t_wall
        print(f"filled module {'loaded from' if self.cached else 'built and saved to'} {self.cache_file} ({self.t_fill:.0f} s): "
              f"{len(ids.grains)} grains, {len(ids.bodies('mesh_cylinders'))} wire legs, {len(ids.bodies('lining'))} lining facets"
              + (f" in {len(ids.modules)} modules" if len(ids.modules) > 1 else ""))
        self.stage = "impact"
        # (summary.json follows the run: a process killed outright during the impact leaves "impact")
        write_json(self.folder.file("summary.json"), dict(status="running", stage=self.stage, pid=os.getpid()))
        self.ids, self.names, self.broken = ids, ids.names(), BrokenElements(ids)
        self.top0 = fill_top(ids)
        self.lining_added, self.lining_own = scale_lining_nodes(ids, p.lining_node_mass)
        if self.lining_added > 0:
            print(f"lining nodes at {1e3 * p.lining_node_mass:g} g or more for the time step (mass scaling): +{self.lining_added:.2f} kg "
                  f"on the lining's own {self.lining_own:.2f} kg")
        bid = add_boulder(p, ids)
        self.size = p.boulder_size()
        self.boulder = O.bodies[bid]
        self.mass = self.boulder.state.mass
        O.engines = p.engines(p.damping)
        self.gravity, self.direction = R.engine("newton").gravity, Vector3(0, 0, -1)
        # the free fall is not damped: numerical damping (--damping) acts on the boulder from its
        # first contact on (NewtonIntegrator's damping scales every acceleration, gravity's too)
        self.boulder.state.isDamped = False
        O.trackEnergy = True
        O.energy.clear()
        O.timingEnabled = True
        write_json(self.folder.file("params.json"),
                   # the values used (the fill preset's resolved), and the parameters as given (None: the preset's)
                   dict(p.resolved(), impact_speed=p.impact_speed(), fill_top=self.top0,
                        cache_file=self.cache_file, contact_law="linear Cundall-Strack (yade-flex law for all sphere and element contacts)",
                        numerical_damping=p.damping, numerical_damping_from="the boulder's first contact (its free fall undamped)",
                        given=dataclasses.asdict(p)))
        # bulging and ring forces of the module hit (the first, centred on the axis)
        self.R0 = 0.5 * p.diameter
        self.mid = [n for n in ids["mesh_nodes"] if abs(O.bodies[n].state.pos[2] - 0.5 * p.height) < 0.15 * p.height]
        self.ring_ids = dict(top=ids["ring_top"], bottom=ids["ring_bottom"], rope=ids.get("rope", []))
        self.e_impact = 0.5 * self.mass * p.impact_speed() ** 2

    # a vertical drop: the vertical force and velocity, the penetration below the fill's top
    def along(self, v):
        return v[2]

    def contact_force(self, acc):
        return self.mass * (acc[2] + G)  # vertical force of the module on the boulder [N]

    def touching(self, f_contact):
        bottom = self.boulder.state.pos[2] - 0.5 * self.size
        return f_contact > 0.01 * self.mass * G and bottom < self.top0 + 0.01

    def penetration(self):
        return max(0.0, self.top0 - (self.boulder.state.pos[2] - 0.5 * self.size))

    def scene_row(self):
        fw = O.forces.f(self.ids["wall"])[2]
        slab = -fw + sum(O.bodies[n].state.mass * G - O.forces.f(n)[2] for n in self.ids["base_nodes"] if O.bodies[n] is not None)
        radial = [math.hypot(O.bodies[n].state.pos[0], O.bodies[n].state.pos[1]) - self.R0 for n in self.mid if O.bodies[n] is not None]
        ring_f = {k: max([O.bodies[c].shape.axialForce for c in v if O.bodies[c] is not None] or [0.0]) for k, v in self.ring_ids.items()}
        broken = self.broken.counts(self.el.rupturedIds)
        return dict(slab_force=slab, bulge_max=max(radial or [0.0]), bulge_mean=(sum(radial) / len(radial) if radial else 0.0),
                    ring_top_force=ring_f["top"], ring_bottom_force=ring_f["bottom"], rope_force=ring_f["rope"],
                    broken_wires=broken["broken_wire_legs"], broken_ring_segments=broken["broken_ring_segments"],
                    broken_rope_segments=broken["broken_rope_segments"], broken_lining_facets=broken["broken_lining_facets"])

    def overlap_advice(self):
        return ("(grain contacts yield at their crushing load: --grain-crushing-is50; or a gentler impact)" if self.p.grain_crushing_is50
                else "(stiffer contacts: --fill-young, --steel-contact-young, or a gentler impact)")

    def head_results(self):
        return dict(n_modules=self.p.n_modules, impact_speed_expected=self.p.impact_speed(), threads=O.numThreads,
                    run_time_s=time.time() - self.t_wall, fill_time_s=self.t_fill, filled_from_cache=self.cached)

    def scene_results(self):
        peak = self.peak
        return dict(slab_force_max=peak("slab_force"), bulge_max=peak("bulge_max"), ring_top_force_max=peak("ring_top_force"),
                    ring_bottom_force_max=peak("ring_bottom_force"), rope_force_max=peak("rope_force"))

    def mass_results(self):
        return dict(lining_mass=self.lining_own, lining_mass_added=self.lining_added)

    def broken_results(self):
        broken = self.broken.counts(self.el.rupturedIds)
        return dict(broken, broken_wires=broken["broken_wire_legs"])

    def plots(self, folder, rows, erows, keys):
        write_plots(folder, rows, erows, keys)

    def summary_line(self, s):
        law = self.law
        return (f"{s['status']} in {s['run_time_s']:.0f} s: peak force {self.peak_f / 1e3:.1f} kN, penetration {1e3 * s['penetration_max']:.0f} mm, "
                f"slab {s['slab_force_max'] / 1e3:.1f} kN, energy residual {100 * self.resid:.2f}% of {self.e_impact:.0f} J, "
                f"contact hand-overs {s['energy_end'].get('flexHandover', 0.0):.3g} J lost (flexHandover; {law.deepOnsets} started deep, "
                f"{law.deepEndings} ended overlapping); results in {self.folder.path}")


def fill_only(params, cache_dir=None):
    """The main job's --fill-only: the filled module of params into cache_dir (default
    ~/.cache/yadeflex/modules), loaded if it is there already; nothing else is run or written.
    Returns the exit status: EXIT["done"] once the module is in the cache, EXIT["failed"] (the
    error printed) if it could not be filled or saved."""
    t0 = time.time()
    try:
        _, f, cached = filled_module(params, cache_dir=cache_dir, progress=fill_progress(t0))
    except Exception as e:  # a fill that does not settle, a cache that cannot be written
        traceback.print_exc()
        print(f"{PROG}: {type(e).__name__}: {e}", file=sys.stderr, flush=True)
        return EXIT["failed"]
    print(f"filled module {'already in' if cached else 'built and saved to'} {f} ({time.time() - t0:.0f} s)", flush=True)
    return EXIT["done"]


def run_impact(params, out, cache_dir=None, progress=True, **settings):
    """The main job: the filled module of params (ModuleParams; loaded from cache_dir, default
    ~/.cache/yadeflex/modules, or filled and saved there), its boulder and the impact, written into
    the folder `out` (yadeflex.files.ResultsFolder: the files an earlier run wrote there are removed
    first): params.json, timeseries.csv and energy.csv row by row, summary.json, impact.png,
    energy.png and, unless no_vtk, vtk/flex.pvd. settings: RunSettings' fields; progress: print
    the progress lines of the fill and of the impact. SIGINT and SIGTERM end the run with what it
    recorded (yadeflex.signals). Returns the summary (as in summary.json, with "status" and
    "exit_status", EXIT's); an output folder that cannot be written returns status "failed" and
    its message, with nothing written."""
    s = RunSettings(**settings)
    return R.run_into(out, RESULT_FILES, PROG, lambda folder, signals: ImpactRun(params, folder, signals, s, cache_dir, progress))
