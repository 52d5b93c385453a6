"""Open YADE's 3D view on a small yade-flex scene and save PNG snapshots (run by test_view.py
under Xvfb: yade-double -j1 -x view_scene.py OUTDIR; not with -n).

Scene, left to right on the screen (view along +y, tilted down; x runs left to right):
a red steel ring (cylinders), a green clamped chain (cylinders) whose middle node has a yellow
display radius larger than the wire, a blue clamped geotextile sheet (facets).
Writes OUTDIR/<name>.png for each state below and OUTDIR/view.json (numbers the test checks).
"""
import json
import os
import sys
import time

import yadeflex as yf
from yade import O, qt
from yade.minieigenHP import Vector3
from yade.wrapper import FlexCylinder, FlexFacet, Gl1_FlexCylinder, Gl1_FlexFacet, Gl1_FlexNode

out = sys.argv[1]
os.makedirs(out, exist_ok=True)
t_start = time.time()

steel = yf.steel()
ring_nodes, ring = yf.ring(center=(0, 0, 0.15), ring_radius=0.15, bar_radius=0.01, material=steel, axis=(0, 1, 0))
chain_nodes, chain = yf.chain([(0.4, 0, 0), (0.8, 0, 0.3)], radius=0.01, material=steel, segments=10, fixed=[0, 10])
sheet = yf.sheet(6, 6, (0.3, 0.3), thickness=0.002, material=yf.geotextile(), origin=(1.0, -0.15, 0.1))
for i in ring_nodes:  # the ring hangs still: only the chain and the sheet deform
    yf.fix([i])
for ids, c in ((ring, (1, 0, 0)), (chain, (0, 1, 0)), (sheet["facets"], (0, 0, 1))):
    for i in ids:
        O.bodies[i].shape.color = Vector3(*c)
mid = O.bodies[chain_nodes[5]].shape
mid.color, mid.radius = Vector3(1, 1, 0), 0.03  # display radius only
O.engines = yf.engines()
O.run(1, True)  # bounds

v = yf.view(color_parts=False)  # the colours set above
v.timeDisp = ""  # no text overlay
r = qt.Renderer()
info = {"screen": list(v.screenSize)}
times = {}


def shot(name):
    t0 = time.time()
    yf.snapshot(os.path.join(out, name + ".png"))
    times[name] = time.time() - t0


shot("all")
r.shape = False
shot("none")
r.shape = True
for i in ring + chain:  # hide the cylinders (renderer.mask), then the facets too
    O.bodies[i].mask = 2
r.mask = ~2
shot("no_cylinders")
for i in sheet["facets"]:
    O.bodies[i].mask = 2
shot("no_elements")
r.mask = ~0
Gl1_FlexNode.show = True
shot("nodes")
Gl1_FlexNode.show = False
r.wire = True
shot("wire")
r.wire = False

# forces: let the chain and the sheet sag for a while, then colour by force
t0 = time.time()
O.run(2000, True)
info["steps_seconds"] = time.time() - t0
F = [O.bodies[i].shape.axialForce for i in ring + chain]
N1 = [O.bodies[i].shape.n1 for i in sheet["facets"]]
info["max_abs_axial_force"] = max(abs(f) for f in F)
info["max_abs_n1"] = max(abs(n) for n in N1)
Gl1_FlexCylinder.colorByForce = Gl1_FlexFacet.colorByForce = True
shot("force_auto")
info["cylinder_range_auto"] = list(Gl1_FlexCylinder.lastRange)
info["facet_range_auto"] = list(Gl1_FlexFacet.lastRange)
M, Mn = info["max_abs_axial_force"], info["max_abs_n1"]
Gl1_FlexCylinder.forceRange = (-3 * M - 2, -2 * M - 1)  # every force above the range: red
Gl1_FlexFacet.forceRange = (2 * Mn + 1, 3 * Mn + 2)  # every n1 below the range: blue
shot("force_user")
info["cylinder_range_user"] = list(Gl1_FlexCylinder.lastRange)
info["facet_range_user"] = list(Gl1_FlexFacet.lastRange)
Gl1_FlexCylinder.forceRange = Gl1_FlexFacet.forceRange = (0, 0)
O.run(1000, True)  # the automatic range follows the forces from frame to frame
info["max_abs_axial_force_later"] = max(abs(O.bodies[i].shape.axialForce) for i in ring + chain)
shot("force_auto_later")
info["cylinder_range_auto_later"] = list(Gl1_FlexCylinder.lastRange)
Gl1_FlexCylinder.colorByForce = Gl1_FlexFacet.colorByForce = False
O.run()  # drawing while the simulation runs in its own thread
shot("running")
O.pause()
O.wait()
info["iter_after_running"] = O.iter

info["snapshot_seconds"] = times
info["total_seconds"] = time.time() - t_start
with open(os.path.join(out, "view.json"), "w") as f:
    json.dump(info, f, indent=1)
print("view_scene done", json.dumps(info))
