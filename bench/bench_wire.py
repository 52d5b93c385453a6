# Benchmark: chain-link panel pulled apart, YADE's built-in WireMat/WirePM against yade-flex,
# in one run (GPL-2.0-or-later).
#
#   YADE_PREFIX=... PYTHONPATH=py yade-double -n -j1 -x bench/bench_wire.py [BUILTIN_DIR] [--quick]
#
# The same geometry on both sides: TECCO G65/3 lattice (rhombus diagonals 83 x 143 mm), 1 x 1 m,
# the same wire curve (yadeflex.wire.TECCO_WIRE_*) and the same distortion (slack scale 0.036,
# force ratio 1: WirePM type 2 with lambda_u, lambda_F). The built-in panel comes from
# bench/builtin_wire.py (BUILTIN_DIR: where it is, default this directory): spheres with
# WirePM links, no contact between wires. yade-flex, twice: FlexCylinder legs with cylinder
# contacts, once as beams (bending and twist, the default mesh) and once as bars (axial only,
# bending_factor 0: the model class of WirePM, plus the contacts). All are pulled along the spirals (y). Time per step: median of REPS
# runs of STEPS steps by O.run (builtin_wire.run_steps: no Python between the steps, as scripts
# run), after a warm-up, with the top row moving (links loaded); per link-step =
# per step / links. Tensile curves: peak force per metre width. Writes
# bench/results/wire_timing.csv, wire_engines.csv (each engine's time per step, one timed run
# per round and side), wire_summary.csv, wire_curves.csv and wire_machine.txt.
import csv
import math
import os
import statistics
import sys
import time

from yade import O

from yadeflex import wire, mesh

from yadeflex.harness import tensile

HERE = os.path.dirname(os.path.abspath(sys.argv[0] if sys.argv[0].endswith(".py") else __file__))
args = [a for a in sys.argv[1:] if not a.startswith("--")]
builtin_dir = args[0] if args else HERE
quick = "--quick" in sys.argv
sys.path.insert(0, builtin_dir)
sys.path.insert(0, HERE)
try:
    import builtin_wire as bw
except ImportError:
    raise SystemExit(f"bench_wire: bench/builtin_wire.py (the built-in WirePM reference scene) not found in {builtin_dir}; "
                     "pass its directory as the first argument")

# many short interleaved rounds: on the shared VM the speed drifts by up to 1.5x over tens of
# seconds, so each round's ratio is taken between runs a second or two apart
STEPS, REPS, WARMUP = (500, 3, 50) if quick else (2000, 5, 100)
ROUNDS = 1 if quick else 11
CURVE = list(zip(wire.TECCO_WIRE_STRAIN, wire.TECCO_WIRE_STRESS))
SLACK, RATIO = mesh.TECCO_MESH_CALIBRATION["slack_scale"], mesh.TECCO_MESH_CALIBRATION["force_ratio"]
out = os.path.join(HERE, "results")
os.makedirs(out, exist_ok=True)


def time_steps():
    for _ in range(WARMUP):
        O.step()
    wall = []
    for _ in range(REPS):
        t0 = time.perf_counter()
        bw.run_steps(STEPS)
        wall.append((time.perf_counter() - t0) / STEPS * 1e6)
    return statistics.median(wall), wall


def engine_times():
    """us per step of each engine over one more timed run of STEPS steps (O.timingEnabled)."""
    for e in O.engines:
        e.execTime = 0
    O.timingEnabled = True
    bw.run_steps(STEPS)
    O.timingEnabled = False
    return {(e.label or e.__class__.__name__): e.execTime * 1e-3 / STEPS for e in O.engines}


def builtin_panel():
    return bw.panel(topology="rhombic", width=1.0, height=1.0, cell=(mesh.TECCO_G65_DX, mesh.TECCO_G65_DY), wire_d=0.003,
                    strain_stress=CURVE, wire_type=2, lambda_u=SLACK, lambda_F=RATIO, seed=12345, damping=0.2)


FLEX = {"yade-flex": 1.0, "yade-flex bars": 0.0}  # implementation -> bending_factor


def flex_panel(speed, bending_factor=1.0):
    return tensile.mesh_panel_scene(width=1.0, height=1.0, direction="longitudinal", speed=speed, damping=0.2,
                                    material=wire.tecco_wire(slack_scale=SLACK, force_ratio=RATIO, bending_factor=bending_factor))


rows, engines = [], []
for rep in range(ROUNDS):  # interleaved: built-in, yade-flex beams, yade-flex bars, built-in, ...
    info = builtin_panel()
    t = bw.time_per_link_step(STEPS, REPS, WARMUP, velocity=0.05)
    rows.append(dict(impl="builtin WirePM", round=rep, links=t["links"], bodies=len(O.bodies), interactions=t["interactions"], dt=O.dt,
                     us_per_step=t["us_per_step"], us_per_link_step=t["us_per_link_step"], contacts="none"))
    engines += [dict(impl="builtin WirePM", round=rep, engine=k, us_per_step=v) for k, v in t["engines"].items()]
    for impl, bf in FLEX.items():
        s = flex_panel(0.05, bf)
        O.step()
        med, _ = time_steps()
        nl = sum(1 for c in s["cylinders"] if O.bodies[c] is not None)
        rows.append(dict(impl=impl, round=rep, links=nl, bodies=len(O.bodies), interactions=len(O.interactions), dt=O.dt,
                         us_per_step=med, us_per_link_step=med / nl, contacts="cylinder-cylinder, sphere-cylinder"))
        engines += [dict(impl=impl, round=rep, engine=k, us_per_step=v) for k, v in engine_times().items()]
    for r in rows[-3:]:
        print(" ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}" for k, v in r.items()), flush=True)

