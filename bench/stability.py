# Stability suite (issue 6): time-step margins, impact speeds, stiff and soft materials, rupture
# (GPL-2.0-or-later).
#
#     yade-double -n -j1 -x bench/stability.py [--quick] [--groups dt,speed,material,rupture] [--no-default-module]
#     yade-double -n -j1 -x bench/stability.py --groups dtmodule   # the default module's margin (25 min)
#
# A run of some of the default groups (--groups speed) replaces those groups' rows of
# results/stability.csv and stability_margins.csv and keeps the other groups' rows.
#
# Every case is a scene of yadeflex (the builders the tests and benchmarks use) run in this one
# process, one after the other, by yadeflex.harness.stability.run_case: time step = factor x the estimated
# critical step at every step, FlexGuard first (its stop recorded, then the run goes on without
# it), the energy balance checked as the run goes; its docstring gives the rules and outcomes.
# Margins (group dt): factors 0.5, 0.75, 1, 1.25, 1.5, 2, 3, 4, 6 up to the first unstable one,
# then bisection (geometric) between the last stable and the first unstable to 5%.
#
# Writes bench/results/stability.csv (one row per run), stability_margins.csv,
# stability.png (max |residual| against the time-step factor, per scene, blow-ups marked) and
# stability_machine.txt (stability_quick* with --quick); prints the tables. See bench/STABILITY.md.
import argparse
import csv
import functools
import math
import os
import sys
import time

BENCH = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if os.path.basename(a) == "stability.py"), os.path.join(os.getcwd(), "bench"))
sys.path.insert(0, BENCH)
sys.path.insert(0, os.path.join(os.path.dirname(BENCH), "py"))

import yade  # noqa: E402
from yade import O  # noqa: E402

from yadeflex.module import ModuleParams  # noqa: E402
from yadeflex.harness.stability import cantilever, net, sheet, panel, punch, fabric, indenter, module, run_case, stable, BLOWUP, COLS  # noqa: E402

ACCURATE = 0.05     # margins also give the largest factor up to which every |residual| stays below this
FACTORS = (0.5, 0.75, 1.0, 1.25, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0, 24.0, 32.0)
BISECT_TOL = 0.05
RESULTS = os.path.join(BENCH, "results")
DEFAULT_GROUPS = ("dt", "speed", "material", "rupture")
OUT = [""]          # file name suffix: "_quick" in --quick mode (the full results stay)


def margin(build, group, scene, params, rows, factors=FACTORS, tol=BISECT_TOL):
    """Run the factors up to the first unstable one, then bisect; returns (last stable, first unstable)."""
    edge = [None, None]  # last stable, first unstable

    def attempt(f):
        r = run_case(build, f, group, scene, params)
        rows.append(r)
        edge[0 if stable(r) else 1] = f
        return stable(r)

    for f in factors:
        if not attempt(f):
            break
    while edge[0] is None and edge[1] is not None and edge[1] > 0.05:  # unstable at the smallest factor: a bug; find the edge
        attempt(0.5 * edge[1])
    while None not in edge and edge[1] / edge[0] > 1 + tol:
        attempt(math.sqrt(edge[0] * edge[1]))
    return tuple(edge)


def kept_rows(groups):
    """The rows and margin rows of the existing results/stability{OUT}.csv whose group was not run
    now, so that --groups speed (say) updates its own rows and keeps the others."""
    path = os.path.join(RESULTS, f"stability{OUT[0]}.csv")
    if not os.path.exists(path):
        return [], []
    with open(path) as f:
        old = [dict(r, factor=float(r["factor"]), max_residual=float(r["max_residual"])) for r in csv.DictReader(f)
               if r["group"] not in groups]
    scenes = {(r["scene"], r["params"]) for r in old}
    mpath = os.path.join(RESULTS, f"stability{OUT[0]}_margins.csv")
    margins = []
    if os.path.exists(mpath):
        with open(mpath) as f:
            rd = csv.reader(f)
            next(rd, None)
            margins = [m for m in rd if (m[0], m[1]) in scenes]
    return old, margins


