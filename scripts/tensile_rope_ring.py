# Boundary rope 6x7 FC pulled to rupture (EA, breaking force) and a steel ring (bar d = 10 mm)
# pulled by two opposite point loads vs curved-beam theory (small loads, three discretisations;
# then pulled to 30% of its radius); writes validation/tensile/rope.*, ring.csv, ring_pull.*.
#   YADE_PREFIX=... PYTHONPATH=py yade-double -n -j1 -x scripts/tensile_rope_ring.py [OUTDIR]
import csv
import sys

from yadeflex.harness import tensile

out = sys.argv[1] if len(sys.argv) > 1 else "validation/tensile"
EA_REF, FB_REF = 96e9 * 24.32e-6, 37.6e3  # rope data (docs/model.md)
r = tensile.rope_tensile_test(length=1.0, segments=10, damping=0.3, steps_per_unit_strain=2e6)
print(f"rope (10 segments): EA {r['EA']:.4e} N ({r['EA'] / EA_REF - 1:+.3%}), breaking force {r['rupture_force']:.1f} N "
      f"({r['rupture_force'] / FB_REF - 1:+.3%}), ruptured {r['ruptured']}")
keep = sorted(set(range(0, len(r["strain"]), 40)) | set(range(max(0, len(r["strain"]) - 200), len(r["strain"]))))  # thinned; rupture kept
tensile.write_curve(out + "/rope", dict(elongation=[r["strain"][k] for k in keep],
                                        force=[r["force"][k] / 1e3 if r["force"][k] is not None else None for k in keep]),
                    "strain [-]", "force [kN]", "rope 6x7 FC d = 8 mm", reference={"MBF 37.6 kN": ("h", 37.6)},
                    params=dict(r["params"], EA=r["EA"], rupture_force=r["rupture_force"]))
rows = []
for n in (24, 48, 96):
    g = tensile.ring_point_loads(ring_radius=0.3, bar_radius=0.005, segments=n)
    rows.append((n, g["delta"], g["theory"], g["delta"] / g["theory"] - 1, (g["delta"] / g["theory"] - 1) * n * n))
    print(f"ring R = 0.3 m, {n} segments: delta {g['delta']:.6e} m, theory {g['theory']:.6e} m, error {rows[-1][3]:+.3e} (x N^2 = {rows[-1][4]:.2f})")
with open(out + "/ring.csv", "w", newline="") as fh:
    w = csv.writer(fh)
    w.writerow(["segments", "delta_m", "theory_m", "rel_error", "rel_error_times_N2"])
    w.writerows(rows)
g = tensile.ring_pull(ring_radius=0.3, bar_radius=0.005, segments=48)
k2 = next(f / d for d, f in zip(g["deflection"], g["force"]) if d >= 0.02 * 0.3)  # secant at 2% of R
print(f"ring pulled to {g['deflection'][-1]:.3f} m: force {g['force'][-1]:.0f} N; secant stiffness at 2% of R {k2:.4e} N/m "
      f"vs thin-ring theory {g['linear_stiffness']:.4e} N/m ({k2 / g['linear_stiffness'] - 1:+.2%}; the ring stiffens as it elongates)")
tensile.write_curve(out + "/ring_pull", dict(deflection=g["deflection"], force=g["force"]), "elongation of the diameter [m]", "force [N]",
                    "steel ring R = 0.3 m, bar d = 10 mm, opposite point loads", x="deflection",
                    reference={"thin-ring theory at 10% R": (0.03, 0.03 * g["linear_stiffness"])}, params=g["params"])
