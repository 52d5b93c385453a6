"""The damping-module impact: run_impact, the main job's run (scripts/damping_module.py), and its
bookkeeping; one use of the generic runner (yadeflex.runner).

- run_impact(params, out, ...): the filled module, the boulder and the impact into a results
  folder, row by row; returns the summary, with the exit status. fill_only: the filled module
  into the cache, nothing else (the main job's --fill-only). ImpactRun: one such run (the
  runner's ImpactRun with the module's hooks); RunSettings, EXIT: as yadeflex.runner's.
- BrokenElements: what broke, by kind.
- SlabMap: the load on the slab as a pressure map over time (yadeflex.slab_load), from the
  slab's contacts and the supports of the structure's pinned nodes.
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
from ..force_filter import low_pass
from .. import slab_load as SL
from . import slab_outputs as SO
from .impact_plots import write_plots
from ..constants import G
from ..module import filled_module, add_boulder, fill_top, scale_lining_nodes, UNBALANCED_TOL
from .ids import BROKEN_KINDS, ModuleIds
from . import fill_scatter

PROG = "damping_module"  # the main job: its name starts the lines it writes to stderr
RESULT_FILES = ("params.json", "timeseries.csv", "energy.csv", "summary.json", "impact.png", "energy.png") + SO.RESULT_FILES

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


class SlabMap:
    """The load on the slab as a pressure map, record by record (yadeflex.slab_load: its
    definitions): the vertical forces on the slab (wall) of its real contacts, at their contact
    points, and the supports of the pinned base nodes (m g - f_z, the force the node puts on the
    slab), at the nodes; the slab force column is their sum. The grid covers every module's
    footprint and a quarter diameter around it (the mesh's bottom pinned at the footprint's edge,
    grains pushed out under it), the first module's axis at a cell's centre; its cells are
    slab_load.cell_size(the largest grain) wide. Forces outside the grid are counted
    (outside_max in the summary)."""
    MARGIN = 0.25  # of the module diameter, around each footprint

    def __init__(self, p, ids):
        self.wall, self.base_nodes = ids["wall"], list(ids["base_nodes"])
        self.outlines = [((float(cx), float(cy)), 0.5 * p.diameter) for cx, cy in p.centers()]
        self.grid = SL.Grid.covering(p.centers(), 0.5 * p.diameter, SL.cell_size(p.preset()["grain_max"]), self.MARGIN * p.diameter)
        self.series = SL.PressureSeries(self.grid)
        self.z = float(O.bodies[self.wall].state.pos[2])
        self.error = None  # why the maps stopped (a non-finite force or position), if they did

    def contacts(self):
        """(x, y, f) lists of the wall's real contacts: contact point [m], downward force on the
        wall [N] (the force on body 1 of an interaction is -(normal + shear force))."""
        xs, ys, fs, w = [], [], [], self.wall
        for i in O.interactions.withBody(w):
            if not i.isReal:
                continue
            fz = (i.phys.normalForce + i.phys.shearForce)[2]
            c = getattr(i.geom, "contactPoint", None)
            if c is None:  # (a geometry without a contact point: the other body's centre)
                c = O.bodies[i.id2 if i.id1 == w else i.id1].state.pos
            xs.append(c[0])
            ys.append(c[1])
            fs.append(fz if i.id1 == w else -fz)
        return xs, ys, fs

    def record(self, t, supports):
        """The map of the record at t [s] from the wall's contacts and supports: (x, y, f) lists of
        the base nodes' positions [m] and support forces [N]. A non-finite value stops the maps
        (self.error says why; the run goes on)."""
        if self.error is not None:
            return
        x, y, f = self.contacts()
        try:
            self.series.add(t, x + supports[0], y + supports[1], f + supports[2])
        except ValueError as e:
            self.error = f"the slab's load is no longer mapped from t = {t:.6g} s: {e}"
            print(f"  ({self.error})", flush=True)

    def results(self, cutoff_hz):
        """summary.json's slab_* numbers and the definitions; self.res: all of slab_load's results."""
        s = self.series
        self.res = res = s.results(low_pass=lambda t, v: low_pass(t, v, cutoff_hz))
        g = self.grid
        out = dict(slab_pressure_cell=g.cell, slab_pressure_grid=dict(x0=g.x0, y0=g.y0, nx=g.nx, ny=g.ny),
                   slab_pressure_peak=None, slab_pressure_peak_at=None, slab_pressure_peak_time=None,
                   slab_pressure_peak_filtered=None, slab_pressure_peak_filtered_at=None,
                   slab_force_peak_time=None, slab_load_centre=None, slab_loaded_radius=None, slab_force_outside_grid_max=None)
        if len(s):
            out.update(slab_pressure_peak=res["peak"], slab_pressure_peak_at=list(res["peak_at"]), slab_pressure_peak_time=res["peak_time"],
                       slab_pressure_peak_filtered=res.get("filtered_peak"),
                       slab_pressure_peak_filtered_at=list(res["filtered_peak_at"]) if res.get("filtered_peak_at") else None,
                       slab_force_peak_time=res["at_peak_time"], slab_load_centre=list(res["centre"]) if res["centre"] else None,
                       slab_loaded_radius=res["loaded_radius"], slab_force_outside_grid_max=res["outside_max"])
        if self.error:
            out["slab_pressure_error"] = self.error
        elif res.get("filter_error"):
            out["slab_pressure_error"] = f"not filtered: {res['filter_error']}"
        out["slab_pressure_definitions"] = dict(SL.DEFINITIONS)
        return out

    def write(self, folder, vtk=None, slab=None):
        """slab_pressure.csv and .png into folder; vtk: dict(folder, t_origin, every, scene_origin)
        for vtk/slab_pressure.pvd (None: no VTK); slab: the slab force over time for the plot
        (slab_outputs.write_png). After results()."""
        res = getattr(self, "res", None)
        if not len(self.series) or res is None or res.get("peak_map") is None:
            return
        SO.write_csv(os.path.join(folder, SO.CSV_FILE), self.grid, res)
        if vtk is not None:
            try:
                SO.write_vtk(vtk["folder"], self.series, res, self.z, vtk["t_origin"], vtk["every"], res.get("filtered"), vtk["scene_origin"])
            except ImportError as e:  # VTK's Python bindings missing: the numbers matter more
                print(f"  (no VTK output of the slab's load: {e})", flush=True)
        SO.write_png(os.path.join(folder, SO.PNG_FILE), self.series, res, self.outlines, slab)


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
    FILTERED = dict(R.ImpactRun.FILTERED, slab_force="slab_force_max_filtered")

    def __init__(self, p, folder, signals, settings, cache_dir=None, progress=True):
        self.p, self.cache_dir = p, cache_dir
        self.t_fill = self.cached = self.cache_file = None
        super().__init__(folder, signals, settings, progress)
        SO.clear_vtk(folder.file(R.VTK_FOLDER))  # (an earlier run's maps; the runner clears its own frames)
        self.stage = "fill"
        write_json(folder.file("summary.json"), dict(status="running", stage=self.stage, pid=os.getpid()))

    def prepare(self):
        p = self.p
        print(f"damping module: {p.n_modules} x {p.diameter} m x {p.height} m{' with a boundary rope' if p.with_rope() else ''}, {p.fill} fill ({self._grains()}), {p.boulder_mass} kg {p.boulder_shape} at {p.impact_speed():.2f} m/s, {O.numThreads} thread(s)")
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
        self.slab_map = SlabMap(p, ids)
        self.e_impact = 0.5 * self.mass * p.impact_speed() ** 2

    def _grains(self):
        """The grain sizes in words, and whether they are the preset's."""
        from ..grains import FILLS
        g = self.p.preset()
        own = FILLS[self.p.fill]
        words = f"grains {1e3 * g['grain_min']:g}-{1e3 * g['grain_max']:g} mm"
        if (g["grain_min"], g["grain_max"]) != (own["grain_min"], own["grain_max"]):
            words += f", not the preset's {1e3 * own['grain_min']:g}-{1e3 * own['grain_max']:g} mm"
        return words

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
        # the supports of the pinned base nodes: the force each puts on the slab [N], at its position
        nodes = [b for b in (O.bodies[n] for n in self.ids["base_nodes"]) if b is not None]
        support = [b.state.mass * G - O.forces.f(b.id)[2] for b in nodes]
        slab = -fw + sum(support)
        self.slab_map.record(O.time - self.start, ([b.state.pos[0] for b in nodes], [b.state.pos[1] for b in nodes], support))
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
                    run_time_s=time.time() - self.t_wall, fill_time_s=self.t_fill, filled_from_cache=self.cached,
                    fill_scatter=fill_scatter.statement(self.p.resolved()))

    def scene_results(self):
        peak = self.peak
        return dict(slab_force_max=peak("slab_force"), bulge_max=peak("bulge_max"), ring_top_force_max=peak("ring_top_force"),
                    ring_bottom_force_max=peak("ring_bottom_force"), rope_force_max=peak("rope_force"), **self.slab_map.results(self.cutoff_hz))

    def mass_results(self):
        return dict(lining_mass=self.lining_own, lining_mass_added=self.lining_added)

    def broken_results(self):
        broken = self.broken.counts(self.el.rupturedIds)
        return dict(broken, broken_wires=broken["broken_wire_legs"])

    def plots(self, folder, rows, erows, keys):
        filtered = getattr(self, "filtered", None) or {}
        write_plots(folder, rows, erows, keys, filtered, self.cutoff_hz)
        vtk = None
        if not self.s.no_vtk:
            # on the clock of vtk/flex.pvd: from the first contact
            t_origin = self.free_fall["t"] if self.free_fall else 0.0
            vtk = dict(folder=self.folder.file(R.VTK_FOLDER), t_origin=t_origin, every=self.s.vtk_every, scene_origin=self.start)
        slab = ([r["t"] for r in rows], [r["slab_force"] for r in rows], filtered.get("slab_force"),
                f"{self.cutoff_hz:g} Hz low-pass")
        self.slab_map.write(folder, vtk, slab)

    def summary_line(self, s):
        law = self.law
        spread = (f" (peak pressure {s['slab_pressure_peak'] / 1e3:.0f} kPa, loaded radius {s['slab_loaded_radius']:.2f} m)"
                  if s.get("slab_pressure_peak") is not None and s.get("slab_loaded_radius") is not None else "")
        filt = lambda k: f" ({s[k] / 1e3:.1f} kN filtered)" if s.get(k) is not None else ""  # noqa: E731
        return (f"{s['status']} in {s['run_time_s']:.0f} s: peak force {self.peak_f / 1e3:.1f} kN{filt('peak_impact_force_filtered')}, "
                f"penetration {1e3 * s['penetration_max']:.0f} mm, "
                f"slab {s['slab_force_max'] / 1e3:.1f} kN{filt('slab_force_max_filtered')}{spread}, energy residual {100 * self.resid:.2f}% of {self.e_impact:.0f} J, "
                f"contact hand-overs {s['energy_end'].get('flexHandover', 0.0):.3g} J lost (flexHandover; {law.deepOnsets} started deep, "
                f"{law.deepEndings} ended overlapping); results in {self.folder.path}\n  {s['fill_scatter']['text']}")


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
    energy.png, the load on the slab (slab_pressure.csv, slab_pressure.png: SlabMap) and, unless
    no_vtk, vtk/flex.pvd and vtk/slab_pressure.pvd. settings: RunSettings' fields; progress: print
    the progress lines of the fill and of the impact. SIGINT and SIGTERM end the run with what it
    recorded (yadeflex.signals). Returns the summary (as in summary.json, with "status" and
    "exit_status", EXIT's); an output folder that cannot be written returns status "failed" and
    its message, with nothing written."""
    s = RunSettings(**settings)
    return R.run_into(out, RESULT_FILES, PROG, lambda folder, signals: ImpactRun(params, folder, signals, s, cache_dir, progress))
