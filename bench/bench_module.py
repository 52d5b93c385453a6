# Benchmark: the damping module, yade-flex against the same module built from YADE's built-in classes
# (GPL-2.0-or-later).
#
#     yade-double -n -j1 -x bench/bench_module.py [--small] [--reps N] [--cache-dir DIR]
#
# One process, one YADE, one filled module:
#   1. ours: the filled yade-flex module (yadeflex.module.filled_module: loaded from the cache, or
#      built), the boulder of add_boulder, yf.engines(damping 0): the main job's scene
#      (scripts/damping_module.py) without its rolling resistance (the built-in's CundallStrack
#      has none: the same contact physics on both sides), recorded the same way (force =
#      m (a_z + g) from the boulder's velocity every 0.2 ms, penetration below the fill top,
#      end = rebound + 20%);
#   2. built-in: builtin_module.py rebuilds that module (same grains, nodes, legs, rings, lining,
#      masses, supports) with WireMat/WirePM, PFacet/GridNode/GridConnection/CohFrict, FrictMat
#      spheres and a Wall; re-settles it under gravity with local damping 0.7, then drops the same
#      boulder at the same speed with NewtonIntegrator damping 0.2 (the usual built-in setting), and
#      again with damping 0 from the same settled state;
#   3. timing: the state of each model 5 ms after first contact is kept (O.saveTmp); windows of
#      --window steps are timed alternately, ours and built-in, --reps times each (O.loadTmp, a
#      warm-up, then yadeflex.scene.step_until(inf, window): the steps in one C++ loop, no Python
#      between them, as the main job steps; O.timingEnabled off); the median is reported.
# Writes bench/results/module_compare[_small][_jN].csv (one row per model; _jN with N > 1 OpenMP threads), ..._timeseries.csv, a PNG of
# force-time and penetration-time, and prints a table.
import argparse
import csv
import json
import math
import os
import statistics
import sys
import time

BENCH = next((os.path.dirname(os.path.abspath(a)) for a in sys.argv if a.endswith("bench_module.py")), os.path.join(os.getcwd(), "bench"))
sys.path.insert(0, BENCH)
sys.path.insert(0, os.path.join(os.path.dirname(BENCH), "py"))

import yade  # noqa: E402
from yade import O  # noqa: E402
from yade.minieigenHP import Vector3  # noqa: E402

import yadeflex as yf  # noqa: E402
from yadeflex.constants import G  # noqa: E402
from yadeflex.module import ModuleParams, filled_module, add_boulder, fill_top, touches  # noqa: E402
import builtin_module as bm  # noqa: E402
from yadeflex.scene import step_until  # noqa: E402


def parse():
    me = next((k for k, a in enumerate(sys.argv) if a.endswith("bench_module.py")), 0)
    ap = argparse.ArgumentParser(prog="bench_module.py", description="Damping module: yade-flex against YADE's built-in classes.")
    ap.add_argument("--small", action="store_true", help="the reduced module of damping_module.py --small (0.4 x 0.3 m, 100 kg)")
    ap.add_argument("--reps", type=int, default=5, help="timed windows per model")
    ap.add_argument("--window", type=int, default=300, help="steps per timed window")
    ap.add_argument("--warmup", type=int, default=30, help="steps before each window")
    ap.add_argument("--timing-at", type=float, default=0.005, help="timed state: this long after first contact [s]")
    ap.add_argument("--cache-dir", default=os.path.join(os.path.expanduser("~"), ".cache", "yadeflex", "modules"),
                    help="filled-module cache (default: the main job's); a file that does not load with the installed plugin is rebuilt")
    ap.add_argument("--builtin-dt-factor", type=float, default=0.5, help="built-in O.dt = this x min sqrt(m/K)")
    ap.add_argument("--no-undamped", action="store_true", help="skip the built-in run with damping 0")
    ap.add_argument("--out", default=os.path.join(BENCH, "results"))
    a = ap.parse_args(sys.argv[me + 1:])
    bm.DT_FACTOR = a.builtin_dt_factor
    return a, ModuleParams.small() if a.small else ModuleParams()


def filled(p, cache_dir):
    """Cache file of the filled module of p, on O (yadeflex.module.filled_module: loaded, or built and
    saved when missing or unreadable by the installed plugin)."""
    t = time.time()
    _, f, cached = filled_module(p, cache_dir=cache_dir)
    if not cached:
        print(f"  filled module built in {time.time() - t:.0f} s: {f}")
    return f


