# The main job: a cylindrical damping module hit by a boulder (GPL-2.0-or-later).
#
#     yade-double -n -x scripts/damping_module.py [--out results/module] [options]
#     (scripts/run does this; --help lists the options)
#
# Builds (or loads from the cache) the filled module, adds the boulder, runs the impact and
# writes into --out: params.json, timeseries.csv, energy.csv, summary.json, plots (*.png)
# and, unless --no-vtk, a VTK time series (vtk/flex.pvd) for ParaView. The files an earlier run
# wrote there are removed first; the time series are on disk row by row, and summary.json says
# how the run ended ("status": done, unstable, interrupted, failed; "running" if the process
# was killed outright), so a run stopped anyhow leaves what it recorded.
# Exit status (also in --help): 0 done; 1 bad input (one line on stderr names the option and the
# values allowed; nothing is filled or written), an output folder that cannot be written, or another
# error; 2 a NaN, an unstable state or a collapsed time step (the message names the body); 3 the
# energy balance residual exceeded --max-residual; 130 interrupted by SIGINT (Ctrl-C), 143 by
# SIGTERM. The options and their checks: yadeflex/module_cli.py.
import contextlib
import dataclasses
import math
import os
import signal
import sys
import time
import traceback

HERE = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if a.endswith("damping_module.py")), os.getcwd())
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "py"))

from yade import O  # noqa: E402
from yade.minieigenHP import Vector3  # noqa: E402

import yadeflex as yf  # noqa: E402
from yadeflex.files import CsvStream, ResultsFolder, write_json  # noqa: E402
from yadeflex.impact import BrokenElements, ImpactTimes, Progress, part_name, part_names  # noqa: E402
from yadeflex.module import filled_module, add_boulder, fill_top, G, UNBALANCED_TOL  # noqa: E402
from yadeflex.module_cli import parse, OptionError, PROG, EXIT  # noqa: E402
from yadeflex.output import VtkRecorder  # noqa: E402

RESULT_FILES = ("params.json", "timeseries.csv", "energy.csv", "summary.json", "impact.png", "energy.png")
VTK_FOLDER, VTK_PREFIX = "vtk", "flex"


class Interrupted(Exception):
    """SIGINT (Ctrl-C) or SIGTERM (kill, a batch system's time limit, timeout): args[0] names it."""


class Signals:
    """SIGINT and SIGTERM raise Interrupted in the main thread, at once, except inside a
    deferred() block (a record: one row to each time series), which they end first. Once one
    has raised, or after hold() (the run is over), further ones are only noted: the summary is
    written whole. A SIGINT the run was started to ignore (nohup, a background job) stays
    ignored. restore() puts the handlers back."""

    def __init__(self):
        self.saved = {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGTERM)}
        self.deferring = self.holding = False
        self.pending = None
        for sig, h in self.saved.items():
            if h != signal.SIG_IGN:
                signal.signal(sig, self._handler)

    def _handler(self, signum, frame):
        name = signal.Signals(signum).name
        if self.deferring or self.holding:
            self.pending = self.pending or name
            return
        self._raise(name)

    def _raise(self, name):
        self.holding = True
        raise Interrupted(name)

    @contextlib.contextmanager
    def deferred(self):
        self.deferring = True
        try:
            yield
        finally:
            self.deferring = False
        if self.pending and not self.holding:
            self._raise(self.pending)

    def hold(self):
        self.holding = True

    def restore(self):
        for sig, h in self.saved.items():
            signal.signal(sig, h)


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


