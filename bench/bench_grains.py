# Benchmark: the damping module's fill alone, yade-flex's sphere contacts against YADE's built-in
# ones (GPL-2.0-or-later).
#
#     yade-double -n -j1 -x bench/bench_grains.py [--small] [--reps N] [--window STEPS] [--cache-dir DIR]
#
# Why: in the module the grains' contacts take most of the step, in both models (bench_module.py's
# engine breakdown). This isolates them: the settled grains of the main job's filled module
# (yadeflex.module.filled_module, from the cache or built) at their positions and radii, on the
# slab (a Wall) inside a rigid frictionless cylinder of YADE facets where the lining was, with
# gravity and nothing else, in two scenes:
#   - "yade-flex": yf.engines() of the main job (the module's rolling resistance, FlexTimeStepper,
#     FlexNewtonIntegrator), damping 0 (--no-rolling: without rolling resistance, the built-in's
#     physics);
#   - "built-in": InsertionSortCollider (same Bo1 functors and sweep), Ig2_Sphere_Sphere_ScGeom,
#     Ig2_Facet_Sphere_ScGeom, Ig2_Wall_Sphere_ScGeom, Ip2_FrictMat_FrictMat_FrictPhys,
#     Law2_ScGeom_FrictPhys_CundallStrack, NewtonIntegrator (damping 0), with yade-flex's time step
#     held fixed (no time-step estimate in its step: its cheapest configuration).
# The two scenes live side by side (O.addScene, O.switchToScene): each runs --warmup steps from rest,
# then windows of --window steps alternate between them, --reps times; the median is reported, with
# the collider runs per step and one more window of each with O.timingEnabled for the engine
# breakdown. Not O.saveTmp/O.loadTmp: after a reload YADE's adaptive collider sweep
# (InsertionSortCollider.targetInterv) shrinks to zero for the grains that have not moved since the
# last bound update, and the collider then runs at 30-60% of the steps where the continuing
# scene runs it at none (measured 2026-11-23), which is not the state of a run.
# The fill is at rest: this is the cost of visiting the contacts and the collider's potential
# pairs, the part that both models pay through YADE's InteractionLoop.
# Writes bench/results/grains_compare[_small][_norolling].csv (and _machine.txt) and prints a table.
import argparse
import csv
import math
import os
import statistics
import sys
import time

BENCH = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if a.endswith("bench_grains.py")), os.path.join(os.getcwd(), "bench"))
sys.path.insert(0, BENCH)
sys.path.insert(0, os.path.join(os.path.dirname(BENCH), "py"))

import yade  # noqa: E402
from yade import O, utils, geom  # noqa: E402
from yade.minieigenHP import Vector3  # noqa: E402
from yade.wrapper import (Bo1_Facet_Aabb, Bo1_Sphere_Aabb, Bo1_Wall_Aabb, ForceResetter, FrictMat, Ig2_Facet_Sphere_ScGeom,  # noqa: E402
                          Ig2_Sphere_Sphere_ScGeom, Ig2_Wall_Sphere_ScGeom, InsertionSortCollider, InteractionLoop,
                          Ip2_FrictMat_FrictMat_FrictPhys, Law2_ScGeom_FrictPhys_CundallStrack, NewtonIntegrator)

import yadeflex as yf  # noqa: E402
from yadeflex.constants import G  # noqa: E402
from yadeflex.module import ModuleParams, filled_module, fill_radii  # noqa: E402
from machine import machine_line  # noqa: E402


def parse():
    me = next((k for k, a in enumerate(sys.argv) if a.endswith("bench_grains.py")), 0)
    ap = argparse.ArgumentParser(prog="bench_grains.py", description="The module's fill alone: yade-flex's sphere contacts against YADE's built-in ones.")
    ap.add_argument("--small", action="store_true", help="the fill of damping_module.py --small")
    ap.add_argument("--reps", type=int, default=7, help="timed windows per scene")
    ap.add_argument("--window", type=int, default=200, help="steps per timed window")
    ap.add_argument("--warmup", type=int, default=300, help="steps from rest before the timing")
    ap.add_argument("--no-rolling", action="store_true", help="yade-flex without rolling resistance")
    ap.add_argument("--cache-dir", default=os.path.join(os.path.expanduser("~"), ".cache", "yadeflex", "modules"))
    ap.add_argument("--out", default=os.path.join(BENCH, "results"))
    a = ap.parse_args(sys.argv[me + 1:])
    for k in ("reps", "window", "warmup"):
        if getattr(a, k) < 1:
            ap.error(f"--{k} must be positive")
    return a, ModuleParams.small() if a.small else ModuleParams()


def grains_of(p, cache_dir):
    """(centre, radius) of the settled grains of the filled module, and its cache file."""
    ids, f, _ = filled_module(p, cache_dir=cache_dir)
    return [(Vector3(O.bodies[g].state.pos), O.bodies[g].shape.radius) for g in ids["grains"] if O.bodies[g] is not None], f


