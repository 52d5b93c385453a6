# Profile of the damping-module impact: time per step, share of each engine, and (with --perf)
# share of each function inside the step, at one or more thread counts (GPL-2.0-or-later).
#
#     yade-double -n -x bench/profile_module.py [--small] [--threads 1 2] [--reps 3] [--steps 1500] [--perf]
#         [--label NAME] [--baseline PREFIX --baseline-label NAME] [--out bench/results/profile_module.csv]
#
# The parent process runs, for each thread count and repetition, a child `yade-double -n -j T -x
# bench/profile_module.py --child ...` (a fresh YADE each time, so that OpenMP's thread count is
# the one asked for). Each child loads the filled module of the main job (yadeflex.module,
# cached in ~/.cache/yadeflex/modules; built on first use), adds the boulder with the main
# job's engines, steps until 5 ms after the boulder's first contact (the fill and the mesh are
# then loaded, as in the body of the impact), then times --steps steps with O.timingEnabled
# (stepped by yadeflex.scene.step_until, as the main job steps):
# wall time per step and each engine's execTime. With --perf (first repetition at -j1 only),
# `perf record` samples the child during that window and the samples are grouped by function.
# --baseline PREFIX also runs another build (installed with `YADE_PREFIX=PREFIX scripts/setup`),
# alternating with the current one run by run, so that both see the same machine load, and prints
# the median of the paired ratios. Writes CSV rows (label, threads, engine, us_per_step, share,
# reps) to --out (rows of other labels already there are kept), the functions to
# <out>_functions.csv, a PNG of engine time per step, and prints medians.
import argparse
import csv
import json
import math
import os
import re
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time

BENCH = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if a.endswith("profile_module.py")), os.path.join(os.getcwd(), "bench"))
REPO = os.path.dirname(BENCH)
sys.path.insert(0, BENCH)
sys.path.insert(0, os.path.join(REPO, "py"))


def parse():
    me = next((k for k, a in enumerate(sys.argv) if a.endswith("profile_module.py")), 0)
    ap = argparse.ArgumentParser(prog="profile_module.py", description="Per-engine and per-function profile of the damping-module impact.")
    ap.add_argument("--small", action="store_true", help="the reduced module of damping_module.py --small")
    ap.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--steps", type=int, default=1500, help="timed steps per run")
    ap.add_argument("--after-contact", type=float, default=5e-3, help="simulated time after first contact before timing [s]")
    ap.add_argument("--perf", action="store_true", help="also sample functions with perf (one -j1 run)")
    ap.add_argument("--label", default="current", help="name of this build in the CSV (e.g. before/after)")
    ap.add_argument("--baseline", default=None, metavar="PREFIX",
                    help="also run the build installed in this YADE_PREFIX, alternating with the current one run by run (paired ratios)")
    ap.add_argument("--baseline-label", default="baseline")
    ap.add_argument("--out", default=None, help="CSV path (default bench/results/profile_module[_small].csv)")
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--perf-data", default=None, help=argparse.SUPPRESS)
    a = ap.parse_args(sys.argv[me + 1:])
    if a.steps < 1 or a.reps < 1 or any(t < 1 for t in a.threads):
        ap.error("--steps, --reps and --threads must be positive")
    return a


def child(a):
    from yade import O
    from yadeflex.module import ModuleParams, impact_start
    impact_start(ModuleParams.small() if a.small else ModuleParams())
    t_contact = O.time
    while O.time < t_contact + a.after_contact:
        for _ in range(50):
            O.step()
    for _ in range(100):  # warm caches after the contact search
        O.step()
    O.timingEnabled = True
    for e in O.engines:
        e.execTime = 0
    perf = None
    if a.perf_data:
        perf = subprocess.Popen(["perf", "record", "-F", "999", "-p", str(os.getpid()), "-o", a.perf_data], stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL)
        time.sleep(1.0)  # perf attaches
    # timed as the main job steps (yadeflex.scene.step_until: no Python between the steps, the
    # scene checked in full as in O.run); O.step() in a loop for a build without it
    try:
        from yade.wrapper import FlexRun  # noqa: F401
        from yadeflex.scene import step_until
        stepping = "step_until"
    except ImportError:
        stepping = "O.step"
    w0 = time.perf_counter()
    if stepping == "step_until":
        step_until(math.inf, a.steps)
    else:
        for _ in range(a.steps):
            O.step()
    wall = time.perf_counter() - w0
    if perf:
        perf.send_signal(signal.SIGINT)
        perf.wait(timeout=60)
    engines = {(e.label or type(e).__name__): e.execTime / 1e3 / a.steps for e in O.engines}
    print("PROFILE " + json.dumps(dict(us_per_step=1e6 * wall / a.steps, engines=engines, dt=O.dt, bodies=len(O.bodies),
                                       interactions=len(O.interactions), real=O.interactions.countReal(),
                                       fast_path=bool(O.engines[-1].usedFastPath), stepping=stepping)), flush=True)


