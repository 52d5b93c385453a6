"""Would the gravel break under the boulder? The grains' contact forces in the default module's
impacts against the point-load failure load of rock (yadeflex.crushing) (GPL-2.0-or-later).

    yade-double -n -j1 -x validation/grain_crushing.py OUT [--workers 2] [--cases a,b] [--to validation/studies/grain_crushing]

The cases are the base and seed2 runs of validation/studies/fill_factors: the main job's module
and cube, 800 kg from 1, 2 and 4 m, 400 and 1600 kg from 2 m (the cube's size kept, its density
scaled), on the main job's fill and on another fill of the same preset (seed 2).
Each case runs in its own yade-double process (--workers at a time, one thread each): the main
job's impact from the cached filled module (yadeflex.module.impact_start) until the boulder stops
moving down (its deepest point), reading every grain's contact forces every SAMPLE_STEPS steps,
and writes OUT/cases/NAME.json. Then this script writes OUT/summary.csv, OUT/crushing.png,
OUT/crushing_section.png (sections through the fill at the deepest point) and the table between
the markers of OUT/README.md (--to DIR: the same files in DIR too).

Strengths screened: Is(50) = 1.5, 4 and 10 MPa, the bounds of Selby's moderately strong and
strong rock (yadeflex.crushing). The same ten runs again with grains that crush (the model of
yadeflex.engines' crushing_is50: a contact yields at the smaller grain's failure load) at 4 and
1.5 MPa give the exponents of the peak force with crushing (OUT/model.csv, OUT/crushing_model.png
and the second table)."""
import csv
import json
import math
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(next((a for a in sys.argv if a.endswith("grain_crushing.py")), __file__)))
REPO = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(REPO, "py"))
sys.path.insert(0, HERE)
import case_processes  # noqa: E402
from readme_table import replace_marked  # noqa: E402

G = 9.81
MARK = ("<!-- table:grain_crushing -->", "<!-- /table:grain_crushing -->")
MARK_MODEL = ("<!-- table:grain_crushing_model -->", "<!-- /table:grain_crushing_model -->")
STRENGTHS = (1.5e6, 4e6, 10e6)  # [Pa] Is(50)
SAMPLE_STEPS = 10  # steps between two readings of the contacts (the time step is about 9 us)
MAX_TIME = 0.3  # [s] after the first contact: the longest a case runs (then "stopped" is False: the boulder still moved down)
CRUSHING = (4e6, 1.5e6)  # [Pa] Is(50) of the crushing model's runs (ModuleParams.grain_crushing_is50)
RUNS = dict(H1=(800.0, 1.0), H2=(800.0, 2.0), H4=(800.0, 4.0), m400=(400.0, 2.0), m1600=(1600.0, 2.0))  # (mass [kg], drop height [m])
# (mass, drop height, the fill's seed, Is(50) of the crushing model, 0: none): each run on the main
# job's fill and on a second fill of the same preset (seed 2: the scatter of every figure), with
# elastic grains (the screen) and with grains that crush
CASES = {f"{k}{'' if seed == 1 else f'_s{seed}'}{'' if not c else f'_c{c / 1e6:g}'}": (m, h, seed, c)
         for c in (0.0,) + CRUSHING for seed in (1, 2) for k, (m, h) in RUNS.items()}


