# Diagnostic: which grains leave the damping module during the impact, and how (GPL-2.0-or-later).
#
#     yade-double -n -j1 -x bench/escape_trace.py [--t-end 0.075] [--every 250] [--rolling]
#
# The scene of bench/bench_module.py's yade-flex model: the main job's filled module (from the
# cache), its boulder, yf.engines() with damping 0 and no rolling resistance (--rolling: the main
# job's engines, with it). Every --every steps each grain is tested with bench_module.escaped (a
# horizontal ray from the axis through its centre against the lining's triangles; outside the
# mesh: also farther out than its nearest mesh node + 5 mm). For every grain found outside it
# prints, from the samples kept: when it crossed the lining's radius, its height, speed and whether
# it was flying free (velocity unchanged but for gravity over the last samples), how far the
# nearest lining facet was, and how high the lining's top row of nodes stood at its angle at
# that time and at the start. At the end: lining facets torn, legs broken.
# Writes bench/results/escape_trace.csv (one row per escaped grain) and prints it.
import argparse
import csv
import math
import os
import sys
import time

BENCH = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if a.endswith("escape_trace.py")), os.path.join(os.getcwd(), "bench"))
sys.path.insert(0, BENCH)
sys.path.insert(0, os.path.join(os.path.dirname(BENCH), "py"))

import numpy as np  # noqa: E402
from yade import O  # noqa: E402

import yadeflex as yf  # noqa: E402
from yadeflex.module import ModuleParams, filled_module, add_boulder  # noqa: E402
import bench_module as bmod  # noqa: E402
from builtin_pfacet import _closest_on_triangle  # noqa: E402  (Ericson's walk of the Voronoi regions)


def parse():
    me = next((k for k, a in enumerate(sys.argv) if a.endswith("escape_trace.py")), 0)
    ap = argparse.ArgumentParser(prog="escape_trace.py", description="Which grains leave the damping module, and how.")
    ap.add_argument("--t-end", type=float, default=0.075, help="simulated time after the start [s]")
    ap.add_argument("--every", type=int, default=250, help="steps between samples")
    ap.add_argument("--rolling", action="store_true", help="the main job's engines (rolling resistance) instead of bench_module's")
    a = ap.parse_args(sys.argv[me + 1:])
    if not (a.t_end > 0 and a.every >= 1):
        ap.error("--t-end and --every must be positive")
    return a


def tri_nodes(f):
    s = O.bodies[f].shape
    return tuple(n if isinstance(n, int) else n.id for n in (s.node1, s.node2, s.node3))