def scene(p, grains, kind, dt=None):
    """The current scene of O with the grains, slab and container, and the engines of `kind`
    (the built-in's at the fixed step dt: yade-flex's on the same fill)."""
    O.resetCurrentScene()
    pre = p.preset()
    fill = FrictMat(young=pre["young"], poisson=0.3, density=pre["density"], frictionAngle=math.radians(pre["friction_deg"]), label="fill")
    O.materials.append(fill)
    cont = FrictMat(young=1e8, poisson=0.3, density=1000, frictionAngle=0.0, label="container")
    O.materials.append(cont)
    O.bodies.append(utils.wall(0, axis=2, sense=1, material=fill))
    # where the lining was: the fill's container radius, or farther out where the settled grains
    # bear on a lining that bulged (the fills since 76fcaeb), 0.1 mm clear of the outermost grain
    _, r_in = fill_radii(p)
    r_in = max(r_in, max(math.hypot(c[0], c[1]) + r for c, r in grains) + 1e-4)
    O.bodies.append(geom.facetCylinder((0, 0, 0.6 * p.height), r_in, 1.2 * p.height, segmentsNumber=48, wallMask=4, material=cont))
    for c, r in grains:
        O.bodies.append(utils.sphere(c, r, material=fill))
    if kind == "builtin":
        O.engines = [ForceResetter(),
                     InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Facet_Aabb(), Bo1_Wall_Aabb()], verletDist=0.5 * min(r for _, r in grains), label="collider"),
                     InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Facet_Sphere_ScGeom(), Ig2_Wall_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                                     [Law2_ScGeom_FrictPhys_CundallStrack()], label="interactionLoop"),
                     NewtonIntegrator(gravity=(0, 0, -G), damping=0.0, label="newton")]
        O.dt = dt
    else:
        O.engines = p.engines(0.0) if kind == "flex" else yf.engines(damping=0.0, timestep_safety=p.timestep_safety)


def main():
    a, p = parse()
    tag = "_small" if a.small else ""
    os.makedirs(a.out, exist_ok=True)
    t_all = time.time()
    grains, f = grains_of(p, a.cache_dir)
    line = machine_line(yade.config.version, O.numThreads)
    print(f"bench_grains: the fill of {f}: {len(grains)} grains; {line.strip()}", flush=True)
    kinds = ["flex_norolling" if a.no_rolling else "flex", "builtin"]
    labels = {"flex": "yade-flex", "flex_norolling": "yade-flex, no rolling", "builtin": "built-in"}
    sid = {}
    dt_flex = None
    for kind in kinds:
        sid[kind] = O.thisScene if not sid else O.addScene()
        O.switchToScene(sid[kind])
        scene(p, grains, kind, dt_flex)
        for _ in range(a.warmup):
            O.step()
        if kind != "builtin":
            dt_flex = O.dt
        ke = sum(0.5 * b.state.mass * b.state.vel.squaredNorm() for b in O.bodies if b is not None and b.dynamic)
        print(f"  {labels[kind]}: {O.interactions.countReal()} real / {len(O.interactions.all(False))} interactions, dt {O.dt:.3g} s, "
              f"kinetic energy {ke:.3g} J after {a.warmup} steps", flush=True)
    tw = {k: [] for k in kinds}
    runs = {k: 0 for k in kinds}
    for _ in range(a.reps):
        for k in kinds:
            O.switchToScene(sid[k])
            coll = [e for e in O.engines if e.label == "collider"][0]
            n0 = coll.numAction
            t0 = time.perf_counter()
            for _ in range(a.window):
                O.step()
            tw[k].append(1e6 * (time.perf_counter() - t0) / a.window)
            runs[k] += coll.numAction - n0
    bd = {}
    for k in kinds:
        O.switchToScene(sid[k])
        for e in O.engines:
            e.execTime = 0
        O.timingEnabled = True
        for _ in range(a.window):
            O.step()
        O.timingEnabled = False
        bd[k] = dict(engines={(e.label or type(e).__name__): round(e.execTime * 1e-3 / a.window, 1) for e in O.engines},
                     interactions_real=O.interactions.countReal(), interactions_all=len(O.interactions.all(False)), dt=O.dt)
    tw = {k: (statistics.median(v), v, bd[k]["dt"]) for k, v in tw.items()}
    ref = tw["builtin"][0]
    rows = []
    print(f"\nus per step, median of {a.reps} interleaved windows of {a.window} steps (-j{O.numThreads})")
    print(f"{'scene':24s} {'us/step':>9s} {'built-in / this':>16s} {'collider runs/step':>19s}  windows; engines (us/step)")
    for k in kinds:
        med, ws, dt = tw[k]
        print(f"{labels[k]:24s} {med:9.1f} {ref / med:16.2f}x {runs[k] / (a.reps * a.window):19.3f}  " + ", ".join(f"{w:.0f}" for w in ws) + "; "
              + ", ".join(f"{e} {v}" for e, v in bd[k]["engines"].items()))
        rows.append(dict(scene=labels[k], grains=len(grains), us_per_step=round(med, 2), builtin_over_this=round(ref / med, 3), dt=dt,
                         collider_runs_per_step=round(runs[k] / (a.reps * a.window), 4), windows=" ".join(f"{w:.1f}" for w in ws), interactions_real=bd[k]["interactions_real"],
                         interactions_all=bd[k]["interactions_all"], engines_us=";".join(f"{e}={v}" for e, v in bd[k]["engines"].items())))
    tag += "_norolling" if a.no_rolling else ""
    path = os.path.join(a.out, f"grains_compare{tag}.csv")
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(a.out, f"grains_compare{tag}_machine.txt"), "w") as fh:
        fh.write(line)
    print(f"wrote {path} ({time.time() - t_all:.0f} s)")


if __name__ == "__main__":  # (bench/lammps_grains.py imports its scene)
    main()
