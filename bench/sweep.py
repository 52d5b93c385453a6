# Run time against error (issue 6), yade-flex against YADE's built-in classes (GPL-2.0-or-later).
#
#     yade-double -n -j1 -x bench/sweep.py [--quick] [--scenes cantilever,membrane,net,module]
#
# For each scene and each accuracy knob, runs yade-flex and the built-in model of the same scene in
# this one process, alternating (built-in, then ours, for each knob value), and records the wall time,
# the steps, the time step and the headline quantities; errors are taken against an analytic solution
# where one exists and against a converged run of the same implementation (the finest setting of the
# knob, which is run too: its distance to the second-finest run is printed and saved as the
# convergence of the reference). Writes bench/results/sweep_<scene>.csv (one row per run),
# sweep_<scene>.png (wall time against error, log-log, one curve per implementation and knob),
# sweep_machine.txt, and prints a table per scene.
#
# Scenes (each built by the scene builders the tests and benchmarks use):
#   cantilever  yadeflex.harness.scenes.cantilever vs builtin_grid.cantilever (GridNode/GridConnection/CohFrict),
#               steel, L = 1 m, r = 10 mm, tip load giving L/1000, local damping 0.8 on both.
#               Knobs: segments (at dt fraction 0.5) and dt fraction (at 10 segments). The run goes on
#               until the tip deflection changes by less than 1e-9 relative over 2 ms of simulated
#               time. Run time = (steps until the deflection stays within 1e-5 of its final value) x
#               (wall time per step, median of 3 timed O.run windows of ~0.2 s on the same scene).
#   membrane    yadeflex.harness.membrane_scenes.pretensioned_square vs the same mesh of PFacets (crossed
#               diagonals), prestretched by 1%, point load 1 N at the centre, local damping 0.8.
#               Deflection at three points a quarter side from the load vs the double sine series of
#               linear membrane theory (at the load point the theory is singular). The PFacet truss
#               gets the bar modulus that gives it our prestress (see membrane_builtin). Knobs: cells
#               per side, dt fraction. Run time defined as for the cantilever.
#   net         yadeflex builders vs GridNode/GridConnection net (the scene of bench_cylinders: 20 x 20
#               wires 50 mm apart, r = 2 mm, border clamped, steel sphere r = 0.1 m at 5 m/s, no
#               damping), each wire leg split into `segments` cylinders. Peak force on the sphere (from
#               its velocity change over 0.1 ms windows), its largest displacement, and the energy it
#               lost to the net (kinetic energy at its release height, moving up, out of contact: the
#               net is undamped and elastic, so this is the energy left vibrating in the net).
#               Knobs: dt fraction and segments per leg. Run time = wall time from release to then.
#   module      the small damping module (damping_module.py --small: 0.4 x 0.3 m, 100 kg cube from 1 m),
#               ours (p.engines(0): no numerical damping, as damping_module.py) vs builtin_module
#               (WirePM, PFacet lining, FrictMat fill; NewtonIntegrator damping 0.2, its usual setting).
#               Peak force on the boulder (velocity change over 0.2 ms, and over 2 ms), deepest penetration below the
#               fill top, energy taken from the boulder 60 ms after first contact. Knobs: dt fraction,
#               grain size (new fill each, cached by yadeflex.module.filled_module).
import argparse
import json
import math
import os
import statistics
import sys
import time

BENCH = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if a.endswith("sweep.py")), os.path.join(os.getcwd(), "bench"))
sys.path.insert(0, BENCH)
sys.path.insert(0, os.path.join(os.path.dirname(BENCH), "py"))

import yade  # noqa: E402
from yade import O  # noqa: E402
from yade.minieigenHP import Vector3  # noqa: E402

import builtin_grid as bg  # noqa: E402
import builtin_pfacet as bp  # noqa: E402
from machine import machine_line  # noqa: E402
from tol_ref import cantilever_reference, E as E_STEEL  # noqa: E402

from yadeflex.harness import scenes  # noqa: E402
from yadeflex.module import ModuleParams, touches  # noqa: E402

DT_FRACTIONS = (0.25, 0.5, 0.8, 1.0)


# ----------------------------------------------------------------------------------------------
# common
# ----------------------------------------------------------------------------------------------
def set_safety(s):
    """Our FlexTimeStepper's safety factor (fraction of the critical step)."""
    for e in O.engines:
        if e.label == "flexDt":
            e.safety = s
            return
    raise RuntimeError("no FlexTimeStepper labelled flexDt in O.engines")


def run_chunk(n):
    """n steps, the same way for both implementations (O.run with a fine poll, builtin_grid.run_steps)."""
    bg.run_steps(n)


