# Stability suite (issue 6): time-step margins, impact speeds, stiff and soft materials, rupture
# (GPL-2.0-or-later).
#
#     yade-double -n -j1 -x bench/stability.py [--quick] [--groups dt,speed,material,rupture] [--no-default-module]
#     yade-double -n -j1 -x bench/stability.py --groups dtmodule   # the default module's margin (25 min)
#
# A run of some of the default groups (--groups speed) replaces those groups' rows of
# results/stability.csv and stability_margins.csv and keeps the other groups' rows.
#
# Every case is a scene of yadeflex (the builders the tests and benchmarks use) run in this one
# process, one after the other, with these common rules:
#   - time step: FlexTimeStepper keeps estimating the critical step (safety 1, its usual interval
#     and collider triggers); a PyRunner right after it sets O.dt = factor x flexDt.dtCritical at
#     every step, so that factors above 1 can be run. yf.engines() uses 0.5 (timestep_safety), the
#     damping module ModuleParams.timestep_safety (1.0 since 2026-11-23, 0.5 before); --groups
#     dtmodule searches its margin.
#   - guard: a FlexGuard with its default settings is the first engine. When it stops the run, its
#     step and message are recorded, it is removed and the run goes on without it, so that every
#     row says both what the guard did and what the run really did (a guard stop followed by a
#     stable run is a false alarm).
#   - energy balance: O.trackEnergy; residual R = (O.energy.total() - total after the first step)
#     - W_ext, W_ext the external work (cantilever: the permanent tip force times the tip
#     displacement; tensile panel: -sum F.v dt of the driven nodes, summed every step after the
#     integrator; all other scenes have none: gravity is booked in O.energy as gravWork); the
#     scale S = largest (sum over O.energy terms of |E_k| + |W_ext|) seen so far. Checked every
#     CHECK steps (a blow-up's first step is known to CHECK steps). The table's residual is the
#     largest |R| of the run over the largest S of the run, with the sign R had there (+: energy
#     created). (Before 2026-11-22 FlexNewtonIntegrator booked Cundall damping on driven, blocked
#     DOFs too, where no damping acts; this suite found it and discounted it on the panel; now
#     fixed in the integrator, see STABILITY.md.)
#   - outcome: 'blown up (non-finite)' when O.energy.total() or any body's position or velocity
#     (scanned every SCAN steps) is not finite; 'blown up (energy created)' when R > BLOWUP x S
#     for CONFIRM steps in a row, or up to the end of the run (a step load's first steps exceed
#     BLOWUP x S while S is tiny: such transient episodes are counted in the detail), or when
#     the largest |R| exceeds BLOWUP x the run's largest S at the end; for the damping module,
#     'stopped by the module check' when the time step falls below 1% of its value at the start
#     (scripts/damping_module.py --min-dt-fraction); 'stable' otherwise. Runs stop at the first
#     of these.
#   - margins (group dt): factors 0.5, 0.75, 1, 1.25, 1.5, 2, 3, 4, 6 up to the first unstable
#     one, then bisection (geometric) between the last stable and the first unstable to 5%.
#
# Writes bench/results/stability.csv (one row per run), stability_margins.csv,
# stability.png (max |residual| against the time-step factor, per scene, blow-ups marked) and
# stability_machine.txt (stability_quick* with --quick); prints the tables. See bench/STABILITY.md.
import argparse
import builtins
import csv
import dataclasses
import functools
import math
import os
import sys
import time

BENCH = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if os.path.basename(a) == "stability.py"), os.path.join(os.getcwd(), "bench"))
sys.path.insert(0, BENCH)
sys.path.insert(0, os.path.join(os.path.dirname(BENCH), "py"))

import yade  # noqa: E402
from yade import O  # noqa: E402
from yade.wrapper import PyRunner, FlexGuard  # noqa: E402

from yadeflex import scenes, membrane_scenes, tensile  # noqa: E402
from yadeflex import membrane as M  # noqa: E402
from yadeflex.materials import steel  # noqa: E402
from yadeflex.module import ModuleParams, filled_module, add_boulder  # noqa: E402

