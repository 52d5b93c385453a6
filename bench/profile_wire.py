# Per-engine time of yade-flex's step on the TECCO panel of bench/bench_wire.py (GPL-2.0-or-later).
#
#     yade-double -n -j1 -x bench/profile_wire.py [--steps 3000]
#
# Builds the same 1 x 1 m panel (same wire curve and distortion), pulls it at 0.05 m/s, warms up
# 200 steps, then times --steps steps with O.timingEnabled. Prints the table and writes
# bench/results/profile_wire.csv (engine, us_per_step, share).
import argparse
import csv
import os
import sys
import time

HERE = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if a.endswith("profile_wire.py")), os.path.join(os.getcwd(), "bench"))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "py"))
from yade import O  # noqa: E402
from yadeflex import mesh, wire  # noqa: E402
from yadeflex.harness import tensile

me = next((k for k, a in enumerate(sys.argv) if a.endswith("profile_wire.py")), 0)
ap = argparse.ArgumentParser(prog="profile_wire.py")
ap.add_argument("--steps", type=int, default=3000)
ap.add_argument("--links", choices=("beam", "bar"), default="beam",
                help="beam: links with bending and twist (the default mesh); bar: axial-only links (bending_factor 0, as WirePM)")
a = ap.parse_args(sys.argv[me + 1:])
if a.steps < 1:
    ap.error("--steps must be positive")
cal = mesh.TECCO_MESH_CALIBRATION
s = tensile.mesh_panel_scene(width=1.0, height=1.0, direction="longitudinal", speed=0.05, damping=0.2,
                             material=wire.tecco_wire(slack_scale=cal["slack_scale"], force_ratio=cal["force_ratio"],
                                                      bending_factor=1.0 if a.links == "beam" else 0.0))
for _ in range(200):
    O.step()
O.timingEnabled = True
for e in O.engines:
    e.execTime = 0
t0 = time.perf_counter()
for _ in range(a.steps):
    O.step()
wall = (time.perf_counter() - t0) / a.steps * 1e6
links = sum(1 for c in s["cylinders"] if O.bodies[c] is not None)
nodes = sum(1 for b in O.bodies if b is not None and type(b.shape).__name__ == "FlexNode")
rows = [("step (wall)", wall)] + [((e.label or type(e).__name__), e.execTime / 1e3 / a.steps) for e in O.engines]
print(f"TECCO panel, {links} links, {nodes} nodes, {len(O.interactions)} interactions, dt {O.dt:.3g} s, {a.steps} steps at -j1")
print(f"{'engine':<20} {'us/step':>8} {'share':>7}")
for name, us in rows:
    print(f"{name:<20} {us:8.2f} {us / wall:7.1%}")
out = os.path.join(HERE, "results", "profile_wire.csv")
with open(out, "w", newline="") as fh:
    w = csv.writer(fh)
    w.writerow(["engine", "us_per_step", "share", "links", "nodes"])
    for name, us in rows:
        w.writerow([name, round(us, 3), round(us / wall, 4), links, nodes])
print("wrote", out)