class ImpactRun:
    """One run into a results folder (yadeflex.files.ResultsFolder): the filled module, the
    boulder, the impact. Time series go to disk row by row (CsvStream); summary.json says
    "running" from the start and is rewritten by finish() however the run ends, with its status:
    done, unstable (a NaN, FlexGuard, a collapsed time step), interrupted (SIGINT, SIGTERM) or
    failed (an error, named)."""

    def __init__(self, a, p, folder, signals):
        self.a, self.p, self.folder, self.signals = a, p, folder, signals
        self.t_wall = time.time()
        self.status, self.signal, self.message = "running", None, None
        self.stage = "fill"
        self.rows = CsvStream(folder.file("timeseries.csv"))
        self.erows = CsvStream(folder.file("energy.csv"), first=("t",), last=("residual",), missing=0.0)
        self.t_fill = self.cached = self.cache_file = None
        self.impact_started = False
        write_json(folder.file("summary.json"), dict(status="running", stage=self.stage, pid=os.getpid()))

    # --- the run
    def run(self):
        a, p = self.a, self.p
        print(f"damping module: {p.n_modules} x {p.diameter} m x {p.height} m{' with a boundary rope' if p.with_rope() else ''}, {p.fill} fill, {p.boulder_mass} kg {p.boulder_shape} at {p.impact_speed():.2f} m/s, {O.numThreads} thread(s)")
        ids, self.cache_file, self.cached = filled_module(p, cache_dir=a.cache_dir, progress=fill_progress(self.t_wall))
        self.t_fill = time.time() - self.t_wall
        print(f"filled module {'loaded from' if self.cached else 'built and saved to'} {self.cache_file} ({self.t_fill:.0f} s): "
              f"{len(ids['grains'])} grains, {sum(len(m['mesh_cylinders']) for m in ids['modules'])} wire legs, "
              f"{sum(len(m['lining']) for m in ids['modules'])} lining facets"
              + (f" in {len(ids['modules'])} modules" if len(ids["modules"]) > 1 else ""))
        self.stage = "impact"
        self.ids, self.names, self.broken = ids, part_names(ids), BrokenElements(ids)
        self.top0 = fill_top(ids)
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
        self.law = yf.contact_law()
        self.v_prev, self.t_prev = Vector3(self.boulder.state.vel), O.time
        self.e_impact = 0.5 * self.mass * p.impact_speed() ** 2
        self.iter0 = O.iter
        O.step()
        self.total0 = O.energy.total()
        self.start = O.time
        self.times = ImpactTimes(self.start, a.duration)
        self.progress = Progress(self.start)
        self.peak_f, self.max_overlap_ratio, self.warned, self.resid, self.free_fall = 0.0, 0.0, False, 0.0, None
        self.impact_started = True
        self.free_fall = self._free_fall()
        self.dt0 = O.dt
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
        a = self.a
        next_rec, next_vtk = self.start, self.start  # (on the grid from the start: every step records until it catches up)
        vtk = None if a.no_vtk else VtkRecorder(self.folder.file(VTK_FOLDER), prefix=VTK_PREFIX)
        ts = next(e for e in O.engines if e.label == "flexDt")
        guard = next((e for e in O.engines if type(e).__name__ == "FlexGuard"), None)
        while O.time < self.times.end:
            try:
                O.step()
            except RuntimeError:  # FlexGuard: non-finite state, runaway step or energy created; names the bodies
                if guard is None or not guard.message:
                    raise
                self._stop("unstable", f"unstable state at t = {1e3 * (O.time - self.start):.2f} ms, stopped by FlexGuard: {guard.message}; "
                           f"bodies: {', '.join(part_name(b, self.names) for b in guard.bodies[:5])}")
                return
            if O.iter % 500 == 0 and O.dt < a.min_dt_fraction * self.dt0:
                self._stop("unstable", f"the stable time step collapsed from {self.dt0:.3g} s to {O.dt:.3g} s at t = {1e3 * (O.time - self.start):.2f} ms; "
                           f"it is set by {part_name(ts.stiffestBody, self.names)} (a crushed lining facet or a light node under a stiff contact); "
                           "stopping (--min-dt-fraction)")
                return
            if O.time >= next_rec:
                next_rec += a.record_every
                with self.signals.deferred():
                    if not self._record():
                        return
            if vtk is not None and O.time >= next_vtk:
                next_vtk += a.vtk_every
                try:
                    with self.signals.deferred():
                        vtk()
                except ImportError as e:  # VTK's Python bindings missing: the numbers matter more
                    print(f"  (no VTK output: {e})", flush=True)
                    vtk = None

    def _stop(self, status, message):
        self.status, self.message = status, message
        print(f"damping_module: {message}", file=sys.stderr, flush=True)

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
        # penalty contacts are valid while overlaps are small against the contact reach R1 + R2
        worst, worst_i = max(((i.geom.penetrationDepth / (i.geom.refR1 + i.geom.refR2), i) for i in O.interactions
                              if i.isReal and hasattr(i.geom, "refR1") and i.geom.refR1 + i.geom.refR2 > 0),
                             key=lambda x: x[0], default=(0.0, None))
        self.max_overlap_ratio = max(self.max_overlap_ratio, worst)
        if worst > 0.5 and not self.warned:
            self.warned = True
            print(f"  WARNING t = {1e3 * (O.time - self.start):.2f} ms: a contact overlaps {100 * worst:.0f}% of its reach (sum of radii), "
                  f"{part_name(worst_i.id1, self.names)} - {part_name(worst_i.id2, self.names)}; contact forces are no longer reliable "
                  "(stiffer contacts: --fill-young, --steel-contact-young, or a gentler impact)", flush=True)
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
        print(f"damping_module: {self.message}; writing what was recorded", file=sys.stderr, flush=True)

    def exit_status(self):
        if self.status == "interrupted":
            return EXIT.get(self.signal, EXIT["SIGINT"])
        if self.status == "done" and self.rows.rows and self.resid > self.a.max_residual:
            return EXIT["residual"]
        return EXIT[self.status]

    def finish(self):
        """Close the time series and write summary.json; returns the summary."""
        self.rows.close()
        self.erows.close()
        s = dict(status=self.status, stage=self.stage, exit_status=self.exit_status(), message=self.message)
        if s["exit_status"] == EXIT["residual"]:
            s["message"] = f"energy balance residual {100 * self.resid:.2f}% exceeds {100 * self.a.max_residual:.1f}%"
        s.update(self._results())
        write_json(self.folder.file("summary.json"), s)
        return s

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
            impact_energy=self.e_impact, max_overlap_ratio=self.max_overlap_ratio,
            deep_contact_onsets=law.deepOnsets, deep_onset_energy=law.deepOnsetEnergy,
            deep_contact_endings=law.deepEndings, deep_ending_energy=law.deepEndingEnergy,
            energy_end={k: last.get(k, 0.0) for k in keys}, energy_residual_max_fraction=self.resid,
            numerical_damping_share=(last.get("nonviscDamp", 0.0) / self.e_impact), impact_steps=O.iter - self.iter0, dt_end=O.dt,
            time_per_step_us=1e6 * (wall_t - self.t_fill) / max(1, O.iter - self.iter0),
            engine_share={e.label or type(e).__name__: round(e.execTime / tot_ns, 4) for e in O.engines})
        broken = self.broken.counts(self.el.rupturedIds)
        out.update(broken, broken_wires=broken["broken_wire_legs"])
        return out

    def report(self, s):
        """The last line, and the plots."""
        if self.rows.rows:
            try:
                _plots(self.folder.path, self.rows.rows, self.erows.rows, [k for k in self.erows.columns or [] if k not in ("t", "residual")])
            except Exception as e:  # plots are a convenience: never lose the numbers over them
                print(f"  (plots failed: {e})")
        if s["status"] not in ("done", "unstable") or not self.rows.rows:
            return
        law = self.law
        print(f"{s['status']} in {s['run_time_s']:.0f} s: peak force {self.peak_f / 1e3:.1f} kN, penetration {1e3 * s['penetration_max']:.0f} mm, "
              f"slab {s['slab_force_max'] / 1e3:.1f} kN, energy residual {100 * self.resid:.2f}% of {self.e_impact:.0f} J, "
              f"contact hand-overs {law.deepOnsetEnergy - law.deepEndingEnergy:+.3g} J ({law.deepOnsets} started deep with "
              f"{law.deepOnsetEnergy:.3g} J, {law.deepEndings} ended overlapping with {law.deepEndingEnergy:.3g} J); results in {self.folder.path}")
        if s["exit_status"] == EXIT["residual"]:
            print(f"damping_module: {s['message']}", file=sys.stderr)


