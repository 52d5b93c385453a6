"""What the yade-flex engines hand to each other (pkg/yade/FlexProtocol.hpp): they need the
order yadeflex.engines() builds, and refuse another with an error naming the engines; the
time stepper's marks of unreachable pairs hold until the collider runs, and no longer, without
writing into YADE's interaction container."""
import pytest
from yade import O
from yade.wrapper import FlexTimeStepper

import yadeflex as yf
from yadeflex.scenes import sphere


def _two_spheres():
    O.reset()
    sphere((0, 0, 0), 0.01)
    sphere((0.05, 0, 0), 0.01)
    O.engines = yf.engines(gravity=(0, 0, -9.81))


def _engine(label):
    return next(e for e in O.engines if e.label == label)


@pytest.mark.parametrize("move,before", [("flexDt", "flexElements"), ("newton", "flexDt"), ("flexElements", "interactionLoop"),
                                         ("interactionLoop", "collider")])
def test_engines_out_of_order_are_refused_by_name(scene, move, before):
    _two_spheres()
    engines = list(O.engines)
    e = next(x for x in engines if x.label == move)
    engines.remove(e)
    engines.insert(engines.index(next(x for x in engines if x.label == before)), e)
    O.engines = engines
    with pytest.raises(ValueError, match=f"label '{move}'.*must come before|must come before.*label '{before}'"):
        O.step()


def test_the_default_order_and_partial_lists_run(scene):
    _two_spheres()
    O.run(5, True)
    # engines left out are not required: a list without time stepper and integrator runs
    O.engines = [e for e in O.engines if e.label not in ("flexDt", "newton")]
    O.dt = 1e-6
    O.run(2, True)
    assert O.iter == 7


def test_marks_hold_until_the_collider_runs(scene):
    """Two spheres 30 mm apart, at rest: the estimate leaves their pair out and marks it; the mark
    holds on the next steps and goes when the collider runs (forced here by dirtying the
    container), and the collider's own bookkeeping field is left as the collider set it."""
    O.reset()
    sphere((0, 0, 0), 0.01)
    sphere((0.03, 0, 0), 0.01)
    O.engines = yf.engines(gravity=(0, 0, 0), verlet=0.02)  # bounds overlap: a potential pair
    O.step()
    dt, col = _engine("flexDt"), _engine("collider")
    assert O.interactions.countReal() == 0 and len(O.interactions) == 1
    assert dt.unreachablePairs() == [(0, 1)]
    assert O.interactions.iterColliderLastRun == -1  # (YADE's value: no sentinel written)
    runs = col.numAction
    O.run(3, True)
    assert col.numAction == runs and dt.skippedPairs == 1
    O.interactions.clear()  # a change the collider must see: it runs on the next step
    O.step()
    assert col.numAction == runs + 1
    assert dt.unreachablePairs() == [(0, 1)] and O.interactions.countReal() == 0
