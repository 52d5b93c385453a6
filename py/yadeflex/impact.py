"""The damping-module impact: run_impact, the main job's run (scripts/damping_module.py), and its
bookkeeping.

- run_impact(params, out, ...): the filled module, the boulder and the impact into a results
  folder, row by row; returns the summary, with the exit status. fill_only: the filled module
  into the cache, nothing else (the main job's --fill-only). RunSettings: how it is run and
  judged. ImpactRun: one such run; EXIT: its exit status by how it ended.
- part_name: which part of the module a body is; BrokenElements: what broke, by kind.
- ImpactTimes: when the run ends and when it is expected to end; Progress, fill_progress: the
  progress lines of the impact and of the fill; unstable_body: the first non-finite body.
"""
import bisect
import contextlib
import dataclasses
import math
import os
import re
import sys
import time
import traceback

from yade import O
from yade.minieigenHP import Vector3

from . import checks as C
from .files import CsvStream, ResultsFolder, overwrite_json, write_failure, write_json
from .impact_plots import write_plots
from .constants import G
from .module import filled_module, add_boulder, fill_top, scale_lining_nodes, UNBALANCED_TOL
from .module_ids import BROKEN_KINDS, ModuleIds
from .output import VtkRecorder
from .params import param, RUN
from .parts import scene_parts
from .scene import contact_law, step_until
from .errors import Unstable
from .signals import Interrupted, Signals

PROG = "damping_module"  # the main job: its name starts the lines it writes to stderr
EXIT = dict(done=0, failed=1, unstable=2, residual=3, SIGINT=130, SIGTERM=143)  # the job's exit status by how it ended
RESULT_FILES = ("params.json", "timeseries.csv", "energy.csv", "summary.json", "impact.png", "energy.png")
VTK_FOLDER, VTK_PREFIX = "vtk", "flex"

# unit of each column of timeseries.csv (its header reads NAME[UNIT])
TIMESERIES_UNITS = dict(t="s", boulder_z="m", boulder_vz="m/s", boulder_az="m/s2", impact_force="N", penetration="m", slab_force="N",
                        bulge_max="m", bulge_mean="m", ring_top_force="N", ring_bottom_force="N", rope_force="N", broken_wires="-",
                        broken_ring_segments="-", broken_rope_segments="-", broken_lining_facets="-", dt="s")
def part_name(bid, names):
    """'grain #12', 'wire leg #300', ...: which part of the module a body is (names: ModuleIds.names())."""
    if bid is None or bid < 0 or bid >= len(O.bodies):
        return "no body"
    if bid in names:
        return f"{names[bid]} #{bid}"
    b = O.bodies[bid]
    if b is not None and b.isClumpMember:
        return f"boulder (clump member #{bid})"
    return f"{type(b.shape).__name__ if b is not None else 'erased body'} #{bid}"


class BrokenElements:
    """Counts of ruptured elements by kind (FlexElementEngine.rupturedIds: every element it
    erased, of any kind): the BROKEN_KINDS keys (yadeflex.module_ids), broken_other_elements (an
    element of none of those kinds) and broken_elements_total, their sum."""

    def __init__(self, ids):
        self.kind = ModuleIds.of(ids).broken_kinds()

    def counts(self, ruptured_ids):
        c = dict.fromkeys(list(BROKEN_KINDS) + ["broken_other_elements"], 0)
        for i in ruptured_ids:
            c[self.kind.get(i, "broken_other_elements")] += 1
        c["broken_elements_total"] = len(ruptured_ids)
        return c


