"""A box gabion: six TECCO G65/3 panels laced at their edges, filled with stones, loaded by a
falling block.

    yade-double -n -x examples/gabion.py [--size 1.0 1.0 0.5] [--mass 200] [--drop 1.5] [--out out/gabion]

The base and four sides are placed around the box (yadeflex.placed) and laced (yadeflex.lace);
stones of 100-150 mm (larger than the mesh's openings) are deposited into it (yadeflex.deposition,
inside a temporary rigid frame), the lid is laced on, the gabion settles on the ground
(yadeflex.settle), and the block falls onto the lid's centre (yadeflex.boulder_impact)."""
import argparse
import os
import sys

HERE = next((os.path.dirname(os.path.abspath(x)) for x in sys.argv if x.endswith(".py")), os.getcwd())
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "py"))  # this checkout's yadeflex
import yadeflex as yf  # noqa: E402
from yade import O, geom, utils  # noqa: E402
from yade.wrapper import FrictMat  # noqa: E402

ap = argparse.ArgumentParser(prog="gabion.py", description=__doc__.split("\n\n")[0])
ap.add_argument("--size", type=float, nargs=3, default=(1.0, 1.0, 0.5), metavar=("L", "W", "H"), help="box [m]")
ap.add_argument("--stones", type=float, nargs=2, default=(0.10, 0.15), metavar=("DMIN", "DMAX"), help="stone sizes [m]")
ap.add_argument("--mass", type=float, default=200.0, help="block mass [kg], a concrete cube")
ap.add_argument("--drop", type=float, default=1.5, help="drop height [m]")
ap.add_argument("--out", default="out/gabion", help="results folder")
ap.add_argument("--no-vtk", action="store_true")
ap.add_argument("--picture", help="save the 3D view of the end state, in part colours, to this PNG (needs YADE's GUI: yade-double without -n)")
a = ap.parse_args(sys.argv[1:])

O.reset()
wire, gap = yf.tecco_wire(), 0.04  # the panels stand apart by a lacing wire of about a mesh leg (a shorter one would set the time step)
base = yf.chain_link_panel(a.size[0], a.size[1], wire)
L, W = base["params"]["width"], base["params"]["height"]
sides = {}
for name, origin, axis, angle, width in (("front", (0, -gap, 0), (1, 0, 0), 90, L), ("back", (0, W + gap, 0), (1, 0, 0), 90, L),
                                         ("left", (-gap, 0, 0), (1, 1, 1), 120, W), ("right", (L + gap, 0, 0), (1, 1, 1), 120, W)):
    with yf.placed(origin, axis, angle):  # a side: the panel's x along the box's edge, its y up
        sides[name] = yf.chain_link_panel(width, a.size[2], wire)
H = sides["front"]["params"]["height"]
lacing = []  # (each node to the nearest across: at most half a cell, 72 mm, along the edge and the gaps across; 0.15 m refuses a misplaced panel)
for name, edge in (("front", "bottom"), ("back", "top"), ("left", "left"), ("right", "right")):
    lacing += yf.lace(sides[name]["edges"]["bottom"], base["edges"][edge], wire, max_gap=0.15)
for (s1, e1), (s2, e2) in ((("front", "left"), ("left", "left")), (("front", "right"), ("right", "left")),
                           (("back", "left"), ("left", "right")), (("back", "right"), ("right", "right"))):  # the four corners
    lacing += yf.lace(sides[s1]["edges"][e1], sides[s2]["edges"][e2], wire, max_gap=0.15)
ground_mat = FrictMat(young=3e10, poisson=0.25, density=2650, label="ground")  # concrete ground (E 30 GPa)
O.materials.append(ground_mat)
ground = O.bodies.append(utils.wall(-0.01, axis=2, sense=1, material=ground_mat))
# the stones, deposited inside a rigid frame that holds them up to H while they settle
frame = O.bodies.append(geom.facetBox((L / 2, W / 2, 1.5 * H), (L / 2 + 3 * gap, W / 2 + 3 * gap, 1.5 * H), wallMask=15, material=ground_mat))
fill = yf.deposit(yf.BoxRegion((0, 0, 0), (L, W, 2.6 * H)), "gravel", seed=1, sizes=yf.GrainSizes.uniform(*a.stones), trim_height=H,
                  node_mass_scaling=1000.0, max_steps=1_000_000,
                  progress=lambda stage, steps, ke, tol: steps % 20000 or print(f"  {stage}: {steps} steps, kinetic energy {ke:.3g} J", flush=True))
for f in frame:
    O.bodies.erase(f)
print(f"{len(fill.grains)} stones, solid fraction {fill.solid_fraction:.2f}")
with yf.placed((0, 0, H + gap)):
    lid = yf.chain_link_panel(L, W, wire)
for edge, name, side_edge in (("bottom", "front", "top"), ("top", "back", "top"), ("left", "left", "top"), ("right", "right", "top")):
    lacing += yf.lace(lid["edges"][edge], sides[name]["edges"][side_edge], wire, max_gap=0.15)
O.engines = []
steps = yf.settle(damping=0.4, node_mass_scaling=100.0)
print(f"gabion settled on the ground in {steps} steps")
panels = [base, lid] + list(sides.values())
O.engines = []  # (the runner sets the undamped engines)
s = yf.boulder_impact(a.out, yf.Boulder(mass=a.mass, shape="cube", density=2400.0, above=(L / 2, W / 2), drop_height=a.drop),
                      parts={"mesh": [c for p in panels for c in p["cylinders"]] + [n for p in panels for n in p["nodes"].values()],
                             "lacing": lacing, "stones": fill.grains, "ground": [ground]},
                      reactions={"ground": [ground]}, no_vtk=a.no_vtk)
print(f"block stopped {1e3 * (s.get('penetration_max') or 0):.0f} mm into the gabion; ground {s.get('reaction_ground_max', 0) / 1e3:.1f} kN "
      f"at most (static {(a.mass + sum(O.bodies[g].state.mass for g in fill.grains)) * 9.81 / 1e3:.1f} kN with the stones); "
      f"{s.get('broken_mesh', 0)} wires broken")
if a.picture:
    yf.view(direction=(1, 1, -0.7), size=(900, 650))
    yf.snapshot(a.picture)
sys.exit(s["exit_status"])