def run_case(name, out):
    """One case in this process (under YADE): OUT/cases/NAME.json."""
    import numpy as np
    from yade import O
    from yadeflex.crushing import PeakGrainForces, scene_contacts
    from yadeflex.module import ModuleParams, fill_top, impact_start
    from yadeflex.scene import step_until
    mass, height, seed, crush = CASES[name]
    base = ModuleParams()
    # the same cube as the main job's (its size kept, the density scaled with the mass)
    p = ModuleParams(boulder_mass=mass, drop_height=height, boulder_density=base.boulder_density * mass / base.boulder_mass, seed=seed,
                     grain_crushing_is50=crush or None)
    t_wall = time.time()
    ids, bid, _ = impact_start(p)
    O.trackEnergy = True  # (from the first contact: the crushing model's dissipation)
    O.energy.clear()
    grains = list(ids["grains"])
    d = [2 * O.bodies[g].shape.radius for g in grains]
    screen = PeakGrainForces(grains, d, STRENGTHS)
    boulder = O.bodies[bid]
    size = p.boulder_size()
    top0 = fill_top(ids)
    t0 = O.time
    series = []
    v_prev, t_prev = boulder.state.vel[2], O.time
    while True:
        step_until(math.inf, SAMPLE_STEPS)
        pen = max(0.0, top0 - (boulder.state.pos[2] - 0.5 * size))
        screen.update(*scene_contacts(), pen)
        vz = boulder.state.vel[2]
        force = mass * ((vz - v_prev) / (O.time - t_prev) + G)
        v_prev, t_prev = vz, O.time
        series.append(dict(t=O.time - t0, penetration=pen, force=force, grain_force_max=float(screen.peak.max()),
                           broken=[int(np.count_nonzero(screen.broken(k))) for k in range(len(STRENGTHS))]))
        if vz >= 0 or O.time - t0 > MAX_TIME:
            break
    pos = np.array([tuple(O.bodies[g].state.pos) for g in grains])
    bz = boulder.state.pos[2] - 0.5 * size  # the cube's face at the deepest point
    under = (np.abs(pos[:, 0] - boulder.state.pos[0]) < 0.5 * size) & (np.abs(pos[:, 1] - boulder.state.pos[1]) < 0.5 * size)
    broken = []
    for k, s in enumerate(STRENGTHS):
        m = screen.broken(k)
        broken.append(dict(is50=s, count=int(m.sum()), under_boulder=int((m & under).sum()), load_ratio_max=float(np.max(screen.peak / screen.load[k])),
                           first_penetration=float(np.nanmin(screen.first[k])) if m.any() else None,
                           depth_below_boulder=[float(x) for x in (bz - pos[m, 2])],
                           penetrations=[float(x) for x in screen.first[k][m]]))
    r = dict(name=name, mass=mass, height=height, seed=seed, crushing_is50=crush, impact_energy=0.5 * mass * p.impact_speed() ** 2,
             crushing_energy=O.energy["flexCrushing"] if "flexCrushing" in O.energy.keys() else 0.0, grains=len(grains), deepest=dict(penetration=series[-1]["penetration"], force=series[-1]["force"]),
             stopped=bool(boulder.state.vel[2] >= 0), peak_force=max(x["force"] for x in series),
             grain_force_max=float(screen.peak.max()), grain_force_p99=float(np.percentile(screen.peak, 99)),
             broken=broken, series=series, wall_seconds=time.time() - t_wall, sample_steps=SAMPLE_STEPS,
             # every grain at the deepest point (the section plot): centre [m], diameter [m], largest contact force [N]
             grain_state=dict(pos=np.round(pos, 5).tolist(), d=np.round(np.asarray(d), 5).tolist(), peak=np.round(screen.peak, 1).tolist()),
             boulder=dict(center=list(boulder.state.pos), size=size))
    os.makedirs(os.path.join(out, "cases"), exist_ok=True)
    with open(os.path.join(out, "cases", name + ".json"), "w") as f:
        json.dump(r, f, indent=1)
    print(f"{name}: done in {r['wall_seconds']:.0f} s", flush=True)


def load(out):
    return case_processes.load(out, CASES)


def _mpa(s):
    return f"{s / 1e6:g} MPa"