class ImpactTimes:
    """When the impact run stops (simulated time [s]) and when it is expected to stop.

    The run lasts `duration` [s] after the first contact if given; otherwise until the rebound
    (the boulder moving up again) plus REBOUND_MARGIN of the contact time (at least MIN_MARGIN),
    and at most MAX_AFTER_CONTACT after the first contact. Before the first contact, the same
    bounds count from the start. Feed it every record (observe); .end is the stop time known so
    far (a bound until the rebound), expected_end() the best estimate."""
    MAX_AFTER_CONTACT = 0.3
    REBOUND_MARGIN = 0.2
    MIN_MARGIN = 0.01
    WINDOW = 0.5  # deceleration over this latest fraction of the contact so far

    def __init__(self, start, duration=None):
        self.start, self.duration = start, duration
        self.t_contact = self.t_rebound = None
        self.end = start + (duration if duration else self.MAX_AFTER_CONTACT)
        self._t, self._vz = [], []  # the records since the first contact

    def observe(self, t, vz, touching):
        """A record at t: the boulder's vertical velocity vz [m/s] (< 0: down); touching: the
        module pushes on it (the first such record is the first contact)."""
        if self.t_contact is None and touching:
            self.t_contact = t
            self.end = t + (self.duration if self.duration else self.MAX_AFTER_CONTACT)
        if self.t_contact is None:
            return
        self._t.append(t)
        self._vz.append(vz)
        if self.t_rebound is None and vz > 0:
            self.t_rebound = t
            if not self.duration:
                self.end = min(self.end, self._after_rebound(t))

    def _after_rebound(self, t_rebound):
        return t_rebound + max(self.REBOUND_MARGIN * (t_rebound - self.t_contact), self.MIN_MARGIN)

    def expected_end(self):
        """The expected stop time after the last record: .end once it is fixed (a given duration,
        or after the rebound); during the contact, the rebound extrapolated from the boulder's
        deceleration over the latest WINDOW of the contact so far (its speed falling linearly to
        zero; exact for a constant force, an overestimate early in a stiffening contact) plus the
        margin, within .end; before the first contact or while the boulder is not slowing down,
        .end (the most it can last)."""
        if self.duration or self.t_rebound is not None or len(self._t) < 2:
            return self.end
        t, vz = self._t[-1], self._vz[-1]
        k = bisect.bisect_left(self._t, t - self.WINDOW * (t - self.t_contact))
        t0, v0 = self._t[k], self._vz[k]
        if t0 >= t or vz >= 0 or vz <= v0:
            return self.end
        return min(self.end, self._after_rebound(t - vz * (t - t0) / (vz - v0)))


class Progress:
    """The impact's progress line: simulated time done of the expected total, steps, wall time
    elapsed and left. The time left is the wall time per simulated second so far times the
    simulated time left to the expected end (ImpactTimes.expected_end). Prints at most every
    `every` wall seconds, and at the end. clock: wall-clock function (tests pass a fake one)."""

    def __init__(self, start, every=5.0, clock=time.time, out=None):
        self.start, self.every, self.clock = start, every, clock
        self.out = out or (lambda line: print(line, flush=True))
        self.t0 = clock()
        self.last = None

    def eta(self, t, expected_end):
        """Wall time left [s] at simulated time t."""
        done = max(1e-12, t - self.start)
        return (self.clock() - self.t0) / done * max(0.0, expected_end - t)

    def __call__(self, t, steps, expected_end, extra=""):
        """Print the line if due; returns it (None if not due)."""
        now = self.clock()
        if self.last is not None and now - self.last < self.every and t < expected_end:
            return None
        self.last = now
        line = (f"  t = {1e3 * (t - self.start):7.2f} ms of {1e3 * (expected_end - self.start):.0f} ms, {steps} steps, "
                f"{now - self.t0:6.0f} s elapsed, ~{self.eta(t, expected_end):.0f} s left {extra}")
        self.out(line)
        return line


def unstable_body():
    """(id, what) of the first body with a non-finite position/velocity, else None."""
    for b in O.bodies:
        if b is None:
            continue
        for what, v in (("position", b.state.pos), ("velocity", b.state.vel)):
            if not all(math.isfinite(x) for x in v):
                return b.id, what
    return None


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


_RUN = ImpactTimes.MAX_AFTER_CONTACT


