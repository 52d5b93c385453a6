# Boundary rope 6x7 FC pulled to rupture (EA, breaking force) and a steel ring (bar d = 10 mm)
# pulled by two opposite point loads vs curved-beam theory; writes validation/tensile/rope.*,
# ring.csv.
#   YADE_PREFIX=... PYTHONPATH=py yade-double -n -j1 -x scripts/tensile_rope_ring.py [OUTDIR]
import csv
import sys

from yadeflex import tensile

out = sys.argv[1] if len(sys.argv) > 1 else "validation/tensile"
EA_REF, FB_REF = 96e9 * 24.32e-6, 37.6e3  # datasheet (DESIGN.md)
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