# function name (substring) -> group, first match wins
GROUPS = [
    ("Ig2_Sphere_Sphere_FlexContactGeom", "sphere-sphere geometry (ours)"),
    ("Law2_FlexContactGeom", "contact law (ours)"),
    ("frictionalStep", "contact law (ours)"),
    ("cappedSpringStep", "contact law (ours)"),
    ("Ig2_", "element contact geometry (ours)"),
    ("flexa::", "element contact geometry (ours)"),
    ("closestPoint", "element contact geometry (ours)"),
    ("InteractionLoop", "InteractionLoop (YADE: loop, dispatch)"),
    ("Dispatcher", "InteractionLoop (YADE: loop, dispatch)"),
    ("Ip2_", "InteractionLoop (YADE: loop, dispatch)"),
    ("InsertionSortCollider", "collider (YADE)"),
    ("Bo1_", "collider (YADE)"),
    ("FlexTimeStepper", "time stepper (ours)"),
    ("omega2", "time stepper (ours)"),
    ("FlexNewtonIntegrator", "integrator (ours)"),
    ("NewtonIntegrator", "integrator (YADE)"),
    ("Clump", "integrator (YADE)"),
    ("FlexElementEngine", "elements (ours)"),
    ("beam", "elements (ours)"),
    ("membrane", "elements (ours)"),
    ("WireLaw", "elements (ours)"),
    ("ForceContainer", "forces (YADE)"),
    ("ForceResetter", "forces (YADE)"),
    ("malloc", "allocation"),
    ("free", "allocation"),
    ("operator new", "allocation"),
    ("operator delete", "allocation"),
    ("(no symbols)", "YADE libraries without symbols (loops, containers)"),
    ("gomp", "OpenMP runtime"),
    ("GOMP", "OpenMP runtime"),
]


def perf_functions(data):
    """[(percent, symbol)] of a perf.data file, self time, sorted."""
    out = subprocess.run(["perf", "report", "-i", data, "--stdio", "--no-children", "--sort", "dso,symbol", "--percent-limit", "0.2"],
                         capture_output=True, text=True).stdout
    rows = []
    for line in out.splitlines():
        line = line.strip()
        if not line or line.startswith("#") or "%" not in line or "[" not in line:
            continue
        pct, _, rest = line.partition("%")
        dso, _, sym = rest.partition("[")
        sym = re.sub(r"\s+-\s+-\s*$", "", sym.split("]", 1)[-1]).strip()
        if sym.startswith("0x"):  # no symbol (YADE's libraries are stripped): name the library
            sym = f"{dso.strip()} (no symbols)"
        try:
            rows.append((float(pct), sym))
        except ValueError:
            continue
    merged = {}
    for pct, sym in rows:
        merged[sym] = merged.get(sym, 0.0) + pct
    return sorted(((p, s) for s, p in merged.items()), reverse=True)


def group_of(sym):
    for key, g in GROUPS:
        if key in sym:
            return g
    return "other"