CHECK = 10          # steps between energy checks
SCAN = 200          # steps between scans of every body for non-finite values and the largest speed
BLOWUP = 0.5        # energy created above this fraction of the energy scale: blown up
CONFIRM = 1000      # ... if it stays above for this many steps (or goes non-finite); a step load's first steps exceed it
MIN_STEPS = 5000    # every run lasts at least this many steps
FALSE_ALARM = 0.1   # a guard stop of a run that stays stable with |residual| below this: a false alarm
ACCURATE = 0.05     # margins also give the largest factor up to which every |residual| stays below this
MIN_DT_FRACTION = 0.01  # the damping module's own check (scripts/damping_module.py)
FACTORS = (0.5, 0.75, 1.0, 1.25, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0, 24.0, 32.0)
BISECT_TOL = 0.05
RESULTS = os.path.join(BENCH, "results")
DEFAULT_GROUPS = ("dt", "speed", "material", "rupture")
OUT = [""]          # file name suffix: "_quick" in --quick mode (the full results stay)


# ---------------------------------------------------------------- scenes
# Each builder sets up O (engines from yadeflex) and returns a Case: how long to run and what
# external work and stop condition the scene has.

@dataclasses.dataclass
class Case:
    t_end: float = math.inf        # simulated time [s] after the first step
    max_steps: int = 10 ** 9
    min_steps: int = MIN_STEPS     # run at least this many steps (an instability needs steps to grow)
    work: object = None            # callable: external work since the start [J] (or None)
    per_step: object = None        # callable run by a PyRunner after the integrator (or None)
    done: object = None            # callable: True when the scene's run is complete
    module: bool = False           # apply the damping module's time-step collapse check
    info: dict = dataclasses.field(default_factory=dict)


def cantilever(damping=0.0, steps=20000):
    """Steel cantilever, 10 cylinders, 1 m, r = 10 mm, clamped; a 100 N tip force applied at
    once (undamped: it vibrates for ever)."""
    s = scenes.cantilever(segments=10, force=100.0, damping=damping)
    tip = O.bodies[s["tip"]]
    z0 = tip.state.pos[2]
    return Case(max_steps=steps, work=lambda: -100.0 * (tip.state.pos[2] - z0))


def net(speed=5.0, scale=1.0, strength=math.inf, t_end=0.03):
    """scenes.net_impact: 20 x 20 steel wires 50 mm apart, r = 2 mm, border clamped; sphere
    r = 0.1 m, 2500 kg/m3 at `speed`; wire E and sphere contact modulus x scale; optional
    tensile strength [Pa] of the wires (rupture)."""
    mat = steel(friction_deg=30.0, young=200e9 * scale, tensile_strength=strength)
    s = scenes.net_impact(speed=speed, sphere_young=5e9 * scale, material=mat)
    return Case(t_end=t_end, info=dict(sphere=s["sphere"]))


def sheet(scale=1.0, t_end=0.15):
    """membrane_scenes.sheet_impact: 1 x 1 m geotextile-like sheet (16 x 16 cells, E t =
    250 kN/m x scale, 0.3 kg/m2), sphere r = 0.1 m released 10 mm above it; contact moduli of
    the sheet and the sphere x scale."""
    orig = M.membrane_material
    M.membrane_material = functools.partial(orig, contact_young=1e9 * scale)
    try:
        s = membrane_scenes.sheet_impact(stiffness=250e3 * scale)
    finally:
        M.membrane_material = orig
    O.bodies[s["sphere"]].material.young = 1e8 * scale
    return Case(t_end=t_end)


def panel(size=0.5, speed=1.0, max_elongation=0.5, damping=0.2):
    """tensile.mesh_panel_scene: TECCO G65/3 panel size x size m pulled along the spirals at
    `speed` [m/s] (local damping 0.2 by default, as the builder) until links have ruptured and the edge force
    fell below 30% of its peak (full rupture), or max_elongation."""
    s = tensile.mesh_panel_scene(width=size, height=size, direction="longitudinal", speed=speed, damping=damping)
    ax, driven = s["axis"], s["driven"]
    x0 = O.bodies[driven[0]].state.pos[ax]
    el = next(e for e in O.engines if e.label == "flexElements")
    st = dict(work=0.0, peak=0.0)

    def per_step():
        fv = [(O.forces.f(i), O.bodies[i].state.vel) for i in driven]
        st["work"] -= sum(f.dot(v) for f, v in fv) * O.dt

    def done():
        f = -sum(O.forces.f(i)[ax] for i in driven)
        st["peak"] = max(st["peak"], f)
        e = (O.bodies[driven[0]].state.pos[ax] - x0) / s["length"]
        return (el.nRuptured > 0 and f < 0.3 * st["peak"]) or e >= max_elongation

    return Case(work=lambda: st["work"], per_step=per_step, done=done, info=dict(peak=st))


