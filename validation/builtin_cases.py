"""The reduced module against the same module built from YADE's built-in classes (WirePM mesh,
PFacet lining, FrictMat fill), at equal numerical damping: bench/bench_module.py --small, run in
its own yade-double process (it rebuilds the module with the built-in classes), its CSV read."""
import csv
import math
import os
import shutil
import subprocess
import sys

from yadeflex.module.impact import run_impact
from yadeflex.module import ModuleParams
from yadeflex.harness.verdict import Case, grade

GROUP = "Damping module against YADE's built-in classes"
PLOTS = [("plots/module_compare_small.png", "force and penetration, ours and built-in")]  # (path under OUT, title), shown under the group's table
REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TOL = 0.25
WHY = ("the two models share the geometry, the masses, the fill and its contact law, and differ in the mesh law (WirePM against the "
       "TECCO wire curve), the lining (a PFacet truss against the membrane) and their contacts; the fill carries most of the impact "
       "energy. 25% is a judgement fixed here: the built-in is not a reference of known accuracy, the case checks that the two do not diverge")


def _row(rows, model):
    return next((r for r in rows if r["model"] == model), None)


def run(full, out, cache_dir=None):
    folder = os.path.join(out, "runs", "builtin")
    os.makedirs(folder, exist_ok=True)
    cmd = ["yade-double", "-n", "-j1", "-x", os.path.join(REPO, "bench", "bench_module.py"), "--small", "--reps", "1", "--window", "50",
           "--out", folder]
    if cache_dir:
        cmd += ["--cache-dir", cache_dir]
    env = dict(os.environ, OMP_NUM_THREADS="1", PYTHONPATH=os.path.join(REPO, "py") + os.pathsep + os.environ.get("PYTHONPATH", ""))
    r = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=REPO)
    path = os.path.join(folder, "module_compare_small.csv")
    if r.returncode != 0 or not os.path.exists(path):
        print(r.stdout[-2000:], r.stderr[-2000:], file=sys.stderr)
        rows = []
    else:
        rows = list(csv.DictReader(open(path)))
    png = os.path.join(folder, "module_compare_small.png")
    if os.path.exists(png):
        shutil.copy(png, os.path.join(out, "module_compare_small.png"))
    # ours at the built-in's usual damping 0.2, run as the main job runs (the same record: the
    # boulder's velocity change every 0.2 ms, the penetration below the fill top), with the
    # lining at its own mass as the built-in's twin has it (no mass scaling)
    s = run_impact(ModuleParams.small(damping=0.2, lining_node_mass=0.0), os.path.join(out, "runs", "ours_d02"), cache_dir=cache_dir, progress=False, no_vtk=True)
    ours = {0.0: _row(rows, "yade-flex"),
            0.2: dict(status="ok", peak_force_kN=s["peak_impact_force"] / 1e3, penetration_max_mm=1e3 * s["penetration_max"])
            if s.get("status") == "done" else dict(status=s.get("status"))}
    res = []
    for model, damping in (("built-in d=0.0", 0.0), ("built-in d=0.2", 0.2)):
        theirs, mine = _row(rows, model), ours[damping]
        status = theirs["status"] if theirs else "not run"
        for q, unit, col in (("peak force", "kN", "peak_force_kN"), ("deepest penetration", "mm", "penetration_max_mm")):
            ref = float(theirs[col]) if theirs and status == "ok" else math.nan
            c = Case(name=f"builtin_d{damping:g}_{col}", group=GROUP,
                     quantity=f"{q} [{unit}], ours against the built-in, both at numerical damping {damping:g}",
                     reference=ref, source="the same module from YADE's built-in classes (bench/builtin_module.py, bench/bench_module.py --small)",
                     tolerance=TOL, kind="relative", justification=WHY)
            ok = mine and mine.get("status") == "ok"
            if not math.isfinite(ref):
                c.open = f"the built-in at damping {damping:g}: {status}; no reference"
            res.append(grade(c, float(mine[col]) if ok and math.isfinite(ref) else math.nan, ours=float(mine[col]) if ok else None,
                             builtin_status=status))
    return res