def settle_history(read, t_check, t_max, rel_change=1e-9, wall_max=None):
    """Steps until the scalar read() changes by less than rel_change x |value| over t_check [s] of
    simulated time, or t_max [s]. Returns (history [(wall s, steps, value)], settled)."""
    if O.dt <= 0 or not math.isfinite(O.dt):
        raise RuntimeError("no time step")
    t0, it0 = time.perf_counter(), O.iter
    hist = [(0.0, 0, read())]
    prev = hist[0][2]
    settled = False
    while O.time < t_max:
        run_chunk(max(1, int(round(t_check / O.dt))))
        v = read()
        hist.append((time.perf_counter() - t0, O.iter - it0, v))
        if not math.isfinite(v):
            break
        if v != 0 and abs(v - prev) <= rel_change * abs(v):
            settled = True
            break
        if wall_max is not None and hist[-1][0] > wall_max:
            break
        prev = v
    return hist, settled


def time_to_tolerance(hist, tol):
    """Steps to the first record after which every value stays within tol x |final| of the final value."""
    final = hist[-1][2]
    k = len(hist) - 1
    while k > 0 and abs(hist[k - 1][2] - final) <= tol * abs(final):
        k -= 1
    return hist[k][1]


def time_per_step(hist, window_s=0.2, windows=3):
    """Median wall time per step [s] of the current scene over `windows` runs of about window_s each
    (O.run of n steps, n from the settling run's rate). Timed apart from the settling run, whose checks
    every few hundred steps cost about 0.5 ms each (measured): more than the steps themselves for a
    cheap scene at a large time step."""
    n = max(200, int(window_s * hist[-1][1] / max(hist[-1][0], 1e-9)))
    out = []
    for _ in range(windows):
        t0 = time.perf_counter()
        run_chunk(n)
        out.append((time.perf_counter() - t0) / n)
    return statistics.median(out)


def rel_err(x, ref):
    if x is None or ref is None or not (math.isfinite(x) and math.isfinite(ref)) or ref == 0:
        return float("nan")
    return abs(x / ref - 1.0)


def add_errors(rows, quantities, ref_of, analytic_of=None):
    """Per row: err_<q>_ref against the reference run of its implementation (ref_of(impl, knob) -> row),
    err_<q>_analytic against analytic_of(row) -> {q: value}."""
    for r in rows:
        ref = ref_of(r["impl"], r["knob"])
        if ref is not None and ref.get("status", "ok") != "ok":
            ref = None  # an unfinished or unstable reference gives no error
        for q in quantities:
            if r.get("status", "ok") != "ok":  # values up to where the run stopped are no result
                r[f"err_{q}_ref"] = float("nan")
                continue
            r[f"err_{q}_ref"] = rel_err(r.get(q), ref.get(q)) if ref is not None else float("nan")
            if analytic_of is not None:
                a = analytic_of(r).get(q)
                r[f"err_{q}_analytic"] = rel_err(r.get(q), a) if a is not None else float("nan")
    return rows


IMPLS = ("built-in", "yade-flex")  # the order of the runs of each knob value


def run_plan(name, plan, run, param, describe):
    """Runs each (knob, value, scene setting, dt fraction) of plan with both implementations, built-in
    first; run(impl, setting, fraction) -> row; the setting is saved under `param`."""
    rows = []
    for knob, value, n, f in plan:
        for impl in IMPLS:
            r = run(impl, n, f)
            r.update(knob=knob, value=value, dt_fraction=f, **{param: n})
            rows.append(r)
            print(f"  {name} {impl:9s} {knob} {value}: {describe(r)}", flush=True)
    return rows


def share_default(rows, source, target):
    """The run at the default of one knob is also the default point of the other: a copy of the
    (knob, value) `source` row of each implementation under (knob, value) `target`."""
    for impl in IMPLS:
        base = next(r for r in rows if r["impl"] == impl and (r["knob"], r["value"]) == source)
        rows.append(dict(base, knob=target[0], value=target[1], shared="same run as %s = %s" % source))


def fmt(x, spec=".3g"):
    if isinstance(x, float):
        return format(x, spec) if math.isfinite(x) else "nan"
    return str(x)


def print_table(title, rows, cols):
    print("\n" + title)
    print("  ".join(f"{c:>14s}" for c in cols))
    for r in rows:
        print("  ".join(f"{fmt(r.get(c)):>14s}" for c in cols))
    sys.stdout.flush()


