# The main job: a cylindrical damping module hit by a boulder (GPL-2.0-or-later).
#
#     yade-double -n -x scripts/damping_module.py [--out results/module] [options]
#     (scripts/run does this; --help lists the options)
#
# Builds (or loads from the cache) the filled module, adds the boulder, runs the impact and
# writes into --out: params.json, timeseries.csv, energy.csv, summary.json, plots (*.png)
# and, unless --no-vtk, a VTK time series (vtk/flex.pvd) for ParaView.
# Exit status (also in --help): 0 done; 1 bad input (one line on stderr names the option and the values allowed) or
# another error; 2 a NaN, an unstable state or a collapsed time step (the message names the body); 3 the energy
# balance residual exceeded --max-residual. The options and their checks: yadeflex/module_cli.py.
import csv
import dataclasses
import json
import math
import os
import sys
import time

HERE = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if a.endswith("damping_module.py")), os.getcwd())
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "py"))

from yade import O  # noqa: E402
from yade.minieigenHP import Vector3  # noqa: E402

import yadeflex as yf  # noqa: E402
from yadeflex.module import filled_module, add_boulder, fill_top, G, UNBALANCED_TOL  # noqa: E402
from yadeflex.module_cli import parse, OptionError, PROG  # noqa: E402


class Progress:
    def __init__(self, total_time):
        self.t0, self.last, self.total = time.time(), 0.0, total_time

    def __call__(self, extra=""):
        now = time.time()
        if now - self.last < 5 and O.time < self.total:
            return
        self.last = now
        done = max(1e-12, O.time - self.start)
        eta = (now - self.t0) / done * max(0.0, self.total - O.time)
        print(f"  t = {1e3 * (O.time - self.start):7.2f} ms of {1e3 * (self.total - self.start):.0f} ms, {O.iter} steps, "
              f"{now - self.t0:6.0f} s elapsed, ~{eta:.0f} s left {extra}", flush=True)


def unstable_body():
    """(id, what) of the first body with a non-finite position/velocity, else None."""
    for b in O.bodies:
        if b is None:
            continue
        for what, v in (("position", b.state.pos), ("velocity", b.state.vel)):
            if not all(math.isfinite(x) for x in v):
                return b.id, what
    return None


def part_name(bid, ids):
    """'grain #12', 'wire leg #300', ...: which part of the module a body is."""
    if bid is None or bid < 0 or bid >= len(O.bodies):
        return "no body"
    for key, name in (("grains", "grain"), ("mesh_cylinders", "wire leg"), ("lining", "lining facet"), ("mesh_nodes", "mesh node"),
                      ("ring_top", "top ring"), ("ring_bottom", "bottom ring"), ("rope", "rope"),
                      ("lining_nodes", "lining node"), ("rope_nodes", "rope node")):
        if bid in ids.get(key, ()):
            return f"{name} #{bid}"
    b = O.bodies[bid]
    if b is not None and b.isClumpMember:
        return f"boulder (clump member #{bid})"
    return f"{type(b.shape).__name__ if b is not None else 'erased body'} #{bid}"


