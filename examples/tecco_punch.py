"""A TECCO G65/3 panel, clamped on its four edges, hit at its centre by a boulder.

    yade-double -n -x examples/tecco_punch.py [--size 2.0] [--mass 400] [--speed 6] [--out out/tecco_punch]

Writes the impact's results (yadeflex.boulder_impact): the force on the boulder (raw and filtered)
against its penetration, the clamped edges' reaction, broken wires, the energy balance."""
import argparse
import os
import sys

HERE = next((os.path.dirname(os.path.abspath(x)) for x in sys.argv if x.endswith(".py")), os.getcwd())
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "py"))  # this checkout's yadeflex
import yadeflex as yf  # noqa: E402
from yade import O  # noqa: E402

ap = argparse.ArgumentParser(prog="tecco_punch.py", description=__doc__.split("\n\n")[0])
ap.add_argument("--size", type=float, default=2.0, help="panel side [m] (default 2.0)")
ap.add_argument("--mass", type=float, default=400.0, help="boulder mass [kg], a concrete sphere (default 400)")
ap.add_argument("--speed", type=float, default=6.0, help="impact speed [m/s] (default 6)")
ap.add_argument("--out", default="out/tecco_punch", help="results folder")
ap.add_argument("--no-vtk", action="store_true")
ap.add_argument("--picture", help="save the 3D view of the end state, in part colours, to this PNG (needs YADE's GUI: yade-double without -n)")
a = ap.parse_args(sys.argv[1:])

O.reset()
wire = yf.tecco_wire()
panel = yf.chain_link_panel(a.size, a.size, wire, origin=(-a.size / 2, -a.size / 2, 0))
edges = sorted({n for side in panel["edges"].values() for n in side})
yf.fix(edges)
s = yf.boulder_impact(a.out, yf.Boulder(mass=a.mass, shape="sphere", density=2400.0, above=(0.0, 0.0), speed=a.speed),
              parts={"mesh": panel["cylinders"] + [n for n in panel["nodes"].values() if n not in edges], "edges": edges},
              reactions={"edges": edges}, no_vtk=a.no_vtk)
print(f"energy absorbed {s.get('energy_absorbed', 0) / 1e3:.2f} kJ of {s.get('impact_energy', 0) / 1e3:.2f} kJ, "
      f"edge reaction {s.get('reaction_edges_max', 0) / 1e3:.1f} kN, {s.get('broken_mesh', 0)} wires broken")
if a.picture:
    yf.view(direction=(0, 1, -0.25), size=(900, 650))
    yf.snapshot(a.picture)
sys.exit(s["exit_status"])