def plugin_line():
    """The yade-flex plugin this process loaded (other worktrees reinstall it: results follow it)."""
    import hashlib
    f = os.path.join(yade.config.libDir, "libyadeflex.so")
    if not os.path.exists(f):
        f = "/usr/lib/x86_64-linux-gnu/yade-double/libyadeflex.so"
    try:
        with open(f, "rb") as fh:
            h = hashlib.sha256(fh.read()).hexdigest()[:12]
        return f"plugin {f}: sha256 {h}, modified {time.strftime('%Y-%m-%d %H:%M:%S', time.gmtime(os.path.getmtime(f)))} UTC"
    except OSError as e:
        return f"plugin: {e}"


def lining_triangles(facets):
    """Node-id triples of the lining's facets (yade-flex FlexFacet: node ids; YADE PFacet: node bodies)."""
    tris = []
    for f in facets:
        b = O.bodies[f]
        if b is None:
            continue
        ns = [b.shape.node1, b.shape.node2, b.shape.node3]
        tris.append(tuple(n if isinstance(n, int) else n.id for n in ns))
    return tris


def escaped(grains, lining_tris, mesh_nodes, axis=(0.0, 0.0)):
    """(grains whose centre lies outside the lining, outside the mesh too), by casting a horizontal
    ray from the module's axis through each grain's centre against the lining's triangles as they
    are now: a grain is outside when the ray meets the lining only nearer to the axis than its
    centre (a ray that meets no triangle, above the lining's top, counts as inside). Outside the
    mesh: outside the lining and farther from the axis than the mesh node nearest to it, + 5 mm
    (a chord between nodes sags 2-3 mm). (Until 2026-11-23 the lining test compared the centre
    with the nearest lining node's radius, which counted grains where the lining bulges between
    its nodes: 35 grains where a ray check of the VTK frames found none outside.)"""
    import numpy as np
    P = np.array([list(O.bodies[g].state.pos) for g in grains if O.bodies[g] is not None])
    if len(P) == 0 or not lining_tris:
        return (0, 0)
    nodes = sorted({k for t in lining_tris for k in t})
    X = np.array([list(O.bodies[n].state.pos) if O.bodies[n] is not None else [np.nan] * 3 for n in nodes])
    index = {n: k for k, n in enumerate(nodes)}
    T = np.array([[index[n] for n in t] for t in lining_tris])
    A, B, C = X[T[:, 0]], X[T[:, 1]], X[T[:, 2]]
    Q = P - np.array([axis[0], axis[1], 0.0])
    r = np.hypot(Q[:, 0], Q[:, 1])
    r_lin_min = np.nanmin(np.hypot(X[:, 0] - axis[0], X[:, 1] - axis[1]))
    cand = np.nonzero(r > 0.8 * r_lin_min)[0]  # grains well inside cannot be out
    outside = np.zeros(len(P), dtype=bool)
    E1, E2 = B - A, C - A
    for k0 in range(0, len(cand), 256):
        k = cand[k0:k0 + 256]
        O_ = np.stack([np.full(len(k), axis[0]), np.full(len(k), axis[1]), P[k, 2]], axis=1)  # ray origins on the axis
        U = np.stack([Q[k, 0] / r[k], Q[k, 1] / r[k], np.zeros(len(k))], axis=1)  # horizontal, through the centre
        # Moller-Trumbore, grains x triangles
        h = np.cross(U[:, None, :], E2[None, :, :])
        det = np.einsum("tj,gtj->gt", E1, h)
        ok = np.abs(det) > 1e-15
        inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
        s_ = O_[:, None, :] - A[None, :, :]
        u = np.einsum("gtj,gtj->gt", s_, h) * inv
        q = np.cross(s_, E1[None, :, :])
        v = np.einsum("gj,gtj->gt", U, q) * inv
        t = np.einsum("tj,gtj->gt", E2, q) * inv
        hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
        any_hit = hit.any(axis=1)
        t_far = np.where(hit, t, -np.inf).max(axis=1)
        outside[k] = any_hit & (t_far < r[k])
    N = np.array([list(O.bodies[n].state.pos) for n in mesh_nodes if O.bodies[n] is not None])
    out_mesh = 0
    if len(N) and outside.any():
        Po = P[outside]
        near = np.argmin(((Po[:, None, :] - N[None, :, :])**2).sum(axis=2), axis=1)
        out_mesh = int(np.sum(np.hypot(Po[:, 0] - axis[0], Po[:, 1] - axis[1]) > np.hypot(N[near, 0] - axis[0], N[near, 1] - axis[1]) + 0.005))
    return int(outside.sum()), out_mesh


