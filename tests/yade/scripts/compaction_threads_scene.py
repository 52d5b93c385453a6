# Run by test_threads.py in yade-double -j2: the reduced damping module a few hundred steps into
# its impact; one step from that state with the loop's copy of the contacts off (compactEvery 0)
# and at that step (compactEvery 1, on every thread from 1024 interactions). Prints, per setting,
# the contacts it could copy before the step, the count it copied and every contact's geometry and
# physics after the step as JSON. Argument: the folder of the filled module (the tests' cache).
import json
import sys

from yade import O

from module_state import reduced_impact


def contacts():
    return [i for i in O.interactions.all(False) if type(i.geom).__name__ == "FlexContactGeom" and type(i.phys).__name__ == "FrictPhys"]


reduced_impact(sys.argv[1])
O.saveTmp("compaction")
out = {}
for name, every in (("off", 0), ("on", 1)):
    O.loadTmp("compaction")
    loop = [e for e in O.engines if e.label == "interactionLoop"][0]
    loop.compactEvery = every
    before = len(contacts())
    O.step()
    rows = sorted([i.id1, i.id2, i.geom.penetrationDepth, i.geom.plasticOverlap, *i.geom.normal, *i.geom.contactPoint, *i.phys.normalForce,
                   *i.phys.shearForce, i.phys.kn, i.phys.ks] for i in contacts())
    out[name] = dict(rows=rows, before=before, compacted=loop.compactedContacts, interactions=len(O.interactions), threads=O.numThreads)
print("COMPACT " + json.dumps(out))
