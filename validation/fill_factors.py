"""What drives the module's force exponents: the peak force and penetration of the default module
over drop height and boulder mass, for variants of the fill and the boulder (GPL-2.0-or-later).

    scripts/study validation/studies/fill_factors/study.csv OUT --workers 2
    /usr/bin/python3 validation/fill_factors.py OUT [--to validation/studies/fill_factors]

The study (study.csv) runs each variant at 800 kg from 1, 2 and 4 m and at 400 and 1600 kg from
2 m with the same cube (its density scaled). Variants: base (the main job's defaults), seed2 (another
fill of the same preset: the scatter of the exponents), norolling (no rolling resistance),
stiff (grain contact modulus x3), smallcube (a 0.5 m cube instead of the 0.69 m one, the masses
kept: a third of the module's top under the boulder instead of three fifths), wide (a module 1.4 m
across instead of 1.0 m: the mesh's confinement farther from the boulder), tall (a module 0.9 m high
instead of 0.6 m: the slab farther below it).

This script reads OUT/results.csv and each run's timeseries.csv and writes, per variant:
  - the exponents b of power fits peak ~ H^b, peak ~ m^b (constant cube), penetration ~ H^b and
    penetration ~ m^b (references: the cushion formulas' 0.6 for the force, Hertz's 0.4 and 0.2 for
    the penetration at constant size);
  - the force on the boulder at its deepest point (where it stops moving down) and the exponent n of
    a power fit of that force against that penetration over the variant's five runs: Hertz's contact
    gives 1.5; a fill that has run out of room to give way, far more;
into summary.csv, factors.png (peak force against H and m, and the force against the penetration
of the 1600 kg runs) and the table between the markers of README.md in --to."""
import argparse
import csv
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from readme_table import replace_marked  # noqa: E402

HEIGHTS = {"H1": 1.0, "H2": 2.0, "H4": 4.0}
MASSES = {"m400": 400.0, "H2": 800.0, "m1600": 1600.0}  # (H2 is the 800 kg run of the mass series)
MARK = ("<!-- table:fill_factors -->", "<!-- /table:fill_factors -->")