def pfacet_overlap():
    """Deepest overlap [m] of the current real contacts on PFacets (ScGridCoGeom), and their number."""
    d, n = 0.0, 0
    for i in O.interactions:
        g = i.geom
        if type(g).__name__ == "ScGridCoGeom" and (isinstance(O.bodies[i.id1].shape, bm.PFacet) or isinstance(O.bodies[i.id2].shape, bm.PFacet)):
            d, n = max(d, g.penetrationDepth), n + 1
    return d, n


def run_model(label, bid, size, top0, grains, lining_tris, mesh_nodes, t_max=0.3, record_every=2e-4, timing_at=0.005, dt_update=None, ruptured=None,
                diag=None):
    """Runs the impact from the current scene of either model, recording the boulder as the main job
    does (force m (a_z + g) every record_every, penetration below top0, end at the rebound + 20%).
    One loop for both models, so that they are recorded and timed alike (yadeflex.module.impact.run_impact
    runs the yade-flex scene only). Returns a dict: rows (time series), summary numbers, energy at
    the end. O.saveTmp(label) at timing_at after contact."""
    boulder = O.bodies[bid]
    mass = boulder.state.mass
    O.trackEnergy = True
    O.energy.clear()
    O.step()
    start = O.time
    total0 = O.energy.total()
    ek0 = O.energy["kinetic"]
    e0 = {k: O.energy[k] for k in O.energy.keys()}  # the settled module already stores elastic energy
    rows = []
    v_prev, t_prev = Vector3(boulder.state.vel), O.time
    next_rec = O.time + record_every
    t_contact = rebound = None
    t_end = start + t_max
    saved = False
    status = "ok"
    steps0, wall0 = O.iter, time.time()
    k = 0
    diag_max = 0.0
    esc = (0, 0)
    v_in, rest = abs(boulder.state.vel[2]), None  # a damped boulder may stop without rebounding: end 5 ms after it is at rest
    while O.time < t_end:
        O.step()
        k += 1
        if dt_update and k % dt_update == 0:
            bm.set_dt(only_decrease=True)
        if O.time < next_rec:
            continue
        next_rec += record_every
        st = boulder.state
        ek = O.energy["kinetic"]
        if not all(math.isfinite(x) for x in st.pos) or not math.isfinite(O.energy.total()) or ek > 20 * (ek0 + 1.0):
            status = f"unstable at t = {1e3 * (O.time - start):.1f} ms (kinetic {ek:.3g} J)"
            print(f"  {label}: {status}; stopping", flush=True)
            break
        acc = (st.vel - v_prev) / (O.time - t_prev)
        v_prev, t_prev = Vector3(st.vel), O.time
        f = mass * (acc[2] + G)
        bottom = st.pos[2] - 0.5 * size
        if t_contact is None and touches(bid):
            t_contact = O.time
            t_end = O.time + t_max
        if t_contact is not None and not saved and O.time >= t_contact + timing_at:
            O.saveTmp(label)
            saved = True
        if t_contact is not None and rebound is None and st.vel[2] > 0:
            rebound = O.time
            t_end = min(t_end, O.time + max(0.2 * (O.time - t_contact), 0.01))
        if t_contact is not None and rebound is None:
            if abs(st.vel[2]) > 0.02 * v_in:
                rest = None
            elif rest is None:
                rest = O.time
            elif O.time - rest > 0.005:
                rebound = rest  # at rest: the impact ends here
                break
        rows.append(dict(model=label, t=O.time, boulder_vz=st.vel[2], impact_force=f,
                         penetration=max(0.0, top0 - bottom), kinetic=ek, nonviscDamp=O.energy["nonviscDamp"] if "nonviscDamp" in O.energy.keys() else 0.0))
        if diag and len(rows) % 10 == 0:
            diag_max = max(diag_max, diag()[0])
        if len(rows) % 100 == 0:
            esc = escaped(grains, lining_tris, mesh_nodes)  # kept: after an instability the end state is NaN
            print(f"  {label}: t = {1e3 * (O.time - start):6.1f} ms, v = {st.vel[2]:+.2f} m/s, force {f / 1e3:7.1f} kN, "
                  f"{time.time() - wall0:.0f} s", flush=True)
    wall = time.time() - wall0
    steps = O.iter - steps0
    for r in rows:  # time from the first contact
        r["t"] -= t_contact if t_contact is not None else start
    en = {k: O.energy[k] - (e0.get(k, 0.0) if k != "kinetic" else 0.0) for k in O.energy.keys()}  # changes since the start
    w_in = ek0 - en.get("gravWork", 0.0)  # kinetic energy at the start + work of gravity (gravWork < 0 when it works)
    after = [r for r in rows if r["t"] >= 0]
    if status == "ok":
        esc = escaped(grains, lining_tris, mesh_nodes)
    return dict(label=label, rows=rows, energy=en, total0=total0, residual=O.energy.total() - total0, w_in=w_in, ek0=ek0, status=status,
                peak_force=max((r["impact_force"] for r in after), default=float("nan")),
                penetration_max=max((r["penetration"] for r in after), default=float("nan")),
                duration=((rebound or O.time) - t_contact) if t_contact is not None else float("nan"),
                rebound_speed=boulder.state.vel[2], dt=O.dt, steps=steps, wall_s=wall, through_lining=esc[0], outside_mesh=esc[1],
                ruptured=ruptured() if ruptured else None, timed_state=saved, pfacet_overlap_max=diag_max if diag else float("nan"))