def plot(path, rows, err_key, title, xlabel):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 5))
    floor = 1e-9  # errors below this (exact to the settling tolerance) are drawn at the floor
    styles = {"yade-flex": ("tab:blue", "-"), "built-in": ("tab:red", "--")}
    markers = {}
    for (impl, knob) in sorted({(r["impl"], r["knob"]) for r in rows}):
        pts = [r for r in rows if r["impl"] == impl and r["knob"] == knob and r.get("status") == "ok" and math.isfinite(r.get(err_key, float("nan")))
               and not r.get("reference")]
        if not pts:
            continue
        pts.sort(key=lambda r: r["value"])
        m = markers.setdefault(knob, "os^vD"[len(markers) % 5])
        c, ls = styles.get(impl, ("k", ":"))
        x = [max(r[err_key], floor) for r in pts]
        y = [r["wall_s"] for r in pts]
        ax.loglog(x, y, marker=m, color=c, ls=ls, label=f"{impl}: {knob}")
        for r, xi, yi in zip(pts, x, y):
            ax.annotate(fmt(r["value"], "g"), (xi, yi), textcoords="offset points", xytext=(4, 3), fontsize=7, color=c)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("wall time [s]")
    ax.set_title(title, fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# ----------------------------------------------------------------------------------------------
# cantilever
# ----------------------------------------------------------------------------------------------
CANT = dict(length=1.0, radius=0.01, damping=0.8, rel_deflection=1e-3, t_check=2e-3, t_max=3.0, tol=1e-5)


def cantilever_run(impl, segments, frac):
    L, r = CANT["length"], CANT["radius"]
    EI = E_STEEL * math.pi * r ** 4 / 4
    force = 3 * EI * CANT["rel_deflection"] * L / L ** 3
    if impl == "built-in":
        res = bg.cantilever(n_seg=segments, length=L, radius_wire=r, load="tip", tip_force=force, damping=CANT["damping"], dt_factor=frac,
                            max_iter=0)  # builds, sets O.dt = frac x min(PWave, stiffness bound), runs nothing
        tip = max(b.id for b in O.bodies if bg._is_node(b))
    else:
        s = scenes.cantilever(segments=segments, length=L, radius=r, load="tip", force=force, damping=CANT["damping"])
        set_safety(frac)
        tip = s["tip"]
        O.step()  # the time stepper sets O.dt
    z0 = 0.0
    hist, settled = settle_history(lambda: z0 - O.bodies[tip].state.pos[2], CANT["t_check"], CANT["t_max"])
    steps = time_to_tolerance(hist, CANT["tol"])
    sps = time_per_step(hist)
    return dict(impl=impl, wall_s=steps * sps, steps=steps, us_per_step=1e6 * sps, dt=O.dt, status="ok" if settled else "not settled", wall_total_s=hist[-1][0],
                steps_total=hist[-1][1], tip_deflection=hist[-1][2], analytic=cantilever_reference("tip", L, r, force))


def sweep_cantilever(quick):
    segs = (2, 5, 10, 20) if quick else (2, 5, 10, 20, 40)
    fracs = (0.5, 1.0) if quick else DT_FRACTIONS
    ref_seg, def_seg, def_frac = segs[-1], 10, 0.5
    plan = [("segments", n, n, def_frac) for n in segs] + [("dt fraction", f, def_seg, f) for f in fracs if f != def_frac]
    rows, reps = [], (1 if quick else 3)
    for rep in range(reps):  # repeats interleaved: the wall time is the median; the deflections are identical
        for knob, value, n, f in plan:
            for impl in IMPLS:
                r = cantilever_run(impl, n, f)
                r.update(knob=knob, value=value, segments=n, dt_fraction=f)
                if rep == 0:
                    r["wall_s_runs"] = [r["wall_s"]]
                    rows.append(r)
                else:
                    old = next(x for x in rows if x["impl"] == impl and x["knob"] == knob and x["value"] == value)
                    if old["tip_deflection"] != r["tip_deflection"]:
                        raise RuntimeError(f"cantilever {impl} {knob} {value}: repeat differs ({old['tip_deflection']!r}, {r['tip_deflection']!r})")
                    old["wall_s_runs"].append(r["wall_s"])
                    old["wall_s"] = statistics.median(old["wall_s_runs"])
                print(f"  cantilever {impl:9s} {knob} {value}: {r['tip_deflection']:.6e} m ({r['status']}), {r['wall_s']:.2f} s to 1e-5, "
                      f"{r['steps']} steps, dt {r['dt']:.3g}", flush=True)
    for r in rows:
        r["wall_s_runs"] = " ".join(f"{w:.3f}" for w in r["wall_s_runs"])
    share_default(rows, ("segments", def_seg), ("dt fraction", def_frac))

    def ref_of(impl, knob):
        return next(r for r in rows if r["impl"] == impl and r["knob"] == "segments" and r["value"] == ref_seg)

    add_errors(rows, ["tip_deflection"], ref_of, lambda r: {"tip_deflection": r["analytic"]})
    for impl in IMPLS:
        a, b = ref_of(impl, None), next(r for r in rows if r["impl"] == impl and r["knob"] == "segments" and r["value"] == segs[-2])
        for r in rows:
            if r["impl"] == impl:
                r["ref_convergence"] = rel_err(b["tip_deflection"], a["tip_deflection"])
    return rows, ["tip_deflection"], "err_tip_deflection_analytic", "tip deflection: |w / w_Euler-Bernoulli - 1|"



# ----------------------------------------------------------------------------------------------
# membrane: pretensioned square, point load
# ----------------------------------------------------------------------------------------------
MEMB = dict(size=1.0, prestrain=0.01, load=1.0, stiffness=20e3, poisson=0.3, areal_mass=0.3, thickness=0.002, damping=0.8,
            t_check=5e-3, t_max=5.0, tol=1e-5)


def _crossed_mesh(n, size):
    """Points and triangles of yadeflex.membrane.sheet(n, n, ..., pattern='crossed'), origin at -size/2."""
    pts = [(size * i / n - size / 2, size * j / n - size / 2, 0.0) for i in range(n + 1) for j in range(n + 1)]
    idx = lambda i, j: i * (n + 1) + j  # noqa: E731
    tris = []
    for i in range(n):
        for j in range(n):
            a, b, c, d = idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)
            tris += [(a, b, c), (a, c, d)] if (i + j) % 2 == 0 else [(a, b, d), (b, c, d)]
    border = [idx(i, j) for i in range(n + 1) for j in range(n + 1) if i in (0, n) or j in (0, n)]
    return pts, tris, border, idx


