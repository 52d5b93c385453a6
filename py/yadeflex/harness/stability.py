"""The stability suite's cases and runner (bench/stability.py, tests/yade/test_stability.py): a
scene run at a factor of its estimated critical time step, judged by its energy balance.

Each case builder (cantilever, net, sheet, panel, punch, fabric, indenter, module) sets up O with a yadeflex scene and
returns a Case: how long to run, and the scene's external work and stop condition. run_case(build,
factor, ...) runs it with these rules and returns its row (COLS):
  - time step: FlexTimeStepper keeps estimating the critical step (safety 1, its usual interval
    and collider triggers); a PyRunner right after it sets O.dt = factor x flexDt.dtCritical at
    every step, so that factors above 1 can be run. yf.engines() uses 0.5 (timestep_safety), the
    damping module ModuleParams.timestep_safety.
  - guard: a FlexGuard with its default settings is the first engine. When it stops the run, its
    step and message are recorded, it is removed and the run goes on without it, so that every
    row says both what the guard did and what the run really did (a guard stop followed by a
    stable run is a false alarm).
  - energy balance: O.trackEnergy; residual R = (O.energy.total() - total after the first step)
    - W_ext, W_ext the external work (cantilever: the permanent tip force times the tip
    displacement; all other scenes have none: gravity is booked in O.energy as gravWork, the
    work of driven nodes and bodies, such as the tensile panel's pulled edge, as driveWork); the
    scale S = largest (sum over O.energy terms of |E_k| + |W_ext|) seen so far. Checked every
    CHECK steps (a blow-up's first step is known to CHECK steps). The row's residual is the
    largest |R| of the run over the largest S of the run, with the sign R had there (+: energy
    created).
  - outcome: 'blown up (non-finite)' when O.energy.total() or any body's position or velocity
    (scanned every SCAN steps) is not finite; 'blown up (energy created)' when R > BLOWUP x S
    for CONFIRM steps in a row, or up to the end of the run (a step load's first steps exceed
    BLOWUP x S while S is tiny: such transient episodes are counted in the detail), or when
    the largest |R| exceeds BLOWUP x the run's largest S at the end; for the damping module,
    'stopped by the module check' when the time step falls below the main job's
    --min-dt-fraction (RunSettings.min_dt_fraction) of its value at the start; 'stable'
    otherwise. Runs stop at the first of these.
"""
import builtins
import dataclasses
import functools
import math
import time

from yade import O
from yade.wrapper import PyRunner, FlexGuard

from . import scenes

from . import membrane_scenes

from . import tensile
from .. import membrane as M
from ..errors import Unstable
from ..runner import RunSettings, unstable_body
from ..materials import steel
from ..module import ModuleParams, filled_module, add_boulder, scale_lining_nodes

CHECK = 10          # steps between energy checks
SCAN = 200          # steps between scans of every body for non-finite values and the largest speed
BLOWUP = 0.5        # energy created above this fraction of the energy scale: blown up
CONFIRM = 1000      # ... if it stays above for this many steps (or goes non-finite); a step load's first steps exceed it
MIN_STEPS = 5000    # every run lasts at least this many steps
FALSE_ALARM = 0.1   # a guard stop of a run that stays stable with |residual| below this: a false alarm


# ---------------------------------------------------------------- cases
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
    mat = steel(friction_deg=30.0, tensile_strength=strength)
    mat.young = 200e9 * scale  # (past any real material's modulus at large scales: a numerical stress case, set after the builder's check)
    s = scenes.net_impact(speed=speed, sphere_young=5e9 * scale, material=mat)
    return Case(t_end=t_end, info=dict(sphere=s["sphere"]))


def sheet(scale=1.0, t_end=0.15):
    """membrane_scenes.sheet_impact: 1 x 1 m geotextile-like sheet (16 x 16 cells, E t =
    250 kN/m x scale, 0.3 kg/m2), sphere r = 0.1 m released 10 mm above it; contact moduli of
    the sheet and the sphere x scale."""
    orig = M.membrane_material
    M.membrane_material = functools.partial(orig, young=1e9 * scale)
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
    st = dict(peak=0.0)

    def done():
        f = -sum(O.forces.f(i)[ax] for i in driven)
        st["peak"] = max(st["peak"], f)
        e = (O.bodies[driven[0]].state.pos[ax] - x0) / s["length"]
        return (el.nRuptured > 0 and f < 0.3 * st["peak"]) or e >= max_elongation

    return Case(done=done, info=dict(peak=st))