def write(rows, margins, line, groups=DEFAULT_GROUPS):
    """results/stability{OUT}.csv, _margins.csv, _machine.txt and .png. A run of some of the default
    groups replaces those groups' rows and keeps the others' (each machine line says which groups
    it measured)."""
    os.makedirs(RESULTS, exist_ok=True)
    partial = OUT[0] == "" and set(groups) < set(DEFAULT_GROUPS)
    old, old_margins = kept_rows(groups) if partial else ([], [])
    old_margins = [m for m in old_margins if (m[0], m[1]) not in margins]
    rows = old + rows
    keys = list(dict.fromkeys(k for r in rows for k in r))  # (kept rows of an older column set get blanks, not a crash)
    with open(os.path.join(RESULTS, f"stability{OUT[0]}.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(RESULTS, f"stability{OUT[0]}_margins.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["scene", "params", "last_stable_factor", "first_unstable_factor", "stable_at_1", f"residual_below_{ACCURATE:g}_up_to"])
        w.writerows(old_margins)
        for (scene, params), (ok, bad) in margins.items():
            w.writerow([scene, params, ok if ok is not None else "", bad if bad is not None else "", *margin_extras(rows, scene, params)])
    mpath = os.path.join(RESULTS, f"stability{OUT[0]}_machine.txt")
    before = ""
    if partial and old and os.path.exists(mpath):
        with open(mpath) as f:
            before = "".join(l for l in f if not any(l.startswith(f"groups {g}:") for g in groups))
    with open(mpath, "w") as f:
        f.write(before + (f"groups {','.join(groups)}: " if partial else "") + line)
    try:
        plot(rows, os.path.join(RESULTS, f"stability{OUT[0]}.png"))
    except Exception as e:  # the numbers are in the CSV; never lose them over a plot
        print(f"(plot failed: {e})")


def margin_extras(rows, scene, params):
    """(stable at factor 1?, largest factor up to which every run is stable with |residual| < ACCURATE)."""
    rs = sorted((r for r in rows if r["scene"] == scene and r["params"] == params), key=lambda r: r["factor"])
    at1 = [stable(r) for r in rs if r["factor"] == 1.0]
    acc = ""
    for r in rs:
        if not (stable(r) and r["max_residual"] < ACCURATE):
            break
        acc = r["factor"]
    return (at1[0] if at1 else "", acc)


def markdown(rows, margins_csv):
    """The tables of bench/STABILITY.md from results/stability.csv and stability_margins.csv:
    margins, impact speeds, materials, rupture, every run of the margin search, guard messages."""
    def num(v):
        return float(v) if v not in ("", None) else None
    rows = [dict(r, factor=float(r["factor"]), max_residual=float(r["max_residual"]), residual_at_max=float(r["residual_at_max"]),
                 sim_time_s=float(r["sim_time_s"]), vmax=float(r["vmax"]), dt_critical_start=float(r["dt_critical_start"])) for r in rows]
    out = []
    dtc = {}
    for r in rows:
        dtc.setdefault((r["scene"], r["params"]), r["dt_critical_start"])
    out += ["| scene | case | estimate at start | stable at 1.0 | last stable | first unstable (sharpness) | headroom of the default step | \\|residual\\| < 5% up to |",
            "|---|---|---|---|---|---|---|---|"]
    for m in margins_csv:
        ok, bad = num(m["last_stable_factor"]), num(m["first_unstable_factor"])
        key = (m["scene"], m["params"])
        default = ModuleParams().timestep_safety if m["scene"].startswith("module") else 0.5  # yf.engines()'s 0.5
        out.append(f"| {m['scene']} | {m['params']} | {1e6 * dtc.get(key, math.nan):.3g} µs | {'yes' if m['stable_at_1'] == 'True' else '**no**'} | "
                   f"{'' if ok is None else f'{ok:.3g}'} | **{'' if bad is None else f'{bad:.3g}'}** | {'' if bad is None else f'{bad / default:.2g}x'} | "
                   f"{m[f'residual_below_{ACCURATE:g}_up_to']} |")
    head = ["| scene | case | factor | outcome | steps | sim. ms | wall s | residual | blow-up step | guard step | broken | max speed m/s (body) |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|"]

    def line(r):
        o = r["outcome"] if r["outcome"] == "stable" else f"**{r['outcome']}**"
        return (f"| {r['scene']} | {r['params']} | {r['factor']:.4g} | {o} | {r['steps']} | {1e3 * r['sim_time_s']:.1f} | {float(r['wall_s']):.3g} | "
                f"{100 * r['residual_at_max']:+.3g}% | {r['blowup_step'] or '—'} | {r['guard_step'] or '—'} | {r['broken']} | {r['vmax']:.3g} ({r['vmax_body']}) |")
    for group, title in (("speed", "Impact speeds"), ("material", "Stiff and soft materials"), ("rupture", "Rupture"), ("dt", "All runs of the margin search")):
        out += ["", f"### {title}", ""] + head + [line(r) for r in rows if r["group"] == group]
    out += ["", "### Guard messages (the rows where FlexGuard stopped a run; first 200 characters)", ""]
    for r in rows:
        if r["guard_step"]:
            out.append(f"- {r['scene']} {r['params']} x{r['factor']:.4g} (guard step {r['guard_step']}, outcome {r['outcome']}): `{r['guard_message'][:200]}`")
    return "\n".join(out) + "\n"


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(9, 5.5))
    keys = []
    for r in rows:
        k = (r["scene"], r["params"])
        if k not in keys:
            keys.append(k)
    for n, k in enumerate(keys):
        rs = sorted((r for r in rows if (r["scene"], r["params"]) == k), key=lambda r: r["factor"])
        if len({r["factor"] for r in rs}) < 2:
            continue
        col = plt.cm.tab20(n % 20)
        fs = [r["factor"] for r in rs if stable(r)]
        ax.plot(fs, [max(r["max_residual"], 1e-7) for r in rs if stable(r)], "o-", color=col, label=f"{k[0]} {k[1]}".strip())
        bad = [r for r in rs if not stable(r)]
        ax.plot([r["factor"] for r in bad], [max(r["max_residual"], 1e-7) if math.isfinite(r["max_residual"]) and r["max_residual"] > 0 else 1.0
                                             for r in bad], "x", color=col, ms=10, mew=2)
    ax.axvline(1.0, color="k", lw=0.8, ls=":")
    ax.axhline(BLOWUP, color="r", lw=0.8, ls="--")
    ax.set(xscale="log", yscale="log", xlabel="time step / estimated critical step (FlexTimeStepper.dtCritical)",
           ylabel="max |energy residual| / energy scale", title="stability: x = blown up (non-finite or energy created > 50%)")
    ax.legend(fontsize=7, ncol=2, loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# ---------------------------------------------------------------- suite

def main():
    ap = argparse.ArgumentParser(prog="stability.py")
    ap.add_argument("--quick", action="store_true", help="a few cases, no bisection (a few minutes)")
    ap.add_argument("--groups", default=",".join(DEFAULT_GROUPS), help="comma-separated; dtmodule (alone): the default module's time-step margin")
    ap.add_argument("--no-default-module", action="store_true", help="skip the default (full-size) module speeds")
    ap.add_argument("--plot-only", action="store_true", help="redraw results/stability.png from results/stability.csv")
    ap.add_argument("--markdown", action="store_true", help="print the tables of STABILITY.md from results/stability*.csv")
    me = next((k for k, a in enumerate(sys.argv) if os.path.basename(a) == "stability.py"), 0)
    a = ap.parse_args(sys.argv[me + 1:])
    groups = a.groups.split(",")
    OUT[0] = "_quick" if a.quick else ""
    if a.markdown:
        with open(os.path.join(RESULTS, f"stability{OUT[0]}.csv")) as f, open(os.path.join(RESULTS, f"stability{OUT[0]}_margins.csv")) as g:
            return print(markdown(list(csv.DictReader(f)), list(csv.DictReader(g))), end="")
    if a.plot_only:
        with open(os.path.join(RESULTS, "stability.csv")) as f:
            rows = [dict(r, factor=float(r["factor"]), max_residual=float(r["max_residual"])) for r in csv.DictReader(f)]
        return plot(rows, os.path.join(RESULTS, "stability.png"))
    from machine import machine_line
    line = machine_line(yade.config.version, O.numThreads)
    print(line, end="")
    print("columns: " + " | ".join(k for k in COLS if k != "group"))
    rows, margins = [], {}
    t_start = time.time()
    q = a.quick
    if "dt" in groups:
        print("== time-step margins", flush=True)
        dt_scenes = [("cantilever", "undamped, 100 N tip force", functools.partial(cantilever, 0.0, 5000 if q else 20000)),
                     ("cantilever", "damping 0.8", functools.partial(cantilever, 0.8, 5000 if q else 20000)),
                     ("net", "5 m/s", functools.partial(net, 5.0, t_end=0.01 if q else 0.03)),
                     ("sheet", "drop 10 mm", functools.partial(sheet, t_end=0.05 if q else 0.15)),
                     ("panel", "0.5 m, to rupture", functools.partial(panel)),
                     ("punch", "bare mesh, 100 kg at 4 m/s", functools.partial(punch, 1e8, "held", 0.03 if q else 0.06)),
                     ("punch", "bare mesh, contact 2e10 Pa", functools.partial(punch, 2e10, "held", 0.03 if q else 0.06)),
                     ("punch", "rope-edged mesh", functools.partial(punch, 1e8, "rope", 0.03 if q else 0.06)),
                     ("fabric", "hanging, folds over", functools.partial(fabric, 0.2 if q else 0.4)),
                     ("indenter", "driven at 0.3 m/s", functools.partial(indenter, 0.1 if q else 0.25)),
                     ("module small", "4.43 m/s", functools.partial(module, True, None, 0.03 if q else 0.08))]
        for scene, params, build in dt_scenes:
            print(f"-- {scene} {params}", flush=True)
            if q:
                for f in (0.5, 1.0, 1.5, 3.0):
                    rows.append(run_case(build, f, "dt", scene, params))
            else:
                margins[(scene, params)] = margin(build, "dt", scene, params, rows)
                if scene == "cantilever":  # a small step: the start of a step load, seen by the guard
                    rows.append(run_case(build, 0.1, "dt", scene, params))
    if "dtmodule" in groups:  # not in the default groups: the default module (6000 bodies, its default fill), 25 min
        if groups != ["dtmodule"]:
            raise SystemExit("--groups dtmodule runs alone (it writes results/stability_dtmodule*)")
        OUT[0] = "_dtmodule"
        print("-- module default, margin", flush=True)
        params = f"{ModuleParams().impact_speed():.2f} m/s"
        margins[("module default", params)] = margin(functools.partial(module, False, None, 0.1), "dt", "module default", params, rows)
    if rows:  # what is measured so far, in case a later group is stopped
        write(rows, margins, line, groups)
    if "material" in groups:
        print("== stiff and soft materials (E and contact moduli x scale)", flush=True)
        for scale in (100.0, 0.01):
            for scene, build in (("net", functools.partial(net, 5.0, scale, t_end=0.01 if q else 0.03)),
                                 ("sheet", functools.partial(sheet, scale, t_end=0.05 if q else 0.15))):
                params = f"E x{scale:g}"
                print(f"-- {scene} {params}", flush=True)
                if q:
                    rows.append(run_case(build, 1.0, "material", scene, params))
                else:
                    rows.append(run_case(build, 0.5, "material", scene, params))
                    margins[(scene, params)] = margin(build, "material", scene, params, rows, factors=FACTORS[2:])
                    if scale < 1:  # soft: the residual against smaller steps (is it the step or the model?)
                        for f in (0.25, 0.1, 0.05):
                            rows.append(run_case(build, f, "material", scene, params))
    if rows:  # what is measured so far, in case a later group is stopped
        write(rows, margins, line, groups)
    if "rupture" in groups:
        print("== rupture", flush=True)
        for f in ((0.5,) if q else (0.5, 1.0)):
            rows.append(run_case(functools.partial(net, 30.0, 1.0, 1770e6, 0.01 if q else 0.03), f, "rupture", "net",
                                 "30 m/s, wires 1770 MPa"))
            if not q or "dt" not in groups:
                rows.append(run_case(panel, f, "rupture", "panel", "0.5 m, to rupture"))
            # more damping (quasi-static tests use up to 0.8): the damping once booked on the driven DOFs grew with it
            rows.append(run_case(functools.partial(panel, damping=0.8), f, "rupture", "panel", "0.5 m, to rupture, damping 0.8"))
    if rows:  # what is measured so far, in case a later group is stopped
        write(rows, margins, line, groups)
    if "speed" in groups:
        fm = ModuleParams().timestep_safety
        print(f"== impact speeds (damping module, time-step factor {fm:g} = ModuleParams.timestep_safety)", flush=True)
        for v in ((5.0, 30.0) if q else (5.0, 10.0, 20.0, 30.0)):
            rows.append(run_case(functools.partial(module, True, v, 0.03 if q else 0.08), fm, "speed", "module small", f"{v:g} m/s"))
        if not q:  # the residual of the fastest impact with smaller steps
            for f in (0.5 * fm, 0.25 * fm):
                rows.append(run_case(functools.partial(module, True, 30.0, 0.08), f, "speed", "module small", "30 m/s"))
        if not (q or a.no_default_module):
            for v in (None, 15.0, 30.0):
                rows.append(run_case(functools.partial(module, False, v, 0.1), fm, "speed", "module default",
                                     f"{v:g} m/s" if v else f"{ModuleParams().impact_speed():.2f} m/s"))
    write(rows, margins, line, groups)
    if margins:
        print("== margins (factor x the estimated critical step)")
        for (scene, params), (ok, bad) in margins.items():
            at1, acc = margin_extras(rows, scene, params)
            print(f"  {scene} {params}: last stable {ok if ok is None else round(ok, 3)}, first unstable {bad if bad is None else round(bad, 3)}, "
                  f"stable at 1.0: {at1}, |residual| < {100 * ACCURATE:g}% up to {acc}")
    print(f"total wall time {time.time() - t_start:.0f} s; results in {RESULTS}")


if __name__ == "__main__":
    main()
