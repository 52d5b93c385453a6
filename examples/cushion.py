"""A cushion of three damping modules in a row, tied by the boundary rope at mid-height (the
combined configuration of the damping-module tests), the boulder on the middle module.

    yade-double -n -x examples/cushion.py [--small] [--drop 5] [--mass 800] [--out out/cushion]

The three modules are filled together (the first run fills and caches them: about 15 min at
the default size; --small takes a minute) and hit as the main job hits one (yadeflex.module.impact's
run_impact): the force on the boulder and on the slab, the rope's force, the energy."""
import argparse
import os
import sys

HERE = next((os.path.dirname(os.path.abspath(x)) for x in sys.argv if x.endswith(".py")), os.getcwd())
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "py"))  # this checkout's yadeflex
import yadeflex as yf  # noqa: E402
from yadeflex.module.impact import run_impact  # noqa: E402
from yadeflex.module import ModuleParams  # noqa: E402

ap = argparse.ArgumentParser(prog="cushion.py", description=__doc__.split("\n\n")[0])
ap.add_argument("--small", action="store_true", help="the reduced modules (0.4 m x 0.3 m, grains of 60-80 mm)")
ap.add_argument("--drop", type=float, default=None, help="drop height [m] (default: the main job's)")
ap.add_argument("--mass", type=float, default=None, help="boulder mass [kg] (default: the main job's)")
ap.add_argument("--cache-dir", default=None, help="filled modules' cache (default ~/.cache/yadeflex/modules)")
ap.add_argument("--out", default="out/cushion", help="results folder")
ap.add_argument("--no-vtk", action="store_true")
ap.add_argument("--picture", help="save the 3D view of the end state, in part colours, to this PNG (needs YADE's GUI: yade-double without -n)")
a = ap.parse_args(sys.argv[1:])

given = {k: v for k, v in (("drop_height", a.drop), ("boulder_mass", a.mass)) if v is not None}
p = (ModuleParams.small(n_modules=3, rope=True, **given) if a.small else ModuleParams(n_modules=3, rope=True, **given))
s = run_impact(p, a.out, cache_dir=a.cache_dir, no_vtk=a.no_vtk)
if s.get("peak_impact_force") is not None:
    print(f"three modules: peak force {s['peak_impact_force'] / 1e3:.1f} kN, slab {s['slab_force_max'] / 1e3:.1f} kN, "
          f"rope {s['rope_force_max'] / 1e3:.2f} kN at most, penetration {1e3 * s['penetration_max']:.0f} mm")
if a.picture:
    yf.view(direction=(0, 1, -0.5), size=(900, 650))
    yf.snapshot(a.picture)
sys.exit(s["exit_status"])