def main():
    a = parse()
    p = ModuleParams()
    ids, _, _ = filled_module(p)
    bid = add_boulder(p, ids)
    O.engines = p.engines(p.damping) if a.rolling else yf.engines(damping=p.damping, timestep_safety=p.timestep_safety)
    grains, lining, mesh = list(ids["grains"]), list(ids["lining"]), list(ids["mesh_nodes"])
    tris = {f: tri_nodes(f) for f in lining}
    ray_tris = bmod.lining_triangles(lining)
    nodes = sorted({n for t in tris.values() for n in t})
    X0 = np.array([list(O.bodies[n].state.pos) for n in nodes])
    ang0 = np.degrees(np.arctan2(X0[:, 1], X0[:, 0]))
    top = X0[:, 2] > X0[:, 2].max() - 0.02  # the lining's top row
    radius = {g: O.bodies[g].shape.radius for g in grains}
    index = {n: k for k, n in enumerate(nodes)}
    r_lin = float(np.median(np.hypot(X0[:, 0], X0[:, 1])))  # the lining's radius at rest
    r_near = r_lin - 0.03 - max(radius.values())  # grains whose surface is within 30 mm of it

    def top_z(angle, X):
        m = top & (np.abs(((ang0 - angle + 180) % 360) - 180) < 6)
        return float(X[m, 2].max()) if m.any() else float("nan")

    history = {}  # grain -> [(t, pos, vel, nearest facet gap, top z at its angle)]
    out, rows = {}, []
    t0, w0 = O.time, time.time()
    while O.time < t0 + a.t_end:
        O.run(a.every, True)
        t = O.time - t0
        X = np.array([list(O.bodies[n].state.pos) for n in nodes])
        P = np.array([list(O.bodies[g].state.pos) for g in grains])
        r = np.hypot(P[:, 0], P[:, 1])
        near_wall = [grains[k] for k in np.nonzero(r > r_near)[0]]
        alive = [f for f in lining if O.bodies[f] is not None]
        T = np.array([[X[index[n]] for n in tris[f]] for f in alive])  # facets x 3 nodes x 3
        C = T.mean(axis=1)
        for g in near_wall:  # keep a trace of the grains next to the lining
            b = O.bodies[g]
            x = np.array(list(b.state.pos))
            ang = math.degrees(math.atan2(x[1], x[0]))
            close = np.nonzero(((C - x)**2).sum(axis=1) < 0.15**2)[0]
            gap = min((np.linalg.norm(x - np.array(_closest_on_triangle(x, *T[k])[0])) for k in close), default=float("inf")) - radius[g]
            history.setdefault(g, []).append((t, x, np.array(list(b.state.vel)), gap, top_z(ang, X)))
        for g in near_wall:
            if g not in out and bmod.escaped([g], ray_tris, mesh)[0]:
                out[g] = t
                print(f"  t = {1e3 * t:5.1f} ms: grain #{g} outside the lining ({time.time() - w0:.0f} s)", flush=True)
    torn = [f for f in lining if O.bodies[f] is None]
    # a ruptured element is erased (FlexElementEngine); its nRuptured counts legs, ring segments and facets alike
    legs = sum(1 for c in list(ids["mesh_cylinders"]) + list(ids["ring_top"]) + list(ids["ring_bottom"]) if O.bodies[c] is None)
    for g, t_out in sorted(out.items(), key=lambda kv: kv[1]):
        h = history[g]
        # the sample at which the grain's centre crossed the lining's radius at rest (about 0.49 m)
        k = next((i for i, s in enumerate(h) if math.hypot(s[1][0], s[1][1]) >= r_lin), len(h) - 1)
        tk, x, v, gap, zt = h[k]
        # flying free: velocity changed by gravity alone over the samples before the crossing
        dv = [np.linalg.norm(h[i][2] - h[i - 1][2] - np.array([0, 0, -9.81]) * (h[i][0] - h[i - 1][0])) for i in range(max(1, k - 3), k + 1)]
        ang = math.degrees(math.atan2(x[1], x[0]))
        torn_near = [f for f in torn if np.linalg.norm(np.mean([X0[index[n]] for n in tris[f]], axis=0)[:2] - x[:2]) < 0.1]
        rows.append(dict(grain=g, radius_mm=1e3 * radius[g], t_outside_ms=1e3 * t_out, t_cross_ms=1e3 * tk, z_cross_m=x[2], speed_m_s=float(np.linalg.norm(v)),
                         free_flight=bool(max(dv) < 0.05), gap_to_lining_mm=1e3 * gap, lining_top_z_then_m=zt, lining_top_z_start_m=top_z(ang, X0),
                         torn_facet_within_0_1_m=len(torn_near) > 0))
    print(f"\n{len(out)} grains outside the lining in {1e3 * a.t_end:.0f} ms; {len(torn)} lining facets torn, {legs} legs and ring segments broken")
    print("grain  R mm  out at ms  crossing ms  z m    speed  free flight  gap mm  lining top z then / at start  torn facet near")
    for r in rows:
        print(f"{r['grain']:5d}  {r['radius_mm']:4.1f}  {r['t_outside_ms']:9.1f}  {r['t_cross_ms']:11.1f}  {r['z_cross_m']:.3f}  {r['speed_m_s']:5.2f}  "
              f"{str(r['free_flight']):11s}  {r['gap_to_lining_mm']:6.1f}  {r['lining_top_z_then_m']:.3f} / {r['lining_top_z_start_m']:.3f}  {r['torn_facet_within_0_1_m']}")
    res = os.path.join(os.path.dirname(BENCH), "bench", "results", "escape_trace" + ("_rolling" if a.rolling else "") + ".csv")
    os.makedirs(os.path.dirname(res), exist_ok=True)
    with open(res, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()) if rows else ["grain"])
        w.writeheader()
        w.writerows(rows)
    print(f"written {res}")


main()
