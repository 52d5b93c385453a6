"""The impact runner: a boulder onto whatever the scene holds, recorded into a results folder.

- boulder_impact(out, boulder, ...) (yadeflex.scene_impact): the generic run on the scene in O (yadeflex.module.impact.run_impact, the
  damping module's main job, is one use of the same machinery).
- ImpactRun: one run, step by step; the scene-specific parts are its hooks (prepare, the
  scene's columns, the summary's numbers, the plots). RunSettings: how a run is run and judged.
- ImpactTimes: when a run ends and when it is expected to end; Progress: its progress line;
  unstable_body: the first non-finite body; run_into: a run into its results folder, with
  its signals and failures handled.
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
from .force_filter import CUTOFF_HZ, describe, low_pass
from .files import CsvStream, ResultsFolder, overwrite_json, write_failure, write_json
from .output import VtkRecorder
from .params import declared, param, RUN
from .scene import contact_law, step_until
from .errors import Unstable
from .signals import Interrupted, Signals

EXIT = dict(done=0, failed=1, unstable=2, residual=3, SIGINT=130, SIGTERM=143)  # a run's exit status by how it ended
VTK_FOLDER, VTK_PREFIX = "vtk", "flex"


class ImpactTimes:
    """When the impact run stops (simulated time [s]) and when it is expected to stop.

    The run lasts `duration` [s] after the first contact if given; otherwise until the rebound
    (the boulder moving back against its direction of travel) plus REBOUND_MARGIN of the contact
    time (at least MIN_MARGIN), and at most MAX_AFTER_CONTACT after the first contact. Before the
    first contact, the same bounds count from the start. release [s], if given: the run also
    ends once the structure has not pushed on the boulder for that long after the first contact
    (it passed through, or rolled or bounced away). Feed it every record (observe); .end is the
    stop time known so far (a bound until the rebound), expected_end() the best estimate."""
    MAX_AFTER_CONTACT = 0.3
    REBOUND_MARGIN = 0.2
    MIN_MARGIN = 0.01
    WINDOW = 0.5  # deceleration over this latest fraction of the contact so far

    def __init__(self, start, duration=None, release=None):
        self.start, self.duration, self.release = start, duration, release
        self.t_contact = self.t_rebound = self.t_released = None
        self._t_touch = None
        self.end = start + (duration if duration else self.MAX_AFTER_CONTACT)
        self._t, self._vz = [], []  # the records since the first contact

    def observe(self, t, vz, touching):
        """A record at t: the boulder's velocity vz [m/s] against its direction of travel (< 0:
        still going; for a drop, the vertical velocity); touching: the structure pushes on it
        (the first such record is the first contact)."""
        if self.t_contact is None and touching:
            self.t_contact = t
            self.end = t + (self.duration if self.duration else self.MAX_AFTER_CONTACT)
        if self.t_contact is None:
            return
        if touching:
            self._t_touch = t
        elif self.release and self.t_released is None and t - self._t_touch >= self.release:
            self.t_released = t
            self.end = min(self.end, t)
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


_RUN = ImpactTimes.MAX_AFTER_CONTACT


@dataclasses.dataclass
class RunSettings:
    """How the impact is run and judged: the run options, each declared once (yadeflex.params)."""
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

    def __post_init__(self):
        # each number against its declared range (the ones the command line checks)
        for name, (_, p) in declared(RunSettings).items():
            if p.kind == "number" and getattr(self, name) is not None:
                setattr(self, name, C.number(name, getattr(self, name), p.allowed))


def engine(label):
    """The engine of O.engines labelled `label` (None if there is none)."""
    return next((e for e in O.engines if e.label == label), None)


class ImpactRun:
    """One run into a results folder (yadeflex.files.ResultsFolder): the scene prepared (prepare,
    a hook), the boulder's approach, the impact. Time series go to disk row by row (CsvStream);
    summary.json says "running" from the start and is rewritten by finish() however the run
    ends, with its status: done, unstable (a NaN, FlexGuard, a collapsed time step), interrupted
    (SIGINT, SIGTERM) or failed (an error, named).

    The hooks a scene fills in: prepare() (sets boulder, mass, e_impact, names, broken), the
    unit of each time-series column (UNITS), scene_row() (its columns between the boulder's and
    dt), scene_results() (its numbers in the summary), plots(), summary_line()."""
    PROG = "impact"  # the name that starts the lines written to stderr
    RELEASE = None  # [s] ImpactTimes' release: end once the boulder has been free this long after the first contact
    # time-series columns whose peak the summary also gives low-pass filtered (yadeflex.force_filter):
    # column -> summary key of the filtered peak
    FILTERED = dict(impact_force="peak_impact_force_filtered")
    cutoff_hz = CUTOFF_HZ  # [Hz] that filter's cut-off
    UNITS = dict(t="s", boulder_z="m", boulder_vz="m/s", boulder_az="m/s2", impact_force="N", penetration="m")
    ENERGY_FILE_UNITS = staticmethod(lambda k: "s" if k == "t" else "J")

    def __init__(self, folder, signals, settings, progress=True):
        self.folder, self.signals, self.s = folder, signals, settings
        self.show_progress = progress
        self.t_wall = time.time()
        self.status, self.signal, self.message = "running", None, None
        self.stage = "prepare"
        self.rows = CsvStream(folder.file("timeseries.csv"), units=self.units())
        self.erows = CsvStream(folder.file("energy.csv"), first=("t",), last=("residual",), missing=0.0, units=self.ENERGY_FILE_UNITS)
        self.t_prepare = None
        self.impact_started = False
        self.wall = dict(free_fall=0.0, steps=0.0, records=0.0, vtk_frames=0.0)  # wall time of the impact's parts [s]
        write_json(folder.file("summary.json"), dict(status="running", stage=self.stage, pid=os.getpid()))

    def units(self):
        """Unit of each time-series column; the header reads NAME[UNIT]."""
        return dict(self.UNITS)

    # --- the hooks
    def prepare(self):
        """Builds or loads the scene, adds the boulder and the engines; sets self.boulder (its
        body), self.mass [kg], self.e_impact [J] (the impact energy the residual is measured
        against), self.names (body id -> part name), self.broken (a BrokenElements-like counter)."""
        raise NotImplementedError

    def along(self, v):
        """The component of velocity v against the boulder's direction of travel (< 0 while it goes on)."""
        return -v.dot(self.direction)

    def contact_force(self, acc):
        """The force of the structure on the boulder against its direction of travel [N], from its acceleration."""
        return -(self.mass * (acc - self.gravity)).dot(self.direction)

    def touching(self, f_contact):
        """Whether the structure pushes on the boulder (the first such record is the first contact)."""
        return f_contact > 0.01 * self.mass * self.gravity.norm()

    def penetration(self):
        """The boulder's travel along its direction since the first contact [m]."""
        if self.contact_pos is None:
            return 0.0
        return max(0.0, (self.boulder.state.pos - self.contact_pos).dot(self.direction))

    def scene_row(self):
        """The scene's columns of a record (between the boulder's and dt)."""
        return {}

    def scene_results(self):
        """The scene's numbers in the summary (after the impact started)."""
        return {}

    def plots(self, folder, rows, erows, keys):
        """The run's plots from its rows."""

    def summary_line(self, s):
        """The last line printed."""
        return (f"{s['status']} in {s['run_time_s']:.0f} s: peak force {self.peak_f / 1e3:.1f} kN, penetration {1e3 * s['penetration_max']:.0f} mm, "
                f"energy residual {100 * self.resid:.2f}% of {self.e_impact:.0f} J; results in {self.folder.path}")

    def part_name(self, bid):
        """'mesh #12', 'boulder (clump member #40)', ...: which part a body is."""
        if bid is None or bid < 0 or bid >= len(O.bodies):
            return "no body"
        if bid in self.names:
            return f"{self.names[bid]} #{bid}"
        b = O.bodies[bid]
        if b is not None and b.isClumpMember:
            return f"boulder (clump member #{bid})"
        return f"{type(b.shape).__name__ if b is not None else 'erased body'} #{bid}"

    def vtk_parts(self):
        """body id -> part id of the VTK series (yadeflex.parts)."""
        from .parts import scene_parts
        return scene_parts()

    # --- the run
    def run(self):
        self.prepare()
        self.stage = "impact"
        write_json(self.folder.file("summary.json"), dict(status="running", stage=self.stage, pid=os.getpid()))
        if self.t_prepare is None:
            self.t_prepare = time.time() - self.t_wall
        self.el = engine("flexElements")
        # contacts found late (a missed or suppressed contact starts deep: its spring energy comes from nothing)
        self.law = contact_law()
        self.v_prev, self.t_prev = Vector3(self.boulder.state.vel), O.time
        self.contact_pos = None
        self.iter0 = O.iter
        O.step()
        self.total0 = O.energy.total()
        self.start = O.time
        self.times = ImpactTimes(self.start, self.s.duration, self.RELEASE)
        self.progress = Progress(self.start, out=None if self.show_progress else lambda line: None)
        self.peak_f, self.max_overlap_ratio, self.warned, self.resid, self.free_fall = 0.0, 0.0, False, 0.0, None
        self.impact_started = True
        with self._timed("free_fall"):
            self.free_fall = self._free_fall()
        ts = engine("flexDt")
        ts.minDtFraction, ts.dtReference = self.s.min_dt_fraction, 0.0  # (the next estimate is the reference)
        self._impact()
        self.signals.hold()
        if self.status == "running":
            self.status = "done"

    def _free_fall(self):
        """Step up to the first force other than gravity on the boulder, checked step by step:
        its speed just before it against sqrt(2 g h), h the whole fall from rest (the height its
        starting speed is worth plus its fall along gravity since). Switches the boulder's damping
        on there. None if it never touched."""
        st = self.boulder.state
        g = self.gravity.norm()
        down = self.gravity / g if g > 0 else self.direction
        p_start, v_start = Vector3(st.pos), st.vel.norm()
        h0 = v_start ** 2 / (2 * g) if g > 0 else 0.0
        while O.time < self.times.end:
            v_before, p_before, vel_before = st.vel.norm(), Vector3(st.pos), Vector3(st.vel)
            O.step()
            dv = (st.vel - vel_before) - self.gravity * O.dt
            if dv.norm() > 1e-6 * max(g, 1.0) * O.dt:  # a force other than gravity acted this step
                st.isDamped = True
                h = h0 + (p_before - p_start).dot(down)
                return dict(v_measured=v_before, v_expected=math.sqrt(max(0.0, 2 * g * h)), fall_height=h, t=O.time - self.start)
        return None

    def _impact(self):
        # the series' clock starts at the boulder's first contact (the CSVs' at the start of the run);
        # on several threads, as many processes write the frames (at most one per CPU this process
        # may run on), a batch at a time; the parts: the scene's, taken once
        origin = self.start + (self.free_fall["t"] if self.free_fall else 0.0)
        workers = max(1, min(O.numThreads, len(os.sched_getaffinity(0))))
        vtk = None if self.s.no_vtk else VtkRecorder(self.folder.file(VTK_FOLDER), prefix=VTK_PREFIX, time_origin=origin, parts=self.vtk_parts(),
                                                     workers=workers)
        try:
            self._impact_steps(vtk)
        except BaseException:  # (the frames taken are written; an error doing so does not hide this one)
            try:
                self._flush_frames(vtk)
            except Exception as e:
                print(f"{self.PROG}: the last VTK frames could not be written: {e}", file=sys.stderr, flush=True)
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
        ts = engine("flexDt")
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
                               f"bodies: {', '.join(self.part_name(b) for b in guard.bodies[:5])}")
                elif "time step collapsed" in str(e):
                    self._stop("unstable", f"{at}: {e}, {self.part_name(ts.stiffestBody)} (a crushed membrane facet or a light node under "
                               "a stiff contact); stopping (min_dt_fraction)")
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
        print(f"{self.PROG}: {message}", file=sys.stderr, flush=True)

    def _record(self):
        """One row of the time series and of the energies; False if the state is not finite."""
        st = self.boulder.state
        if not all(math.isfinite(x) for x in st.pos) or not math.isfinite(O.energy.total()):
            bad = unstable_body()
            self._stop("unstable", f"unstable state at t = {O.time:.6f} s: body #{bad[0] if bad else '?'} has a non-finite "
                                   f"{bad[1] if bad else 'energy'}; stopping")
            return False
        dt_rec = O.time - self.t_prev
        acc = (st.vel - self.v_prev) / dt_rec if dt_rec > 0 else Vector3(0, 0, 0)
        self.v_prev, self.t_prev = Vector3(st.vel), O.time
        f_contact = self.contact_force(acc)
        touching = self.touching(f_contact)
        if touching and self.contact_pos is None:
            self.contact_pos = Vector3(st.pos)
        self.times.observe(O.time, self.along(st.vel), touching=touching)
        self.peak_f = max(self.peak_f, f_contact)
        row = dict(t=O.time - self.start, boulder_z=st.pos[2], boulder_vz=st.vel[2], boulder_az=acc[2], impact_force=f_contact,
                   penetration=self.penetration())
        row.update(self.scene_row())
        row["dt"] = O.dt
        self.rows.append(row)
        # penalty contacts are valid while overlaps are small against the contact reach R1 + R2:
        # the law's largest overlap ratio at any step since the last record
        worst, worst_ids = self.law.maxOverlapRatio, self.law.maxOverlapIds
        self.law.maxOverlapRatio = 0.0
        self.max_overlap_ratio = max(self.max_overlap_ratio, worst)
        if worst > 0.5 and not self.warned:
            self.warned = True
            print(f"  WARNING t = {1e3 * (O.time - self.start):.2f} ms: a contact overlaps {100 * worst:.0f}% of its reach (sum of radii), "
                  f"{self.part_name(worst_ids[0])} - {self.part_name(worst_ids[1])}; contact forces are no longer reliable "
                  + self.overlap_advice(), flush=True)
        e = {k: O.energy[k] for k in O.energy.keys()}
        e["t"] = O.time - self.start
        e["residual"] = O.energy.total() - self.total0
        self.erows.append(e)
        self.resid = max(self.resid, abs(e["residual"]) / self.e_impact)
        self.progress(O.time, O.iter, self.times.expected_end(), f"| boulder v = {st.vel.norm():.2f} m/s, force {f_contact / 1e3:.1f} kN")
        return True

    def overlap_advice(self):
        return "(stiffer contacts or a gentler impact)"

    # --- however it ended
    def stopped(self, status, signal_name=None, message=None):
        """The run was cut short: status 'interrupted' (by signal_name) or 'failed' (message)."""
        self.status, self.signal = status, signal_name
        self.message = message or f"interrupted by {signal_name} during the {self.stage}"
        print(f"{self.PROG}: {self.message}; writing what was recorded", file=sys.stderr, flush=True)

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
                print(f"{self.PROG}: {s['message']}", file=sys.stderr, flush=True)
        try:
            overwrite_json(path, {k: s[k] for k in ("status", "stage", "exit_status", "message")})
        except OSError:
            pass

    def head_results(self):
        """The summary's first numbers, known before the impact starts."""
        return dict(threads=O.numThreads, run_time_s=time.time() - self.t_wall)

    def _results(self):
        """The summary's numbers, from what was recorded (None where nothing was)."""
        out = self.head_results()
        wall_t = out["run_time_s"]
        if not self.impact_started:
            return out
        rows, erows, times = self.rows.rows, self.erows.rows, self.times
        self.peak = (lambda k: max(r[k] for r in rows)) if rows else (lambda k: None)
        last = erows[-1] if erows else {}
        keys = [k for k in (self.erows.columns or []) if k not in ("t", "residual")]
        tot_ns = sum(e.execTime for e in O.engines) or 1
        law = self.law
        out.update(
            free_fall_check=self.free_fall, peak_impact_force=self.peak_f, peak_deceleration=self.peak_f / self.mass,
            penetration_max=self.peak("penetration"),
            impact_duration=((times.t_rebound or (times._t_touch if times.t_released else None) or O.time) - times.t_contact)
            if times.t_contact is not None else None,
            rebound=times.t_rebound is not None, released=times.t_released is not None)
        out.update(self.filtered_results())
        out.update(self.scene_results())
        out.update(self.energy_results())
        out.update(
            impact_energy=self.e_impact, max_overlap_ratio=self.max_overlap_ratio)
        out.update(self.mass_results())
        out.update(
            deep_contact_onsets=law.deepOnsets, deep_onset_energy=law.deepOnsetEnergy,
            deep_contact_endings=law.deepEndings, deep_ending_energy=law.deepEndingEnergy,
            energy_end={k: last.get(k, 0.0) for k in keys}, energy_residual_max_fraction=self.resid,
            numerical_damping_share=(last.get("nonviscDamp", 0.0) / self.e_impact), impact_steps=O.iter - self.iter0, dt_end=O.dt,
            time_per_step_us=1e6 * (wall_t - self.t_prepare) / max(1, O.iter - self.iter0),
            impact_time_s=dict(total=wall_t - self.t_prepare, **self.wall),
            engine_share={e.label or type(e).__name__: round(e.execTime / tot_ns, 4) for e in O.engines})
        out.update(self.broken_results())
        return out

    def filtered_results(self):
        """The peaks of the FILTERED columns after the low-pass filter (the raw peaks are the
        summary's other keys), and the filter in words (force_filter); self.filtered: the
        filtered series by column, for the plots."""
        rows, self.filtered = self.rows.rows, {}
        out = {key: None for key in self.FILTERED.values()}
        try:
            t = [r["t"] for r in rows]
            for col, key in self.FILTERED.items():
                self.filtered[col] = low_pass(t, [r[col] for r in rows], self.cutoff_hz)
                out[key] = float(max(self.filtered[col]))
            out["force_filter"] = describe(self.cutoff_hz)
        except ValueError as e:  # too few records
            out["force_filter"] = f"not filtered: {e}"
        return out

    def energy_results(self):
        """The boulder's kinetic energy at the end, gravity's work on it since its first contact
        and the energy the structure took: energy_absorbed = impact energy + that work - the
        boulder's energy left [J]."""
        st = self.boulder.state
        ke_end = 0.5 * self.mass * st.vel.squaredNorm()
        g = getattr(self, "gravity", None)
        w_gravity = (self.mass * g).dot(st.pos - self.contact_pos) if self.contact_pos is not None and g is not None else 0.0
        return dict(boulder_energy_end=ke_end, gravity_work_after_contact=w_gravity, energy_absorbed=self.e_impact + w_gravity - ke_end)

    def mass_results(self):
        """The summary's mass-scaling numbers."""
        return {}

    def broken_results(self):
        """The summary's counts of broken elements."""
        return self.broken.counts(self.el.rupturedIds) if self.el is not None else {}

    def report(self, s):
        """The last line, and the plots."""
        if self.rows.rows:
            try:
                self.plots(self.folder.path, self.rows.rows, self.erows.rows, [k for k in self.erows.columns or [] if k not in ("t", "residual")])
            except OSError as e:  # a full disk: the run failed (summary.json and the exit status say so)
                if s["status"] != "failed":
                    s.update(status="failed", exit_status=EXIT["failed"], message=write_failure(e.filename or "the plots", e))
                    print(f"{self.PROG}: {s['message']}", file=sys.stderr, flush=True)
                    self._write_summary(s)
                return
            except Exception as e:  # plots are a convenience: never lose the numbers over them
                print(f"  (plots failed: {e})")
        if s["status"] not in ("done", "unstable") or not self.rows.rows:
            return
        print(self.summary_line(s))
        if s["exit_status"] == EXIT["residual"]:
            print(f"{self.PROG}: {s['message']}", file=sys.stderr)