@dataclasses.dataclass
class RunSettings:
    """How the impact is run and judged: the main job's run options, each declared once
    (yadeflex.params)."""
    duration: float = param(None, unit="s", stage=RUN, row="duration",
                            default_text=f"until the rebound + {100 * ImpactTimes.REBOUND_MARGIN:g}%, at most {_RUN:g} s",
                            meaning="simulated time after the first contact",
                            allowed=C.Range(0.0, 2.0, "s", lo_open=True))
    record_every: float = param(2e-4, unit="s", stage=RUN, row="duration", meaning="time-series interval (timeseries.csv, energy.csv)",
                                allowed=C.Range(1e-6, 1e-3, "s", note="at most duration/10: the impact force pulse lasts 10-50 ms "
                                                "and its peak needs ten records or more"))
    vtk_every: float = param(1e-3, unit="s", stage=RUN, row="duration", meaning="VTK frame interval, from the first contact",
                             allowed=C.Range(1e-3, 2.0, "s", note=f"at most the run's length (--duration, else {_RUN:g} s): a frame per millisecond at most"))
    no_vtk: bool = param(False, "flag", stage=RUN, row="duration", meaning="no VTK time series")
    min_dt_fraction: float = param(0.01, unit="-", stage=RUN, meaning="stop when the time step falls below this fraction of its value at impact; 0: never",
                                   allowed=C.Range(0.0, 1.0, hi_open=True))
    max_residual: float = param(0.02, unit="-", stage=RUN, row="min_dt_fraction",
                                meaning="largest accepted energy-balance residual, fraction of the impact energy (else the exit status says so)",
                                allowed=C.Range(0.0, 1.0, lo_open=True))


