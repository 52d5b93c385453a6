# Run by test_threads.py in yade-double with -j1 / -j2; prints one JSON line.
#   threads_guard_scene.py energy      a cube of 1,728 overlapping grains, one step: the energy
#                                      terms the contact law names on its first step (on every
#                                      thread at once)
#   threads_guard_scene.py plainloop   the net impact with YADE's own InteractionLoop holding the
#                                      yade-flex functors: refused on several threads, runs with
#                                      ompThreads=1
import json
import sys

from yade import O
from yade.wrapper import InteractionLoop

import yadeflex as yf
from yadeflex.harness import scenes

mode = sys.argv[1]
if mode == "energy":
    O.reset()
    R = 0.01
    for i in range(12):
        for j in range(12):
            for k in range(12):
                scenes.sphere((i * 1.9 * R, j * 1.9 * R, k * 1.9 * R), R)
    O.engines = yf.engines(damping=0, gravity=(0, 0, 0))
    O.trackEnergy = True
    O.step()
    keys = sorted(O.energy.keys())
    print("ENERGY " + json.dumps({"keys": keys, "values": {k: O.energy[k] for k in keys}, "sum": sum(O.energy[k] for k in keys),
                                  "total": O.energy.total(), "contacts": O.interactions.countReal()}))
else:
    scenes.net_impact(n=12, spacing=0.05, wire_radius=0.002, sphere_radius=0.08, speed=8.0)
    loop = next(e for e in O.engines if e.label == "interactionLoop")
    plain = InteractionLoop(loop.geomDispatcher.functors, loop.physDispatcher.functors, loop.lawDispatcher.functors, label="plain")
    O.engines = [plain if e is loop else e for e in O.engines]
    refused = ""
    try:
        O.step()
    except ValueError as e:
        refused = str(e)
    plain.ompThreads = 1
    for k in range(50):
        O.step()
    print("PLAIN " + json.dumps({"refused": refused, "iter": O.iter}))