def shares(res, builtin):
    """Where the energy put in went, as fractions of w_in (kinetic energy at the start + work of gravity):
    each term's change since the start, the kinetic energy at the end, and what no law booked (for ours
    minus the balance residual; for the built-in the WirePM and CohFrict-bond energies, and any energy
    the model created)."""
    e, w = res["energy"], res["w_in"]
    s = dict(kinetic=e.get("kinetic", 0.0), numerical_damping=e.get("nonviscDamp", 0.0))
    if builtin:
        s["friction"] = e.get("plastDissip", 0.0) + e.get("shearDissip", 0.0)
        s["elastic_booked"] = e.get("elastPotential", 0.0)
        s["plastic_wire"] = s["rupture"] = float("nan")  # WirePM books nothing
        s["unbooked"] = w - sum(v for k, v in s.items() if math.isfinite(v))
    else:
        s["friction"] = e.get("flexFriction", 0.0) + e.get("plastDissip", 0.0)
        s["elastic_booked"] = sum(e.get(k, 0.0) for k in ("flexBondElastic", "flexContactElastic", "flexMembraneElastic", "elastPotential"))
        s["plastic_wire"] = e.get("flexBondPlastic", 0.0)
        s["rupture"] = e.get("flexRupture", 0.0)
        s["unbooked"] = w - sum(v for k, v in s.items() if math.isfinite(v))  # = minus the balance residual
    return {k: v / w for k, v in s.items()}


def time_windows(labels, reps, window, warmup):
    """Median us/step of each saved state, timed alternately (O.loadTmp, warm-up, then the window
    by yadeflex.scene.step_until: the steps in one C++ loop in this thread, as the main job steps)."""
    out = {lb: [] for lb in labels}
    dts = {}
    O.timingEnabled = False
    for _ in range(reps):
        for lb in labels:
            O.loadTmp(lb)
            for _ in range(warmup):
                O.step()
            t0 = time.perf_counter()
            step_until(math.inf, window)
            out[lb].append(1e6 * (time.perf_counter() - t0) / window)
            dts[lb] = O.dt
    res = {lb: (statistics.median(v), v, dts[lb]) for lb, v in out.items()}
    return res


def breakdown(labels, window, warmup):
    """One more window of each saved state with O.timingEnabled (run as the timed windows are):
    us/step per engine, and the
    interactions (real / all, all = with the collider's potential pairs)."""
    out = {}
    for lb in labels:
        O.loadTmp(lb)
        for _ in range(warmup):
            O.step()
        for e in O.engines:
            e.execTime = 0
        O.timingEnabled = True
        step_until(math.inf, window)
        O.timingEnabled = False
        out[lb] = dict(engines={(e.label or type(e).__name__): round(e.execTime * 1e-3 / window, 1) for e in O.engines},
                       interactions_real=O.interactions.countReal(), interactions_all=len(O.interactions.all(False)), bodies=len(O.bodies))
    return out


