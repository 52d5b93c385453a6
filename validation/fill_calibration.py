"""What the fill presets rest on: laboratory tests of each preset's spheres (yadeflex.harness.calibration)
against documented values of the real material (GPL-2.0-or-later).

    PYTHONPATH=py yade-double -n -j1 -x validation/fill_calibration.py OUT [--workers 2] [--cases a,b] [--to validation/calibration]

Each case runs in its own yade-double process (--workers
at a time, one thread each) and writes OUT/cases/NAME.json; then this script writes OUT/results.csv
(one row per case), OUT/summary.json (the graded figures), the plots and the table between the
markers of OUT/README.md; --to DIR writes the same files into DIR too (the committed report is
validation/calibration). Cases:
  - oedometer_<fill>_s<seed>: confined compression to 400 kPa at a strain rate of 0.05 /s (and
    oedometer_gravel_slow at 0.02 /s: rate independence);
  - repose_<fill>_s<seed>: angle of repose by lifting a cylinder at LIFT_SPEED (and repose_gravel_v<v>
    at the faster v m/s); repose_gravel_rf<x>: the gravel with rolling friction x instead of its 0.1
    (the calibration curve of the rolling resistance);
  - plate_gravel_s<seed>: plate-load test, a 0.3 m plate pressed at PLATE_SPEED into a gravel layer as
    thick as the module (PLATE), and plate_gravel_slow at half the speed (rate independence); the
    gravel only: the sand's grains would number about seven times as many;
the oedometer and repose geometries in units of the preset's largest grain, so that both presets hold
about as many grains."""
import csv
import json
import math
import os
import re
import sys
import time

HERE = os.path.dirname(os.path.abspath(next((a for a in sys.argv if a.endswith("fill_calibration.py")), __file__)))
sys.path.insert(0, HERE)
import case_processes  # noqa: E402
from readme_table import replace_marked  # noqa: E402

G = 9.81
MARK = ("<!-- table:fill_calibration -->", "<!-- /table:fill_calibration -->")
GRAIN_MAX = {"gravel": 0.063, "sand": 0.030}  # yadeflex.module.FILLS (checked when a case runs)

# Documented values of the real materials: (lo, hi) and where they come from.
REFERENCES = {
    "gravel": dict(
        bulk_density=((15.0e3 / G, 16.0e3 / G), "EN 1991-1-1:2002, Annex A, Table A.6: ballast, gravel (loose), 15.0-16.0 kN/m3"),
        repose_deg=((30.0, 45.0), "tabulated angles of repose of loose dry gravel, 30-45 deg (construction tables; no primary "
                                  "measurement of a 32-63 mm gravel was found)"),
        constrained_modulus=((1 / 5.2e-3 * 1e6, 1 / 0.1e-3 * 1e6), "Domenico & Mifflin (1965), as tabulated by Ameratunga, Sivakugan "
                                                                   "& Das (2016), Table 2.10: dense sandy gravel, m_v = (0.1-5.2)e-3 1/MPa"),
    ),
    "sand": dict(
        bulk_density=((15.0e3 / G, 16.0e3 / G), "EN 1991-1-1:2002, Annex A, Table A.6: sand (dry), 15.0-16.0 kN/m3"),
        repose_deg=((30.0, 35.0), "tabulated angles of repose of dry sand, 30-35 deg (construction tables)"),
        constrained_modulus=((1 / 0.1 * 1e6, 1 / 0.013 * 1e6), "Domenico & Mifflin (1965), as tabulated by Ameratunga, Sivakugan & "
                                                              "Das (2016), Table 2.10: loose sand to dense sand, m_v = 0.1-0.013 1/MPa"),
    ),
}
# [m/s] the cylinder's lift: the heap is steeper the slower the lift; the slowest lift measured
# makes the cases, two faster ones are shown
LIFT_SPEED = 0.025
# the plate-load test: the plate of the standard tests (0.3 m), a layer as thick as the default
# module (0.6 m) on a rigid floor, its frictionless container half a plate from the plate's edge
PLATE = dict(plate_diameter=0.3, radius=0.3, height=0.6, max_stress=200e3, max_settlement=0.06)
PLATE_SPEED = 0.01  # [m/s]
MODULUS_RANGE = (100e3, 200e3)  # [Pa] the stress range of the graded constrained modulus: the impact's order of magnitude