def module(small=True, speed=None, t_cap=0.08):
    """The damping module of the main job (scripts/damping_module.py): ModuleParams() or its
    --small variant, cached fill, boulder with p.engines(p.damping). Runs until the boulder
    moves up again (rebound) plus 5 ms, or t_cap [s] of simulated time."""
    p = ModuleParams()
    if small:
        p = dataclasses.replace(p, diameter=0.4, height=0.3, grain_min=0.06, grain_max=0.08, boulder_mass=100.0, drop_height=1.0)
    if speed is not None:
        p.impact_velocity = speed
    ids, _, _ = filled_module(p)
    bid = add_boulder(p, ids)
    O.engines = [FlexGuard(label="guard")] + p.engines(p.damping)
    b = O.bodies[bid]
    st = dict(rebound=None)

    def done():
        if st["rebound"] is None and b.state.vel[2] > 0:
            st["rebound"] = O.time
        return st["rebound"] is not None and O.time > st["rebound"] + 0.005

    parts = {k: set(ids[key]) for k, key in (("grain", "grains"), ("lining node", "lining_nodes"), ("mesh node", "mesh_nodes"))}
    return Case(t_end=t_cap, done=done, module=True, info=dict(boulder=bid, rebound=st, speed=p.impact_speed(), parts=parts))


# ---------------------------------------------------------------- runner

def _finite(v):
    return all(math.isfinite(x) for x in v)


def _first_nonfinite():
    for b in O.bodies:
        if b is not None and not (_finite(b.state.pos) and _finite(b.state.vel)):
            return b.id
    return None


def _max_speed(parts=None):
    """(largest speed, 'what #id' of that body) over bodies with their own DOFs; parts: {name: ids}
    to say which part of a structure the body is (else its shape's class)."""
    v, b = max(((b.state.vel.norm(), b) for b in O.bodies if b is not None and not b.isClumpMember), key=lambda x: x[0], default=(0.0, None))
    if b is None:
        return v, ""
    name = next((k for k, ids in (parts or {}).items() if b.id in ids), type(b.shape).__name__)
    return v, f"{name} #{b.id} ({1e3 * b.state.mass:.3g} g)"


def _install(factor, case):
    """Guard first (if the builder did not put one), stepper at safety 1, the dt setter after
    it, the per-step hook after the integrator."""
    eng = list(O.engines)
    if not any(isinstance(e, FlexGuard) for e in eng):
        eng.insert(0, FlexGuard(label="guard"))
    k = next(i for i, e in enumerate(eng) if e.label == "flexDt")
    ts = eng[k]
    ts.safety = 1.0
    builtins._stability_dt = lambda: setattr(O, "dt", factor * ts.dtCritical)
    eng.insert(k + 1, PyRunner(command="_stability_dt()", iterPeriod=1, label="stabilityDt"))
    if case.per_step is not None:
        builtins._stability_step = case.per_step
        eng.append(PyRunner(command="_stability_step()", iterPeriod=1, label="stabilityWork"))
    O.engines = eng
    return ts


