# TECCO G65/3 panel 1 x 1 m (and 0.5, 2 m wide; knots modelled or shared nodes) clamped on two opposite edges, pulled quasi-statically (1 m/s,
# local damping 0.2); peak resistance per metre and elongation at peak vs the datasheet
# (150 kN/m longitudinal). Writes validation/tensile/mesh_*.{csv,png,json} and mesh_summary.csv.
#   YADE_PREFIX=... PYTHONPATH=py yade-double -n -j1 -x scripts/tensile_mesh.py [OUTDIR] [--quick] [--case=NAME ...]
# --case=NAME: only these cases; their rows replace the same cases' rows of an existing mesh_summary.csv
import csv
import os
import sys

from yadeflex import mesh

from yadeflex.harness import tensile

args = [a for a in sys.argv[1:] if not a.startswith("--")]
out = args[0] if args else "validation/tensile"
quick = "--quick" in sys.argv
REF = mesh.TECCO_G65_STRENGTH
cases = [  # name, direction, speed [m/s], seed, slack_scale (None: calibration), loaded width [m], knot model (default: shared)
    ("longitudinal_knots", "longitudinal", 1.0, 12345, None, 1.0, "beam"),
    ("longitudinal_hooks", "longitudinal", 1.0, 12345, None, 1.0, "hook"),
    ("longitudinal", "longitudinal", 1.0, 12345, None, 1.0),
    ("longitudinal_2ms", "longitudinal", 2.0, 12345, None, 1.0),
    ("longitudinal_seed1", "longitudinal", 1.0, 1, None, 1.0),
    ("longitudinal_seed2", "longitudinal", 1.0, 2, None, 1.0),
    ("longitudinal_straight", "longitudinal", 1.0, 12345, 0.0, 1.0),
    ("longitudinal_width0.5", "longitudinal", 1.0, 12345, None, 0.5),
    ("longitudinal_width2", "longitudinal", 1.0, 12345, None, 2.0),
    ("transverse", "transverse", 1.0, 12345, None, 1.0),
    ("longitudinal_knots_2ms", "longitudinal", 2.0, 12345, None, 1.0, "beam"),
    ("transverse_knots", "transverse", 1.0, 12345, None, 1.0, "beam"),
]
only = [a.split("=", 1)[1] for a in sys.argv[1:] if a.startswith("--case=")]
unknown = sorted(set(only) - {c[0] for c in cases})
if unknown:
    sys.exit(f"tensile_mesh.py: no case {', '.join(unknown)}; cases: {', '.join(c[0] for c in cases)}")
if only:
    cases = [c for c in cases if c[0] in only]
elif quick:  # the shared-node knots (seconds; the knotted panels take minutes)
    cases = cases[2:4]
rows = []
for name, direction, speed, seed, slack, width, *knots in cases:
    knots = knots[0] if knots else "shared"
    s, r, secs = tensile.tecco_panel_test(direction, width, speed, seed, slack, knots=knots)
    rows.append(dict(case=name, knots=knots, direction=direction, loaded_width=s["loaded_width"], speed=speed, seed=seed, slack_scale=s["material"].wireSlackScale,
                     peak_kN_per_m=r["peak"] / 1e3, vs_datasheet=r["peak"] / REF - 1, elongation_at_peak=r["elongation_at_peak"],
                     ruptured=r["ruptured"], edge_unbalance_at_peak=r["unbalance_at_peak"], steps=r["iterations"], seconds=secs,
                     quasi_static_peak_kN_per_m=r["quasi_static_peak"] / 1e3, elongation_at_quasi_static_peak=r["elongation_at_quasi_static_peak"]))
    print(" ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}" for k, v in rows[-1].items()), flush=True)
    tensile.write_curve(f"{out}/mesh_{name}", dict(elongation=r["elongation"], force_kN_per_m=[x / 1e3 for x in r["force_per_m"]]),
                        "elongation [-]", "force per metre width [kN/m]", f"TECCO G65/3, {name}", y="force_kN_per_m",
                        reference={"datasheet 150 kN/m": ("h", REF / 1e3)}, params=s["params"])
summary = f"{out}/mesh_summary.csv"
if only and os.path.exists(summary):  # keep the other cases' rows, in their order
    with open(summary, newline="") as fh:
        old = list(csv.DictReader(fh))
    for r in old:
        r.setdefault("knots", "shared")  # (rows written before the column)
    mine = {r["case"]: r for r in rows}
    rows = [mine.pop(r["case"], r) for r in old] + list(mine.values())
with open(summary, "w", newline="") as fh:
    w = csv.DictWriter(fh, fieldnames=list(dict.fromkeys(k for r in rows for k in r)))
    w.writeheader()
    w.writerows(rows)