def main():
    a, p = parse()
    tag = ("_small" if a.small else "") + (f"_j{O.numThreads}" if O.numThreads > 1 else "")  # -j2: its own files
    os.makedirs(a.out, exist_ok=True)
    t_all = time.time()
    print(f"bench_module: {p.diameter} m x {p.height} m module, {p.boulder_mass} kg {p.boulder_shape} at {p.impact_speed():.2f} m/s; "
          f"YADE {yade.config.version}, {O.numThreads} thread(s), {time.strftime('%Y-%m-%d %H:%M', time.gmtime())} UTC, "
          f"load average {os.getloadavg()[0]:.2f}")
    print("  " + plugin_line())
    cache = filled(p, a.cache_dir)
    # ---- ours
    geo = bm.extract(cache)  # loads the cache on O
    ids = json.loads(O.tags["yadeflex_module"])
    top0 = fill_top(ids)
    bid = add_boulder(p, ids)
    O.engines = yf.engines(damping=p.damping, timestep_safety=p.timestep_safety)
    el = [e for e in O.engines if e.label == "flexElements"][0]
    print(f"ours: {len(ids['grains'])} grains, {len(ids['mesh_cylinders'])} wire legs, {len(ids['ring_top']) + len(ids['ring_bottom'])} ring "
          f"segments, {len(ids['lining'])} lining facets; damping {p.damping}", flush=True)
    results = [run_model("yade-flex", bid, p.boulder_size(), top0, ids["grains"], lining_triangles(ids["lining"]), ids["mesh_nodes"], timing_at=a.timing_at,
                         ruptured=lambda: el.nRuptured)]
    # ---- built-in
    info = bm.build(geo)
    print(f"built-in: {len(info['grains'])} grains, {info['links']} WirePM links ({info['ring_links']} ring), {len(info['lining_facets'])} PFacets, "
          f"{len(info['lining_conns'])} GridConnections; lining bar modulus {info['lining_young_bar']:.3g} Pa; dt {O.dt:.3g} s", flush=True)
    t0 = time.time()
    t_settle, ke = bm.settle(info, progress=lambda t, ke: None)
    print(f"  settled {1e3 * t_settle:.0f} ms (damping 0.7) in {time.time() - t0:.0f} s: grain kinetic energy {ke:.3g} J, dt {O.dt:.3g} s", flush=True)
    O.saveTmp("builtin_settled")
    n_links0 = info["links"]

    def broken():
        return n_links0 - sum(1 for i in O.interactions if isinstance(i.phys, bm.WirePhys) and i.phys.isLinked)

    for damping in ([0.2] if a.no_undamped else [0.2, 0.0]):
        O.loadTmp("builtin_settled")
        for e in O.engines:
            if isinstance(e, bm.NewtonIntegrator):
                e.damping = damping
        top_b = bm.fill_top(info)
        b = bm.add_boulder(info, p)
        label = f"built-in d={damping}"
        results.append(run_model(label, b, p.boulder_size(), top_b, info["grains"], lining_triangles(info["lining_facets"]), info["mesh_nodes"], timing_at=a.timing_at, dt_update=200,
                                 ruptured=broken, diag=pfacet_overlap))
        results[-1]["top0"] = top_b
    results[0]["top0"] = top0
    # ---- timing, interleaved
    labels = [r["label"] for r in results if r["timed_state"] and r["label"] in ("yade-flex", "built-in d=0.2")]
    tw = time_windows(labels, a.reps, a.window, a.warmup) if len(labels) == 2 else {}
    ours_us = tw.get("yade-flex", (float("nan"),))[0]
    bd = breakdown(labels, a.window, a.warmup) if len(labels) == 2 else {}
    for lb, d in bd.items():
        print(f"  {lb}: {d['bodies']} bodies, {d['interactions_real']} real / {d['interactions_all']} interactions; us/step by engine: "
              + ", ".join(f"{k} {v}" for k, v in d["engines"].items()))
    # ---- outputs
    grains_of = {r["label"]: (ids["grains"] if r["label"] == "yade-flex" else info["grains"]) for r in results}
    rows = []
    for r in results:
        builtin = r["label"] != "yade-flex"
        s = shares(r, builtin)
        us, all_us, dt = tw.get(r["label"], (float("nan"), [], r["dt"]))
        rows.append(dict(model=r["label"], damping=(0.0 if not builtin else float(r["label"].split("=")[1])), status=r["status"], dt_s=r["dt"],
                         us_per_step=us, us_per_step_all=" ".join(f"{x:.0f}" for x in all_us), speedup_per_step=(us / ours_us if builtin else 1.0),
                         s_per_simulated_s=us * 1e-6 / dt if us == us else float("nan"), dt_timed_s=dt, fill_top_m=r["top0"],
                         peak_force_kN=r["peak_force"] / 1e3, penetration_max_mm=1e3 * r["penetration_max"], impact_duration_ms=1e3 * r["duration"],
                         boulder_vz_end=r["rebound_speed"], energy_in_J=r["w_in"], broken_wires=r["ruptured"], grains_through_lining=r["through_lining"],
                         grains_outside_mesh=r["outside_mesh"], grains=len(grains_of[r["label"]]), pfacet_overlap_max_mm=1e3 * r["pfacet_overlap_max"],
                         interactions_real=bd.get(r["label"], {}).get("interactions_real"), interactions_all=bd.get(r["label"], {}).get("interactions_all"),
                         engines_us=json.dumps(bd.get(r["label"], {}).get("engines", {})),
                         booked_over_input=sum(v for k, v in s.items() if k != "unbooked" and math.isfinite(v)), run_steps=r["steps"], run_wall_s=r["wall_s"],
                         **{f"share_{k}": v for k, v in s.items()}, energy_end=json.dumps({k: round(v, 3) for k, v in r["energy"].items()})))
    with open(os.path.join(a.out, f"module_compare{tag}.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(a.out, f"module_compare{tag}_timeseries.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(results[0]["rows"][0].keys()))
        w.writeheader()
        for r in results:
            w.writerows(r["rows"])
    _plot(results, os.path.join(a.out, f"module_compare{tag}.png"), p)
    print(f"\n{'model':16s} {'us/step':>8s} {'x ours':>7s} {'s/sim s':>7s} {'dt [s]':>9s} {'peak kN':>8s} {'pen mm':>7s} {'dur ms':>7s} {'E in J':>8s} "
          f"{'damp%':>6s} {'fric%':>6s} {'plast%':>6s} {'rupt%':>6s} {'elast%':>6s} {'kin%':>5s} {'unbook%':>7s} {'broken':>6s} {'thru':>5s} {'out':>4s}")
    for r in rows:
        print(f"{r['model']:16s} {r['us_per_step']:8.0f} {r['speedup_per_step']:7.2f} {r['s_per_simulated_s']:7.0f} {r['dt_s']:9.3g} {r['peak_force_kN']:8.1f} "
              f"{r['penetration_max_mm']:7.0f} {r['impact_duration_ms']:7.1f} {r['energy_in_J']:8.0f} {100 * r['share_numerical_damping']:6.1f} "
              f"{100 * r['share_friction']:6.1f} {100 * r['share_plastic_wire']:6.1f} {100 * r['share_rupture']:6.1f} "
              f"{100 * r['share_elastic_booked']:6.1f} {100 * r['share_kinetic']:5.1f} {100 * r['share_unbooked']:7.1f} {r['broken_wires']!s:>6s} "
              f"{r['grains_through_lining']:5d} {r['grains_outside_mesh']:4d}   {r['status']}")
    print(f"(us/step: median of {a.reps} windows of {a.window} steps {1e3 * a.timing_at:.0f} ms after contact, interleaved; total {time.time() - t_all:.0f} s)")


def _plot(results, path, p):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    for r in results:
        t = [1e3 * x["t"] for x in r["rows"] if x["t"] >= -0.002]
        ax[0].plot(t, [x["impact_force"] / 1e3 for x in r["rows"] if x["t"] >= -0.002], label=r["label"])
        ax[1].plot(t, [1e3 * x["penetration"] for x in r["rows"] if x["t"] >= -0.002], label=r["label"])
    ax[0].set(xlabel="t after first contact [ms]", ylabel="force on the boulder m (a + g) [kN]",
              title=f"{p.boulder_mass:.0f} kg {p.boulder_shape} at {p.impact_speed():.2f} m/s on a {p.diameter} m module")
    ax[1].set(xlabel="t after first contact [ms]", ylabel="penetration below the fill top [mm]", title="penetration")
    for x in ax:
        x.legend()
        x.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