def punch(contact_young=1e8, edge="held", t_end=0.06):
    """scenes.mesh_punch: a 1 x 1 m TECCO panel (edges held, or edge='rope') hit at its centre by
    a rigid 100 kg sphere (r = 0.2 m) at 4 m/s; contact modulus contact_young [Pa]."""
    s = scenes.mesh_punch(contact_young=contact_young, edge=edge)
    return Case(t_end=t_end, info=dict(sphere=s["boulder"]))


def fabric(t_end=0.4):
    """membrane_scenes.hanging_fabric: a 0.5 m square of geotextile held along one edge, released
    flat: it swings down and folds over under its own weight (no facet may tear)."""
    membrane_scenes.hanging_fabric()
    return Case(t_end=t_end)


def indenter(t_end=0.25):
    """membrane_scenes.driven_indenter: a rigid sphere held in every DOF driven down at 0.3 m/s
    into a clamped geotextile sheet (its work booked as driveWork)."""
    membrane_scenes.driven_indenter()
    return Case(t_end=t_end)


def module(small=True, speed=None, t_cap=0.08):
    """The damping module of the main job (scripts/damping_module.py): ModuleParams() or its
    --small variant, cached fill, the lining's nodes scaled as the main job scales them, boulder
    with p.engines(p.damping). Runs until the boulder
    moves up again (rebound) plus 5 ms, or t_cap [s] of simulated time."""
    p = ModuleParams.small() if small else ModuleParams()
    if speed is not None:
        p.impact_velocity = speed
    ids, _, _ = filled_module(p)
    scale_lining_nodes(ids, p.lining_node_mass)
    bid = add_boulder(p, ids)
    O.engines = [FlexGuard(label="guard")] + p.engines(p.damping)
    b = O.bodies[bid]
    st = dict(rebound=None)

    def done():
        if st["rebound"] is None and b.state.vel[2] > 0:
            st["rebound"] = O.time
        return st["rebound"] is not None and O.time > st["rebound"] + 0.005

    parts = {k: ids.bodies(key) for k, key in (("grain", "grains"), ("lining node", "lining_nodes"), ("mesh node", "mesh_nodes"))}
    return Case(t_end=t_cap, done=done, module=True, info=dict(boulder=bid, rebound=st, speed=p.impact_speed(), parts=parts))


# ---------------------------------------------------------------- runner
def _first_nonfinite():
    """Id of the first body with a non-finite position or velocity, else None."""
    bad = unstable_body()
    return bad[0] if bad else None


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
    if case.module:  # the module's check: the run stops when the step collapses (as the main job)
        ts.minDtFraction, ts.dtReference = RunSettings.min_dt_fraction, 0.0
    O.step()
    total0, t0, it0 = O.energy.total(), O.time, O.iter
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
        except Unstable as e:
            g = next((x for x in O.engines if isinstance(x, FlexGuard)), None)
            if g is not None and g.message and g.detectedIter == O.iter:  # the guard: noted, and the run goes on without it
                guard_step, guard_msg = O.iter - it0, f"{g.message} [bodies {list(g.bodies)[:5]}]"
                if not quiet:
                    print(f"    guard stopped step {guard_step}: {g.message}", flush=True)
                O.engines = [x for x in O.engines if not isinstance(x, FlexGuard)]
                continue
            if "time step collapsed" in str(e):  # the module's check (FlexTimeStepper.minDtFraction)
                outcome, blow_step, detail = "stopped by the module check", steps, str(e)
            else:  # a state gone past 1e100 (or non-finite)
                outcome, blow_step, detail = "blown up (non-finite)", first or steps, str(e)
            break
        except ValueError as e:  # a step made non-finite by the critical step of a scene left with nothing to bound it
            # (every element ruptured): a blow-up
            if "O.dt must be finite" not in str(e):
                raise
            outcome, blow_step, detail = "blown up (non-finite)", first or steps, str(e)
            break
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


# ---------------------------------------------------------------- rows
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