def run_case(build, factor, group, scene, params, quiet=False):
    """Build a scene (build() returns a Case), run it at `factor` x the critical step; returns the row."""
    case = build()
    ts = _install(factor, case)
    el = next((e for e in O.engines if e.label == "flexElements"), None)
    O.trackEnergy = True
    O.energy.clear()
    t_wall = time.time()
    O.step()
    total0, t0, it0, dt0 = O.energy.total(), O.time, O.iter, O.dt
    w0 = case.work() if case.work else 0.0
    dtc0 = ts.dtCritical
    scale, max_abs, vmax = 0.0, 0.0, 0.0
    outcome, detail, blow_step = "stable", "", None
    pending, first, episodes, notes = None, None, 0, []  # energy created above BLOWUP x scale: since step, first seen, transient episodes
    max_signed, vmax_body = 0.0, ""
    guard_step, guard_msg = None, ""
    steps = 0
    while True:
        if steps >= case.max_steps or (O.time - t0 >= case.t_end and steps >= case.min_steps):
            break
        try:
            O.step()
        except RuntimeError:
            g = next((x for x in O.engines if isinstance(x, FlexGuard)), None)
            if g is None or not g.message:
                raise
            guard_step, guard_msg = O.iter - it0, f"{g.message} [bodies {list(g.bodies)[:5]}]"
            if not quiet:
                print(f"    guard stopped step {guard_step}: {g.message}", flush=True)
            O.engines = [x for x in O.engines if not isinstance(x, FlexGuard)]
            continue
        steps += 1
        if steps % CHECK and steps < case.max_steps:
            continue
        tot = O.energy.total()
        w = (case.work() - w0) if case.work else 0.0
        if not (math.isfinite(tot) and math.isfinite(w)):
            outcome, blow_step = "blown up (non-finite)", first or steps
            bad = _first_nonfinite()
            detail = f"O.energy.total() = {tot}" + (f"; first non-finite body #{bad}" if bad is not None else "")
            break
        scale = max(scale, sum(abs(O.energy[k]) for k in O.energy.keys()) + abs(w))
        res = (tot - total0) - w
        if abs(res) > max_abs:
            max_abs, max_signed = abs(res), res
        if res > BLOWUP * scale and scale > 0:
            if pending is None:
                pending = steps
                first = first or steps
            elif steps - pending >= CONFIRM:
                outcome, blow_step = "blown up (energy created)", first
                detail = f"residual {res:.3g} J > {BLOWUP} x scale {scale:.3g} J for {CONFIRM} steps; stiffest body #{ts.stiffestBody}"
                break
        elif pending is not None:
            episodes += 1
            pending = None
        if steps % SCAN == 0:
            bad = _first_nonfinite()
            if bad is not None:
                outcome, blow_step, detail = "blown up (non-finite)", first or steps, f"first non-finite body #{bad}"
                break
            v, vb = _max_speed(case.info.get("parts"))
            if v > vmax:
                vmax, vmax_body = v, vb
        if case.module and steps % 500 == 0 and O.dt < MIN_DT_FRACTION * dt0:
            outcome = "stopped by the module check"
            detail = f"time step collapsed from {dt0:.3g} s to {O.dt:.3g} s; set by body #{ts.stiffestBody}"
            blow_step = steps
            break
        if case.done is not None and case.done() and steps >= case.min_steps:
            break
    if episodes:
        notes.append(f"{episodes} transient episode(s) of energy created > {BLOWUP} x scale, the first from step {first}")
    if pending is not None and outcome == "stable":
        outcome, blow_step = "blown up (energy created)", first
        detail = f"residual > {BLOWUP} x scale from step {pending} to the end ({steps})"
    max_res = max_abs / scale if scale > 0 else 0.0
    if outcome == "stable" and max_res > BLOWUP and first is not None:  # episodes that reached half of the run's largest scale
        outcome, blow_step = "blown up (energy created)", first
        detail = f"energy created reached {100 * max_res:.0f}% of the run's largest energy scale, in transient episodes"
    detail = "; ".join([x for x in [detail] + notes if x])
    wall = time.time() - t_wall
    if outcome == "stable" and guard_step is not None:  # the guard stopped a run that did not blow up
        judged = "guard false alarm" if max_res < FALSE_ALARM else f"guard stop of a run that did not blow up but created {100 * max_res:.0f}%"
        detail = judged + ("; " + detail if detail else "")
    row = dict(group=group, scene=scene, params=params, factor=round(factor, 4), outcome=outcome, steps=steps,
               sim_time_s=O.time - t0, wall_s=round(wall, 2), max_residual=max_res, blowup_step=blow_step if blow_step is not None else "",
               guard_step=guard_step if guard_step is not None else "", guard_message=guard_msg, detail=detail,
               residual_at_max=max_signed / scale if scale > 0 else 0.0,
               broken=el.nRuptured if el is not None else 0, vmax=vmax, vmax_body=vmax_body, dt_critical_start=dtc0, dt_end=O.dt,
               energy_scale=scale)
    if case.info.get("boulder") is not None:
        b = O.bodies[case.info["boulder"]]
        row["detail"] = (row["detail"] + "; " if row["detail"] else "") + (
            f"boulder vz end {b.state.vel[2]:+.2f} m/s, rebound at {1e3 * (case.info['rebound']['rebound'] - t0):.1f} ms"
            if case.info["rebound"]["rebound"] is not None else f"boulder vz end {b.state.vel[2]:+.2f} m/s, no rebound")
    if "peak" in case.info:
        row["detail"] = (row["detail"] + "; " if row["detail"] else "") + f"peak edge force {case.info['peak']['peak'] / 1e3:.1f} kN"
    if not quiet:
        print_row(row)
    return row


