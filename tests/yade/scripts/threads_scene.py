# Run by test_threads.py in yade-double with -j1 / -j2; prints final positions as JSON.
#   threads_scene.py STEPS SCENE   SCENE: 'sag' (net sagging under gravity with a ball resting
#   on it, no impact) or 'impact' (ball hitting the net at 8 m/s)
import json
import sys

from yade import O

from yadeflex.harness import scenes

N = int(sys.argv[1]) if len(sys.argv) > 1 else 600
kind = sys.argv[2] if len(sys.argv) > 2 else "sag"
if kind == "impact":
    scenes.net_impact(n=12, spacing=0.05, wire_radius=0.002, sphere_radius=0.08, speed=8.0)
else:
    scenes.net_impact(n=12, spacing=0.05, wire_radius=0.002, sphere_radius=0.08, speed=0.0, damping=0.2)
contacts = 0
for k in range(N):
    O.step()
    contacts = max(contacts, sum(1 for i in O.interactions if i.isReal and getattr(i.geom, "active", True)))
pos = [list(b.state.pos) for b in O.bodies if b is not None]
print("POS " + json.dumps({"pos": pos, "contacts": contacts, "dt": O.dt}))
