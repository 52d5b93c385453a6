# Side-by-side cases for the cylinder benchmark, run inside yade-double by bench_cylinders.py:
#   yade-double -n -jN -x bench/cylinder_cases.py timing STEPS REPEATS WARMUP
#   yade-double -n -j1 -x bench/cylinder_cases.py cantilever
# Prints one "RESULT {json}" line per case. The same geometry is built once with YADE's
# built-in GridNode/GridConnection/CohFrict classes (bench/builtin_grid.py) and once with
# yade-flex (yadeflex.harness.scenes), interleaved so that machine load hits both alike.
import json
import os
import sys

# bench/ is on PYTHONPATH (set by bench_cylinders.py)
import builtin_grid as bg  # noqa: E402
from yade import O  # noqa: E402

from yadeflex.harness import scenes  # noqa: E402

HELIX = dict(n_seg=200, radius_wire=0.002, coil_radius=0.05, pitch=0.01)
NET = dict(n=20, spacing=0.05, radius_wire=0.002, sphere_radius=0.1, speed=5.0, young=200e9, density=7850.0, friction_deg=30.0,
           gap=0.001)


def emit(d):
    print("RESULT " + json.dumps(d), flush=True)


def real_interactions():
    return sum(1 for i in O.interactions if i.isReal)


def timing(steps, repeats, warmup):
    for rep in range(repeats):
        for impl in ("builtin", "flex"):
            for scene in ("helix", "net"):
                if impl == "builtin":
                    if scene == "helix":
                        bg.helix(n_seg=HELIX["n_seg"], radius_wire=HELIX["radius_wire"], coil_radius=HELIX["coil_radius"], pitch=HELIX["pitch"])
                    else:
                        bg.net(n=NET["n"], spacing=NET["spacing"], radius_wire=NET["radius_wire"], sphere_radius=NET["sphere_radius"],
                               sphere_speed=NET["speed"], friction_deg=NET["friction_deg"], gap=NET["gap"])
                else:
                    if scene == "helix":
                        scenes.helix_scene(segments=HELIX["n_seg"], coil_radius=HELIX["coil_radius"], pitch=HELIX["pitch"],
                                           wire_radius=HELIX["radius_wire"])
                    else:
                        scenes.net_impact(n=NET["n"], spacing=NET["spacing"], wire_radius=NET["radius_wire"], sphere_radius=NET["sphere_radius"],
                                          speed=NET["speed"], sphere_young=NET["young"], sphere_density=NET["density"],
                                          friction_deg=NET["friction_deg"], gap=NET["gap"])
                    O.step()  # the time stepper sets O.dt
                t = bg.time_per_step(steps, 1, warmup, per_engine=(rep == 0))
                emit(dict(case="timing", impl=impl, scene=scene, threads=O.numThreads, repeat=rep, s_per_step=t["median_s_per_step"],
                          dt=O.dt, bodies=len([b for b in O.bodies if b is not None]), interactions=len(O.interactions),
                          real=real_interactions(), per_engine=t.get("per_engine_s_per_step")))


def cantilever():
    for load in ("tip", "self"):
        for n in (2, 5, 10, 20):
            r = bg.cantilever(n_seg=n, load=load)
            emit(dict(case="cantilever", impl="builtin", load=load, segments=n, ratio=r["ratio"], converged=r["converged"],
                      iterations=r["iterations"]))
            force = 1.0
            s = scenes.cantilever(segments=n, length=1.0, radius=0.01, load=load, force=force)
            steps = scenes.settle([s["tip"]], rel_tol=1e-7, chunk=5000)
            w = -O.bodies[s["tip"]].state.pos[2]
            from tol_ref import cantilever_reference  # noqa: E402
            emit(dict(case="cantilever", impl="flex", load=load, segments=n, ratio=w / cantilever_reference(load, 1.0, 0.01, force),
                      converged=True, iterations=steps))


if __name__ == "__main__" or True:
    what = sys.argv[1] if len(sys.argv) > 1 else "timing"
    if what == "timing":
        timing(int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4]))
    else:
        cantilever()
