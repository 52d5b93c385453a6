# Is the main job's filled module in equilibrium when the impact starts? (GPL-2.0-or-later)
#
#     yade-double -n -j1 -x bench/fill_equilibrium.py [--steps 12000] [--chunk 2000] [--damping 0.7 0.3 0]
#         [--no-rolling --out bench/results/fill_equilibrium_norolling.csv]
#
# Loads the filled default module (yadeflex.module.filled_module: from the cache, or filled on
# first use, as scripts/run does), without the boulder, and lets it run on with the main job's
# engines at each local damping given (0.7 is the filling's settle_damping, 0 the impact's), each
# time from the same saved state. Every --chunk steps it records: the grains' kinetic energy,
# the drop of their centre of mass, YADE's unbalanced-force ratio (utils.unbalancedForce: 0 in
# static equilibrium), the mean coordination number of the grains (2 x grain-grain contacts /
# grains), the contacts between grains and lining and their total normal force, and the largest
# radius of a lining node. A module in equilibrium keeps its centre of mass, a kinetic energy
# near zero and an unbalanced force well below 0.01-0.05, at any damping.
# Prints a table, writes bench/results/fill_equilibrium.csv and .png and the machine line.
import argparse
import csv
import math
import os
import sys
import time

HERE = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if a.endswith("fill_equilibrium.py")), os.path.join(os.getcwd(), "bench"))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "py"))
sys.path.insert(0, HERE)
from yade import O, utils  # noqa: E402
from yadeflex import module  # noqa: E402
from machine import machine_line  # noqa: E402

me = next((k for k, a in enumerate(sys.argv) if a.endswith("fill_equilibrium.py")), 0)
ap = argparse.ArgumentParser(prog="fill_equilibrium.py")
ap.add_argument("--steps", type=int, default=12000)
ap.add_argument("--chunk", type=int, default=2000)
ap.add_argument("--damping", type=float, nargs="+", default=[0.7, 0.3, 0.0])
ap.add_argument("--no-rolling", action="store_true", help="switch the grains' rolling resistance off (a diagnosis: is it the driver?)")
ap.add_argument("--small", action="store_true", help="the reduced module of the tests (scripts/damping_module.py --small)")
ap.add_argument("--timestep-safety", type=float, default=None, help="time step x the estimate (default: the module's, ModuleParams.timestep_safety; the fill is the same)")
ap.add_argument("--cache-dir", default=None, help="where filled modules are cached (default ~/.cache/yadeflex/modules)")
ap.add_argument("--out", default=None, help="CSV to write (default bench/results/fill_equilibrium.csv; the PNG and machine line next to it)")
a = ap.parse_args(sys.argv[me + 1:])
if a.steps < 1 or a.chunk < 1:
    ap.error("--steps and --chunk must be positive")

p = module.ModuleParams()
if a.small:
    import dataclasses
    p = dataclasses.replace(p, diameter=0.4, height=0.3, grain_min=0.06, grain_max=0.08, boulder_mass=100.0, drop_height=1.0)
if a.timestep_safety is not None:
    p.timestep_safety = a.timestep_safety
    try:
        p.validate()
    except ValueError as e:
        ap.error(str(e))
ids, cache, _ = module.filled_module(p, cache_dir=a.cache_dir)
saved = "/tmp/yadeflex_fill_equilibrium.yade.gz"
O.engines = []
O.save(saved)
out = os.path.join(HERE, "results")
os.makedirs(out, exist_ok=True)
rows = []


