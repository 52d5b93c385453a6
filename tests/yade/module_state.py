"""The reduced damping module under load, shared by tests that compare settings on one state
(test_loop.py in-process, scripts/sums_threads_scene.py in yade-double -j2)."""
from yade import O

from yadeflex.module import ModuleParams, filled_module, add_boulder


def reduced_impact(cache_dir, steps_after_contact=200, grain_engine=False):
    """On O: the reduced module (filled, or loaded from the folder cache_dir) with its boulder and
    the main job's engines without damping, energies tracked, run until the boulder touches and
    then `steps_after_contact` steps (contacts under load). grain_engine: ModuleParams.engines'
    (False, the default here: the grain-grain contacts stay in the interaction loop, whose
    machinery the scenes built on this exercise). Returns the boulder's id and the module's ids."""
    p = ModuleParams.small()
    ids, _, _ = filled_module(p, cache_dir=cache_dir)
    bid = add_boulder(p, ids)
    O.engines = p.engines(0.0, grain_engine=grain_engine)
    O.trackEnergy = True
    while O.forces.f(bid).norm() == 0:
        O.run(50, True)
    O.run(steps_after_contact, True)
    return bid, ids
