"""FlexTimeStepper's estimate on a bed of spheres big enough for its parallel pass (more than
4096 interactions): prints the estimate made in the first step (with its unreachable-pair marks,
as action() makes it) and the number of pairs it left out, then, after the step, the estimate
again (critical()) and the serial list of the pairs left out, as JSON after 'EST '.
Run: yade-double -n -jN -x stepper_threads_scene.py"""
import json

from yade import O

import yadeflex as yf
from sphere_bed import sphere_bed

n = sphere_bed()
O.engines = yf.engines(gravity=(0, 0, -9.81), damping=0.0, timestep_safety=0.5)
O.dt = 1e-9
O.step()  # the collider finds the pairs; FlexTimeStepper makes its estimate and marks
st = [e for e in O.engines if e.label == "flexDt"][0]
print("EST " + json.dumps(dict(spheres=n, interactions=len(O.interactions.all(False)), real=O.interactions.countReal(),
                               dtCritical=st.dtCritical, skipped=st.skippedPairs, critical=st.critical(),
                               unreachable=sorted(sorted(p) for p in st.unreachablePairs()))), flush=True)
