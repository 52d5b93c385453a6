"""Rockfall drapery: a TECCO G65/3 panel anchored at the crest of a 65 degree rock slope, a
boulder rolling down between the slope and the mesh.

    yade-double -n -x examples/drapery.py [--width 2] [--length 4] [--mass 90] [--speed 3] [--out out/drapery]

The panel is built flat and placed on the slope (yadeflex.placed), hangs from its anchors and
settles onto the slope and over the boulder held near the crest; then the boulder is released
down the slope (yadeflex.boulder_impact): the anchors' reaction, the boulder's speed and the energy."""
import argparse
import math
import os
import sys

HERE = next((os.path.dirname(os.path.abspath(x)) for x in sys.argv if x.endswith(".py")), os.getcwd())
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "py"))  # this checkout's yadeflex
import yadeflex as yf  # noqa: E402
from yade import O, utils  # noqa: E402
from yade.minieigenHP import Vector3  # noqa: E402
from yade.wrapper import FrictMat  # noqa: E402

ap = argparse.ArgumentParser(prog="drapery.py", description=__doc__.split("\n\n")[0])
ap.add_argument("--width", type=float, default=2.0, help="panel width across the slope [m]")
ap.add_argument("--length", type=float, default=4.0, help="panel length down the slope [m]")
ap.add_argument("--slope", type=float, default=65.0, help="slope angle [deg]")
ap.add_argument("--mass", type=float, default=90.0, help="boulder mass [kg], a rock sphere")
ap.add_argument("--speed", type=float, default=3.0, help="boulder speed down the slope when released [m/s]")
ap.add_argument("--out", default="out/drapery", help="results folder")
ap.add_argument("--no-vtk", action="store_true")
ap.add_argument("--picture", help="save the 3D view of the end state, in part colours, to this PNG (needs YADE's GUI: yade-double without -n)")
a = ap.parse_args(sys.argv[1:])

O.reset()
th = math.radians(a.slope)
up, normal = Vector3(0, math.cos(th), math.sin(th)), Vector3(0, -math.sin(th), math.cos(th))  # up the slope; out of the rock
on_slope = lambda x, s, off=0.0: Vector3(x, 0, 0) + up * s + normal * off
# the rock face: rigid facets in strips 0.2 m high (a tilted facet's bounding box spans its whole
# height: narrow strips keep the wires from being tested against the whole face at every step)
rock = FrictMat(young=1e9, poisson=0.25, density=2650, frictionAngle=math.radians(35), label="rock")
O.materials.append(rock)
slope = []
for k in range(int((a.length + 4.0) / 0.2)):
    s0, s1 = -3.0 + 0.2 * k, -3.0 + 0.2 * (k + 1)
    c = [on_slope(-a.width, s0), on_slope(a.width, s0), on_slope(a.width, s1), on_slope(-a.width, s1)]
    slope += [O.bodies.append(utils.facet(v, material=rock, fixed=True)) for v in ((c[0], c[1], c[2]), (c[0], c[2], c[3]))]
# the boulder near the crest, on the rock; the panel over it, anchored along its top edge
r = (3 * a.mass / (4 * math.pi * 2650)) ** (1 / 3)
stone = O.bodies.append(utils.sphere(on_slope(0.0, a.length - 1.0, r), r, material=rock))
O.bodies[stone].state.blockedDOFs = "xyzXYZ"
with yf.placed(origin=on_slope(-a.width / 2, 0.0, 2 * r + 0.01), axis=(1, 0, 0), angle=a.slope):
    panel = yf.chain_link_panel(a.width, a.length, yf.tecco_wire())
anchors = panel["edges"]["top"]
yf.fix(anchors)
mesh = [n for n in panel["nodes"].values() if n not in anchors]
# the panel settles onto the rock and the boulder (numerically damped, the boulder held)
steps = yf.settle(damping=0.4, node_mass_scaling=100.0)
print(f"panel settled on the slope in {steps} steps")
O.bodies[stone].state.blockedDOFs = ""
O.engines = []  # (the runner sets the undamped engines)
s = yf.boulder_impact(a.out, yf.Boulder(body=stone, speed=a.speed, direction=-up), duration=1.5,
                      parts={"mesh": panel["cylinders"] + mesh, "anchors": anchors, "rock": slope}, reactions={"anchors": anchors},
                      no_vtk=a.no_vtk)
b = O.bodies[stone].state
print(f"anchors {s.get('reaction_anchors_max', 0) / 1e3:.1f} kN at most; boulder {b.vel.norm():.2f} m/s at the end, "
      f"{(b.pos - on_slope(0.0, a.length - 1.0, r)).dot(-up):.2f} m down the slope; {s.get('broken_mesh', 0)} wires broken")
if a.picture:
    yf.view(direction=(0.2, 0.9, -0.42), size=(900, 650))
    yf.snapshot(a.picture)
sys.exit(s["exit_status"])
