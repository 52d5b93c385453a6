# Run by test_grain_engine.py in yade-double -j1 and -j2: a bed of 1960 overlapping spheres
# (sphere_bed) falling under gravity for 30 steps with its grain contacts in FlexGrainEngine,
# which runs on every thread from parallelMin = 0 listed pairs on. Prints every sphere's force
# and torque after the last step, the energy terms and the threads the engine ran on, as JSON.
import json

from yade import O

import yadeflex as yf
from sphere_bed import sphere_bed

n = sphere_bed()
O.engines = yf.engines(rolling_stiffness=1.0, rolling_friction=0.1, grains=O.materials[0])
ge = yf.grain_engine()
ge.parallelMin = 0
O.engines[[e.label for e in O.engines].index("flexDt")].dead = True
O.dt = 2e-5
O.trackEnergy = True
O.run(30, True)
out = dict(ft=[list(O.forces.f(i)) + list(O.forces.t(i)) for i in range(n)], threads=ge.threadsUsed, contacts=ge.contacts,
           energy={k: O.energy[k] for k in ("flexContactElastic", "flexFriction", "flexRolling")})
print("GRAINS " + json.dumps(out))
