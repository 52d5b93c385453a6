# Deformable facets: yade-flex against YADE's built-in PFacet, same scenes (same mesh, same
# contact stiffness, same sphere), same YADE, same run (GPL-2.0-or-later).
#
#     yade-double -n -j1 -x bench/bench_facets.py [--reps 5] [--steps 300] [--quick]
#
# 1. Time per step, interleaved (built-in, ours, built-in, ours, ...), medians of --reps runs:
#    - sheet n = 12 and 16: clamped membrane, E t = 30 kN/m, 0.4 kg/m2, 2 n^2 facets, a 5 kg
#      sphere (R = 0.1 m) dropped 5 mm onto its centre (timed from the moment of contact on);
#    - bumpy n = 16: a fixed heightfield (512 facets), a 1 kg sphere rolling over it.
#    The built-in side is bench/builtin_pfacet.py (helper notes: bench/BUILTIN_NOTES.md).
# 2. Contact correctness on the bumpy surface: the exact geometric gap to the mesh is sampled
#    every 10 steps; a sample with overlap but no active contact is a missed contact; the
#    sphere's mechanical energy shows whether contacts create energy.
# Writes bench/results/facets_timing.csv and facets_bumpy.csv; prints the tables.
import csv
import math
import os
import statistics
import sys
import time

HERE = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if a.endswith("bench_facets.py")), os.getcwd())
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "py"))

from yade import O  # noqa: E402
from yade.minieigenHP import Vector3  # noqa: E402

import builtin_pfacet as bp  # noqa: E402
import yadeflex as yf  # noqa: E402
import yadeflex.harness.scenes as S  # noqa: E402

OUT = os.path.join(HERE, "results")
_me = next((k for k, a in enumerate(sys.argv) if a.endswith("bench_facets.py")), -1)
args = sys.argv[_me + 1:] if _me >= 0 else sys.argv[1:]
REPS = int(args[args.index("--reps") + 1]) if "--reps" in args else 5
STEPS = int(args[args.index("--steps") + 1]) if "--steps" in args else 300
QUICK = "--quick" in args


def ours_sheet(n, ref):
    """Our side of bp.sheet(n): the same mesh (bp.grid_mesh), materials and sphere."""
    O.reset()
    pts, tris, border = bp.grid_mesh(n, 1.0)
    mat = yf.membrane_material(30e3, 0.4, poisson=0.3, tension_only=False, young=ref["young_contact"], friction_deg=30.0)
    nodes, facets = yf.triangle_mesh(pts, tris, mat, 0.004, fixed=border)
    R, m = 0.1, 5.0
    s = S.sphere((0.5, 0.5, 0.002 + R + 0.005), R, density=m / (4 / 3 * math.pi * R ** 3), young=1e9, friction_deg=30.0,
                 contact_ratio=0.3)
    O.engines = yf.engines(damping=0.0)
    return dict(sphere_id=s, facets=facets)


def ours_bumpy(n, ref):
    O.reset()
    k = 2 * math.pi / 0.5
    pts, tris, _ = bp.grid_mesh(n, 1.0, lambda x, y: 0.005 * math.sin(k * x) * math.sin(k * y))
    mat = yf.membrane_material(30e3, 0.4, poisson=0.3, tension_only=False, young=1e9, friction_deg=30.0, contact_ratio=0.3)
    nodes, facets = yf.triangle_mesh(pts, tris, mat, 0.004, fixed=list(range(len(pts))))
    R = 0.05
    x0, y0 = 2 * R, 0.5 + 0.5 / 8
    ztop = max(p[2] for p in pts if (p[0] - x0) ** 2 + (p[1] - y0) ** 2 <= (R + 1.0 / n) ** 2)
    s = S.sphere((x0, y0, ztop + 0.002 + R), R, density=1.0 / (4 / 3 * math.pi * R ** 3), young=1e9, friction_deg=30.0,
                 contact_ratio=0.3, velocity=(0.5, 0, 0))
    O.engines = yf.engines(damping=0.0)
    return dict(sphere_id=s, facets=facets)


def advance_to_contact(sid, active, limit=20000):
    for _ in range(limit):
        if active(sid):
            return
        O.step()


def ours_active(sid):
    return len(yf.contacts_on(sid))


