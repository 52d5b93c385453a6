"""One exception for a run that became unstable, yadeflex.Unstable (a ValueError and a
RuntimeError), from each place that finds it: the integrator, the time stepper (a collapsed
critical step) and FlexGuard; each blown up on purpose."""
import math

import pytest
from yade import O
from yade.wrapper import FlexTimeStepper, FlexGuard

import yadeflex as yf
from yadeflex.harness import scenes


def test_unstable_is_a_value_error_and_a_runtime_error():
    assert issubclass(yf.Unstable, ValueError) and issubclass(yf.Unstable, RuntimeError)


# Central differences blow up above the critical step: with the time stepper taken out and the
# step set at 20x the critical one, the integrator refuses the first motion that is no longer
# finite and names the body.
def test_a_step_far_above_the_critical_one_raises_unstable(scene):
    scenes.drop_on_surface("net", "wall", drop=0.0)
    crit = yf.critical_timestep()
    O.engines = [e for e in O.engines if not isinstance(e, FlexTimeStepper)]
    O.dt = 20 * crit
    with pytest.raises(yf.Unstable, match=r"body #\d+ .*(non-finite|must be finite)"):
        yf.step_until(math.inf, 100000)


# The floor's contacts made a million times stiffer in the middle of a run: the next estimate of
# the critical step falls below a tenth of the one before (the bars' bound gave it: about 1/70 of
# it, sqrt of the ratio of the stiffnesses), below FlexTimeStepper.minDtFraction: the run
# stops and names the body that sets it, instead of going on at a vanishing step.
def test_a_collapsed_time_step_raises_unstable(scene):
    s = scenes.drop_on_surface("net", "wall", drop=0.0)
    ts = next(e for e in O.engines if isinstance(e, FlexTimeStepper))
    ts.minDtFraction = 0.1
    yf.step_until(math.inf, 200)
    assert ts.dtReference > 0 and ts.dtCritical >= 0.1 * ts.dtReference
    floor = O.bodies[s["floor"][0]].material
    floor.young *= 1e6
    for n in s["nodes"]:
        O.bodies[n].material.young *= 1e6
    for i in O.interactions:  # (the contacts already made keep the stiffness they were given)
        i.phys.kn *= 1e6
    with pytest.raises(yf.Unstable, match=r"critical time step collapsed .* set by body #\d+"):
        yf.step_until(math.inf, 200)


def test_flexguard_stops_with_unstable(scene):
    scenes.drop_on_surface("net", "wall", drop=0.0)
    crit = yf.critical_timestep()
    O.engines = [FlexGuard(label="guard")] + [e for e in O.engines if not isinstance(e, FlexTimeStepper)]
    O.dt = 3 * crit
    with pytest.raises(yf.Unstable, match="FlexGuard: instability"):
        yf.step_until(math.inf, 100000)