def main():
    me = next((k for k, a in enumerate(sys.argv) if a.endswith("damping_module.py")), 0)
    try:
        a, p = parse(sys.argv[me + 1:])
    except OptionError as e:  # every option is checked before anything is filled or built
        print(f"{PROG}: {e}", file=sys.stderr)
        return 1
    out = os.path.abspath(a.out)
    os.makedirs(out, exist_ok=True)
    t_wall = time.time()
    print(f"damping module: {p.n_modules} x {p.diameter} m x {p.height} m{' with a boundary rope' if p.with_rope() else ''}, {p.fill} fill, {p.boulder_mass} kg {p.boulder_shape} at {p.impact_speed():.2f} m/s, {O.numThreads} thread(s)")

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
    ids, cache_file, cached = filled_module(p, cache_dir=a.cache_dir, progress=prog)
    t_fill = time.time() - t_wall
    print(f"filled module {'loaded from' if cached else 'built and saved to'} {cache_file} ({t_fill:.0f} s): "
          f"{len(ids['grains'])} grains, {sum(len(m['mesh_cylinders']) for m in ids['modules'])} wire legs, "
          f"{sum(len(m['lining']) for m in ids['modules'])} lining facets"
          + (f" in {len(ids['modules'])} modules" if len(ids["modules"]) > 1 else ""))
    top0 = fill_top(ids)
    bid = add_boulder(p, ids)
    s = p.boulder_size()
    boulder = O.bodies[bid]
    mass = boulder.state.mass
    O.engines = p.engines(p.damping)
    O.trackEnergy = True
    O.energy.clear()
    O.timingEnabled = True
    with open(os.path.join(out, "params.json"), "w") as f:
        # the values used (the fill preset's resolved), and the parameters as given (None: the preset's)
        json.dump(dict(p.resolved(), impact_speed=p.impact_speed(), fill_top=top0, cache_file=cache_file,
                       contact_law="linear Cundall-Strack (yade-flex law for all sphere and element contacts)",
                       numerical_damping=p.damping, given=dataclasses.asdict(p)), f, indent=1)
    # --- run
    wall = ids["wall"]
    base = ids["base_nodes"]
    mesh_nodes = ids["mesh_nodes"]
    R0 = 0.5 * p.diameter
    mid = [n for n in mesh_nodes if abs(O.bodies[n].state.pos[2] - 0.5 * p.height) < 0.15 * p.height]
    ring_ids = dict(top=ids["ring_top"], bottom=ids["ring_bottom"], rope=ids.get("rope", []))
    el = [e for e in O.engines if e.label == "flexElements"][0]
    # contacts found late (a missed or suppressed contact starts deep: its spring energy comes from nothing)
    law = yf.contact_law()
    rows, erows = [], []
    v_prev, t_prev = Vector3(boulder.state.vel), O.time
    e_impact = 0.5 * mass * p.impact_speed() ** 2
    iter0 = O.iter
    O.step()
    total0 = O.energy.total()
    start = O.time
    t_contact = None
    t_end = (start + a.duration) if a.duration else start + 0.3
    prog2 = Progress(t_end)
    prog2.start = start
    next_rec, next_vtk = O.time, O.time
    vtk = None
    if not a.no_vtk:
        try:
            from yadeflex.output import VtkRecorder
            vtk = VtkRecorder(os.path.join(out, "vtk"), prefix="flex")
        except ImportError:
            print("  (VTK output not available in this version)")
    peak_f, rebound_t = 0.0, None
    max_overlap_ratio, warned = 0.0, False
    status = 0
    # free fall up to the first contact, checked step by step: the speed just before the first
    # contact force against sqrt(2 g h), h the whole fall from rest (drop height)
    z_start, v_start = boulder.state.pos[2], -boulder.state.vel[2]
    h0 = v_start ** 2 / (2 * G)  # fall already done at the start (the drop height minus the gap)
    free_fall = None
    while free_fall is None and O.time < t_end:
        v_before, z_before = -boulder.state.vel[2], boulder.state.pos[2]
        O.step()
        dv = -boulder.state.vel[2] - v_before
        if abs(dv - G * O.dt) > 1e-6 * G * O.dt:  # a force other than gravity acted this step
            h = h0 + (z_start - z_before)
            free_fall = dict(v_measured=v_before, v_expected=math.sqrt(2 * G * h), fall_height=h, t=O.time - start)
    dt0 = O.dt
    ts = next(e for e in O.engines if e.label == "flexDt")
    guard = next((e for e in O.engines if type(e).__name__ == "FlexGuard"), None)
    while O.time < t_end:
        try:
            O.step()
        except RuntimeError as e:  # FlexGuard: non-finite state, runaway step or energy created; names the bodies
            if guard is None or not guard.message:
                raise
            print(f"damping_module: unstable state at t = {1e3 * (O.time - start):.2f} ms, stopped by FlexGuard: {guard.message}; "
                  f"bodies: {', '.join(part_name(b, ids) for b in guard.bodies[:5])}", file=sys.stderr)
            status = 2
            break
        if O.iter % 500 == 0 and O.dt < a.min_dt_fraction * dt0:
            print(f"damping_module: the stable time step collapsed from {dt0:.3g} s to {O.dt:.3g} s at t = {1e3 * (O.time - start):.2f} ms; "
                  f"it is set by {part_name(ts.stiffestBody, ids)} (a crushed lining facet or a light node under a stiff contact); "
                  "stopping (--min-dt-fraction)", file=sys.stderr)
            status = 2
            break
        if O.time >= next_rec:
            next_rec += a.record_every
            st = boulder.state
            if not all(math.isfinite(x) for x in st.pos) or not math.isfinite(O.energy.total()):
                bad = unstable_body()
                print(f"damping_module: unstable state at t = {O.time:.6f} s: body #{bad[0] if bad else '?'} has a non-finite "
                      f"{bad[1] if bad else 'energy'}; stopping", file=sys.stderr)
                status = 2
                break
            dt_rec = O.time - t_prev
            acc = (st.vel - v_prev) / dt_rec if dt_rec > 0 else Vector3(0, 0, 0)
            v_prev, t_prev = Vector3(st.vel), O.time
            f_contact = mass * (acc[2] + G)  # vertical force of the module on the boulder [N]
            fw = O.forces.f(wall)[2]
            slab = -fw + sum(O.bodies[n].state.mass * G - O.forces.f(n)[2] for n in base if O.bodies[n] is not None)
            radial = [math.hypot(O.bodies[n].state.pos[0], O.bodies[n].state.pos[1]) - R0 for n in mid if O.bodies[n] is not None]
            ring_f = {k: max([O.bodies[c].shape.axialForce for c in v if O.bodies[c] is not None] or [0.0]) for k, v in ring_ids.items()}
            bottom = st.pos[2] - 0.5 * s
            if t_contact is None and f_contact > 0.01 * mass * G and bottom < top0 + 0.01:
                t_contact = O.time
                if a.duration is None:
                    t_end = O.time + 0.3
                prog2.total = t_end
            peak_f = max(peak_f, f_contact)
            if t_contact is not None and rebound_t is None and st.vel[2] > 0:
                rebound_t = O.time
                if a.duration is None:
                    t_end = min(t_end, O.time + max(0.2 * (O.time - t_contact), 0.01))
                    prog2.total = t_end
            rows.append(dict(t=O.time - start, boulder_z=st.pos[2], boulder_vz=st.vel[2], boulder_az=acc[2], impact_force=f_contact,
                             penetration=max(0.0, top0 - bottom), slab_force=slab, bulge_max=max(radial or [0.0]),
                             bulge_mean=(sum(radial) / len(radial) if radial else 0.0), ring_top_force=ring_f["top"],
                             ring_bottom_force=ring_f["bottom"], rope_force=ring_f["rope"], broken_wires=el.nRuptured, dt=O.dt))
            # penalty contacts are valid while overlaps are small against the contact reach R1 + R2
            worst, worst_i = max(((i.geom.penetrationDepth / (i.geom.refR1 + i.geom.refR2), i) for i in O.interactions
                                  if i.isReal and hasattr(i.geom, "refR1") and i.geom.refR1 + i.geom.refR2 > 0),
                                 key=lambda x: x[0], default=(0.0, None))
            max_overlap_ratio = max(max_overlap_ratio, worst)
            if worst > 0.5 and not warned:
                warned = True
                print(f"  WARNING t = {1e3 * (O.time - start):.2f} ms: a contact overlaps {100 * worst:.0f}% of its reach (sum of radii), "
                      f"{part_name(worst_i.id1, ids)} - {part_name(worst_i.id2, ids)}; contact forces are no longer reliable "
                      "(stiffer contacts: --fill-young, --steel-contact-young, or a gentler impact)", flush=True)
            e = {k: O.energy[k] for k in O.energy.keys()}
            e["t"] = O.time - start
            e["residual"] = O.energy.total() - total0
            erows.append(e)
            prog2(f"| boulder v = {st.vel[2]:+.2f} m/s, force {f_contact / 1e3:.1f} kN")
        if vtk is not None and O.time >= next_vtk:
            next_vtk += a.vtk_every
            vtk()
    # --- outputs
    keys = sorted({k for e in erows for k in e if k not in ("t", "residual")})
    with open(os.path.join(out, "timeseries.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(out, "energy.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["t"] + keys + ["residual"])
        w.writeheader()
        for e in erows:
            w.writerow({k: e.get(k, 0.0) for k in ["t"] + keys + ["residual"]})
    resid = max(abs(e["residual"]) for e in erows) / e_impact
    last = erows[-1]
    timing = {}
    tot_ns = sum(e.execTime for e in O.engines) or 1
    for e in O.engines:
        timing[e.label or type(e).__name__] = round(e.execTime / tot_ns, 4)
    steps = len(rows) and O.iter
    wall_t = time.time() - t_wall
    summary = dict(
        impact_speed_expected=p.impact_speed(), free_fall_check=free_fall,
        peak_impact_force=peak_f, peak_deceleration=peak_f / mass, penetration_max=max(r["penetration"] for r in rows),
        impact_duration=((rebound_t or O.time) - t_contact) if t_contact is not None else None,
        slab_force_max=max(r["slab_force"] for r in rows), bulge_max=max(r["bulge_max"] for r in rows),
        ring_top_force_max=max(r["ring_top_force"] for r in rows), ring_bottom_force_max=max(r["ring_bottom_force"] for r in rows),
        rope_force_max=max(r["rope_force"] for r in rows), n_modules=p.n_modules,
        broken_wires=el.nRuptured, impact_energy=e_impact, max_overlap_ratio=max_overlap_ratio,
        deep_contact_onsets=law.deepOnsets, deep_onset_energy=law.deepOnsetEnergy,
        deep_contact_endings=law.deepEndings, deep_ending_energy=law.deepEndingEnergy,
        energy_end={k: last.get(k, 0.0) for k in keys},
        energy_residual_max_fraction=resid,
        numerical_damping_share=(last.get("nonviscDamp", 0.0) / e_impact),
        threads=O.numThreads, run_time_s=wall_t, fill_time_s=t_fill, filled_from_cache=cached, impact_steps=O.iter - iter0, dt_end=O.dt,
        time_per_step_us=1e6 * (wall_t - t_fill) / max(1, O.iter - iter0),
        engine_share=timing, status=status)
    with open(os.path.join(out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
    try:
        _plots(out, rows, erows, keys)
    except Exception as e:  # plots are a convenience: never lose the numbers over them
        print(f"  (plots failed: {e})")
    print(f"done in {wall_t:.0f} s: peak force {peak_f / 1e3:.1f} kN, penetration {1e3 * summary['penetration_max']:.0f} mm, "
          f"slab {summary['slab_force_max'] / 1e3:.1f} kN, energy residual {100 * resid:.2f}% of {e_impact:.0f} J, "
          f"contact hand-overs {law.deepOnsetEnergy - law.deepEndingEnergy:+.3g} J ({law.deepOnsets} started deep with "
          f"{law.deepOnsetEnergy:.3g} J, {law.deepEndings} ended overlapping with {law.deepEndingEnergy:.3g} J); results in {out}")
    if status:
        return status
    if resid > a.max_residual:
        print(f"damping_module: energy balance residual {100 * resid:.2f}% exceeds {100 * a.max_residual:.1f}%", file=sys.stderr)
        return 3
    return 0


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
