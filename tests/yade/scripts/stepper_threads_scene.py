"""FlexTimeStepper's estimate on a bed of spheres big enough for its parallel pass (more than
4096 interactions): prints the estimate made in the first step (with its unreachable-pair marks,
as action() makes it) and the number of pairs it left out, then, after the step, the estimate
again (critical()) and the serial list of the pairs left out, as JSON after 'EST '.
Run: yade-double -n -jN -x stepper_threads_scene.py"""
import json
import random

from yade import O, Vector3
from yade.wrapper import FrictMat

import yadeflex as yf
from yadeflex.module import _sphere_body

random.seed(3)
O.reset()
mat = FrictMat(young=1e8, poisson=0.3, density=2650, frictionAngle=0.6)
O.materials.append(mat)
n = 0
for i in range(14):
    for j in range(14):
        for k in range(10):
            r = random.uniform(0.009, 0.011)
            x = Vector3(0.02 * i + random.uniform(-1e-3, 1e-3), 0.02 * j + random.uniform(-1e-3, 1e-3), 0.02 * k + 0.011)
            _sphere_body(x, r, mat)
            n += 1
O.engines = yf.engines(gravity=(0, 0, -9.81), damping=0.0, timestep_safety=0.5)
O.dt = 1e-9
O.step()  # the collider finds the pairs; FlexTimeStepper makes its estimate and marks
st = [e for e in O.engines if e.label == "flexDt"][0]
print("EST " + json.dumps(dict(spheres=n, interactions=len(O.interactions.all(False)), real=O.interactions.countReal(),
                               dtCritical=st.dtCritical, skipped=st.skippedPairs, critical=st.critical(),
                               unreachable=sorted(sorted(p) for p in st.unreachablePairs()))), flush=True)
