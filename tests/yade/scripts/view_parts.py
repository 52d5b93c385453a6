"""The 3D view colours a module-like scene by part (run by test_view.py under Xvfb:
yade-double -j1 -x view_parts.py OUTDIR; not with -n).

Left to right along x (the view looks along +y, tilted down): a ring (top ring), a clamped
chain (mesh), a second clamped chain (rope), a sheet (lining), two spheres (grains) and a clump
of eight spheres (the boulder), named as yadeflex.module names a module's bodies
(O.tags['yadeflex_module']). Writes OUTDIR/parts.png (by part), OUTDIR/force.png (wires and
lining by force) and OUTDIR/parts.json.
"""
import json
import os
import sys

import yadeflex as yf
from yade import O, qt, utils

out = sys.argv[1]
os.makedirs(out, exist_ok=True)
steel = yf.steel()
ring_nodes, ring = yf.ring(center=(0, 0, 0.15), ring_radius=0.15, bar_radius=0.012, material=steel, axis=(0, 1, 0))
mesh_nodes, mesh = yf.chain([(0.35, 0, 0), (0.65, 0, 0.3)], radius=0.012, material=steel, segments=6, fixed=[0, 6])
rope_nodes, rope = yf.chain([(0.8, 0, 0), (1.1, 0, 0.3)], radius=0.012, material=steel, segments=6, fixed=[0, 6])
sheet = yf.sheet(4, 4, (0.3, 0.3), thickness=0.002, material=yf.geotextile(), origin=(1.25, -0.15, 0.1))
grains = [O.bodies.append(utils.sphere((x, 0, 0.15), 0.08)) for x in (1.75, 1.95)]
boulder = O.bodies.appendClumped([utils.sphere((2.25 + 0.1 * i, 0.1 * j, 0.1 + 0.1 * k), 0.05)
                                  for i in (0, 1) for j in (0, 1) for k in (0, 1)])[0]
for i in ring_nodes:
    yf.fix([i])
O.tags["yadeflex_module"] = json.dumps(dict(grains=grains, rope=rope, rope_nodes=rope_nodes, modules=[dict(
    mesh_cylinders=mesh, mesh_nodes=mesh_nodes + ring_nodes,  # a module's ring nodes are mesh nodes
    ring_top=ring, ring_bottom=[], lining=sheet["facets"],
    lining_nodes=sorted({n for row in sheet["grid"] for n in row}))]))
O.engines = yf.engines(gravity=(0, 0, 0))
O.run(1, True)  # bounds
v = yf.view()
v.timeDisp = ""
counts = yf.color_by_part()
yf.snapshot(os.path.join(out, "parts.png"))
# pull the mesh chain's middle node: tension in the mesh chain, drawn by force
O.bodies[mesh_nodes[3]].state.pos += (0, 0, -0.05)
O.run(1, True)
forces = [O.bodies[c].shape.axialForce for c in mesh]
yf.view(color_by_force=True)
v.timeDisp = ""
yf.snapshot(os.path.join(out, "force.png"))
r = qt.Renderer()
r.shape = False
yf.snapshot(os.path.join(out, "none.png"))
with open(os.path.join(out, "parts.json"), "w") as f:
    json.dump(dict(counts=counts, mesh_forces=forces), f)
print("view_parts done", json.dumps(counts))
