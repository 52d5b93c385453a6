"""What the yade-flex engines hand to each other (pkg/yade/FlexProtocol.hpp): they need the
order yadeflex.engines() builds, and refuse another with an error naming the engines; the
time stepper's marks of unreachable pairs hold until the collider runs."""
import pytest
from yade import O

import yadeflex as yf
from yadeflex.harness.scenes import sphere


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
    # the message names both engines: the one found out of place must come before the other
    with pytest.raises(ValueError, match=f"(?=.*label '{move}')(?=.*label '{before}').*must come before"):
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
    """Two spheres at rest whose bounds overlap (boxes along the diagonal) with a gap of 11 mm, far
    more than both sweeps (2 mm): the estimate leaves their pair out and marks it; the mark holds
    on the next steps, while the collider does not run."""
    O.reset()
    sphere((0, 0, 0), 0.01)
    sphere((0.022, 0.022, 0), 0.01)
    O.engines = yf.engines(gravity=(0, 0, 0), verlet=0.002)
    O.step()
    dt, col = _engine("flexDt"), _engine("collider")
    assert O.interactions.countReal() == 0 and len(O.interactions) == 1
    assert dt.unreachablePairs() == [(0, 1)]
    runs = col.numAction
    O.run(3, True)
    assert col.numAction == runs and dt.skippedPairs == 1
    # that the collider's next run retires them: test_timestep.py's teleported body (the contact
    # is found one step late, not never)


def test_marks_are_not_read_after_the_engines_are_replaced(scene):
    """The marks belong to the collider whose runs retire them. With O.engines replaced (here by a
    list without the time stepper, at a fixed step), the old collider never runs again: its marks
    must not be read, else the marked pair would be left out for good. The two spheres of the test
    above, marked; then the second moved into contact (5 mm overlap) and the engines replaced:
    the contact is found on the first step."""
    O.reset()
    sphere((0, 0, 0), 0.01)
    sphere((0.022, 0.022, 0), 0.01)
    O.engines = yf.engines(gravity=(0, 0, 0), verlet=0.002)
    O.step()
    assert _engine("flexDt").unreachablePairs() == [(0, 1)] and O.interactions.countReal() == 0
    O.bodies[1].state.pos = (0.015, 0, 0)
    O.engines = [e for e in yf.engines(gravity=(0, 0, 0), verlet=0.002) if e.label != "flexDt"]
    O.dt = 1e-6
    O.step()
    assert O.interactions.countReal() == 1
    assert O.forces.f(1)[0] > 0  # pushed away from the first sphere


def test_two_scenes_stepped_in_turn_keep_their_own_state(scene):
    """Each scene has its own engine state (pkg/yade/FlexSceneState.hpp). Two scenes of O, stepped
    in turn: the marks of the first survive the second's estimates (its marked pair is still left
    out without being read, no collider run between), and a wire sagging in the second moves exactly
    as it does alone."""
    from yadeflex import builders as B

    def marked_pair():
        sphere((0, 0, 0), 0.01)
        sphere((0.022, 0.022, 0), 0.01)
        O.engines = yf.engines(gravity=(0, 0, 0), verlet=0.002)
        _engine("interactionLoop").quickReject = False  # (the pair left out for its mark only)

    def net():  # a wire clamped at one end, sagging under its own weight, its step estimated at every step
        B.chain([(0, 0, 0), (0.3, 0, 0)], 0.002, yf.steel(), segments=6, fixed=[0])
        O.engines = yf.engines(gravity=(0, 0, -9.81))
        _engine("flexDt").interval = 1

    def positions():
        return [tuple(b.state.pos) for b in O.bodies if b is not None]

    # the net alone, 40 steps
    O.reset()
    net()
    O.run(40, True)
    alone = positions()
    # the two scenes in turn
    O.reset()
    marked_pair()
    O.step()
    assert _engine("flexDt").unreachablePairs() == [(0, 1)]
    runs = _engine("collider").numAction
    other = O.addScene()
    O.switchToScene(other)
    net()
    try:
        recalled = []
        for _ in range(40):
            O.switchToScene(other)
            O.step()
            O.switchToScene(0)
            O.step()
            recalled.append(_engine("interactionLoop").recalledSkips)
        # the first scene's mark still read on every step: from its second step on, the loop
        # leaves the pair out from its record of it, which lasts while the marks are the same
        assert recalled[1:] == [1] * 39, recalled
        assert _engine("collider").numAction == runs
        O.switchToScene(other)
        assert positions() == alone
    finally:
        O.switchToScene(0)


@pytest.mark.parametrize("label", ["collider", "flexElements", "flexDt", "newton"])
def test_engines_inside_a_parallel_engine_are_refused(scene, label):
    """A ParallelEngine runs its slave groups at the same time; the yade-flex engines share the
    scene's bodies and interactions and must run one after another. Looked at on every step (a
    slave can be swapped without a change of O.engines). (Refused by the first yade-flex engine
    outside it: an exception thrown inside the ParallelEngine's threads ends the process.)"""
    from yade.wrapper import ParallelEngine, PyRunner
    _two_spheres()
    O.step()
    engines = list(O.engines)
    i = engines.index(_engine(label))
    engines[i] = ParallelEngine([[engines[i]], [PyRunner(command="pass")]])
    O.engines = engines
    with pytest.raises(ValueError, match=f"ParallelEngine.*holds {type(_engine_in(engines[i])).__name__}.*at the same time"):
        O.step()


def _engine_in(par):
    return par.slaves[0][0] if isinstance(par.slaves[0], list) else par.slaves[0]


def test_the_readme_names_every_engine_label(scene):
    """The README's row of engines() lists the labels a script finds the engines by; they are the
    labels engines(guard=True) gives (and the law's)."""
    import os
    import re
    readme = open(os.path.join(os.path.dirname(__file__), "..", "..", "README.md")).read()
    row = next(line for line in readme.splitlines() if line.startswith("| `engines("))
    listed = set(re.findall(r"`(\w+)`", row.split("labelled", 1)[1].split("(find one", 1)[0])) - {"contact_law"}
    law_labels = {f.label for e in yf.engines() if hasattr(e, "lawDispatcher") for f in e.lawDispatcher.functors if f.label}
    assert listed == {e.label for e in yf.engines(guard=True) if e.label} | law_labels, listed