summary = {}
for impl in ("builtin WirePM", *FLEX):
    sel = [r for r in rows if r["impl"] == impl]
    summary[impl] = dict(us_per_step=statistics.median(r["us_per_step"] for r in sel),
                         us_per_link_step=statistics.median(r["us_per_link_step"] for r in sel), dt=sel[0]["dt"], links=sel[0]["links"])
ref = summary["builtin WirePM"]
for impl in FLEX:
    d = summary[impl]
    # the median of the per-round ratios (each round: both sides under the same load)
    per_round = [b["us_per_link_step"] / f["us_per_link_step"] for b, f in
                 zip((r for r in rows if r["impl"] == "builtin WirePM"), (r for r in rows if r["impl"] == impl))]
    q = statistics.quantiles(per_round, n=4) if len(per_round) > 1 else [per_round[0]] * 3
    d.update(speedup_per_link_step=statistics.median(per_round), speedup_q1=q[0], speedup_q3=q[2],
             speedup_per_simulated_s=statistics.median(per_round) * d["dt"] / ref["dt"])
    print(f"per link-step: built-in {ref['us_per_link_step']:.4f} us, {impl} {d['us_per_link_step']:.4f} us -> "
          f"{d['speedup_per_link_step']:.2f}x (rounds' ratios {', '.join(f'{x:.2f}' for x in sorted(per_round))}); "
          f"per simulated second {d['speedup_per_simulated_s']:.2f}x")

# where each side's step goes: the median over the rounds of each engine's time (one timed run
# per round, O.timingEnabled)
print(f"{'engine (us/step, median of rounds)':36s}" + "".join(f"{i:>16s}" for i in ("builtin WirePM", *FLEX)))
names = list(dict.fromkeys(r["engine"] for r in engines))
for name in names:
    vals = [statistics.median([r["us_per_step"] for r in engines if r["impl"] == i and r["engine"] == name] or [float("nan")])
            for i in ("builtin WirePM", *FLEX)]
    print(f"{name:36s}" + "".join(f"{v:16.2f}" for v in vals))

# tensile curves (one run each, quasi-static 1 m/s), sampled every 0.3 mm of elongation (a
# coarser sampling misses the peak: bench/wire_convergence.py)
curves = {}
info = builtin_panel()
res = bw.pull(velocity=1.0, max_elongation=0.3 * info["size_y"], record_every=50, max_steps=2_000_000)
curves["builtin WirePM"] = [(u / info["size_y"], f / info["size_x"]) for u, f, _ in res["curve"]]
for impl, bf in FLEX.items():
    s = flex_panel(1.0, bf)
    r = tensile.mesh_tensile_test(s, chunk=40, max_elongation=0.3)
    curves[impl] = list(zip(r["elongation"], r["force_per_m"]))
for impl, c in curves.items():
    pk = max(c, key=lambda p: p[1])
    summary[impl].update(peak_kN_per_m=pk[1] / 1e3, elongation_at_peak=pk[0])
    print(f"{impl}: peak {pk[1] / 1e3:.1f} kN/m at elongation {pk[0]:.4f}")

with open(os.path.join(out, "wire_timing.csv"), "w", newline="") as fh:
    w = csv.DictWriter(fh, fieldnames=list(rows[0]))
    w.writeheader()
    w.writerows(rows)
with open(os.path.join(out, "wire_engines.csv"), "w", newline="") as fh:
    w = csv.DictWriter(fh, fieldnames=list(engines[0]))
    w.writeheader()
    w.writerows(engines)
with open(os.path.join(out, "wire_summary.csv"), "w", newline="") as fh:
    keys = ["impl", "links", "dt", "us_per_step", "us_per_link_step", "speedup_per_link_step", "speedup_q1", "speedup_q3", "speedup_per_simulated_s",
            "peak_kN_per_m", "elongation_at_peak"]
    w = csv.writer(fh)
    w.writerow(keys)
    for impl, d in summary.items():
        w.writerow([impl] + [d.get(k) for k in keys[1:]])
with open(os.path.join(out, "wire_curves.csv"), "w", newline="") as fh:
    w = csv.writer(fh)
    w.writerow(["impl", "elongation", "force_per_m"])
    for impl, c in curves.items():
        w.writerows([impl, e, f] for e, f in c)
from machine import machine_line  # noqa: E402  (bench/machine.py, next to this script)

with open(os.path.join(out, "wire_machine.txt"), "w") as fh:
    fh.write(machine_line().rstrip("\n") + f"; threads {O.numThreads}, steps {STEPS} x {REPS} (median), warm-up {WARMUP}, "
             f"{ROUNDS} interleaved rounds\n")
