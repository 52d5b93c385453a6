"""A geotextile bag of gravel: a closed woven-geotextile box filled with gravel, settled on the
ground, then loaded by a falling block.

    yade-double -n -x examples/geotextile_bag.py [--size 0.8 0.5 0.5] [--mass 150] [--drop 1.0] [--out out/geotextile_bag]

The bag is a closed membrane (yadeflex.bag); the gravel (the 'gravel' preset, 32-63 mm) is
deposited inside it (yadeflex.deposit: placed loose, it settles to about half the bag's height,
the fabric above it slack), the filled bag slumps on the ground (yadeflex.settle),
and the block falls on its top (yadeflex.boulder_impact): the ground's load, the fabric's
largest membrane force, torn facets and the energy."""
import argparse
import os
import sys

HERE = next((os.path.dirname(os.path.abspath(x)) for x in sys.argv if x.endswith(".py")), os.getcwd())
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "py"))  # this checkout's yadeflex
import yadeflex as yf  # noqa: E402
from yade import O, utils  # noqa: E402
from yade.wrapper import FrictMat  # noqa: E402

ap = argparse.ArgumentParser(prog="geotextile_bag.py", description=__doc__.split("\n\n")[0])
ap.add_argument("--size", type=float, nargs=3, default=(0.8, 0.5, 0.5), metavar=("L", "W", "H"), help="bag before filling [m]")
ap.add_argument("--cell", type=float, default=0.05, help="membrane cell size [m]")
ap.add_argument("--fill", default="gravel", help="fill preset (gravel, sand)")
ap.add_argument("--mass", type=float, default=150.0, help="block mass [kg], a concrete cube")
ap.add_argument("--drop", type=float, default=1.0, help="drop height [m]")
ap.add_argument("--out", default="out/geotextile_bag", help="results folder")
ap.add_argument("--no-vtk", action="store_true")
ap.add_argument("--picture", help="save the 3D view of the end state, in part colours, to this PNG (needs YADE's GUI: yade-double without -n)")
a = ap.parse_args(sys.argv[1:])

O.reset()
L, W, H = a.size
thickness = 0.002
bag = yf.bag((0, 0, thickness), (L, W, H), max(1, round(max(L, W, H) / a.cell)), thickness, yf.geotextile())
ground_mat = FrictMat(young=3e10, poisson=0.25, density=2650, frictionAngle=0.6, label="ground")  # concrete (E 30 GPa), friction 34 deg
O.materials.append(ground_mat)
ground = O.bodies.append(utils.wall(0.0, axis=2, sense=1, material=ground_mat))
fill = yf.deposit(yf.BoxRegion((0, 0, thickness), (L, W, H)), a.fill, seed=1,
                  progress=lambda stage, steps, ke, tol: steps % 20000 or print(f"  {stage}: {steps} steps, kinetic energy {ke:.3g} J", flush=True))
print(f"{len(fill.grains)} grains, solid fraction {fill.solid_fraction:.2f}, top {fill.top:.3f} m")
O.engines = []
steps = yf.settle(damping=0.4, node_mass_scaling=100.0)
top = max(O.bodies[n].state.pos[2] for n in bag["nodes"] if n >= 0)
print(f"bag settled on the ground in {steps} steps, its top at {top:.3f} m")
O.engines = []  # (the runner sets the undamped engines)
s = yf.boulder_impact(a.out, yf.Boulder(mass=a.mass, shape="cube", density=2400.0, above=(L / 2, W / 2), drop_height=a.drop),
                      parts={"bag": bag["facets"] + [n for n in bag["nodes"] if n >= 0], "gravel": fill.grains, "ground": [ground]},
                      reactions={"ground": [ground]}, no_vtk=a.no_vtk)
n1 = max((O.bodies[f].shape.n1 for f in bag["facets"] if O.bodies[f] is not None), default=0.0)
print(f"block stopped {1e3 * (s.get('penetration_max') or 0):.0f} mm into the bag; ground {s.get('reaction_ground_max', 0) / 1e3:.1f} kN at most; "
      f"fabric {n1 / 1e3:.1f} kN/m at the end; {s.get('broken_bag', 0)} facets torn")
if a.picture:
    yf.view(direction=(1, 1, -0.7), size=(900, 650))
    yf.snapshot(a.picture)
sys.exit(s["exit_status"])
