"""Would the gravel break under the boulder? The grains' contact forces in the default module's
impacts against the point-load failure load of rock (yadeflex.crushing) (GPL-2.0-or-later).

    yade-double -n -j1 -x validation/grain_crushing.py OUT [--workers 2] [--cases a,b] [--to validation/studies/grain_crushing]

The cases are the base and seed2 runs of validation/studies/fill_factors: the main job's module
and cube, 800 kg from 1, 2 and 4 m, 400 and 1600 kg from 2 m (the cube's size kept, its density
scaled), on the main job's fill and on another fill of the same preset (seed 2).
Each case runs in its own yade-double process (--workers at a time, one thread each): the main
job's impact from the cached filled module (yadeflex.module.impact_start) until the boulder stops
moving down (its deepest point), reading every grain's contact forces every SAMPLE_STEPS steps,
and writes OUT/cases/NAME.json. Then this script writes OUT/summary.csv, OUT/crushing.png and the
table between the markers of OUT/README.md (--to DIR: the same files in DIR too).

Strengths screened: Is(50) = 1.5, 4 and 10 MPa, the bounds of Selby's moderately strong and
strong rock (yadeflex.crushing)."""
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

G = 9.81
MARK = ("<!-- table:grain_crushing -->", "<!-- /table:grain_crushing -->")
STRENGTHS = (1.5e6, 4e6, 10e6)  # [Pa] Is(50)
SAMPLE_STEPS = 10  # steps between two readings of the contacts (the time step is about 9 us)
MAX_TIME = 0.3  # [s] after the first contact: the longest a case runs (then "stopped" is False: the boulder still moved down)
# (mass [kg], drop height [m], the fill's seed): each on the main job's fill and on a second fill of
# the same preset (seed 2: the scatter of every figure)
CASES = {f"{k}{'' if seed == 1 else f'_s{seed}'}": (m, h, seed) for seed in (1, 2)
         for k, (m, h) in dict(H1=(800.0, 1.0), H2=(800.0, 2.0), H4=(800.0, 4.0), m400=(400.0, 2.0), m1600=(1600.0, 2.0)).items()}


def run_case(name, out):
    """One case in this process (under YADE): OUT/cases/NAME.json."""
    import numpy as np
    from yade import O
    from yadeflex.crushing import PeakGrainForces, scene_contacts
    from yadeflex.module import ModuleParams, fill_top, impact_start
    from yadeflex.scene import step_until
    mass, height, seed = CASES[name]
    base = ModuleParams()
    # the same cube as the main job's (its size kept, the density scaled with the mass)
    p = ModuleParams(boulder_mass=mass, drop_height=height, boulder_density=base.boulder_density * mass / base.boulder_mass, seed=seed)
    t_wall = time.time()
    ids, bid, _ = impact_start(p)
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
    r = dict(name=name, mass=mass, height=height, seed=seed, grains=len(grains), deepest=dict(penetration=series[-1]["penetration"], force=series[-1]["force"]),
             stopped=bool(boulder.state.vel[2] >= 0), peak_force=max(x["force"] for x in series),
             grain_force_max=float(screen.peak.max()), grain_force_p99=float(np.percentile(screen.peak, 99)),
             broken=broken, series=series, wall_seconds=time.time() - t_wall, sample_steps=SAMPLE_STEPS)
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
        row = dict(case=name, mass_kg=r["mass"], height_m=r["height"], fill_seed=r["seed"], peak_force_kN=r["peak_force"] / 1e3,
                   deepest_penetration_mm=1e3 * r["deepest"]["penetration"], deepest_force_kN=r["deepest"]["force"] / 1e3,
                   stopped=r["stopped"], grain_force_max_kN=r["grain_force_max"] / 1e3, grain_force_p99_kN=r["grain_force_p99"] / 1e3)
        for b in r["broken"]:
            tag = f"{b['is50'] / 1e6:g}MPa"
            row[f"broken_{tag}"] = b["count"]
            row[f"broken_under_boulder_{tag}"] = b["under_boulder"]
            row[f"load_ratio_max_{tag}"] = b["load_ratio_max"]
            row[f"broken_second_half_{tag}"] = sum(1 for x in b["penetrations"] if x >= 0.5 * r["deepest"]["penetration"])
            row[f"first_break_penetration_mm_{tag}"] = None if b["first_penetration"] is None else 1e3 * b["first_penetration"]
            row[f"median_depth_below_boulder_mm_{tag}"] = (1e3 * sorted(b["depth_below_boulder"])[len(b["depth_below_boulder"]) // 2]
                                                           if b["depth_below_boulder"] else None)
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
    for r in rs:
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
    for r in res.values():
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


def write(folder, res):
    os.makedirs(folder, exist_ok=True)
    rs = rows(res)
    if rs:
        with open(os.path.join(folder, "summary.csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rs[0]))
            w.writeheader()
            w.writerows(rs)
        plot(res, os.path.join(folder, "crushing.png"))
    readme = os.path.join(folder, "README.md")
    if os.path.isfile(readme):
        with open(readme) as f:
            s = f.read()
        if MARK[0] in s and MARK[1] in s:
            s = s[:s.index(MARK[0]) + len(MARK[0])] + "\n" + table(rs) + "\n" + s[s.index(MARK[1]):]
            with open(readme, "w") as f:
                f.write(s)
    return rs


def main():
    rs = case_processes.main("grain_crushing.py", __doc__.split("\n\n")[0], CASES, run_case, write,
                             "also write the report (summary.csv, crushing.png, README table) into this folder")
    if rs is not None:
        print(table(rs))


if __name__ == "__main__" or any(a.endswith("grain_crushing.py") for a in sys.argv):
    main()
