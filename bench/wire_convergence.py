# Is the 1 m/s pull of bench/bench_wire.py converged in the time step? (GPL-2.0-or-later)
#
#     yade-double -n -j1 -x bench/wire_convergence.py [--factors 1,0.5,0.25]
#
# The same 1 x 1 m TECCO panel as bench_wire.py (same wire curve, same distortion), pulled along
# the spirals at 1 m/s to rupture, on all three sides: YADE's WirePM (its step dt_factor x the
# links' limit; bench_wire uses 0.5), yade-flex beam links and bar links (FlexTimeStepper.safety;
# bench_wire uses 0.5). Each side is run at its bench step times each factor. Prints the peak
# force per metre and the elongation at the peak, and the change against the smallest step;
# writes bench/results/wire_convergence.csv. The curves are sampled every 0.3 mm of elongation.
import argparse
import csv
import os
import sys
import time

HERE = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if a.endswith("wire_convergence.py")), os.path.join(os.getcwd(), "bench"))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "py"))
sys.path.insert(0, HERE)
from yade import O  # noqa: E402
from yadeflex import mesh, wire  # noqa: E402
from yadeflex.harness import tensile
import builtin_wire as bw  # noqa: E402

me = next((k for k, a in enumerate(sys.argv) if a.endswith("wire_convergence.py")), 0)
ap = argparse.ArgumentParser(prog="wire_convergence.py")
ap.add_argument("--factors", default="1,0.5,0.25", help="step factors, relative to each side's bench_wire step")
a = ap.parse_args(sys.argv[me + 1:])
factors = [float(x) for x in a.factors.split(",")]
if not factors or any(not (0 < f <= 1) for f in factors):
    ap.error("--factors must be numbers in (0, 1]")

CURVE = list(zip(wire.TECCO_WIRE_STRAIN, wire.TECCO_WIRE_STRESS))
SLACK, RATIO = mesh.TECCO_MESH_CALIBRATION["slack_scale"], mesh.TECCO_MESH_CALIBRATION["force_ratio"]
# steps between samples of the curve at factor 1 (divided by the factor: the same elongation
# between samples at every step, 0.3 mm at 1 m/s); the peak is the largest sample
SAMPLE = 40
dt0 = [None]  # each run's step at its start


def builtin(f):
    info = bw.panel(topology="rhombic", width=1.0, height=1.0, cell=(mesh.TECCO_G65_DX, mesh.TECCO_G65_DY), wire_d=0.003,
                    strain_stress=CURVE, wire_type=2, lambda_u=SLACK, lambda_F=RATIO, seed=12345, damping=0.2, dt_factor=0.5 * f)
    dt0[0] = O.dt
    res = bw.pull(velocity=1.0, max_elongation=0.3 * info["size_y"], record_every=max(1, round(SAMPLE / f)), max_steps=4_000_000)
    return [(u / info["size_y"], F / info["size_x"]) for u, F, _ in res["curve"]]


def flex(f, bending_factor):
    s = tensile.mesh_panel_scene(width=1.0, height=1.0, direction="longitudinal", speed=1.0, damping=0.2,
                                 material=wire.tecco_wire(slack_scale=SLACK, force_ratio=RATIO, bending_factor=bending_factor))
    next(e for e in O.engines if type(e).__name__ == "FlexTimeStepper").safety = 0.5 * f  # bench_wire: 0.5 (scene.engines' default)
    O.step()  # the stepper sets O.dt
    dt0[0] = O.dt
    r = tensile.mesh_tensile_test(s, chunk=max(1, round(SAMPLE / f)), max_elongation=0.3)
    return list(zip(r["elongation"], r["force_per_m"]))


sides = {"builtin WirePM": builtin, "yade-flex beams": lambda f: flex(f, 1.0), "yade-flex bars": lambda f: flex(f, 0.0)}
rows = []
for name, run in sides.items():
    for f in factors:
        t0 = time.time()
        c = run(f)
        pk = max(c, key=lambda p: p[1])
        rows.append(dict(side=name, factor=f, dt=dt0[0], steps=O.iter, peak_kN_per_m=pk[1] / 1e3, elongation_at_peak=pk[0], wall_s=time.time() - t0))
        print(f"{name:16s} x{f:<5g} dt {dt0[0]:.3g} s, {O.iter} steps: peak {pk[1] / 1e3:.2f} kN/m at {pk[0]:.4f} ({time.time() - t0:.0f} s)", flush=True)

print(f"\n{'side':16s} {'factor':>6s} {'peak kN/m':>10s} {'vs smallest':>12s} {'el. at peak':>12s}")
for name in sides:
    sel = [r for r in rows if r["side"] == name]
    ref = min(sel, key=lambda r: r["factor"])
    for r in sel:
        r["peak_change_vs_smallest"] = r["peak_kN_per_m"] / ref["peak_kN_per_m"] - 1
        print(f"{name:16s} {r['factor']:6g} {r['peak_kN_per_m']:10.2f} {r['peak_change_vs_smallest']:+12.2%} {r['elongation_at_peak']:12.4f}")
out = os.path.join(HERE, "results", "wire_convergence.csv")
with open(out, "w", newline="") as fh:
    w = csv.DictWriter(fh, fieldnames=list(rows[0]))
    w.writeheader()
    w.writerows(rows)
print("wrote", out)