def read_results(out):
    with open(os.path.join(out, "results.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    runs = {}
    for r in rows:
        variant, kind = r["name"].rsplit("-", 1)
        runs.setdefault(variant, {})[kind] = r
    return runs


def number(r, key):
    try:
        v = float(r.get(key, "nan"))
    except ValueError:
        return math.nan
    return v if r.get("status") == "done" else math.nan


def curve(out, name, rebound=None):
    """(penetration [m], force on the boulder [N]) of a run's time series, from the start to the
    deepest point (the first record where the boulder no longer moves down; the run's last record
    if it never does). rebound: a list that gets whether the boulder stopped moving down."""
    path = os.path.join(out, "runs", name, "timeseries.csv")
    if not os.path.isfile(path):
        return [], []
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    k = next((i for i, r in enumerate(rows) if float(r["boulder_vz[m/s]"]) >= 0), None)
    if rebound is not None:
        rebound.append(k is not None)
    k = len(rows) - 1 if k is None else k
    return [float(r["penetration[m]"]) for r in rows[:k + 1]], [float(r["impact_force[N]"]) for r in rows[:k + 1]]


def deepest(out, name):
    """(penetration [m], force [N], whether the boulder stopped moving down within the run) at
    the deepest point of a run (NaN, NaN, False without its series)."""
    rebound = []
    d, F = curve(out, name, rebound)
    return (d[-1], F[-1], rebound[0]) if d else (math.nan, math.nan, False)


def fit(xs, ys):
    """b of the least-squares fit log y = log a + b log x over the positive, finite points (NaN
    below two)."""
    pts = [(math.log(x), math.log(y)) for x, y in zip(xs, ys) if x > 0 and y > 0 and math.isfinite(y)]
    if len(pts) < 2:
        return math.nan
    mx, my = sum(a for a, _ in pts) / len(pts), sum(b for _, b in pts) / len(pts)
    sxx = sum((a - mx) ** 2 for a, _ in pts)
    return sum((a - mx) * (b - my) for a, b in pts) / sxx if sxx > 0 else math.nan


def summarise(out):
    rows = []
    for variant, runs in read_results(out).items():
        peak = lambda k: number(runs.get(k, {}), "peak_impact_force")  # noqa: E731
        pen = lambda k: number(runs.get(k, {}), "penetration_max")  # noqa: E731
        deep = {k: deepest(out, f"{variant}-{k}") for k in runs}
        rows.append(dict(
            variant=variant, runs_done=sum(r.get("status") == "done" for r in runs.values()), runs=len(runs),
            peak_kN_H1=peak("H1") / 1e3, peak_kN_H2=peak("H2") / 1e3, peak_kN_H4=peak("H4") / 1e3,
            peak_kN_m400=peak("m400") / 1e3, peak_kN_m1600=peak("m1600") / 1e3,
            pen_mm_H1=1e3 * pen("H1"), pen_mm_H2=1e3 * pen("H2"), pen_mm_H4=1e3 * pen("H4"),
            pen_mm_m400=1e3 * pen("m400"), pen_mm_m1600=1e3 * pen("m1600"),
            force_height_exp=fit(list(HEIGHTS.values()), [peak(k) for k in HEIGHTS]),
            force_mass_exp=fit(list(MASSES.values()), [peak(k) for k in MASSES]),
            pen_height_exp=fit(list(HEIGHTS.values()), [pen(k) for k in HEIGHTS]),
            pen_mass_exp=fit(list(MASSES.values()), [pen(k) for k in MASSES]),
            deep_kN_H1=deep.get("H1", (0, math.nan))[1] / 1e3, deep_kN_H2=deep.get("H2", (0, math.nan))[1] / 1e3,
            deep_kN_H4=deep.get("H4", (0, math.nan))[1] / 1e3,
            deep_force_depth_exp=fit([v[0] for v in deep.values()], [v[1] for v in deep.values()]),
            stopped_runs=sum(bool(v[2]) for v in deep.values()),
            max_residual_pct=max((100 * number(r, "energy_residual_max_fraction") for r in runs.values()), default=math.nan)))
    return rows


def table(rows):
    head = ("| variant | runs done | peak [kN] H = 1 / 2 / 4 m | peak [kN] m = 400 / 1600 kg | penetration [mm] H = 1 / 2 / 4 m | "
            "force at the deepest point [kN] H = 1 / 2 / 4 m | peak ~ H^b | peak ~ m^b | penetration ~ H^b | penetration ~ m^b | "
            "deepest force ~ penetration^n (5 runs) | runs whose boulder stopped moving down | largest residual |\n"
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n")
    f = lambda x, p=0: "-" if not math.isfinite(x) else f"{x:.{p}f}"  # noqa: E731
    body = "".join(
        f"| {r['variant']} | {r['runs_done']}/{r['runs']} | {f(r['peak_kN_H1'])} / {f(r['peak_kN_H2'])} / {f(r['peak_kN_H4'])} | "
        f"{f(r['peak_kN_m400'])} / {f(r['peak_kN_m1600'])} | {f(r['pen_mm_H1'])} / {f(r['pen_mm_H2'])} / {f(r['pen_mm_H4'])} | "
        f"{f(r['deep_kN_H1'])} / {f(r['deep_kN_H2'])} / {f(r['deep_kN_H4'])} | "
        f"{f(r['force_height_exp'], 2)} | {f(r['force_mass_exp'], 2)} | {f(r['pen_height_exp'], 2)} | {f(r['pen_mass_exp'], 2)} | "
        f"{f(r['deep_force_depth_exp'], 1)} | {r['stopped_runs']}/{r['runs']} | {f(r['max_residual_pct'], 2)}% |\n" for r in rows)
    return head + body + ("\nReferences: peak ~ H^0.6 and m^0.6 (Labiouse 1996, ASTRA 2008; JRA 2000: m^2/3); Hertz's penetration ~ H^0.4, "
                          "m^0.2 at constant size; force ~ penetration^1.5 (Hertz). Where the boulder did not stop moving down within the run, its "
                          "\"deepest point\" is the run's last record: it came to rest in the fill, and n is not a lock-up's.\n")


def plot(out, rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axs = plt.subplots(1, 3, figsize=(15, 4.5))
    for r in rows:
        v = r["variant"]
        axs[0].loglog(list(HEIGHTS.values()), [r[f"peak_kN_{k}"] for k in ("H1", "H2", "H4")], "o-", label=v)
        axs[1].loglog(list(MASSES.values()), [r["peak_kN_m400"], r["peak_kN_H2"], r["peak_kN_m1600"]], "o-", label=v)
        d, F = curve(out, f"{v}-m1600")
        axs[2].plot([1e3 * x for x in d], [1e-3 * y for y in F], "-", label=v)
    for ax, xl in ((axs[0], "drop height H [m] (800 kg)"), (axs[1], "boulder mass m [kg] (H = 2 m, same cube)"),
                   (axs[2], "penetration d [mm] (1600 kg from 2 m, to the deepest point)")):
        ax.set_xlabel(xl)
        ax.set_ylabel("peak force [kN]" if ax is not axs[2] else "force on the boulder [kN]")
        ax.grid(True, which="both", lw=0.3)
        if ax is axs[2]:
            ax.set_ylim(bottom=0)
        ax.legend(fontsize=8)
    x0 = list(HEIGHTS.values())
    axs[0].loglog(x0, [100 * (h / x0[0]) ** 0.6 for h in x0], "k:", label="H^0.6")
    m0 = list(MASSES.values())
    axs[1].loglog(m0, [100 * (m / m0[0]) ** 0.6 for m in m0], "k:", label="m^0.6")
    axs[0].legend(fontsize=8)
    axs[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out", help="the study's output folder (scripts/study ... OUT)")
    ap.add_argument("--to", default=os.path.join(HERE, "studies", "fill_factors"), help="where summary.csv, factors.png and README.md go")
    a = ap.parse_args(argv)
    rows = summarise(a.out)
    if not rows:
        raise SystemExit(f"{a.out}/results.csv has no runs")
    os.makedirs(a.to, exist_ok=True)
    with open(os.path.join(a.to, "summary.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows({k: (round(v, 4) if isinstance(v, float) else v) for k, v in r.items()} for r in rows)
    plot(a.out, rows, os.path.join(a.to, "factors.png"))
    t = table(rows)
    print(t)
    replace_marked(os.path.join(a.to, "README.md"), MARK, t)


if __name__ == "__main__":
    main(sys.argv[1:])