def rows(res):
    """One summary row per case."""
    out = []
    for name, r in res.items():
        row = dict(case=name, mass_kg=r["mass"], height_m=r["height"], fill_seed=r["seed"], crushing_is50_MPa=r["crushing_is50"] / 1e6,
                   crushing_energy_share=r["crushing_energy"] / r["impact_energy"], peak_force_kN=r["peak_force"] / 1e3,
                   deepest_penetration_mm=1e3 * r["deepest"]["penetration"], deepest_force_kN=r["deepest"]["force"] / 1e3,
                   stopped=r["stopped"], grain_force_max_kN=r["grain_force_max"] / 1e3, grain_force_p99_kN=r["grain_force_p99"] / 1e3)
        # the screen's counts are for elastic grains: with crushing on, a capped contact sits at its
        # failure load to the last bit, and whether it counts would be round-off
        for b in (r["broken"] if r["crushing_is50"] == 0 else []):
            tag = f"{b['is50'] / 1e6:g}MPa"
            row[f"broken_{tag}"] = b["count"]
            row[f"broken_under_boulder_{tag}"] = b["under_boulder"]
            row[f"load_ratio_max_{tag}"] = b["load_ratio_max"]
            row[f"broken_second_half_{tag}"] = sum(1 for x in b["penetrations"] if x >= 0.5 * r["deepest"]["penetration"])
            row[f"first_break_penetration_mm_{tag}"] = None if b["first_penetration"] is None else 1e3 * b["first_penetration"]
            row[f"median_depth_below_boulder_mm_{tag}"] = (1e3 * sorted(b["depth_below_boulder"])[len(b["depth_below_boulder"]) // 2]
                                                           if b["depth_below_boulder"] else None)
            row[f"max_depth_below_boulder_mm_{tag}"] = 1e3 * max(b["depth_below_boulder"]) if b["depth_below_boulder"] else None
        out.append(row)
    return out


def _f(v, fmt="{:.0f}"):
    return "-" if v is None or (isinstance(v, float) and not math.isfinite(v)) else fmt.format(v)


def table(rs):
    head = ["case", "mass [kg]", "drop height [m]", "fill seed", "peak force [kN]", "penetration at the deepest point [mm]",
            "largest grain contact force [kN] (99th percentile of the grains')"]
    head += [f"grains at their failure load, Is(50) = {_mpa(s)}: all (under the boulder, in the second half of the penetration)" for s in STRENGTHS]
    head += [f"penetration at the first one, {_mpa(s)} [mm]" for s in STRENGTHS]
    head += [f"largest grain force / the grain's failure load at {_mpa(STRENGTHS[-1])}"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in (r for r in rs if r["crushing_is50_MPa"] == 0):
        cells = [r["case"], _f(r["mass_kg"]), _f(r["height_m"], "{:g}"), str(r["fill_seed"]), _f(r["peak_force_kN"]), _f(r["deepest_penetration_mm"]),
                 f"{r['grain_force_max_kN']:.1f} ({r['grain_force_p99_kN']:.1f})"]
        for s in STRENGTHS:
            t = f"{s / 1e6:g}MPa"
            cells.append(f"{r[f'broken_{t}']} ({r[f'broken_under_boulder_{t}']}, {r[f'broken_second_half_{t}']})")
        for s in STRENGTHS:
            cells.append(_f(r[f"first_break_penetration_mm_{s / 1e6:g}MPa"]))
        cells.append(f"{r[f'load_ratio_max_{STRENGTHS[-1] / 1e6:g}MPa']:.2f}")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def plot(res, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axs = plt.subplots(1, 3, figsize=(16, 4.6))
    colors = {}
    for r in (r for r in res.values() if r["crushing_is50"] == 0):
        key = (r["mass"], r["height"])
        color = colors.setdefault(key, f"C{len(colors)}")
        style = "-" if r["seed"] == 1 else "--"
        pen = [1e3 * x["penetration"] for x in r["series"]]
        axs[0].plot(pen, [x["force"] / 1e3 for x in r["series"]], style, color=color, lw=1,
                    label=f"{r['mass']:g} kg, {r['height']:g} m, fill {r['seed']}")
        for a, k in zip(axs[1:], (0, 1)):
            a.plot(pen, [x["broken"][k] for x in r["series"]], style, color=color, lw=1)
    axs[0].set(xlabel="penetration [mm]", ylabel="force on the boulder [kN]", title="force on the boulder, to its deepest point")
    for a, k in zip(axs[1:], (0, 1)):
        a.set(xlabel="penetration [mm]", ylabel="grains at their failure load",
              title=f"grains whose largest contact force reached\ntheir point-load failure load, Is(50) = {_mpa(STRENGTHS[k])}")
    axs[0].legend(fontsize=7, ncol=2)
    for a in axs:
        a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def _fit(points):
    from yadeflex.module.cushion import power_fit
    points = [(x, y) for x, y in points if y is not None and math.isfinite(y)]
    return power_fit(*zip(*points))[1] if len(points) >= 2 else None


def model_rows(res):
    """One row per crushing strength (0: elastic grains) and fill: the peak forces and
    penetrations over the five runs, their exponents, and the energy the crushing took."""
    out = []
    for crush in (0.0,) + CRUSHING:
        for seed in (1, 2):
            runs = {k: next((r for r in res.values() if (r["mass"], r["height"], r["seed"], r["crushing_is50"]) == (m, h, seed, crush)), None)
                    for k, (m, h) in RUNS.items()}
            get = lambda k, f: f(runs[k]) if runs[k] else None  # noqa: E731
            peak = {k: get(k, lambda r: r["peak_force"] / 1e3) for k in RUNS}
            pen = {k: get(k, lambda r: 1e3 * r["deepest"]["penetration"]) for k in RUNS}
            out.append(dict(crushing_is50_MPa=crush / 1e6, fill_seed=seed, runs=sum(1 for r in runs.values() if r),
                            **{f"peak_kN_{k}": v for k, v in peak.items()}, **{f"penetration_mm_{k}": v for k, v in pen.items()},
                            peak_height_exp=_fit([(RUNS[k][1], peak[k]) for k in ("H1", "H2", "H4")]),
                            peak_mass_exp=_fit([(RUNS[k][0], peak[k]) for k in ("m400", "H2", "m1600")]),
                            peak_mass_exp_800_1600=_fit([(RUNS[k][0], peak[k]) for k in ("H2", "m1600")]),
                            penetration_height_exp=_fit([(RUNS[k][1], pen[k]) for k in ("H1", "H2", "H4")]),
                            crushing_energy_share_H2=get("H2", lambda r: r["crushing_energy"] / r["impact_energy"]),
                            crushing_energy_share_m1600=get("m1600", lambda r: r["crushing_energy"] / r["impact_energy"])))
    return out


def model_table(ms):
    head = ["grains' rock Is(50)", "fill seed", "runs", "peak [kN] H = 1 / 2 / 4 m", "peak [kN] m = 400 / 1600 kg",
            "penetration [mm] H = 1 / 2 / 4 m", "penetration [mm] m = 400 / 1600 kg", "peak ~ H^b", "peak ~ m^b (400-1600 kg)",
            "peak ~ m^b (800-1600 kg)", "penetration ~ H^b", "energy to crushing, 800 / 1600 kg from 2 m [% of the impact energy]"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for m in ms:
        exp = lambda k: _f(m[k], "{:.2f}")  # noqa: E731
        share = lambda k: _f(None if m[k] is None else 100 * m[k], "{:.1f}")  # noqa: E731
        lines.append("| " + " | ".join([
            "elastic (no crushing)" if m["crushing_is50_MPa"] == 0 else f"{m['crushing_is50_MPa']:g} MPa", str(m["fill_seed"]), f"{m['runs']}/5",
            " / ".join(_f(m[f"peak_kN_{k}"]) for k in ("H1", "H2", "H4")), " / ".join(_f(m[f"peak_kN_{k}"]) for k in ("m400", "m1600")),
            " / ".join(_f(m[f"penetration_mm_{k}"]) for k in ("H1", "H2", "H4")), " / ".join(_f(m[f"penetration_mm_{k}"]) for k in ("m400", "m1600")),
            exp("peak_height_exp"), exp("peak_mass_exp"), exp("peak_mass_exp_800_1600"), exp("penetration_height_exp"),
            f"{share('crushing_energy_share_H2')} / {share('crushing_energy_share_m1600')}"]) + " |")
    return "\n".join(lines)


def model_plot(res, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axs = plt.subplots(1, 3, figsize=(16, 4.6))
    for k, crush in enumerate((0.0,) + CRUSHING):
        label = "elastic grains" if crush == 0 else f"crushing, Is(50) = {_mpa(crush)}"
        for a, key in zip(axs[:2], ("m400", "m1600")):
            m, h = RUNS[key]
            r = next((r for r in res.values() if (r["mass"], r["height"], r["seed"], r["crushing_is50"]) == (m, h, 1, crush)), None)
            if r:
                a.plot([1e3 * x["penetration"] for x in r["series"]], [x["force"] / 1e3 for x in r["series"]], color=f"C{k}", lw=1, label=label)
                a.set(title=f"{m:g} kg from {h:g} m (fill 1)")
        for seed, style in ((1, "o-"), (2, "s--")):
            pts = sorted((r["mass"], r["peak_force"] / 1e3) for r in res.values()
                         if r["height"] == 2.0 and r["seed"] == seed and r["crushing_is50"] == crush)
            if pts:
                axs[2].plot(*zip(*pts), style, color=f"C{k}", lw=1, label=f"{label}, fill {seed}")
    for a in axs[:2]:
        a.set(xlabel="penetration [mm]", ylabel="force on the boulder [kN]")
    axs[2].set(xscale="log", yscale="log", xlabel="boulder mass [kg] (constant cube size, 2 m)", ylabel="peak force [kN]",
               title="peak force against the mass")
    for a in axs:
        a.grid(alpha=0.3, which="both")
        a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


SECTION_CASES = ("H1", "m1600")  # elastic runs drawn in the section plot
SECTION_SLAB = 0.03  # [m] grains whose centre is within this distance of the plane y = the boulder's y (about one grain)


def section_plot(res, path, strength=1.5e6):
    """Vertical sections through the boulder's centre at its deepest point (grains within
    SECTION_SLAB of the plane), each grain coloured by its largest contact force over its
    point-load failure load at `strength`: 1 and more, it would have broken."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from matplotlib.patches import Circle, Rectangle
    from yadeflex.crushing import failure_load
    cases = [res[k] for k in SECTION_CASES if k in res and "grain_state" in res[k]]
    if not cases:
        return
    fig, axs = plt.subplots(1, len(cases), figsize=(6.0 * len(cases) + 1.5, 4.4), squeeze=False, layout="constrained")
    cmap = plt.get_cmap("viridis").copy()
    cmap.set_over("red")
    for a, r in zip(axs[0], cases):
        g, b = r["grain_state"], r["boulder"]
        pos, d, peak = np.array(g["pos"]), np.array(g["d"]), np.array(g["peak"])
        near = np.abs(pos[:, 1] - b["center"][1]) < SECTION_SLAB
        ratio = peak[near] / failure_load(d[near], strength)
        for (x, z), dia, q in zip(pos[near][:, [0, 2]], d[near], ratio):
            a.add_patch(Circle((x, z), 0.5 * dia, color=cmap(q if q < 1 else 2.0), lw=0))  # (past 1: the colour map's "over", red)
        half = 0.5 * b["size"]
        a.add_patch(Rectangle((b["center"][0] - half, b["center"][2] - half), b["size"], b["size"], fill=False, ec="magenta", lw=1.5))
        broken = int(np.count_nonzero(peak / failure_load(d, strength) >= 1))
        a.set(xlim=(-0.6, 0.6), ylim=(-0.02, 0.7), aspect="equal", xlabel="x [m]", ylabel="z [m]",
              title=f"{r['mass']:g} kg from {r['height']:g} m, at the deepest point:\n{broken} of {len(d)} grains reached their failure load (red)")
    sm = plt.cm.ScalarMappable(cmap=cmap, norm=matplotlib.colors.Normalize(0, 1))
    fig.colorbar(sm, ax=axs[0].tolist(), extend="max", shrink=0.8,
                 label=f"largest contact force / failure load\nof {_mpa(strength)} rock; section {2 * SECTION_SLAB:g} m thick")
    fig.savefig(path, dpi=100)
    plt.close(fig)


def write(folder, res):
    os.makedirs(folder, exist_ok=True)
    rs, ms = rows(res), model_rows(res)
    for name, table_rows in (("summary.csv", rs), ("model.csv", ms)):
        if table_rows:
            with open(os.path.join(folder, name), "w", newline="") as f:
                w = csv.DictWriter(f, fieldnames=list(dict.fromkeys(k for row in table_rows for k in row)))
                w.writeheader()
                w.writerows(table_rows)
    if rs:
        plot(res, os.path.join(folder, "crushing.png"))
        model_plot(res, os.path.join(folder, "crushing_model.png"))
        section_plot(res, os.path.join(folder, "crushing_section.png"))
    readme = os.path.join(folder, "README.md")
    replace_marked(readme, MARK, table(rs))
    replace_marked(readme, MARK_MODEL, model_table(ms))
    return rs


def main():
    rs = case_processes.main("grain_crushing.py", __doc__.split("\n\n")[0], CASES, run_case, write,
                             "also write the report (summary.csv, crushing.png, README table) into this folder")
    if rs is not None:
        print(table(rs))


if __name__ == "__main__" or any(a.endswith("grain_crushing.py") for a in sys.argv):
    main()