def timing_rows():
    rows = []
    cases = [("sheet", 12), ("sheet", 16), ("bumpy", 16)] if not QUICK else [("sheet", 12), ("bumpy", 16)]
    for scene, n in cases:
        res = {"builtin": [], "yade-flex": []}
        info = {}
        for rep in range(REPS):
            for impl in ("builtin", "yade-flex"):
                if scene == "sheet":
                    ref = bp.sheet(n=n)
                    if impl == "yade-flex":
                        ref = dict(ref, **ours_sheet(n, ref))
                        advance_to_contact(ref["sphere_id"], ours_active)
                    else:
                        advance_to_contact(ref["sphere_id"], bp.active_contacts)
                else:
                    ref = bp.bumpy(n=n)
                    if impl == "yade-flex":
                        ref = dict(ref, **ours_bumpy(n, ref))
                t = bp.time_per_step(n_steps=STEPS, reps=1, warmup=50)
                res[impl].append(t["us_per_step"])
                info[impl] = dict(dt=O.dt, interactions=len(O.interactions), real=O.interactions.countReal())
        med = {k: statistics.median(v) for k, v in res.items()}
        row = dict(scene=scene, n=n, facets=2 * n * n, builtin_us=med["builtin"], ours_us=med["yade-flex"],
                   speedup=med["builtin"] / med["yade-flex"], builtin_dt=info["builtin"]["dt"], ours_dt=info["yade-flex"]["dt"],
                   per_sim_second=(med["builtin"] / info["builtin"]["dt"]) / (med["yade-flex"] / info["yade-flex"]["dt"]),
                   builtin_interactions=info["builtin"]["interactions"], ours_interactions=info["yade-flex"]["interactions"],
                   builtin_runs=" ".join("%.1f" % x for x in res["builtin"]), ours_runs=" ".join("%.1f" % x for x in res["yade-flex"]))
        rows.append(row)
        print("%-6s n=%-3d %4d facets: built-in %7.1f us/step, yade-flex %6.1f us/step, %5.1fx per step, %5.1fx per simulated second"
              % (scene, n, 2 * n * n, row["builtin_us"], row["ours_us"], row["speedup"], row["per_sim_second"]), flush=True)
    return rows


def bumpy_rows(n_steps=6000):
    out = []
    for impl in ("builtin", "yade-flex"):
        ref = bp.bumpy(n=16)
        if impl == "yade-flex":
            ref = dict(ref, **ours_bumpy(16, ref))
        sid = ref["sphere_id"]
        act = ours_active if impl == "yade-flex" else bp.active_contacts
        st = O.bodies[sid].state
        e0 = 0.5 * st.mass * st.vel.squaredNorm() + st.mass * 9.81 * st.pos[2]
        samples = missed = 0
        deepest = 0.0
        emax = e0
        steps = 0
        while steps < n_steps:
            g = bp.mesh_gap(sid)
            O.step()
            steps += 1
            samples += 1
            if g < 0:
                deepest = max(deepest, -g)
                if act(sid) == 0:
                    missed += 1
            for _ in range(9):
                O.step()
                steps += 1
            w = st.angVel
            e = 0.5 * st.mass * st.vel.squaredNorm() + 0.5 * sum(st.inertia[i] * w[i] ** 2 for i in range(3)) + st.mass * 9.81 * st.pos[2]
            emax = max(emax, e)
        out.append(dict(impl=impl, steps=steps, time=O.time, samples=samples, missed=missed, deepest_overlap_mm=1e3 * deepest,
                        energy_start=e0, energy_max=emax, x_end=st.pos[0]))
        print("bumpy %-9s: %d samples, %d with overlap but no contact, deepest overlap %.2f mm, sphere energy %.3f J -> max %.3f J"
              % (impl, samples, missed, 1e3 * deepest, e0, emax), flush=True)
    return out


def write(name, rows):
    os.makedirs(OUT, exist_ok=True)
    with open(os.path.join(OUT, name), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)


t0 = time.time()
write("facets_timing.csv", timing_rows())
write("facets_bumpy.csv", bumpy_rows(3000 if QUICK else 6000))
with open(os.path.join(OUT, "facets_machine.txt"), "w") as f:
    f.write(bp._machine_line() + "\n")
print("done in %.0f s; CSV in %s" % (time.time() - t0, OUT))