def _cases():
    out = {}
    for fill in ("gravel", "sand"):
        d = GRAIN_MAX[fill]
        oed = dict(radius=4.75 * d, height=4.75 * d)
        rep = dict(radius=4.0 * d, height=8.0 * d, lift_speed=LIFT_SPEED)
        for s in (1, 2, 3) if fill == "gravel" else (1, 2):
            out[f"oedometer_{fill}_s{s}"] = ("oedometer", dict(fill=fill, seed=s, **oed))
            out[f"repose_{fill}_s{s}"] = ("repose", dict(fill=fill, seed=s, **rep))
    for s in (1, 2, 3):
        out[f"plate_gravel_s{s}"] = ("plate", dict(fill="gravel", seed=s, speed=PLATE_SPEED, **PLATE))
    out["plate_gravel_slow"] = ("plate", dict(fill="gravel", seed=1, speed=0.5 * PLATE_SPEED, **PLATE))
    d = GRAIN_MAX["gravel"]
    out["oedometer_gravel_slow"] = ("oedometer", dict(fill="gravel", seed=1, strain_rate=0.02, radius=4.75 * d, height=4.75 * d))
    for v in (0.1, 0.05):
        out[f"repose_gravel_v{v:g}"] = ("repose", dict(fill="gravel", seed=1, lift_speed=v, radius=4.0 * d, height=8.0 * d))
    for rf in (0.0, 0.05, 0.2):
        out[f"repose_gravel_rf{rf:g}"] = ("repose", dict(fill="gravel", seed=1, rolling_friction=rf, radius=4.0 * d, height=8.0 * d,
                                                         lift_speed=LIFT_SPEED))
    return out


CASES = _cases()


def run_case(name, out):
    """One case in this process (under YADE): OUT/cases/NAME.json."""
    from yadeflex.harness import calibration as K
    kind, kw = CASES[name]
    t = time.time()
    if kind in ("oedometer", "plate"):
        r = (K.oedometer_test if kind == "oedometer" else K.plate_load_test)(**kw)
        c = r.pop("curve")
        r["curve"] = {k: [float(x) for x in v] for k, v in c.items()}
    else:
        r = K.repose_test(**kw)
        h = r.pop("heap")
        r["heap"] = dict(h, r=[float(x) for x in h["r"]], top=[float(x) for x in h["top"]])
    r.update(name=name, kind=kind, args=kw, wall_seconds=time.time() - t)
    os.makedirs(os.path.join(out, "cases"), exist_ok=True)
    with open(os.path.join(out, "cases", name + ".json"), "w") as f:
        json.dump(r, f, indent=1, default=float)
    print(f"{name}: done in {time.time() - t:.0f} s", flush=True)


def load(out):
    return case_processes.load(out, CASES)


def _stats(xs):
    xs = [x for x in xs if x is not None and math.isfinite(x)]
    if not xs:
        return math.nan, math.nan, 0
    m = sum(xs) / len(xs)
    sd = math.sqrt(sum((x - m) ** 2 for x in xs) / (len(xs) - 1)) if len(xs) > 1 else math.nan
    return m, sd, len(xs)


def _range_row(r, lo, hi):
    return next((row for row in r["ranges"] if abs(row["lo"] - lo) < 1 and abs(row["hi"] - hi) < 1), {})


