# Run by test_threads.py in yade-double -j2: the reduced damping module a few hundred steps into
# its impact; one step from that state with each setting of the per-thread force sums
# (FlexInteractionLoop.threadSums; FlexElementEngine.parallelMin 1: both element loops on two
# threads, with their sums; huge: serial, addForce per node). Prints, per setting, every body's
# force and torque after the step as JSON. Argument: the folder of the filled module (the tests' cache).
import json
import sys

from yade import O

from module_state import reduced_impact

bid, ids = reduced_impact(sys.argv[1])
O.saveTmp("sums")
out = {}
for name, sums, pmin in (("reference", False, 10**9), ("sums", True, 1), ("sums_default", True, None)):
    O.loadTmp("sums")
    loop = [e for e in O.engines if e.label == "interactionLoop"][0]
    elem = [e for e in O.engines if e.label == "flexElements"][0]
    loop.threadSums = sums
    loop.threadSumsMin = 0  # (the reduced module has fewer interactions than the default minimum)
    if pmin is not None:
        elem.parallelMin = pmin
    for _ in range(3):  # (the loop's split among threads uses the last step's block times)
        O.step()
    f = [list(O.forces.f(b.id)) + list(O.forces.t(b.id)) for b in O.bodies if b is not None]
    out[name] = dict(ft=f, usedThreadSums=loop.usedThreadSums, real=O.interactions.countReal(), iter=O.iter,
                     threads=O.numThreads, cylinders=len(ids["mesh_cylinders"]), facets=len(ids["lining"]))
print("SUMS " + json.dumps(out))
