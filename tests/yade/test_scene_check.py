"""The scene check during O.run(): a value a script sets while the run goes on (from a PyRunner, or
from the interactive prompt while O.run() runs in the background), and a value an engine makes
non-finite, are refused with the body and the field named; the run stops there.

O.step() checks the whole scene before every step (test_errors, test_fuzz). Inside one O.run() the
full pass runs when something says a script can have run (a periodic engine such as a PyRunner
ran, the engine list or the bodies changed) and at least every FULL_CHECK_PERIOD steps, and the
integrator refuses the motions it makes non-finite."""
import math
import re
import time

import pytest
from yade import O
from yade.minieigenHP import Vector3
from yade.wrapper import PyRunner, TranslationEngine

import yadeflex as yf
from yadeflex.harness import scenes

FULL_CHECK_PERIOD = 32  # tuning::kFullCheckPeriod (pkg/yade/speed/FlexTuning.hpp)


def _net():
    s = scenes.net_impact(n=6, spacing=0.05, wire_radius=0.002, sphere_radius=0.06, speed=3.0)
    O.step()
    return s


def _run_refused(n):
    """O.run(n, True); (the refusal's message, whether it came from the run) or (None, True) if the
    run went through. YADE 2023.02a's O.wait() misses an error when the run thread has already
    stopped by the time it looks (test_guard.test_nan_is_reported_through_O_run_and_wait): a run
    that stopped early is asked again with O.step(), whose full check names what is wrong now."""
    start = O.iter
    try:
        O.run(n, True)
    except RuntimeError as e:
        return str(e), True
    if O.iter == start + n:
        return None, True
    stopped = O.iter
    try:
        O.step()
    except (RuntimeError, ValueError) as e:
        assert O.iter == stopped
        return str(e), False
    pytest.fail(f"the run stopped at iteration {stopped} of {start + n} without an error")


def _run_in_background():
    """O.run() as from YADE's prompt, returning once its thread has taken a step (or stopped).
    YADE 2023.02a's run thread is detached: O.pause() and then O.reset() (the scene fixture's)
    before that thread has started free the ThreadRunner it is about to use, and the process
    crashes later, in another test (O.run(); O.pause(); O.wait(); O.reset() in a loop segfaults
    within a few hundred rounds; waiting for the first step, 3000 rounds pass)."""
    start = O.iter
    O.run()
    t0 = time.time()
    while O.iter == start and O.running:
        assert time.time() - t0 < 600, "the run thread took no step in 600 s"
        time.sleep(0.001)


def _py(name, fn):
    import __main__
    setattr(__main__, name, fn)


@pytest.mark.parametrize("attr, value, field", [("vel", Vector3(0, math.nan, 0), "state.vel must be finite"), ("mass", -1.0, "state.mass"),
                                                 ("radius", 0.0, "shape.radius")])
def test_a_value_a_pyrunner_sets_is_refused_at_the_next_step(scene, attr, value, field):
    s = _net()
    victim = s["sphere"]
    at = O.iter + 40  # (past a full check of the period: the PyRunner's run is what triggers this one)

    def spoil():
        b = O.bodies[victim]
        setattr(b.shape if attr == "radius" else b.state, attr, value)

    _py("_spoil_scene", spoil)
    O.engines = O.engines + [PyRunner(command="_spoil_scene()", iterPeriod=1, firstIterRun=at, nDo=1)]
    message, _ = _run_refused(100)
    assert message is not None and f"body #{victim} (Sphere): {field}" in message
    assert O.iter == at + 1  # the PyRunner ran at the end of step `at`; the next step is refused before it computes


def test_a_value_set_from_the_prompt_while_running_is_refused_within_the_period(scene):
    """A negative mass keeps every motion finite for a while: only the periodic full pass finds it."""
    s = _net()
    victim = s["sphere"]
    _run_in_background()
    assert O.running
    O.bodies[victim].state.mass = -1.0
    set_by = O.iter  # (read after setting: the value was set at this iteration or before)
    t0 = time.time()
    while O.running and time.time() - t0 < 30:
        time.sleep(0.01)
    assert not O.running, "the run went on with a negative mass"
    assert set_by <= O.iter <= set_by + FULL_CHECK_PERIOD + 1
    with pytest.raises(ValueError, match=f"body #{victim} \\(Sphere\\): state.mass must be finite .* and >= 0"):
        O.step()


def test_a_step_run_again_after_a_refusal_is_checked_again(scene):
    """A step the integrator refused left O.iter where it was; the same iteration run again by
    O.step() is checked again (not taken as checked already)."""
    s = _net()
    victim = s["grid"][3][2]
    pos, vel = Vector3(O.bodies[victim].state.pos), Vector3(O.bodies[victim].state.vel)
    O.forces.setPermF(victim, Vector3(0, 0, math.nan))
    start = O.iter
    with pytest.raises(ValueError, match="became non-finite"):
        O.step()
    assert O.iter == start
    O.forces.setPermF(victim, Vector3(0, 0, 0))
    O.bodies[victim].state.pos, O.bodies[victim].state.vel = pos, vel
    O.bodies[s["sphere"]].shape.radius = 0.0
    with pytest.raises(ValueError, match=f"body #{s['sphere']} \\(Sphere\\): shape.radius"):
        O.step()
    assert O.iter == start