def summarise(res):
    """Per preset: mean and scatter over its seeds of every figure, and the verdicts against
    REFERENCES (inside the documented band or not)."""
    out = {}
    for fill, refs in REFERENCES.items():
        oed = [r for n, r in res.items() if re.fullmatch(f"oedometer_{fill}_s[0-9]+", n)]
        rep = [r for n, r in res.items() if re.fullmatch(f"repose_{fill}_s[0-9]+", n)]
        s = dict(fill=fill, params=(oed or rep or [{}])[0].get("params"))
        s["bulk_density"] = _stats([r["core_bulk_density"] for r in oed])
        s["solid_fraction"] = _stats([r["core_solid_fraction"] for r in oed])
        s["repose_deg"] = _stats([r["angle_deg"] for r in rep])
        for lo, hi in [(row["lo"], row["hi"]) for row in (oed[0]["ranges"] if oed else [])]:
            key = f"{lo / 1e3:g}-{hi / 1e3:g}kPa"  # (validation/cushion_cases.py reads these keys)
            rows = [_range_row(r, lo, hi) for r in oed]
            s[f"M_{key}"] = _stats([row.get("M") for row in rows])
            s[f"K0_{key}"] = _stats([row.get("K0") for row in rows])
            s[f"lame_{key}"] = _stats([row.get("lame") for row in rows])
            s[f"plate_load_{key}"] = _stats([row.get("plate_load") for row in rows])
        plate = [r for n, r in res.items() if re.fullmatch(f"plate_{fill}_s[0-9]+", n)]
        for lo, hi in [(row["lo"], row["hi"]) for row in (plate[0]["ranges"] if plate else [])]:
            s[f"plate_test_{lo / 1e3:g}-{hi / 1e3:g}kPa"] = _stats([_range_row(r, lo, hi).get("M_E") for r in plate])
        if plate:
            s["plate_reached"] = [bool(r["reached"]) for r in plate]
            s["plate_imbalance"] = _stats([r.get("imbalance") for r in plate])
        key = f"{MODULUS_RANGE[0] / 1e3:g}-{MODULUS_RANGE[1] / 1e3:g}kPa"
        s["constrained_modulus"] = s.get(f"M_{key}", (math.nan, math.nan, 0))
        s["verdicts"] = {}
        for q, ((lo, hi), src) in refs.items():
            m = s[q][0]
            s["verdicts"][q] = dict(measured=m, band=[lo, hi], source=src,
                                    verdict="NOT MEASURED" if not math.isfinite(m) else ("PASS" if lo <= m <= hi else "FAIL"))
        out[fill] = s
    rf = sorted((r["params"]["rolling_friction"], r["angle_deg"]) for n, r in res.items()
                if n.startswith("repose_gravel_rf") or n == "repose_gravel_s1")
    out["rolling_curve_gravel"] = rf
    for n in ("oedometer_gravel_slow", "repose_gravel_v0.1", "repose_gravel_v0.05", "plate_gravel_slow"):
        if n in res:
            out[n] = (res[n]["angle_deg"] if n.startswith("repose") else
                      _range_row(res[n], *MODULUS_RANGE).get("M" if n.startswith("oedometer") else "M_E"))
    return out


def _fmt(v, scale=1.0, nd=3):
    m, sd, n = v
    if not math.isfinite(m):
        return "not measured"
    v = f"{m * scale:.0f}" if abs(m * scale) >= 1000 else f"{m * scale:.{nd}g}"
    return v + (f" ± {sd * scale:.2g}" if math.isfinite(sd) else "") + f" ({n})"


def table(s):
    lines = ["| preset | quantity | model: mean ± sd (runs) | documented | verdict |", "|---|---|---|---|---|"]
    units = dict(bulk_density=("bulk density of the settled fill's core [kg/m3]", 1.0, (1.0,)),
                 repose_deg=("angle of repose [deg]", 1.0, (1.0,)),
                 constrained_modulus=(f"constrained modulus M, {MODULUS_RANGE[0] / 1e3:g}-{MODULUS_RANGE[1] / 1e3:g} kPa [MPa]", 1e-6, (1e-6,)))
    for fill in REFERENCES:
        for q, v in s[fill]["verdicts"].items():
            label, scale, _ = units[q]
            lo, hi = v["band"]
            lines.append(f"| {fill} | {label} | {_fmt(s[fill][q], scale)} | {lo * scale:.0f}-{hi * scale:.0f}: {v['source']} | **{v['verdict']}** |")
    return "\n".join(lines)