def main():
    me = next((k for k, a in enumerate(sys.argv) if a.endswith("damping_module.py")), 0)
    try:
        a, p = parse(sys.argv[me + 1:])
    except OptionError as e:  # every option is checked before anything is filled or built
        print(f"{PROG}: {e}", file=sys.stderr)
        return 1
    # the folder is checked, taken and cleared of an earlier run's files before anything costly runs
    try:
        folder = ResultsFolder(a.out, RESULT_FILES, {VTK_FOLDER: VtkRecorder.files_pattern(VTK_PREFIX)},
                               waiting=lambda: print(f"damping_module: waiting for the other run writing into {os.path.abspath(a.out)}", flush=True))
    except ValueError as e:
        print(f"damping_module: {e}", file=sys.stderr)
        return 1
    signals = Signals()
    try:
        run = ImpactRun(a, p, folder, signals)
        try:
            run.run()
        except (Interrupted, KeyboardInterrupt) as e:
            run.stopped("interrupted", e.args[0] if isinstance(e, Interrupted) else "SIGINT")
        except Exception as e:
            traceback.print_exc()
            run.stopped("failed", message=f"{type(e).__name__}: {e}")
        signals.hold()  # the run is over: a signal now must not cut the summary short
        s = run.finish()
    finally:
        signals.restore()
        folder.close()
    run.report(s)
    return s["exit_status"]