def write_failure_of(err):
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


def run_into(out, result_files, prog, make_run):
    """A run into the folder `out` (yadeflex.files.ResultsFolder: checked, locked and cleared of an
    earlier run's result_files and VTK frames before anything costly runs): make_run(folder,
    signals) gives the ImpactRun. SIGINT and SIGTERM end it with what it recorded; an error
    ends it as failed, named. Returns the summary (as in summary.json, with "status" and
    "exit_status", EXIT's); an output folder that cannot be written returns status "failed" and
    its message, with nothing written."""
    try:
        folder = ResultsFolder(out, result_files, {VTK_FOLDER: VtkRecorder.files_pattern(VTK_PREFIX)},
                               waiting=lambda: print(f"{prog}: waiting for the other run writing into {os.path.abspath(out)}", flush=True))
    except ValueError as e:
        print(f"{prog}: {e}", file=sys.stderr)
        return dict(status="failed", exit_status=EXIT["failed"], message=str(e))
    signals = Signals()
    try:
        run = make_run(folder, signals)
        try:
            run.run()
        except (Interrupted, KeyboardInterrupt) as e:
            run.stopped("interrupted", e.args[0] if isinstance(e, Interrupted) else "SIGINT")
        except OSError as e:  # an output file that could not be written (a full disk): one line naming it
            run.stopped("failed", message=write_failure_of(e))
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