def membrane_builtin(n):
    """The pretensioned square of membrane_scenes with built-in PFacets (crossed diagonals, as ours).
    A PFacet mesh is a truss of CohFrict bars (builtin_pfacet header). Stretched by lam = 1 + e after the
    bonds are made, each bar carries F = EA (lam - 1) (checked: kn x elongation); per unit current
    width the crossed truss then has the isotropic prestress T = EA (lam - 1)(1 + sqrt2/2)/(h lam)
    (x or y bar, plus half of each diagonal direction per cell). EA is chosen so that T equals ours,
    Et/(1 - nu)(lam^2 - 1)/2. The linear membrane theory of the point load involves only T. Node mass:
    areal mass 0.3 kg/m2 as ours (builtin_pfacet.sheet's density rule)."""
    c = MEMB
    lam = 1 + c["prestrain"]
    T = c["stiffness"] / (1 - c["poisson"]) * (lam * lam - 1) / 2
    h, r = c["size"] / n, 0.5 * c["thickness"]
    EA = T * h * lam / ((lam - 1) * (1 + math.sqrt(2) / 2))
    young = EA / (math.pi * r * r)
    pts, tris, border, idx = _crossed_mesh(n, c["size"])
    total_len = sum(math.dist(pts[a], pts[b]) for a, b in bp._edges(tris))
    rho = c["areal_mass"] * c["size"] ** 2 / (math.pi * r * r * total_len)
    O.reset()
    bp._engines(gravity=(0, 0, 0), damping=c["damping"])
    node_mat, ext_mat = bp._mesh_materials(young, c["poisson"], rho, young, 0.0)
    m = bp.build_mesh(pts, tris, r, node_mat, ext_mat, fixed=border)
    for i in m["nodes"]:
        O.bodies[i].state.pos = O.bodies[i].state.pos * lam
    grid = [[m["nodes"][idx(i, j)] for j in range(n + 1)] for i in range(n + 1)]
    O.forces.setPermF(grid[n // 2][n // 2], Vector3(0, 0, -c["load"]))
    return grid, T, c["size"] * lam


def membrane_run(impl, n, frac):
    from yadeflex.harness import membrane_scenes as MS
    c = MEMB
    if impl == "built-in":
        grid, T, side = membrane_builtin(n)
        O.dt = frac * bg.stiffness_dt()  # builtin_pfacet's bond bound (no contacts here)
    else:
        sc = MS.pretensioned_square(n=n, size=c["size"], prestrain=c["prestrain"], load=c["load"], stiffness=c["stiffness"],
                                    poisson=c["poisson"], damping=c["damping"])
        grid, T, side = sc["sheet"]["grid"], sc["tension"], sc["side"]
        set_safety(frac)
        O.step()
    pts = [grid[n // 4][n // 2], grid[n // 4][n // 4], grid[n // 2][n // 4]]  # a quarter side from the load (the test's points)
    hist, settled = settle_history(lambda: -sum(O.bodies[i].state.pos[2] for i in pts) / 3, c["t_check"], c["t_max"])
    steps = time_to_tolerance(hist, c["tol"])
    w = [-O.bodies[i].state.pos[2] for i in pts]
    sps = time_per_step(hist)
    ana = []
    for i in pts:
        p = O.bodies[i].state.pos
        ana.append(MS.square_membrane_deflection(p[0] + side / 2, p[1] + side / 2, side / 2, side / 2, c["load"], T, side, terms=200))
    worst = max(range(3), key=lambda k: abs(w[k] / ana[k] - 1))
    return dict(impl=impl, wall_s=steps * sps, steps=steps, us_per_step=1e6 * sps, dt=O.dt, status="ok" if settled else "not settled",
                wall_total_s=hist[-1][0], steps_total=hist[-1][1], w_edge=w[0], w_diag=w[1], w_quarter=w[2], analytic_edge=ana[0], analytic_diag=ana[1],
                analytic_quarter=ana[2], worst_point=("edge", "diag", "quarter")[worst], tension=T,
                err_worst_analytic=max(abs(w[k] / ana[k] - 1) for k in range(3)))


def sweep_membrane(quick):
    cells = (4, 8, 16) if quick else (4, 8, 16, 24)
    fracs = (0.5, 1.0) if quick else DT_FRACTIONS
    def_n, def_frac = 8, 0.5
    plan = [("cells per side", n, n, def_frac) for n in cells] + [("dt fraction", f, def_n, f) for f in fracs if f != def_frac]
    rows = run_plan("membrane", plan, membrane_run, "cells",
                    lambda r: f"w {1e3 * r['w_edge']:.5f} {1e3 * r['w_diag']:.5f} mm, worst error {r['err_worst_analytic']:.4f} ({r['status']}), "
                              f"{r['wall_s']:.2f} s to 1e-5, {r['steps']} steps, dt {r['dt']:.3g}")
    share_default(rows, ("cells per side", def_n), ("dt fraction", def_frac))
    qs = ["w_edge", "w_diag", "w_quarter"]

    def ref_of(impl, knob):
        return next(r for r in rows if r["impl"] == impl and r["knob"] == "cells per side" and r["value"] == cells[-1])

    add_errors(rows, qs, ref_of, lambda r: {q: r["analytic" + q[1:]] for q in qs})
    for impl in IMPLS:
        a, b = ref_of(impl, None), next(r for r in rows if r["impl"] == impl and r["knob"] == "cells per side" and r["value"] == cells[-2])
        for r in rows:
            if r["impl"] == impl:
                r["ref_convergence"] = max(rel_err(b[q], a[q]) for q in qs)
    return rows, qs, "err_worst_analytic", "deflection a quarter side from the load: worst |w / w_series - 1| of 3 points"


# ----------------------------------------------------------------------------------------------
# net impact
# ----------------------------------------------------------------------------------------------
NET = dict(n=20, spacing=0.05, radius=0.002, sphere_radius=0.1, speed=5.0, young=200e9, density=7850.0, friction_deg=30.0, gap=0.001,
           window=0.05, record=1e-4)


def _net_points(n, spacing, segments):
    """Node positions of an n x n wire net with each leg split in `segments`: dict key -> (x, y),
    keys (i, j) for crossings and (i, j, 'x'|'y', k) for the k-th inner node of the leg from (i, j);
    legs as lists of keys, and the keys on the border lines (clamped)."""
    pos, legs = {}, []
    for i in range(n):
        for j in range(n):
            pos[(i, j)] = (i * spacing, j * spacing)
    for i in range(n):
        for j in range(n):
            for d, (di, dj) in (("x", (1, 0)), ("y", (0, 1))):
                if i + di >= n or j + dj >= n:
                    continue
                chain = [(i, j)]
                for k in range(1, segments):
                    key = (i, j, d, k)
                    pos[key] = ((i + di * k / segments) * spacing, (j + dj * k / segments) * spacing)
                    chain.append(key)
                chain.append((i + di, j + dj))
                legs.append(chain)
    edge = (n - 1) * spacing
    border = [k for k, (x, y) in pos.items() if min(x, y) < 1e-9 * spacing or max(x, y) > edge - 1e-9 * spacing]
    return pos, legs, border


def net_scene(impl, segments):
    c = NET
    pos, legs, border = _net_points(c["n"], c["spacing"], segments)
    mid = 0.5 * (c["n"] - 1) * c["spacing"]
    sc = Vector3(mid, mid, c["radius"] + c["sphere_radius"] + c["gap"])
    if impl == "built-in":
        from yade import utils
        from yade.gridpfacet import gridConnection, gridNode
        from yade.wrapper import FrictMat
        O.reset()
        bg._engines(gravity=(0, 0, -bg.G_ACC), damping=0.0, with_spheres=True)
        node_mat, conn_mat = bg._materials(c["young"], 0.3, c["density"], c["friction_deg"])
        sph_mat = O.materials.append(FrictMat(young=c["young"], poisson=0.3, density=c["density"], frictionAngle=math.radians(c["friction_deg"])))
        ids = {k: O.bodies.append(gridNode(Vector3(x, y, 0.0), c["radius"], material=node_mat)) for k, (x, y) in pos.items()}
        for chain in legs:
            for a, b in zip(chain[:-1], chain[1:]):
                O.bodies.append(gridConnection(ids[a], ids[b], c["radius"], material=conn_mat, mask=bg.GC_MASK))
        for k in border:
            O.bodies[ids[k]].state.blockedDOFs = "xyzXYZ"
        sid = O.bodies.append(utils.sphere(sc, c["sphere_radius"], material=sph_mat, mask=bg.SPHERE_MASK))
        O.bodies[sid].state.vel = Vector3(0, 0, -c["speed"])
    else:
        from yadeflex import builders as B
        from yadeflex.materials import steel
        from yadeflex.scene import engines
        O.reset()
        mat = steel(friction_deg=c["friction_deg"])
        ids = {k: B.node(Vector3(x, y, 0.0), c["radius"], mat) for k, (x, y) in pos.items()}
        for chain in legs:
            for a, b in zip(chain[:-1], chain[1:]):
                B.cylinder(ids[a], ids[b], c["radius"], mat)
        B.fix([ids[k] for k in border])
        sid = scenes.sphere(sc, c["sphere_radius"], density=c["density"], young=c["young"], friction_deg=c["friction_deg"],
                            velocity=(0, 0, -c["speed"]))
        O.engines = engines(gravity=(0, 0, -9.81), damping=0.0)
    return sid


def net_run(impl, segments, frac):
    sid = net_scene(impl, segments)
    if impl == "built-in":
        bg._set_dt(frac)  # frac x min(PWave, stiffness bound): builtin_grid's rule
    else:
        set_safety(frac)
        O.step()
    c = NET
    st = O.bodies[sid].state
    m = st.mass
    z0, e0 = st.pos[2], 0.5 * m * st.vel.squaredNorm()
    t_start, it0, w0 = O.time, O.iter, time.perf_counter()
    v_prev, t_prev, next_rec = st.vel[2], O.time, O.time + c["record"]
    t_contact, t_sep, t_end, peak, zmin, status = None, None, O.time + 1.0, 0.0, z0, "ok"
    while O.time < t_end:
        O.step()
        if O.time < next_rec:
            continue
        next_rec += c["record"]
        if not all(math.isfinite(x) for x in st.pos):
            status = "unstable"
            break
        f = m * ((st.vel[2] - v_prev) / (O.time - t_prev) + bg.G_ACC)
        v_prev, t_prev = st.vel[2], O.time
        touching = any(i.isReal for i in O.interactions.withBody(sid))
        if t_contact is None and touching:
            t_contact = O.time
            t_end = t_contact + c["window"]
        peak, zmin = max(peak, f), min(zmin, st.pos[2])
        if t_contact is not None and not touching and st.vel[2] > 0 and st.pos[2] >= z0:
            t_sep = O.time
            break
    wall = time.perf_counter() - w0
    absorbed = e0 - 0.5 * m * st.vel.squaredNorm() + m * bg.G_ACC * (z0 - st.pos[2])
    if status == "ok" and t_sep is None:
        status = "not back at its release height at the end of the window"
    return dict(impl=impl, wall_s=wall, steps=O.iter - it0, dt=O.dt, status=status, peak_force=peak, max_deflection=z0 - zmin,
                contact_ms=1e3 * ((t_sep or O.time) - t_contact) if t_contact is not None else float("nan"),
                absorbed_energy=absorbed if status == "ok" else float("nan"), kinetic_in=e0, rebound_vz=st.vel[2],
                bodies=len([b for b in O.bodies if b is not None]))


def sweep_net(quick):
    segs = (1, 2) if quick else (1, 2, 4)
    fracs = (0.25, 0.5, 1.0) if quick else (0.125,) + DT_FRACTIONS
    def_seg, def_frac = 1, 0.5
    plan = [("dt fraction", f, def_seg, f) for f in fracs] + [("segments per leg", n, n, def_frac) for n in segs if n != def_seg]
    rows = run_plan("net", plan, net_run, "segments",
                    lambda r: f"peak {r['peak_force'] / 1e3:.2f} kN, deflection {1e3 * r['max_deflection']:.2f} mm, absorbed {r['absorbed_energy']:.2f} J, "
                              f"{r['wall_s']:.1f} s, {r['steps']} steps, dt {r['dt']:.3g} ({r['status']})")
    share_default(rows, ("dt fraction", def_frac), ("segments per leg", def_seg))
    # references: the smallest dt fraction (at 1 segment per leg); the most segments per leg (at dt fraction 0.5)
    for r in rows:
        r["reference"] = (r["knob"] == "dt fraction" and r["value"] == fracs[0]) or (r["knob"] == "segments per leg" and r["value"] == segs[-1])
    qs = ["peak_force", "max_deflection", "absorbed_energy"]

    def ref_of(impl, knob):
        return next(r for r in rows if r["impl"] == impl and r["knob"] == knob and r["reference"])

    add_errors(rows, qs, ref_of)
    for impl in IMPLS:
        a, b = [r for r in rows if r["impl"] == impl and r["knob"] == "dt fraction" and r["value"] in fracs[:2]]
        for r in rows:
            if r["impl"] == impl and r["knob"] == "dt fraction":
                r["ref_convergence"] = max(rel_err(b[q], a[q]) for q in qs)
    return rows, qs, "err_max_deflection_ref", "max deflection: |d / d_ref - 1| (reference: smallest dt fraction / most segments)"

# ----------------------------------------------------------------------------------------------
# damping module (small)
# ----------------------------------------------------------------------------------------------
MOD = dict(window=0.060, record=2e-4, builtin_damping=0.2, dt_update=200, builtin_wall_cap=300.0)  # cap [s]: see impact_window


def filled_cache(p):
    """Cache file of the filled module of p, on O (yadeflex.module.filled_module: loaded, or built and
    saved when missing or unreadable by the installed plugin)."""
    from yadeflex.module import filled_module
    t = time.time()
    _, f, cached = filled_module(p)
    if not cached:
        print(f"  filled module {p.grain_min}-{p.grain_max} m built in {time.time() - t:.0f} s", flush=True)
    return f


def impact_window(bid, top0, size, window, record, every=None, each=None, wall_cap=math.inf):
    """Steps from the boulder's release to `window` [s] after its first contact. Peak force
    m (dv_z/dt + g) over `record` [s] intervals, deepest penetration of its lowest point below top0,
    energy it lost (kinetic + potential) at the end. each(): called every `every` steps (time-step update).
    wall_cap [s]: a run still going after this much wall time stops with status "not finished"
    (the built-in module's step collapses on fine fills: one such run had not ended after 45 min).
    One loop for both implementations, so that their wall times compare (yadeflex.module.impact.run_impact
    runs the yade-flex scene only, and records much more)."""
    from yadeflex.constants import G
    st = O.bodies[bid].state
    m = st.mass
    z0, v0 = st.pos[2], Vector3(st.vel)
    e0 = 0.5 * m * v0.squaredNorm()
    t_start, it0, w0 = O.time, O.iter, time.perf_counter()
    v_prev, t_prev = Vector3(st.vel), O.time
    next_rec = O.time + record
    t_contact, t_end = None, O.time + 1.0
    peak, pen, status, k = 0.0, 0.0, "ok", 0
    hist = []
    while O.time < t_end:
        O.step()
        k += 1
        if every and k % every == 0:
            each()
        if O.time < next_rec:
            continue
        next_rec += record
        if time.perf_counter() - w0 > wall_cap:
            status = (f"not finished in {wall_cap:.0f} s: reached {1e3 * (O.time - t_contact):.1f} ms after contact" if t_contact is not None
                      else f"not finished in {wall_cap:.0f} s: no contact yet") + f", dt {O.dt:.3g} s"
            break
        if not all(math.isfinite(x) for x in st.pos) or not all(math.isfinite(x) for x in st.vel):
            status = f"unstable at {1e3 * (O.time - (t_contact or t_start)):.1f} ms"
            break
        f = m * ((st.vel[2] - v_prev[2]) / (O.time - t_prev) + G)
        v_prev, t_prev = Vector3(st.vel), O.time
        if t_contact is None and touches(bid):
            t_contact = O.time
            t_end = t_contact + window
        if t_contact is not None:
            peak = max(peak, f)
            pen = max(pen, top0 - (st.pos[2] - 0.5 * size))
            hist.append((O.time, st.vel[2]))
    wall = time.perf_counter() - w0
    absorbed = e0 - 0.5 * m * st.vel.squaredNorm() + m * G * (z0 - st.pos[2])
    lag = max(1, int(round(0.002 / record)))  # the force averaged over 2 ms: m (v(t + 2 ms) - v(t)) / 2 ms + m g
    peak2 = max((m * ((hist[k + lag][1] - hist[k][1]) / (hist[k + lag][0] - hist[k][0]) + G) for k in range(len(hist) - lag)), default=float("nan"))
    if status == "ok" and t_contact is None:
        status = "no contact"
    return dict(wall_s=wall, steps=O.iter - it0, dt=O.dt, status=status, peak_force=peak, peak_force_2ms=peak2, penetration=pen,
                absorbed_energy=absorbed if status == "ok" else float("nan"), kinetic_in=e0,
                t_contact=(t_contact - t_start) if t_contact is not None else float("nan"))


def module_runs(p, fracs, rows, knob, value_of):
    """Ours and the built-in on the filled module of p, for each dt fraction, alternating."""
    import builtin_module as bm
    from yadeflex.module import add_boulder, fill_top
    cache = filled_cache(p)
    geo = bm.extract(cache)
    info = bm.build(geo)
    t0 = time.time()
    ts, ke = bm.settle(info)
    print(f"  built-in module settled {1e3 * ts:.0f} ms in {time.time() - t0:.0f} s ({len(info['grains'])} grains)", flush=True)
    O.saveTmp("sweep_builtin")
    for f in fracs:
        # built-in: NewtonIntegrator damping 0.2, O.dt = f x min sqrt(m/K), recomputed (only decreasing) every 200 steps
        O.loadTmp("sweep_builtin")
        for e in O.engines:
            if isinstance(e, bm.NewtonIntegrator):
                e.damping = MOD["builtin_damping"]
        top_b = bm.fill_top(info)
        b = bm.add_boulder(info, p)
        dt0 = bm.set_dt(f)
        r = impact_window(b, top_b, p.boulder_size(), MOD["window"], MOD["record"], MOD["dt_update"], lambda: bm.set_dt(f, only_decrease=True),
                          wall_cap=MOD["builtin_wall_cap"])
        r.update(impl="built-in", knob=knob, value=value_of(f), dt_fraction=f, grain_min=p.grain_min, grain_max=p.grain_max,
                 grains=len(info["grains"]), damping=MOD["builtin_damping"], dt_start=dt0)
        rows.append(r)
        print(f"  module built-in  {knob} {r['value']}: peak {r['peak_force'] / 1e3:.2f} kN, penetration {1e3 * r['penetration']:.1f} mm, "
              f"absorbed {r['absorbed_energy']:.1f} J, {r['wall_s']:.1f} s, {r['steps']} steps, dt {r['dt']:.3g} ({r['status']})", flush=True)
        # ours: the main job's engines (damping 0), FlexTimeStepper.safety = f
        O.load(cache)
        ids = json.loads(O.tags["yadeflex_module"])
        top0 = fill_top(ids)
        bid = add_boulder(p, ids)
        O.engines = p.engines(p.damping)
        set_safety(f)
        r = impact_window(bid, top0, p.boulder_size(), MOD["window"], MOD["record"])
        r.update(impl="yade-flex", knob=knob, value=value_of(f), dt_fraction=f, grain_min=p.grain_min, grain_max=p.grain_max,
                 grains=len(ids["grains"]), damping=p.damping)
        rows.append(r)
        print(f"  module yade-flex {knob} {r['value']}: peak {r['peak_force'] / 1e3:.2f} kN, penetration {1e3 * r['penetration']:.1f} mm, "
              f"absorbed {r['absorbed_energy']:.1f} J, {r['wall_s']:.1f} s, {r['steps']} steps, dt {r['dt']:.3g} ({r['status']})", flush=True)


def sweep_module(quick):
    qs = ["peak_force", "peak_force_2ms", "penetration", "absorbed_energy"]
    ref_frac, def_frac = 0.125, 0.5
    fracs = (0.25, 0.5, 1.0) if quick else (0.125,) + DT_FRACTIONS
    ref_frac = fracs[0]
    grain_sizes = [] if quick else [(0.045, 0.06), (0.035, 0.045)]
    rows = []
    module_runs(ModuleParams.small(), fracs, rows, "dt fraction", lambda f: f)
    for r in rows:
        r["reference"] = r["value"] == ref_frac
    # grain size: mean diameter [m] as the knob value, at the default dt fraction
    for r in [r for r in rows if r["dt_fraction"] == def_frac]:
        rows.append(dict(r, knob="grain size", value=0.5 * (r["grain_min"] + r["grain_max"]), reference=False, shared="same run as dt fraction 0.5"))
    for g in grain_sizes:
        module_runs(ModuleParams.small(grain_min=g[0], grain_max=g[1]), (def_frac,), rows, "grain size", lambda f, g=g: 0.5 * (g[0] + g[1]))
    if grain_sizes:
        finest = min(r["value"] for r in rows if r["knob"] == "grain size")
        for r in rows:
            if r["knob"] == "grain size":
                r["reference"] = r["value"] == finest

    def ref_of(impl, knob):
        return next((r for r in rows if r["impl"] == impl and r["knob"] == knob and r.get("reference")), None)

    add_errors(rows, qs, ref_of)
    for impl in IMPLS:  # convergence of the dt reference: the two smallest fractions
        a, b = [r for r in rows if r["impl"] == impl and r["knob"] == "dt fraction" and r["value"] in fracs[:2]]
        for r in rows:
            if r["impl"] == impl:
                r["ref_convergence"] = max(rel_err(b[q], a[q]) for q in qs)
    return rows, qs, "err_peak_force_ref", "peak force: |F / F_ref - 1| (reference: smallest dt fraction / finest grains)"


# ----------------------------------------------------------------------------------------------
# main
# ----------------------------------------------------------------------------------------------
SCENES = {"cantilever": sweep_cantilever, "membrane": sweep_membrane, "net": sweep_net, "module": sweep_module}


def main():
    me = next((k for k, a in enumerate(sys.argv) if a.endswith("sweep.py")), 0)
    ap = argparse.ArgumentParser(prog="sweep.py", description="Run time against error, yade-flex and YADE's built-ins.")
    ap.add_argument("--quick", action="store_true", help="fewer knob values (a few minutes)")
    ap.add_argument("--scenes", default=",".join(SCENES), help="comma-separated: " + ",".join(SCENES))
    ap.add_argument("--out", default=os.path.join(BENCH, "results"))
    a = ap.parse_args(sys.argv[me + 1:])
    os.makedirs(a.out, exist_ok=True)
    line = machine_line(yade.config.version, O.numThreads)
    print("sweep: " + line.strip(), flush=True)
    with open(os.path.join(a.out, "sweep_machine.txt" if not a.quick else "sweep_machine_quick.txt"), "w") as f:
        f.write(line)
    tag = "_quick" if a.quick else ""
    t_all = time.time()
    for name in a.scenes.split(","):
        t0 = time.time()
        rows, qs, err_key, xlabel = SCENES[name](a.quick)
        for r in rows:
            r["scene"] = name
        bp._write_csv(os.path.join(a.out, f"sweep_{name}{tag}.csv"), rows)
        plot(os.path.join(a.out, f"sweep_{name}{tag}.png"), rows, err_key, f"{name}: wall time against error ({line.strip()})", xlabel)
        cols = ["impl", "knob", "value", "wall_s", "steps", "dt", "status"] + qs + [f"err_{q}_ref" for q in qs] + \
            [k for k in (f"err_{q}_analytic" for q in qs) if any(k in r for r in rows)] + [k for k in ("err_worst_analytic", "ref_convergence") if any(k in r for r in rows)]
        print_table(f"{name} ({time.time() - t0:.0f} s)", rows, cols)
    print(f"\nsweep: total {time.time() - t_all:.0f} s")


main()
