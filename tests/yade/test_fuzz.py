"""Seeded fuzz of scene edits from Python: whatever a script assigns between two steps (or a
PyRunner during O.run), the next step raises an exception that names the body, material or engine and the field, or runs on with
every value finite. Never a crash, never a silent NaN.

Each case runs in a forked copy of this process (a crash kills only the copy): the copy applies
one edit to a scene holding every kind of body (wire net, membrane sheet, spheres) and steps it."""
import math
import os
import random

import pytest
from yade import O
from yade.minieigenHP import Vector3
from yade.wrapper import FlexCylinder, FlexFacet, FlexNode, Sphere, FlexMat, FlexMembraneMat, PyRunner

import yadeflex as yf
from yadeflex.harness import scenes
from yadeflex.membrane import sheet, geotextile

SEED, CASES, STEPS = 20261203, 400, 5
RUN_EDIT_AT, RUN_STEPS = 10, 15  # (the scene check's periodic full pass: every 32 steps from the run's first)
CLEAN, HARMLESS, SILENT, UNNAMED = 10, 11, 12, 13
BAD_REALS = (math.nan, math.inf, -math.inf, 0.0, -1.0, -1e-9, 1e300, -1e300)
BAD_IDS = (-1, -7, 10 ** 6, 2 ** 31 - 1)
NAMES = ("body #", "O.dt", "No TimeStepper", "material", "NewtonIntegrator", "FlexTimeStepper", "Law2_", "must be", "is not")


def _scene():
    s = scenes.net_impact(n=5, spacing=0.05, wire_radius=0.002, sphere_radius=0.03, speed=2.0, gap=1e-4)
    sheet(3, 3, (0.1, 0.1), 0.001, geotextile(), origin=(0.0, 0.0, -0.05))
    O.engines = yf.engines()
    O.trackEnergy = True
    for _ in range(5):
        O.step()
    by = lambda cls: [b.id for b in O.bodies if b is not None and isinstance(b.shape, cls)]
    return dict(cylinders=by(FlexCylinder), facets=by(FlexFacet), nodes=by(FlexNode), spheres=by(Sphere))


def _edits(ids, rnd):
    """One random edit: (description, function applying it)."""
    kind = rnd.choice(("cyl_node", "facet_node", "radius", "state", "material", "dt", "engine", "erase", "reshape"))
    if kind in ("cyl_node", "facet_node"):
        group = ids["cylinders"] if kind == "cyl_node" else ids["facets"]
        b = rnd.choice(group)
        attr = rnd.choice(("node1", "node2") if kind == "cyl_node" else ("node1", "node2", "node3"))
        v = rnd.choice(BAD_IDS + (rnd.choice(ids["spheres"]), rnd.choice(ids["cylinders"]), rnd.choice(ids["facets"]),
                                  rnd.choice(ids["nodes"]), getattr(O.bodies[b].shape, "node1")))
        return f"#{b}.shape.{attr} = {v}", lambda: setattr(O.bodies[b].shape, attr, v)
    if kind == "radius":
        b = rnd.choice(ids["cylinders"] + ids["facets"] + ids["spheres"])
        v = rnd.choice(BAD_REALS)
        return f"#{b}.shape.radius = {v}", lambda: setattr(O.bodies[b].shape, "radius", v)
    if kind == "state":
        b = rnd.choice(ids["nodes"] + ids["spheres"])
        attr = rnd.choice(("pos", "vel", "angVel", "mass", "inertia"))
        v = rnd.choice(BAD_REALS)
        if attr in ("mass",):
            val = v
        else:
            k = rnd.randrange(3)
            base = Vector3(getattr(O.bodies[b].state, attr))
            base[k] = v
            val = base
        return f"#{b}.state.{attr} = {val}", lambda: setattr(O.bodies[b].state, attr, val)
    if kind == "material":
        b = rnd.choice(ids["cylinders"] + ids["facets"] + ids["spheres"])
        m = O.bodies[b].material
        attrs = ["young", "poisson", "frictionAngle"]
        if isinstance(m, FlexMat):
            attrs += ["elementYoung", "beamPoisson", "bendingFactor", "yieldStress", "hardening", "tensileStrength", "ruptureStrain",
                      "wireSlackScale", "wireForceRatio"]
        if isinstance(m, FlexMembraneMat):
            attrs += ["stiffness", "membranePoisson", "membranePoisson"]
        attr = rnd.choice(attrs)
        v = rnd.choice(BAD_REALS + (0.5, 1.0, -0.2))
        return f"#{b}.material.{attr} = {v}", lambda: setattr(m, attr, v)
    if kind == "dt":
        v = rnd.choice(BAD_REALS)
        return f"O.dt = {v}", lambda: setattr(O, "dt", v)
    if kind == "engine":
        label, attr = rnd.choice((("newton", "damping"), ("newton", "gravity"), ("flexDt", "safety"), ("flexDt", "interval"),
                                  ("flexLaw", "rollingStiffness"), ("flexLaw", "rollingFriction"), ("flexLaw", "onsetFactor")))
        v = rnd.choice(BAD_REALS + (1.0, 1.5))
        if attr == "gravity":
            v = Vector3(0, v, -9.81)
        elif attr == "interval":
            v = rnd.choice((0, -1, -(2 ** 31)))
        eng = (lambda: yf.contact_law()) if label == "flexLaw" else (lambda: next(e for e in O.engines if e.label == label))
        return f"{label}.{attr} = {v}", lambda: setattr(eng(), attr, v)
    if kind == "erase":
        b = rnd.choice(ids["nodes"] + ids["cylinders"] + ids["facets"] + ids["spheres"])
        return f"O.bodies.erase({b})", lambda: O.bodies.erase(b)
    b = rnd.choice(ids["nodes"])
    return f"#{b}.shape = Sphere", lambda: setattr(O.bodies[b], "shape", Sphere(radius=0.002))