def stable(row):
    return row["outcome"] == "stable"


def margin(build, group, scene, params, rows, factors=FACTORS, tol=BISECT_TOL):
    """Run the factors up to the first unstable one, then bisect; returns (last stable, first unstable)."""
    edge = [None, None]  # last stable, first unstable

    def attempt(f):
        r = run_case(build, f, group, scene, params)
        rows.append(r)
        edge[0 if stable(r) else 1] = f
        return stable(r)

    for f in factors:
        if not attempt(f):
            break
    while edge[0] is None and edge[1] is not None and edge[1] > 0.05:  # unstable at the smallest factor: a bug; find the edge
        attempt(0.5 * edge[1])
    while None not in edge and edge[1] / edge[0] > 1 + tol:
        attempt(math.sqrt(edge[0] * edge[1]))
    return tuple(edge)


# ---------------------------------------------------------------- output

COLS = ("group", "scene", "params", "factor", "outcome", "steps", "sim_time_s", "wall_s", "residual_at_max", "blowup_step", "guard_step",
        "broken", "vmax", "vmax_body", "detail")


def _fmt(k, v):
    if k in ("sim_time_s",) and v != "":
        return f"{1e3 * v:.2f} ms"
    if k == "residual_at_max":
        return f"{100 * v:+.3g}%"
    if k == "vmax":
        return f"{v:.3g}"
    return str(v)


def print_row(r):
    print("  " + " | ".join(_fmt(k, r[k]) for k in COLS if k not in ("group",)), flush=True)


def kept_rows(groups):
    """The rows and margin rows of the existing results/stability{OUT}.csv whose group was not run
    now, so that --groups speed (say) updates its own rows and keeps the others."""
    path = os.path.join(RESULTS, f"stability{OUT[0]}.csv")
    if not os.path.exists(path):
        return [], []
    with open(path) as f:
        old = [dict(r, factor=float(r["factor"]), max_residual=float(r["max_residual"])) for r in csv.DictReader(f)
               if r["group"] not in groups]
    scenes = {(r["scene"], r["params"]) for r in old}
    mpath = os.path.join(RESULTS, f"stability{OUT[0]}_margins.csv")
    margins = []
    if os.path.exists(mpath):
        with open(mpath) as f:
            rd = csv.reader(f)
            next(rd, None)
            margins = [m for m in rd if (m[0], m[1]) in scenes]
    return old, margins