def moduli_table(s):
    keys = [k[2:] for k in s["gravel"] if k.startswith("M_")]
    lines = ["| preset | vertical stress | M [MPa] | K0 [-] | Lame constant [MPa] | plate-load modulus M_E [MPa] |", "|---|---|---|---|---|---|"]
    for fill in REFERENCES:
        for k in keys:
            lines.append(f"| {fill} | {k.replace('kPa', ' kPa')} | {_fmt(s[fill]['M_' + k], 1e-6)} | {_fmt(s[fill]['K0_' + k], 1.0)} | "
                         f"{_fmt(s[fill]['lame_' + k], 1e-6)} | {_fmt(s[fill]['plate_load_' + k], 1e-6)} |")
    return "\n".join(lines)


def plate_table(s):
    keys = [k[len("plate_test_"):] for k in s["gravel"] if k.startswith("plate_test_")]
    if not keys:
        return ""
    lines = [f"\n\nPlate-load test of the gravel (a {PLATE['plate_diameter']:g} m plate at {PLATE_SPEED:g} m/s into a layer "
             f"{PLATE['height']:g} m thick; secant M_E = D dp/ds over each range of plate pressure):\n",
             "| plate pressure | M_E from the plate-load test [MPa] | M_E from the oedometer's moduli [MPa] |", "|---|---|---|"]
    for k in keys:
        lines.append(f"| {k.replace('kPa', ' kPa')} | {_fmt(s['gravel']['plate_test_' + k], 1e-6)} | {_fmt(s['gravel'].get('plate_load_' + k, (math.nan,) * 3), 1e-6)} |")
    reached = s["gravel"].get("plate_reached", [])
    imb = s["gravel"].get("plate_imbalance", (math.nan,) * 3)
    tail = f"\nThe plate reached {PLATE['max_stress'] / 1e3:g} kPa in {sum(reached)} of {len(reached)} runs"
    tail += (f"; the floor carried the plate's load and the weight to {100 * imb[0]:.2g}% on average (quasi-static)" if math.isfinite(imb[0]) else "")
    tail += "." if all(reached) else f" (the others sank {PLATE['max_settlement'] * 1e3:g} mm first: the layer gave way under the plate)."
    if s.get("plate_gravel_slow") is not None:
        tail += f" At half the speed (seed 1): M_E = {s['plate_gravel_slow'] / 1e6:.3g} MPa at {MODULUS_RANGE[0] / 1e3:g}-{MODULUS_RANGE[1] / 1e3:g} kPa."
    return "\n".join(lines) + "\n" + tail


def write(out, res, readme=None):
    s = summarise(res)
    with open(os.path.join(out, "summary.json"), "w") as f:
        json.dump(s, f, indent=1, default=float)
    with open(os.path.join(out, "results.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["case", "fill", "seed", "rolling_friction", "grains", "angle_deg", "core_solid_fraction", "core_bulk_density",
                    "M_100_200kPa", "K0_100_200kPa", "plate_M_E_100_200kPa", "steps", "wall_seconds"])
        for n, r in sorted(res.items()):
            row = _range_row(r, *MODULUS_RANGE) if r["kind"] != "repose" else {}
            w.writerow([n, r["args"]["fill"], r["args"]["seed"], r["params"]["rolling_friction"], r["grains"], r.get("angle_deg", ""),
                        r.get("core_solid_fraction", ""), r.get("core_bulk_density", ""), row.get("M", ""), row.get("K0", ""), row.get("M_E", ""),
                        r["steps"], round(r["wall_seconds"], 1)])
    _plots(out, res, s)
    readme = readme or os.path.join(out, "README.md")
    if not os.path.isfile(readme):  # (the tables need every case; a partial run without a README writes the files above only)
        return s
    body = table(s) + "\n\nStress-dependent moduli from the oedometer (secant over each range):\n\n" + moduli_table(s)
    body += plate_table(s)
    rc = ", ".join(f"{rf:g}: {ang:.1f}" for rf, ang in s["rolling_curve_gravel"])
    body += f"\n\nGravel's angle of repose against its rolling friction (seed 1) [deg]: {rc}."
    fast = [f"{s[n]:.1f} deg at {v:g} m/s" for n, v in (("repose_gravel_v0.1", 0.1), ("repose_gravel_v0.05", 0.05)) if n in s]
    if fast:
        body += f" Lifted faster than the {LIFT_SPEED:g} m/s above (seed 1): {', '.join(fast)}."
    if "oedometer_gravel_slow" in s and s["oedometer_gravel_slow"] is not None:
        body += f" Compressed at 0.02 /s instead of 0.05 /s: M = {s['oedometer_gravel_slow'] / 1e6:.3g} MPa (seed 1)."
    replace_marked(readme, MARK, body)
    return s