def _plots(out, rows, erows, keys):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    t = [1e3 * r["t"] for r in rows]
    fig, ax = plt.subplots(2, 2, figsize=(11, 7))
    ax[0, 0].plot(t, [r["impact_force"] / 1e3 for r in rows], label="on the boulder")
    ax[0, 0].plot(t, [r["slab_force"] / 1e3 for r in rows], label="on the slab")
    ax[0, 0].set(xlabel="t [ms]", ylabel="force [kN]", title="impact and slab forces")
    ax[0, 0].legend()
    ax[0, 1].plot(t, [1e3 * r["penetration"] for r in rows])
    ax[0, 1].set(xlabel="t [ms]", ylabel="penetration [mm]", title="boulder penetration")
    ax[1, 0].plot(t, [1e3 * r["bulge_max"] for r in rows], label="max")
    ax[1, 0].plot(t, [1e3 * r["bulge_mean"] for r in rows], label="mean")
    ax[1, 0].set(xlabel="t [ms]", ylabel="radial bulging [mm]", title="mesh at mid-height")
    ax[1, 0].legend()
    ax[1, 1].plot(t, [r["ring_top_force"] / 1e3 for r in rows], label="top ring")
    ax[1, 1].plot(t, [r["ring_bottom_force"] / 1e3 for r in rows], label="bottom ring")
    if any(r["rope_force"] for r in rows):
        ax[1, 1].plot(t, [r["rope_force"] / 1e3 for r in rows], label="boundary rope")
    ax[1, 1].set(xlabel="t [ms]", ylabel="max axial force [kN]", title="rings and rope")
    ax[1, 1].legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "impact.png"), dpi=110)
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(10, 6))
    te = [1e3 * e["t"] for e in erows]
    for k in keys:
        ax.plot(te, [e.get(k, 0.0) for e in erows], label=k)
    ax.plot(te, [e["residual"] for e in erows], "k--", label="balance residual")
    ax.set(xlabel="t [ms]", ylabel="energy [J]", title="energy budget (work terms with YADE's signs)")
    ax.legend(fontsize=8, ncol=2)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "energy.png"), dpi=110)
    plt.close(fig)


sys.exit(main())