def _all_finite():
    for b in O.bodies:
        if b is None:
            continue
        st = b.state
        for v in (st.pos, st.vel, st.angVel):
            if not all(math.isfinite(x) for x in v):
                return False
        if not (math.isfinite(O.forces.f(b.id).norm()) and math.isfinite(O.forces.t(b.id).norm())):
            return False
    return math.isfinite(O.energy.total()) and math.isfinite(O.dt)


def _run_with_edit(edit):
    """The edit made by a PyRunner at the end of step RUN_EDIT_AT of O.run(RUN_STEPS, True), as a
    script does mid-run: past the run's first steps, which are checked in full anyway, and before
    the periodic full pass, so that only the PyRunner's having run makes the next step check it.
    YADE's O.wait() can miss the run thread's error when that thread has already stopped
    (test_guard): a run that stopped early is asked again with O.step()."""
    import __main__
    __main__._fuzz_edit = edit
    O.engines = O.engines + [PyRunner(command="_fuzz_edit()", iterPeriod=1, firstIterRun=O.iter + RUN_EDIT_AT, nDo=1)]
    target = O.iter + RUN_STEPS
    O.run(RUN_STEPS, True)
    if O.iter != target:
        O.step()  # (raises what stopped the run)
        raise RuntimeError(f"the run stopped at iteration {O.iter} of {target} without an error")


def _case(edit, during_run):
    """Runs in the forked copy: the exit status is the outcome."""
    try:
        try:
            if during_run:
                _run_with_edit(edit)
            else:
                edit()
                for _ in range(STEPS):
                    O.step()
        except Exception as e:  # noqa: BLE001 (any exception is a refusal; its text is checked)
            return CLEAN if any(n in str(e) for n in NAMES) else UNNAMED
        return HARMLESS if _all_finite() else SILENT
    except BaseException:  # noqa: BLE001
        return UNNAMED


@pytest.mark.parametrize("during_run", [False, True], ids=["between O.step calls", "by a PyRunner during O.run"])
def test_scene_edits_from_python_never_crash_and_never_leave_a_silent_nan(scene, during_run):
    ids = _scene()
    rnd = random.Random(SEED)
    outcomes, bad = {}, []
    for k in range(CASES):
        what, edit = _edits(ids, rnd)
        pid = os.fork()
        if pid == 0:  # the copy: never returns into pytest
            code = 1
            try:
                code = _case(edit, during_run)
            finally:
                os._exit(code)
        _, status = os.waitpid(pid, 0)
        if os.WIFSIGNALED(status):
            outcome = f"crash (signal {os.WTERMSIG(status)})"
        else:
            outcome = {CLEAN: "clean error", HARMLESS: "ran on, finite", SILENT: "silent NaN", UNNAMED: "unnamed error"}.get(
                os.WEXITSTATUS(status), f"exit {os.WEXITSTATUS(status)}")
        outcomes[outcome] = outcomes.get(outcome, 0) + 1
        if outcome not in ("clean error", "ran on, finite"):
            bad.append(f"case {k}: {what}: {outcome}")
    print(f"fuzz, seed {SEED}, {CASES} cases, {'during O.run' if during_run else 'between steps'}: {outcomes}")
    assert not bad, "\n".join(bad[:20])
    assert outcomes.get("clean error", 0) >= CASES // 2  # the edits are bad ones: most must be refused
