# Cost of one VTK frame of the damping-module impact (yadeflex.vtk_frames.VtkRecorder), per group,
# against the time of the steps between two frames (GPL-2.0-or-later).
#
#     yade-double -n -x bench/vtk_frame.py [--small] [--reps 5] [--steps 200] [--out bench/results/vtk_frame.csv]
#
# Loads the main job's filled module (yadeflex.module, cached in ~/.cache/yadeflex/modules),
# adds the boulder with the main job's engines, steps to 5 ms after the first contact (the
# fill loaded, contacts under load), then --reps times: one frame (each group's build and write
# timed) and --steps steps (timed). Prints the medians and the frame's cost as a share of a run
# writing a frame every 1 ms (the main job's default); writes CSV rows (module, what, seconds).
import argparse
import csv
import os
import statistics
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(next((a for a in sys.argv if a.endswith("vtk_frame.py")), __file__)))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "py"))

from yade import O  # noqa: E402

import yadeflex.vtk_frames as YO  # noqa: E402
from yadeflex.module import ModuleParams, impact_start  # noqa: E402


def main(argv):
    ap = argparse.ArgumentParser()
    ap.add_argument("--small", action="store_true")
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--out", default=os.path.join(HERE, "results", "vtk_frame.csv"))
    a = ap.parse_args(argv)
    p = ModuleParams.small() if a.small else ModuleParams()
    impact_start(p)
    t0 = O.time
    while O.time < t0 + 5e-3:
        O.run(100, True)
    build = {g: [] for g in YO.GROUPS}
    frame, step = [], []
    with tempfile.TemporaryDirectory() as tmp:
        rec = YO.VtkRecorder(tmp)
        orig = dict(YO._BUILD)
        for g, f in orig.items():  # time each group's build (and its write, in _write_vtu: below)
            def timed(vtk, items, fr, g=g, f=f):
                s = time.perf_counter()
                out = f(vtk, items, fr)
                build[g].append(time.perf_counter() - s)
                return out
            YO._BUILD[g] = timed
        for _ in range(a.reps):
            s = time.perf_counter()
            rec()
            frame.append(time.perf_counter() - s)
            s = time.perf_counter()
            O.run(a.steps, True)
            step.append((time.perf_counter() - s) / a.steps)
        YO._BUILD.update(orig)
    n = dict(bodies=len([b for b in O.bodies if b is not None]), contacts=len(YO.real_contacts()))
    tag = "small" if a.small else "default"
    med = lambda xs: statistics.median(xs) if xs else 0.0
    steps_per_ms = 1e-3 / O.dt
    rows = [(tag, "frame", med(frame)), (tag, "step", med(step)), (tag, "steps_per_ms", steps_per_ms)]
    rows += [(tag, f"build_{g}", med(v)) for g, v in build.items() if v]
    print(f"{tag} module: {n['bodies']} bodies, {n['contacts']} contacts, dt {O.dt:.3g} s; medians of {a.reps}")
    print(f"  {'what':22s} {'seconds':>10s}")
    for _, w, v in rows:
        print(f"  {w:22s} {v:10.4g}")
    share = med(frame) / (med(frame) + steps_per_ms * med(step))
    print(f"  a frame every 1 ms of impact: {100 * share:.0f}% of the run's wall time")
    rows.append((tag, "frame_share_at_1ms", share))
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    old = []
    if os.path.exists(a.out):
        with open(a.out, newline="") as f:
            old = [r for r in csv.reader(f)][1:]
    with open(a.out, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["module", "what", "value"])
        w.writerows([r for r in old if r[0] != tag] + [(t, wh, repr(v)) for t, wh, v in rows])


main([x for x in sys.argv[next((k for k, x in enumerate(sys.argv) if x.endswith("vtk_frame.py")), 0) + 1:]])