def write(rows, margins, line, groups=DEFAULT_GROUPS):
    """results/stability{OUT}.csv, _margins.csv, _machine.txt and .png. A run of some of the default
    groups replaces those groups' rows and keeps the others' (each machine line says which groups
    it measured)."""
    os.makedirs(RESULTS, exist_ok=True)
    partial = OUT[0] == "" and set(groups) < set(DEFAULT_GROUPS)
    old, old_margins = kept_rows(groups) if partial else ([], [])
    old_margins = [m for m in old_margins if (m[0], m[1]) not in margins]
    rows = old + rows
    keys = list(dict.fromkeys(k for r in rows for k in r))  # (kept rows of an older column set get blanks, not a crash)
    with open(os.path.join(RESULTS, f"stability{OUT[0]}.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(RESULTS, f"stability{OUT[0]}_margins.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["scene", "params", "last_stable_factor", "first_unstable_factor", "stable_at_1", f"residual_below_{ACCURATE:g}_up_to"])
        w.writerows(old_margins)
        for (scene, params), (ok, bad) in margins.items():
            w.writerow([scene, params, ok if ok is not None else "", bad if bad is not None else "", *margin_extras(rows, scene, params)])
    mpath = os.path.join(RESULTS, f"stability{OUT[0]}_machine.txt")
    before = ""
    if partial and old and os.path.exists(mpath):
        with open(mpath) as f:
            before = "".join(l for l in f if not any(l.startswith(f"groups {g}:") for g in groups))
    with open(mpath, "w") as f:
        f.write(before + (f"groups {','.join(groups)}: " if partial else "") + line)
    try:
        plot(rows, os.path.join(RESULTS, f"stability{OUT[0]}.png"))
    except Exception as e:  # the numbers are in the CSV; never lose them over a plot
        print(f"(plot failed: {e})")


def margin_extras(rows, scene, params):
    """(stable at factor 1?, largest factor up to which every run is stable with |residual| < ACCURATE)."""
    rs = sorted((r for r in rows if r["scene"] == scene and r["params"] == params), key=lambda r: r["factor"])
    at1 = [stable(r) for r in rs if r["factor"] == 1.0]
    acc = ""
    for r in rs:
        if not (stable(r) and r["max_residual"] < ACCURATE):
            break
        acc = r["factor"]
    return (at1[0] if at1 else "", acc)


def markdown(rows, margins_csv):
    """The tables of bench/STABILITY.md from results/stability.csv and stability_margins.csv:
    margins, impact speeds, materials, rupture, every run of the margin search, guard messages."""
    def num(v):
        return float(v) if v not in ("", None) else None
    rows = [dict(r, factor=float(r["factor"]), max_residual=float(r["max_residual"]), residual_at_max=float(r["residual_at_max"]),
                 sim_time_s=float(r["sim_time_s"]), vmax=float(r["vmax"]), dt_critical_start=float(r["dt_critical_start"])) for r in rows]
    out = []
    dtc = {}
    for r in rows:
        dtc.setdefault((r["scene"], r["params"]), r["dt_critical_start"])
    out += ["| scene | case | estimate at start | stable at 1.0 | last stable | first unstable (sharpness) | headroom of the default step | \\|residual\\| < 5% up to |",
            "|---|---|---|---|---|---|---|---|"]
    for m in margins_csv:
        ok, bad = num(m["last_stable_factor"]), num(m["first_unstable_factor"])
        key = (m["scene"], m["params"])
        default = ModuleParams().timestep_safety if m["scene"].startswith("module") else 0.5  # yf.engines()'s 0.5
        out.append(f"| {m['scene']} | {m['params']} | {1e6 * dtc.get(key, math.nan):.3g} µs | {'yes' if m['stable_at_1'] == 'True' else '**no**'} | "
                   f"{'' if ok is None else f'{ok:.3g}'} | **{'' if bad is None else f'{bad:.3g}'}** | {'' if bad is None else f'{bad / default:.2g}x'} | "
                   f"{m[f'residual_below_{ACCURATE:g}_up_to']} |")
    head = ["| scene | case | factor | outcome | steps | sim. ms | wall s | residual | blow-up step | guard step | broken | max speed m/s (body) |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|"]

    def line(r):
        o = r["outcome"] if r["outcome"] == "stable" else f"**{r['outcome']}**"
        return (f"| {r['scene']} | {r['params']} | {r['factor']:.4g} | {o} | {r['steps']} | {1e3 * r['sim_time_s']:.1f} | {float(r['wall_s']):.3g} | "
                f"{100 * r['residual_at_max']:+.3g}% | {r['blowup_step'] or '—'} | {r['guard_step'] or '—'} | {r['broken']} | {r['vmax']:.3g} ({r['vmax_body']}) |")
    for group, title in (("speed", "Impact speeds"), ("material", "Stiff and soft materials"), ("rupture", "Rupture"), ("dt", "All runs of the margin search")):
        out += ["", f"### {title}", ""] + head + [line(r) for r in rows if r["group"] == group]
    out += ["", "### Guard messages (the rows where FlexGuard stopped a run; first 200 characters)", ""]
    for r in rows:
        if r["guard_step"]:
            out.append(f"- {r['scene']} {r['params']} x{r['factor']:.4g} (guard step {r['guard_step']}, outcome {r['outcome']}): `{r['guard_message'][:200]}`")
    return "\n".join(out) + "\n"


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(9, 5.5))
    keys = []
    for r in rows:
        k = (r["scene"], r["params"])
        if k not in keys:
            keys.append(k)
    for n, k in enumerate(keys):
        rs = sorted((r for r in rows if (r["scene"], r["params"]) == k), key=lambda r: r["factor"])
        if len({r["factor"] for r in rs}) < 2:
            continue
        col = plt.cm.tab20(n % 20)
        fs = [r["factor"] for r in rs if stable(r)]
        ax.plot(fs, [max(r["max_residual"], 1e-7) for r in rs if stable(r)], "o-", color=col, label=f"{k[0]} {k[1]}".strip())
        bad = [r for r in rs if not stable(r)]
        ax.plot([r["factor"] for r in bad], [max(r["max_residual"], 1e-7) if math.isfinite(r["max_residual"]) and r["max_residual"] > 0 else 1.0
                                             for r in bad], "x", color=col, ms=10, mew=2)
    ax.axvline(1.0, color="k", lw=0.8, ls=":")
    ax.axhline(BLOWUP, color="r", lw=0.8, ls="--")
    ax.set(xscale="log", yscale="log", xlabel="time step / estimated critical step (FlexTimeStepper.dtCritical)",
           ylabel="max |energy residual| / energy scale", title="stability: x = blown up (non-finite or energy created > 50%)")
    ax.legend(fontsize=7, ncol=2, loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# ---------------------------------------------------------------- suite

def main():
    ap = argparse.ArgumentParser(prog="stability.py")
    ap.add_argument("--quick", action="store_true", help="a few cases, no bisection (a few minutes)")
    ap.add_argument("--groups", default=",".join(DEFAULT_GROUPS), help="comma-separated; dtmodule (alone): the default module's time-step margin")
    ap.add_argument("--no-default-module", action="store_true", help="skip the default (full-size) module speeds")
    ap.add_argument("--plot-only", action="store_true", help="redraw results/stability.png from results/stability.csv")
    ap.add_argument("--markdown", action="store_true", help="print the tables of STABILITY.md from results/stability*.csv")
    me = next((k for k, a in enumerate(sys.argv) if os.path.basename(a) == "stability.py"), 0)
    a = ap.parse_args(sys.argv[me + 1:])
    groups = a.groups.split(",")
    OUT[0] = "_quick" if a.quick else ""
    if a.markdown:
        with open(os.path.join(RESULTS, f"stability{OUT[0]}.csv")) as f, open(os.path.join(RESULTS, f"stability{OUT[0]}_margins.csv")) as g:
            return print(markdown(list(csv.DictReader(f)), list(csv.DictReader(g))), end="")
    if a.plot_only:
        with open(os.path.join(RESULTS, "stability.csv")) as f:
            rows = [dict(r, factor=float(r["factor"]), max_residual=float(r["max_residual"])) for r in csv.DictReader(f)]
        return plot(rows, os.path.join(RESULTS, "stability.png"))
    from machine import machine_line
    line = machine_line(yade.config.version, O.numThreads)
    print(line, end="")
    print("columns: " + " | ".join(k for k in COLS if k != "group"))
    rows, margins = [], {}
    t_start = time.time()
    q = a.quick
    if "dt" in groups:
        print("== time-step margins", flush=True)
        dt_scenes = [("cantilever", "undamped, 100 N tip force", functools.partial(cantilever, 0.0, 5000 if q else 20000)),
                     ("cantilever", "damping 0.8", functools.partial(cantilever, 0.8, 5000 if q else 20000)),
                     ("net", "5 m/s", functools.partial(net, 5.0, t_end=0.01 if q else 0.03)),
                     ("sheet", "drop 10 mm", functools.partial(sheet, t_end=0.05 if q else 0.15)),
                     ("panel", "0.5 m, to rupture", functools.partial(panel)),
                     ("module small", "4.43 m/s", functools.partial(module, True, None, 0.03 if q else 0.08))]
        for scene, params, build in dt_scenes:
            print(f"-- {scene} {params}", flush=True)
            if q:
                for f in (0.5, 1.0, 1.5, 3.0):
                    rows.append(run_case(build, f, "dt", scene, params))
            else:
                margins[(scene, params)] = margin(build, "dt", scene, params, rows)
                if scene == "cantilever":  # a small step: the start of a step load, seen by the guard
                    rows.append(run_case(build, 0.1, "dt", scene, params))
    if "dtmodule" in groups:  # not in the default groups: the default module (6000 bodies, its default fill), 25 min
        if groups != ["dtmodule"]:
            raise SystemExit("--groups dtmodule runs alone (it writes results/stability_dtmodule*)")
        OUT[0] = "_dtmodule"
        print("-- module default, margin", flush=True)
        params = f"{ModuleParams().impact_speed():.2f} m/s"
        margins[("module default", params)] = margin(functools.partial(module, False, None, 0.1), "dt", "module default", params, rows)
    if rows:  # what is measured so far, in case a later group is stopped
        write(rows, margins, line, groups)
    if "material" in groups:
        print("== stiff and soft materials (E and contact moduli x scale)", flush=True)
        for scale in (100.0, 0.01):
            for scene, build in (("net", functools.partial(net, 5.0, scale, t_end=0.01 if q else 0.03)),
                                 ("sheet", functools.partial(sheet, scale, t_end=0.05 if q else 0.15))):
                params = f"E x{scale:g}"
                print(f"-- {scene} {params}", flush=True)
                if q:
                    rows.append(run_case(build, 1.0, "material", scene, params))
                else:
                    rows.append(run_case(build, 0.5, "material", scene, params))
                    margins[(scene, params)] = margin(build, "material", scene, params, rows, factors=FACTORS[2:])
                    if scale < 1:  # soft: the residual against smaller steps (is it the step or the model?)
                        for f in (0.25, 0.1, 0.05):
                            rows.append(run_case(build, f, "material", scene, params))
    if rows:  # what is measured so far, in case a later group is stopped
        write(rows, margins, line, groups)
    if "rupture" in groups:
        print("== rupture", flush=True)
        for f in ((0.5,) if q else (0.5, 1.0)):
            rows.append(run_case(functools.partial(net, 30.0, 1.0, 1770e6, 0.01 if q else 0.03), f, "rupture", "net",
                                 "30 m/s, wires 1770 MPa"))
            if not q or "dt" not in groups:
                rows.append(run_case(panel, f, "rupture", "panel", "0.5 m, to rupture"))
            # more damping (quasi-static tests use up to 0.8): the damping once booked on the driven DOFs grew with it
            rows.append(run_case(functools.partial(panel, damping=0.8), f, "rupture", "panel", "0.5 m, to rupture, damping 0.8"))
    if rows:  # what is measured so far, in case a later group is stopped
        write(rows, margins, line, groups)
    if "speed" in groups:
        fm = ModuleParams().timestep_safety
        print(f"== impact speeds (damping module, time-step factor {fm:g} = ModuleParams.timestep_safety)", flush=True)
        for v in ((5.0, 30.0) if q else (5.0, 10.0, 20.0, 30.0)):
            rows.append(run_case(functools.partial(module, True, v, 0.03 if q else 0.08), fm, "speed", "module small", f"{v:g} m/s"))
        if not q:  # the residual of the fastest impact with smaller steps
            for f in (0.5 * fm, 0.25 * fm):
                rows.append(run_case(functools.partial(module, True, 30.0, 0.08), f, "speed", "module small", "30 m/s"))
        if not (q or a.no_default_module):
            for v in (None, 15.0, 30.0):
                rows.append(run_case(functools.partial(module, False, v, 0.1), fm, "speed", "module default",
                                     f"{v:g} m/s" if v else f"{ModuleParams().impact_speed():.2f} m/s"))
    write(rows, margins, line, groups)
    if margins:
        print("== margins (factor x the estimated critical step)")
        for (scene, params), (ok, bad) in margins.items():
            at1, acc = margin_extras(rows, scene, params)
            print(f"  {scene} {params}: last stable {ok if ok is None else round(ok, 3)}, first unstable {bad if bad is None else round(bad, 3)}, "
                  f"stable at 1.0: {at1}, |residual| < {100 * ACCURATE:g}% up to {acc}")
    print(f"total wall time {time.time() - t_start:.0f} s; results in {RESULTS}")


if __name__ == "__main__":
    main()