class ImpactRun:
    """One run into a results folder (yadeflex.files.ResultsFolder): the filled module, the
    boulder, the impact. Time series go to disk row by row (CsvStream); summary.json says
    "running" from the start and is rewritten by finish() however the run ends, with its status:
    done, unstable (a NaN, FlexGuard, a collapsed time step), interrupted (SIGINT, SIGTERM) or
    failed (an error, named)."""

    def __init__(self, p, folder, signals, settings, cache_dir=None, progress=True):
        self.p, self.folder, self.signals, self.s = p, folder, signals, settings
        self.cache_dir, self.show_progress = cache_dir, progress
        self.t_wall = time.time()
        self.status, self.signal, self.message = "running", None, None
        self.stage = "fill"
        self.rows = CsvStream(folder.file("timeseries.csv"), units=TIMESERIES_UNITS)
        self.erows = CsvStream(folder.file("energy.csv"), first=("t",), last=("residual",), missing=0.0,
                               units=lambda k: "s" if k == "t" else "J")
        self.t_fill = self.cached = self.cache_file = None
        self.impact_started = False
        self.wall = dict(free_fall=0.0, steps=0.0, records=0.0, vtk_frames=0.0)  # wall time of the impact's parts [s]
        write_json(folder.file("summary.json"), dict(status="running", stage=self.stage, pid=os.getpid()))

    # --- the run
    def run(self):
        p = self.p
        print(f"damping module: {p.n_modules} x {p.diameter} m x {p.height} m{' with a boundary rope' if p.with_rope() else ''}, {p.fill} fill, {p.boulder_mass} kg {p.boulder_shape} at {p.impact_speed():.2f} m/s, {O.numThreads} thread(s)")
        ids, self.cache_file, self.cached = filled_module(p, cache_dir=self.cache_dir, progress=fill_progress(self.t_wall) if self.show_progress else None)
        self.t_fill = time.time() - self.t_wall
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
        self.el = next(e for e in O.engines if e.label == "flexElements")
        # contacts found late (a missed or suppressed contact starts deep: its spring energy comes from nothing)
        self.law = contact_law()
        self.v_prev, self.t_prev = Vector3(self.boulder.state.vel), O.time
        self.e_impact = 0.5 * self.mass * p.impact_speed() ** 2
        self.iter0 = O.iter
        O.step()
        self.total0 = O.energy.total()
        self.start = O.time
        self.times = ImpactTimes(self.start, self.s.duration)
        self.progress = Progress(self.start, out=None if self.show_progress else lambda line: None)
        self.peak_f, self.max_overlap_ratio, self.warned, self.resid, self.free_fall = 0.0, 0.0, False, 0.0, None
        self.impact_started = True
        with self._timed("free_fall"):
            self.free_fall = self._free_fall()
        ts = next(e for e in O.engines if e.label == "flexDt")
        ts.minDtFraction, ts.dtReference = self.s.min_dt_fraction, 0.0  # (the next estimate is the reference)
        self._impact()
        self.signals.hold()
        if self.status == "running":
            self.status = "done"

    def _free_fall(self):
        """Step up to the first force other than gravity on the boulder, checked step by step:
        the speed just before it against sqrt(2 g h), h the whole fall from rest (drop height).
        Switches the boulder's damping on there. None if it never touched."""
        st = self.boulder.state
        z_start, v_start = st.pos[2], -st.vel[2]
        h0 = v_start ** 2 / (2 * G)  # fall already done at the start (the drop height minus the gap)
        while O.time < self.times.end:
            v_before, z_before = -st.vel[2], st.pos[2]
            O.step()
            dv = -st.vel[2] - v_before
            if abs(dv - G * O.dt) > 1e-6 * G * O.dt:  # a force other than gravity acted this step
                st.isDamped = True
                h = h0 + (z_start - z_before)
                return dict(v_measured=v_before, v_expected=math.sqrt(2 * G * h), fall_height=h, t=O.time - self.start)
        return None

    def _impact(self):
        # the series' clock starts at the boulder's first contact (the CSVs' at the start of the run);
        # on several threads, as many processes write the frames (at most one per CPU this process
        # may run on), a batch at a time; the parts: the module's, taken once
        origin = self.start + (self.free_fall["t"] if self.free_fall else 0.0)
        workers = max(1, min(O.numThreads, len(os.sched_getaffinity(0))))
        vtk = None if self.s.no_vtk else VtkRecorder(self.folder.file(VTK_FOLDER), prefix=VTK_PREFIX, time_origin=origin, parts=scene_parts(),
                                                     workers=workers)
        try:
            self._impact_steps(vtk)
        except BaseException:  # (the frames taken are written; an error doing so does not hide this one)
            try:
                self._flush_frames(vtk)
            except Exception as e:
                print(f"{PROG}: the last VTK frames could not be written: {e}", file=sys.stderr, flush=True)
            raise
        self._flush_frames(vtk)

    def _flush_frames(self, vtk):
        if vtk is not None and vtk.pending:
            with self._timed("vtk_frames"), self.signals.deferred():
                vtk.flush()

    def _impact_steps(self, vtk):
        a = self.s
        # records on the grid from the start (every step records until it catches up); frames from the first contact on
        next_rec, next_vtk = self.start, O.time
        ts = next(e for e in O.engines if e.label == "flexDt")
        guard = next((e for e in O.engines if type(e).__name__ == "FlexGuard"), None)
        while O.time < self.times.end:
            # the steps up to the next record, frame, end or multiple of 500 steps (where the step is
            # looked at) in one call: the same steps as O.step() one at a time, the scene checked
            # once for what this loop might have changed (it changes nothing)
            until = min(next_rec, self.times.end, next_vtk if vtk is not None else math.inf)
            steps = 500 - O.iter % 500
            if O.time >= until:  # (a record or frame due again at once: one step, as one O.step())
                until, steps = math.inf, 1
            try:
                with self._timed("steps"):
                    step_until(until, steps)
            except Unstable as e:  # the scene check, the integrator, FlexGuard or the time stepper; the message names the body
                at = f"unstable state at t = {1e3 * (O.time - self.start):.2f} ms"
                if guard is not None and guard.message and guard.detectedIter == O.iter:
                    self._stop("unstable", f"{at}, stopped by FlexGuard: {guard.message}; "
                               f"bodies: {', '.join(part_name(b, self.names) for b in guard.bodies[:5])}")
                elif "time step collapsed" in str(e):
                    self._stop("unstable", f"{at}: {e}, {part_name(ts.stiffestBody, self.names)} (a crushed lining facet or a light node under "
                               "a stiff contact); stopping (--min-dt-fraction)")
                else:
                    self._stop("unstable", f"{at}: {e}; stopping")
                return
            if O.time >= next_rec:
                next_rec += a.record_every
                with self._timed("records"), self.signals.deferred():
                    if not self._record():
                        return
            if vtk is not None and O.time >= next_vtk:
                next_vtk += a.vtk_every
                try:
                    with self._timed("vtk_frames"), self.signals.deferred():
                        vtk()
                except ImportError as e:  # VTK's Python bindings missing: the numbers matter more
                    print(f"  (no VTK output: {e})", flush=True)
                    vtk = None

    @contextlib.contextmanager
    def _timed(self, part):
        """Adds the block's wall time to self.wall[part], however it ends."""
        t0 = time.time()
        try:
            yield
        finally:
            self.wall[part] += time.time() - t0

    def _stop(self, status, message):
        self.status, self.message = status, message
        print(f"{PROG}: {message}", file=sys.stderr, flush=True)

    def _record(self):
        """One row of the time series and of the energies; False if the state is not finite."""
        st, mass = self.boulder.state, self.mass
        if not all(math.isfinite(x) for x in st.pos) or not math.isfinite(O.energy.total()):
            bad = unstable_body()
            self._stop("unstable", f"unstable state at t = {O.time:.6f} s: body #{bad[0] if bad else '?'} has a non-finite "
                                   f"{bad[1] if bad else 'energy'}; stopping")
            return False
        dt_rec = O.time - self.t_prev
        acc = (st.vel - self.v_prev) / dt_rec if dt_rec > 0 else Vector3(0, 0, 0)
        self.v_prev, self.t_prev = Vector3(st.vel), O.time
        f_contact = mass * (acc[2] + G)  # vertical force of the module on the boulder [N]
        fw = O.forces.f(self.ids["wall"])[2]
        slab = -fw + sum(O.bodies[n].state.mass * G - O.forces.f(n)[2] for n in self.ids["base_nodes"] if O.bodies[n] is not None)
        radial = [math.hypot(O.bodies[n].state.pos[0], O.bodies[n].state.pos[1]) - self.R0 for n in self.mid if O.bodies[n] is not None]
        ring_f = {k: max([O.bodies[c].shape.axialForce for c in v if O.bodies[c] is not None] or [0.0]) for k, v in self.ring_ids.items()}
        bottom = st.pos[2] - 0.5 * self.size
        self.times.observe(O.time, st.vel[2], touching=f_contact > 0.01 * mass * G and bottom < self.top0 + 0.01)
        self.peak_f = max(self.peak_f, f_contact)
        broken = self.broken.counts(self.el.rupturedIds)
        self.rows.append(dict(t=O.time - self.start, boulder_z=st.pos[2], boulder_vz=st.vel[2], boulder_az=acc[2], impact_force=f_contact,
                              penetration=max(0.0, self.top0 - bottom), slab_force=slab, bulge_max=max(radial or [0.0]),
                              bulge_mean=(sum(radial) / len(radial) if radial else 0.0), ring_top_force=ring_f["top"],
                              ring_bottom_force=ring_f["bottom"], rope_force=ring_f["rope"], broken_wires=broken["broken_wire_legs"],
                              broken_ring_segments=broken["broken_ring_segments"], broken_rope_segments=broken["broken_rope_segments"],
                              broken_lining_facets=broken["broken_lining_facets"], dt=O.dt))
        # penalty contacts are valid while overlaps are small against the contact reach R1 + R2:
        # the law's largest overlap ratio at any step since the last record
        worst, worst_ids = self.law.maxOverlapRatio, self.law.maxOverlapIds
        self.law.maxOverlapRatio = 0.0
        self.max_overlap_ratio = max(self.max_overlap_ratio, worst)
        if worst > 0.5 and not self.warned:
            self.warned = True
            print(f"  WARNING t = {1e3 * (O.time - self.start):.2f} ms: a contact overlaps {100 * worst:.0f}% of its reach (sum of radii), "
                  f"{part_name(worst_ids[0], self.names)} - {part_name(worst_ids[1], self.names)}; contact forces are no longer reliable "
                  + ("(grain contacts yield at their crushing load: --grain-crushing-is50; or a gentler impact)" if self.p.grain_crushing_is50
                     else "(stiffer contacts: --fill-young, --steel-contact-young, or a gentler impact)"), flush=True)
        e = {k: O.energy[k] for k in O.energy.keys()}
        e["t"] = O.time - self.start
        e["residual"] = O.energy.total() - self.total0
        self.erows.append(e)
        self.resid = max(self.resid, abs(e["residual"]) / self.e_impact)
        self.progress(O.time, O.iter, self.times.expected_end(), f"| boulder v = {st.vel[2]:+.2f} m/s, force {f_contact / 1e3:.1f} kN")
        return True

    # --- however it ended
    def stopped(self, status, signal_name=None, message=None):
        """The run was cut short: status 'interrupted' (by signal_name) or 'failed' (message)."""
        self.status, self.signal = status, signal_name
        self.message = message or f"interrupted by {signal_name} during the {self.stage}"
        print(f"{PROG}: {self.message}; writing what was recorded", file=sys.stderr, flush=True)

    def exit_status(self):
        if self.status == "interrupted":
            return EXIT.get(self.signal, EXIT["SIGINT"])
        if self.status == "done" and self.rows.rows and self.resid > self.s.max_residual:
            return EXIT["residual"]
        return EXIT[self.status]

    def finish(self):
        """Close the time series and write summary.json; returns the summary. A file that cannot
        be written (a full disk) makes the run failed, with one line naming it."""
        try:
            self.rows.close()
            self.erows.close()
        except OSError as e:
            if self.status != "failed":
                self.stopped("failed", message=write_failure(e.filename or "the time series", e))
        s = dict(status=self.status, stage=self.stage, exit_status=self.exit_status(), message=self.message)
        if s["exit_status"] == EXIT["residual"]:
            s["message"] = f"energy balance residual {100 * self.resid:.2f}% exceeds {100 * self.s.max_residual:.1f}%"
        s.update(self._results())
        self._write_summary(s)
        return s

    def _write_summary(self, s):
        """summary.json, whole; if the disk is full, the run failed: its status and message in
        place of the old summary (which still holds its block), or else only the line on stderr."""
        path = self.folder.file("summary.json")
        try:
            write_json(path, s)
            return
        except OSError as e:
            if s["status"] != "failed":
                s.update(status="failed", exit_status=EXIT["failed"], message=write_failure(path, e))
                print(f"{PROG}: {s['message']}", file=sys.stderr, flush=True)
        try:
            overwrite_json(path, {k: s[k] for k in ("status", "stage", "exit_status", "message")})
        except OSError:
            pass

    def _results(self):
        """The summary's numbers, from what was recorded (None where nothing was)."""
        wall_t = time.time() - self.t_wall
        out = dict(n_modules=self.p.n_modules, impact_speed_expected=self.p.impact_speed(), threads=O.numThreads, run_time_s=wall_t,
                   fill_time_s=self.t_fill, filled_from_cache=self.cached)
        if not self.impact_started:
            return out
        rows, erows, times = self.rows.rows, self.erows.rows, self.times
        peak = (lambda k: max(r[k] for r in rows)) if rows else (lambda k: None)
        last = erows[-1] if erows else {}
        keys = [k for k in (self.erows.columns or []) if k not in ("t", "residual")]
        tot_ns = sum(e.execTime for e in O.engines) or 1
        law = self.law
        out.update(
            free_fall_check=self.free_fall, peak_impact_force=self.peak_f, peak_deceleration=self.peak_f / self.mass,
            penetration_max=peak("penetration"),
            impact_duration=((times.t_rebound or O.time) - times.t_contact) if times.t_contact is not None else None,
            rebound=times.t_rebound is not None,
            slab_force_max=peak("slab_force"), bulge_max=peak("bulge_max"), ring_top_force_max=peak("ring_top_force"),
            ring_bottom_force_max=peak("ring_bottom_force"), rope_force_max=peak("rope_force"),
            impact_energy=self.e_impact, max_overlap_ratio=self.max_overlap_ratio, lining_mass=self.lining_own, lining_mass_added=self.lining_added,
            deep_contact_onsets=law.deepOnsets, deep_onset_energy=law.deepOnsetEnergy,
            deep_contact_endings=law.deepEndings, deep_ending_energy=law.deepEndingEnergy,
            energy_end={k: last.get(k, 0.0) for k in keys}, energy_residual_max_fraction=self.resid,
            numerical_damping_share=(last.get("nonviscDamp", 0.0) / self.e_impact), impact_steps=O.iter - self.iter0, dt_end=O.dt,
            time_per_step_us=1e6 * (wall_t - self.t_fill) / max(1, O.iter - self.iter0),
            impact_time_s=dict(total=wall_t - self.t_fill, **self.wall),
            engine_share={e.label or type(e).__name__: round(e.execTime / tot_ns, 4) for e in O.engines})
        broken = self.broken.counts(self.el.rupturedIds)
        out.update(broken, broken_wires=broken["broken_wire_legs"])
        return out

    def report(self, s):
        """The last line, and the plots."""
        if self.rows.rows:
            try:
                write_plots(self.folder.path, self.rows.rows, self.erows.rows, [k for k in self.erows.columns or [] if k not in ("t", "residual")])
            except OSError as e:  # a full disk: the run failed (summary.json and the exit status say so)
                if s["status"] != "failed":
                    s.update(status="failed", exit_status=EXIT["failed"], message=write_failure(e.filename or "the plots", e))
                    print(f"{PROG}: {s['message']}", file=sys.stderr, flush=True)
                    self._write_summary(s)
                return
            except Exception as e:  # plots are a convenience: never lose the numbers over them
                print(f"  (plots failed: {e})")
        if s["status"] not in ("done", "unstable") or not self.rows.rows:
            return
        law = self.law
        print(f"{s['status']} in {s['run_time_s']:.0f} s: peak force {self.peak_f / 1e3:.1f} kN, penetration {1e3 * s['penetration_max']:.0f} mm, "
              f"slab {s['slab_force_max'] / 1e3:.1f} kN, energy residual {100 * self.resid:.2f}% of {self.e_impact:.0f} J, "
              f"contact hand-overs {s['energy_end'].get('flexHandover', 0.0):.3g} J lost (flexHandover; {law.deepOnsets} started deep, "
              f"{law.deepEndings} ended overlapping); results in {self.folder.path}")
        if s["exit_status"] == EXIT["residual"]:
            print(f"{PROG}: {s['message']}", file=sys.stderr)


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