def parent(a):
    out = a.out or os.path.join(BENCH, "results", f"profile_module{'_small' if a.small else ''}.csv")
    os.makedirs(os.path.dirname(out), exist_ok=True)
    me = os.path.abspath(sys.argv[next(k for k, x in enumerate(sys.argv) if x.endswith("profile_module.py"))])
    runs, funcs = [], []
    builds = ([(a.baseline_label, a.baseline)] if a.baseline else []) + [(a.label, None)]
    for rep in range(a.reps):
        for t in a.threads:
            for label, prefix in builds:  # alternating: both builds see the same machine load
                cmd = ["yade-double", "-n", "-j", str(t), "-x", me, "--child", "--steps", str(a.steps), "--after-contact", str(a.after_contact)]
                if a.small:
                    cmd.append("--small")
                tmp = None
                if a.perf and t == 1 and rep == 0 and prefix is None and shutil.which("perf"):
                    tmp = tempfile.mkdtemp()
                    cmd += ["--perf-data", os.path.join(tmp, "perf.data")]
                env = dict(os.environ, OMP_NUM_THREADS=str(t))
                if prefix:
                    env["YADE_PREFIX"] = prefix
                r = subprocess.run(cmd, capture_output=True, text=True, env=env)
                line = next((x for x in r.stdout.splitlines() if x.startswith("PROFILE ")), None)
                if r.returncode != 0 or line is None:
                    sys.exit(f"child failed ({r.returncode}):\n{r.stdout[-2000:]}\n{r.stderr[-2000:]}")
                d = json.loads(line[8:])
                d.update(threads=t, rep=rep, label=label)
                runs.append(d)
                print(f"  {label} -j{t} rep {rep}: {d['us_per_step']:.0f} us/step, {d['interactions']} interactions ({d['real']} real), "
                      f"dt {d['dt']:.3g} s, fast path {d['fast_path']}, {d.get('stepping', 'O.step')}", flush=True)
                if tmp:
                    funcs = perf_functions(os.path.join(tmp, "perf.data"))
                    shutil.rmtree(tmp, ignore_errors=True)
    # medians per build, thread count and engine
    rows = []
    for label, _ in builds:
        for t in a.threads:
            rs = [r for r in runs if r["threads"] == t and r["label"] == label]
            total = statistics.median(r["us_per_step"] for r in rs)
            dt = statistics.median(r["dt"] for r in rs)
            stepping = "/".join(sorted({r.get("stepping", "O.step") for r in rs}))
            rows.append(dict(label=label, threads=t, engine="step (wall)", us_per_step=round(total, 1), share=1.0, reps=len(rs), dt=dt,
                             wall_s_per_simulated_s=round(total * 1e-6 / dt, 1), stepping=stepping))
            for name in rs[0]["engines"]:
                us = statistics.median(r["engines"][name] for r in rs)
                rows.append(dict(label=label, threads=t, engine=name, us_per_step=round(us, 1), share=round(us / total, 4), reps=len(rs), dt=dt,
                                 wall_s_per_simulated_s=round(us * 1e-6 / dt, 1), stepping=stepping))
    methods = {r["label"]: r["stepping"] for r in rows}
    if len(set(methods.values())) > 1:
        print("NOTE: the builds were stepped differently (" + ", ".join(f"{k}: {v}" for k, v in methods.items())
              + "): an O.step() loop checks the whole scene at every step, so their ratio includes that difference")
    if a.baseline:
        for t in a.threads:
            pairs = [(b["us_per_step"], c["us_per_step"]) for b in runs for c in runs if b["threads"] == c["threads"] == t
                     and b["rep"] == c["rep"] and b["label"] == a.baseline_label and c["label"] == a.label]
            print(f"-j{t}: {a.label} faster than {a.baseline_label} by {statistics.median(x / y for x, y in pairs):.2f}x "
                  f"(median of {len(pairs)} paired runs: " + ", ".join(f"{x / y:.2f}" for x, y in pairs) + ")")
            sim = [(b["us_per_step"] / b["dt"], c["us_per_step"] / c["dt"]) for b in runs for c in runs if b["threads"] == c["threads"] == t
                   and b["rep"] == c["rep"] and b["label"] == a.baseline_label and c["label"] == a.label]
            print(f"-j{t}: per simulated second, {a.label} faster than {a.baseline_label} by {statistics.median(x / y for x, y in sim):.2f}x "
                  f"(paired: " + ", ".join(f"{x / y:.2f}" for x, y in sim) + ")")
    from machine import machine_line
    with open(os.path.splitext(out)[0] + "_machine.txt", "a") as f:
        f.write(f"{', '.join(lb for lb, _ in builds)}: " + machine_line())
    old = []
    if os.path.exists(out):
        with open(out) as f:
            old = [r for r in csv.DictReader(f) if r["label"] not in {lb for lb, _ in builds}]
    with open(out, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(old + rows)
    cols = [(lb, t) for lb, _ in builds for t in a.threads]
    print(f"\nmodule {'(--small) ' if a.small else ''}impact, medians of {a.reps} runs x {a.steps} steps")
    for lb, t in cols:
        r = next(x for x in rows if x["threads"] == t and x["engine"] == "step (wall)" and x["label"] == lb)
        print(f"{lb} -j{t}: time step {r['dt']:.3g} s, {r['wall_s_per_simulated_s']:.0f} s of wall time per simulated second")
    print(f"{'engine':24s}" + "".join(f"{(lb[:14] + ' -j' + str(t)):>24s}{'share':>8s}" for lb, t in cols))
    for name in [r["engine"] for r in rows if r["threads"] == a.threads[0] and r["label"] == a.label]:
        line = f"{name:24s}"
        for lb, t in cols:
            r = next((x for x in rows if x["threads"] == t and x["engine"] == name and x["label"] == lb), None)
            line += f"{r['us_per_step']:24.1f}{100 * r['share']:7.1f}%" if r else f"{'-':>24s}{'':>8s}"
        print(line)
    if len(a.threads) > 1:
        for lb, _ in builds:
            base = next(r for r in rows if r["threads"] == a.threads[0] and r["engine"] == "step (wall)" and r["label"] == lb)["us_per_step"]
            for t in a.threads[1:]:
                x = next(r for r in rows if r["threads"] == t and r["engine"] == "step (wall)" and r["label"] == lb)["us_per_step"]
                print(f"{lb}: speed-up -j{t} vs -j{a.threads[0]}: {base / x:.2f}x")
    if funcs:
        groups = {}
        for pct, sym in funcs:
            groups[group_of(sym)] = groups.get(group_of(sym), 0.0) + pct
        fout = os.path.splitext(out)[0] + "_functions.csv"
        with open(fout, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["label", "kind", "name", "percent_of_samples"])
            for g, pct in sorted(groups.items(), key=lambda x: -x[1]):
                w.writerow([a.label, "group", g, round(pct, 2)])
            for pct, sym in funcs:
                w.writerow([a.label, "function", sym, pct])
        print("\nperf, -j1, share of samples by group (functions >= 0.2%):")
        for g, pct in sorted(groups.items(), key=lambda x: -x[1]):
            print(f"  {g:42s}{pct:6.1f}%")
        print("top functions:")
        for pct, sym in funcs[:12]:
            print(f"  {pct:5.1f}%  {sym[:100]}")
    _plot(out)


def _plot(out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    with open(out) as f:
        rows = list(csv.DictReader(f))
    bars = sorted({(r["label"], int(r["threads"])) for r in rows}, key=lambda x: (x[1], x[0]))
    engines = [e for e in dict.fromkeys(r["engine"] for r in rows) if e != "step (wall)"]
    fig, ax = plt.subplots(figsize=(1.6 * len(bars) + 3, 4.5))
    for k, (label, t) in enumerate(bars):
        bottom = 0.0
        for j, e in enumerate(engines):
            v = next((float(r["us_per_step"]) for r in rows if r["label"] == label and int(r["threads"]) == t and r["engine"] == e), 0.0)
            ax.bar(k, v, bottom=bottom, color=f"C{j}", label=e if k == 0 else None)
            bottom += v
    ax.set_xticks(range(len(bars)), [f"{l}\n-j{t}" for l, t in bars])
    ax.set_ylabel("time per step [us]")
    ax.set_title("damping-module impact: time per step by engine (medians)")
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1, 1))
    fig.tight_layout()
    fig.savefig(os.path.splitext(out)[0] + ".png", dpi=110)


args = parse()
if args.child:
    child(args)
else:
    parent(args)