def record(c, t0, z0):
    grains = [g for g in ids["grains"] if O.bodies[g] is not None]
    mass = sum(O.bodies[g].state.mass for g in grains)
    ke = sum(0.5 * O.bodies[g].state.mass * O.bodies[g].state.vel.squaredNorm() for g in grains)
    zc = sum(O.bodies[g].state.pos[2] * O.bodies[g].state.mass for g in grains) / mass
    fc = module.fill_contacts(ids)
    gg, gl, fl = fc["grain_grain"], fc["grain_lining"], fc["grain_lining_force"]
    rl = max(math.hypot(O.bodies[n].state.pos[0], O.bodies[n].state.pos[1]) for n in ids["lining_nodes"])
    return dict(damping=c, steps=O.iter - t0[0], time_ms=(O.time - t0[1]) * 1e3, kinetic_J=ke, com_drop_mm=(z0 - zc) * 1e3,
                unbalanced=utils.unbalancedForce() if O.iter > t0[0] else float("nan"), coordination=2.0 * gg / len(grains),
                grain_lining_contacts=gl, grain_lining_force_N=fl, lining_rmax_m=rl)


for c in a.damping:
    O.load(saved)
    O.engines = p.engines(c)
    if a.no_rolling:
        for f in next(e for e in O.engines if e.label == "interactionLoop").lawDispatcher.functors:
            if hasattr(f, "rollingFriction"):
                f.rollingFriction, f.rollingStiffness = 0.0, 0.0
    t0 = (O.iter, O.time)
    grains = [g for g in ids["grains"] if O.bodies[g] is not None]
    z0 = sum(O.bodies[g].state.pos[2] * O.bodies[g].state.mass for g in grains) / sum(O.bodies[g].state.mass for g in grains)
    rows.append(record(c, t0, z0))
    wall = time.time()
    while O.iter - t0[0] < a.steps:
        O.run(a.chunk, True)
        rows.append(record(c, t0, z0))
        r = rows[-1]
        print(f"  damping {c}: {r['time_ms']:6.1f} ms, kinetic {r['kinetic_J']:.3g} J, centre of mass down {r['com_drop_mm']:.2f} mm, "
              f"unbalanced {r['unbalanced']:.3f}, coordination {r['coordination']:.2f} ({time.time() - wall:.0f} s)", flush=True)

keys = list(rows[0])
print(f"filled module {os.path.basename(cache)}: {len([g for g in ids['grains'] if O.bodies[g] is not None])} grains")
print(" ".join(f"{k:>20s}" for k in keys))
for r in rows:
    print(" ".join(f"{r[k]:20.4g}" for k in keys))
csv_path = a.out or os.path.join(out, "fill_equilibrium.csv")
base = os.path.splitext(csv_path)[0]
with open(csv_path, "w", newline="") as fh:
    w = csv.DictWriter(fh, fieldnames=keys)
    w.writeheader()
    w.writerows(rows)
with open(base + "_machine.txt", "w") as fh:
    fh.write(machine_line().rstrip("\n") + f"; {a.steps} steps per damping, -j{O.numThreads}{', rolling resistance off' if a.no_rolling else ''}\n")
try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 3, figsize=(13, 3.8))
    for c in a.damping:
        sel = [r for r in rows if r["damping"] == c]
        t = [r["time_ms"] for r in sel]
        ax[0].plot(t, [r["com_drop_mm"] for r in sel], "o-", label=f"damping {c}")
        ax[1].plot(t, [r["kinetic_J"] for r in sel], "o-", label=f"damping {c}")
        ax[2].plot(t[1:], [r["unbalanced"] for r in sel][1:], "o-", label=f"damping {c}")
    ax[0].set_ylabel("fill centre of mass drop [mm]")
    ax[1].set_ylabel("grains' kinetic energy [J]")
    ax[2].set_ylabel("unbalanced force ratio [-]")
    for x in ax:
        x.set_xlabel("time after the filled state [ms]")
        x.grid(alpha=0.3)
    ax[0].legend()
    fig.suptitle("Filled default module left alone (no boulder): does it stay put?")
    fig.tight_layout()
    fig.savefig(base + ".png", dpi=110)
except ImportError:
    print("matplotlib missing: no plot")
print(f"wrote {csv_path}")