def _refused_in_the_step(message, from_run, victim, kind, start):
    """The integrator refused the motion in the step that made it: that step did not count (O.iter
    unchanged; refused by the next step's check instead, it would have)."""
    assert message is not None
    assert O.iter == start
    if from_run:
        assert f"body #{victim} ({kind}): state.vel became non-finite" in message and f"from iteration {start}" in message
    else:  # (O.step's full check, on the state the refused step left)
        assert re.search(f"body #{victim} \\({kind}\\): state.(vel|pos) must be finite", message)
    return message


def test_a_motion_an_engine_makes_non_finite_is_refused_in_that_step(scene):
    s = _net()
    victim = s["sphere"]
    assert type(O.engines[-1]).__name__ == "FlexNewtonIntegrator"
    # (just before the integrator, as kinematic engines go: after the step's check)
    O.engines = O.engines[:-1] + [TranslationEngine(ids=[victim], translationAxis=(1, 0, 0), velocity=math.nan)] + O.engines[-1:]
    start = O.iter
    _refused_in_the_step(*_run_refused(50), victim, "Sphere", start)


def test_a_non_finite_permanent_force_is_refused_in_the_step_it_acts(scene):
    s = _net()
    victim = s["grid"][3][2]
    O.forces.setPermF(victim, Vector3(0, 0, math.nan))
    start = O.iter
    message, from_run = _run_refused(50)
    _refused_in_the_step(message, from_run, victim, "FlexNode", start)
    if from_run:
        assert re.search(r"the force on the body was \([^)]*nan\)", message)


def test_bodies_added_by_a_pyrunner_are_checked(scene):
    _net()
    at = O.iter + 40

    def add():
        yf.node((0.5, 0.5, 0.5), 0.01)  # free, and without a cylinder it has no mass

    _py("_add_bad_body", add)
    O.engines = O.engines + [PyRunner(command="_add_bad_body()", iterPeriod=1, firstIterRun=at, nDo=1)]
    message, _ = _run_refused(100)
    assert message is not None and "state.mass" in message and "free body" in message
    assert O.iter == at + 1


def test_a_clean_run_is_not_refused_and_gives_the_same_motion_as_stepping(scene):
    """The same 200 steps by O.run() (full checks only now and then) and by O.step() (a full check
    at every step): same positions to the last bit."""
    _net()
    O.saveTmp("start")
    O.loadTmp("start")
    assert _run_refused(200) == (None, True)
    by_run = [tuple(b.state.pos) for b in O.bodies if b is not None]
    O.loadTmp("start")
    for _ in range(200):
        O.step()
    by_step = [tuple(b.state.pos) for b in O.bodies if b is not None]
    assert by_run == by_step


# ---- yf.step_until: the steps of a recording loop without the interpreter between them


def test_step_until_takes_the_same_steps_as_O_step(scene):
    _net()
    O.saveTmp("start")
    O.loadTmp("start")
    t_end = O.time + 150.5 * O.dt
    n = yf.step_until(t_end, 10 ** 6)
    by_until = ([tuple(b.state.pos) for b in O.bodies if b is not None], O.iter, O.time)
    O.loadTmp("start")
    k = 0
    while O.time < t_end:
        O.step()
        k += 1
    assert n == k and by_until == ([tuple(b.state.pos) for b in O.bodies if b is not None], O.iter, O.time)
    assert yf.step_until(t_end, 10) == 0  # (already there)
    assert yf.step_until(math.inf, 7) == 7 and yf.step_until(math.inf, 0) == 0


def test_step_until_checks_what_the_script_changed_and_what_the_steps_make(scene):
    s = _net()
    start = O.iter
    O.bodies[s["sphere"]].state.mass = -1.0
    with pytest.raises(ValueError, match=f"body #{s['sphere']} \\(Sphere\\): state.mass"):
        yf.step_until(math.inf, 100)
    assert O.iter == start
    O.bodies[s["sphere"]].state.mass = 1.0
    victim = s["grid"][3][2]
    O.forces.setPermF(victim, Vector3(0, 0, math.nan))
    with pytest.raises(ValueError, match=f"body #{victim} \\(FlexNode\\): state.vel became non-finite"):
        yf.step_until(math.inf, 100)
    assert O.iter == start


def test_step_until_runs_pyrunners_and_checks_what_they_change(scene):
    s = _net()
    calls = []
    _py("_count_call", lambda: calls.append(O.iter))
    at = O.iter + 40
    _py("_spoil_radius", lambda: setattr(O.bodies[s["sphere"]].shape, "radius", -0.1))
    O.engines = O.engines + [PyRunner(command="_count_call()", iterPeriod=10),
                             PyRunner(command="_spoil_radius()", iterPeriod=1, firstIterRun=at, nDo=1)]
    with pytest.raises(ValueError, match=f"body #{s['sphere']} \\(Sphere\\): shape.radius"):
        yf.step_until(math.inf, 100)
    assert O.iter == at + 1 and len(calls) == 4


@pytest.mark.parametrize("args, match", [((math.nan, 10), "time"), ((1.0, -1), "max_steps"), ((1.0, 2.5), "max_steps"), (("1", 10), "time")])
def test_step_until_refuses_bad_arguments(scene, args, match):
    _net()
    with pytest.raises(ValueError, match=match):
        yf.step_until(*args)


def test_step_until_is_refused_while_running(scene):
    _net()
    _run_in_background()
    try:
        with pytest.raises(RuntimeError, match="running"):
            yf.step_until(math.inf, 10)
    finally:
        O.pause()
        O.wait()