def _plots(out, res, s):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axs = plt.subplots(2, 3, figsize=(16, 9))
    axs = axs.ravel()
    for n, r in sorted(res.items()):
        if r["kind"] != "oedometer":
            continue
        c = r["curve"]
        style = "-" if r["args"]["fill"] == "gravel" else "--"
        axs[0].plot([100 * e for e in c["strain"]], [v / 1e3 for v in c["sigma_v"]], style, lw=1, label=n)
        axs[1].plot([v / 1e3 for v in c["sigma_v"]], [v / 1e3 for v in c["sigma_h"]], style, lw=1, label=n)
    axs[0].set_xlabel("vertical strain [%]")
    axs[0].set_ylabel("vertical stress [kPa]")
    axs[0].set_title("oedometer")
    axs[1].set_xlabel("vertical stress [kPa]")
    axs[1].set_ylabel("radial stress [kPa]")
    axs[1].set_title("radial against vertical stress (slope K0)")
    for ax in axs[:2]:
        ax.grid(True, lw=0.3)
        ax.legend(fontsize=6)
    for n, r in sorted(res.items()):
        if r["kind"] != "repose":
            continue
        h = r["heap"]
        axs[2].plot(h["r"], h["top"], ".-", lw=0.8, label=f"{n}: {r['angle_deg']:.1f} deg")
    axs[2].set_xlabel("distance from the heap's axis [m]")
    axs[2].set_ylabel("height of the highest grain top [m]")
    axs[2].set_title("heaps (flank fitted between 20% and 80% of the height)")
    axs[2].grid(True, lw=0.3)
    axs[2].legend(fontsize=6)
    rc = s["rolling_curve_gravel"]
    if rc:
        lo, hi = REFERENCES["gravel"]["repose_deg"][0]
        axs[3].axhspan(lo, hi, color="0.9", label="documented band (loose dry gravel)")
        axs[3].plot([a for a, _ in rc], [b for _, b in rc], "ko-", label=f"model, seed 1, lift {LIFT_SPEED:g} m/s")
        m, sd, n = s["gravel"]["repose_deg"]
        pr = s["gravel"]["params"]["rolling_friction"]
        if math.isfinite(sd):
            axs[3].errorbar([pr], [m], yerr=[sd], fmt="rs", capsize=4, label=f"preset ({n} seeds, mean and sd)")
        axs[3].set_xlabel("rolling friction [-]")
        axs[3].set_ylabel("angle of repose [deg]")
        axs[3].set_title("gravel: angle of repose against rolling friction")
        axs[3].grid(True, lw=0.3)
        axs[3].legend(fontsize=7)
    for n, r in sorted(res.items()):
        if r["kind"] == "plate":
            c = r["curve"]
            axs[4].plot([1e3 * x for x in c["s"]], [v / 1e3 for v in c["p"]], "-", lw=1, label=n)
    axs[4].set_xlabel("settlement of the plate s [mm]")
    axs[4].set_ylabel("mean pressure under the plate p [kPa]")
    axs[4].set_title(f"plate-load test, gravel ({PLATE['plate_diameter']:g} m plate, {PLATE['height']:g} m layer)")
    axs[4].grid(True, lw=0.3)
    axs[4].legend(fontsize=7)
    axs[5].axis("off")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "calibration.png"), dpi=100)
    plt.close(fig)


def main():
    s = case_processes.main("fill_calibration.py", __doc__.split("\n\n")[0], CASES, run_case, write,
                            "also write the report (README table, summary.json, results.csv, calibration.png) into this folder")
    if s is None:
        return
    for fill in REFERENCES:
        for q, v in s[fill]["verdicts"].items():
            print(f"{fill} {q}: {v['measured']:.4g} against {v['band'][0]:.4g}-{v['band'][1]:.4g}: {v['verdict']}")


if __name__ == "__main__" or any(a.endswith("fill_calibration.py") for a in sys.argv):
    main()