def _write_failure_of(err):
    """The line for an OSError while writing the results: its file and reason; for a frame a child
    process could not write (its message relayed: '... VTK could not write PATH: REASON ...'),
    that file and reason."""
    if err.filename:
        return write_failure(err.filename, err)
    text = str(err)
    m = re.search(r"VTK could not (?:write|build) (\S+?)(?:: ([^:;'\]]+))?(?=[:;'\]]|$)", text)
    if m is None:
        return f"cannot write the results: {text}"
    return f"cannot write {m.group(1)}: {m.group(2)}" if m.group(2) else write_failure(m.group(1), err)


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
    # the folder is checked, taken and cleared of an earlier run's files before anything costly runs
    try:
        folder = ResultsFolder(out, RESULT_FILES, {VTK_FOLDER: VtkRecorder.files_pattern(VTK_PREFIX)},
                               waiting=lambda: print(f"{PROG}: waiting for the other run writing into {os.path.abspath(out)}", flush=True))
    except ValueError as e:
        print(f"{PROG}: {e}", file=sys.stderr)
        return dict(status="failed", exit_status=EXIT["failed"], message=str(e))
    signals = Signals()
    try:
        run = ImpactRun(params, folder, signals, s, cache_dir, progress)
        try:
            run.run()
        except (Interrupted, KeyboardInterrupt) as e:
            run.stopped("interrupted", e.args[0] if isinstance(e, Interrupted) else "SIGINT")
        except OSError as e:  # an output file that could not be written (a full disk): one line naming it
            run.stopped("failed", message=_write_failure_of(e))
        except Exception as e:
            traceback.print_exc()
            run.stopped("failed", message=f"{type(e).__name__}: {e}")
        signals.hold()  # the run is over: a signal now must not cut the summary short
        summary = run.finish()
        run.report(summary)  # (the plots too: a signal while they are drawn is only noted, so that summary.json and the exit status agree)
    finally:
        signals.restore()
        folder.close()
    return summary
