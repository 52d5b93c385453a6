# Run by test_threads.py in yade-double -j2: FlexInteractionLoop's copy of the contacts
# (compactEvery) on a bed of spheres (sphere_bed: more than 4096 interactions, contacts over the
# whole container). Per setting, compactEvery 0 and 1: the bed built, one step with the loop and
# the collider on one thread (the same state in both), then one step on every thread with the
# collider left out, so that the copy sees the container listed here, each thread its part n t / 2
# to n (t + 1) / 2.
# Prints the contacts it could copy in each part, the count and blocks it copied and every
# contact's geometry and physics after the step as JSON.
import json

from yade import O

import yadeflex as yf
from sphere_bed import sphere_bed


def movable(i):
    return type(i.geom).__name__ == "FlexContactGeom" and type(i.phys).__name__ == "FrictPhys"


out = {}
for name, every in (("off", 0), ("on", 1)):
    sphere_bed()
    O.engines = yf.engines(gravity=(0, 0, -9.81), damping=0.0, timestep_safety=0.5)
    loop = next(e for e in O.engines if e.label == "interactionLoop")
    collider = next(e for e in O.engines if e.label == "collider")
    # the first step on one thread where the order of additions depends on the threads: the
    # collider's sort (the order of the container) and the loop (the sums of the forces)
    loop.compactEvery = 0
    loop.ompThreads = collider.ompThreads = 1
    O.dt = 1e-9
    O.step()
    loop.ompThreads = -1
    loop.compactEvery = every
    collider.dead = True
    listed = O.interactions.all(False)
    n = len(listed)
    parts = [sum(movable(i) for i in listed[n * t // 2:n * (t + 1) // 2]) for t in (0, 1)]
    O.step()
    rows = sorted([i.id1, i.id2, i.geom.penetrationDepth, i.geom.plasticOverlap, *i.geom.normal, *i.geom.contactPoint, *i.phys.normalForce,
                   *i.phys.shearForce, i.phys.kn, i.phys.ks] for i in O.interactions.all(False) if movable(i))
    out[name] = dict(rows=rows, before=sum(parts), parts=parts, compacted=loop.compactedContacts, blocks=loop.compactedBlocks, interactions=n,
                     threads=O.numThreads)
print("COMPACT " + json.dumps(out))
