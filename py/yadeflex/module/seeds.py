"""The main job on several fills built alike (scripts/damping_module.py --seeds N): the same
configuration on the seeds seed, seed + 1, ... (each its own fill: grain sizes and positions,
wire slack), each run into OUT/seedS/, then the scatter of their results (the study's tables,
yadeflex.module.study_results): OUT/configurations.csv, OUT/summary.json, OUT/scatter.png."""
import dataclasses
import os

from ..files import write_json
from . import study_results as SR
from .impact import run_impact, RESULT_FILES
from ..runner import EXIT

MAX_SEED = 2 ** 31 - 1


def run_seeds(params, out, n, cache_dir=None, progress=True, **settings):
    """run_impact of params on n seeds (params.seed, +1, ...) into out/seedS/, then the scatter
    files into out; returns the exit status (0 if every run was done, else the first failed
    run's; an interrupted run stops the others)."""
    if params.seed + n - 1 > MAX_SEED:  # (the command line refuses it first)
        raise ValueError(f"seeds: {n} from seed {params.seed} pass the largest seed {MAX_SEED}")
    os.makedirs(out, exist_ok=True)
    for f in RESULT_FILES:  # (an earlier single run's files: not this configuration's scatter)
        if os.path.exists(os.path.join(out, f)):
            os.unlink(os.path.join(out, f))
    runs, rows, status = [], [], EXIT["done"]
    for k in range(n):
        p = dataclasses.replace(params, seed=params.seed + k)
        name = f"seed{p.seed}"
        print(f"=== fill {k + 1} of {n}: seed {p.seed}, into {os.path.join(out, name)}", flush=True)
        s = run_impact(p, os.path.join(out, name), cache_dir=cache_dir, progress=progress, **settings)
        ok = s["exit_status"] == EXIT["done"]
        rows.append(dict(s, name=name, status="done" if ok else ("residual" if s["exit_status"] == EXIT["residual"] else s["status"])))
        runs.append(dict(name=name, configuration="this configuration", params=p.resolved(), inputs={}))
        if not ok and status == EXIT["done"]:
            status = s["exit_status"]
        if s["status"] == "interrupted":
            break
    from .study import param_units, software_version, _scatter_line
    confs = SR.configurations(rows, runs)
    SR.write_configurations(confs, os.path.join(out, "configurations.csv"), os.path.join(out, "summary.json"), param_units(),
                            dict(runs=len(rows), runs_done=sum(r["status"] == "done" for r in rows), seeds=[r["params"]["seed"] for r in runs],
                                 software=software_version()))
    write_json(os.path.join(out, "runs.json"), [dict(name=r["name"], status=row["status"], exit_status=row["exit_status"])
                                                 for r, row in zip(runs, rows)])
    try:
        print(f"scatter plot {write_scatter_plot(out, [r['name'] for r in runs])}")
    except Exception as e:  # a convenience: the tables are the result
        print(f"  (scatter plot failed: {e})")
    print(f"over {len(rows)} fill(s): {_scatter_line(confs[0])}; tables in {os.path.join(out, 'configurations.csv')}", flush=True)
    return status


def write_scatter_plot(out, names):
    """out/scatter.png: each fill's force on the boulder, force on the slab (both low-pass
    filtered) and penetration against time."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from ..energy_csv import read_csv
    from ..force_filter import low_pass, CUTOFF_HZ
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.6))
    for k, name in enumerate(names):
        path = os.path.join(out, name, "timeseries.csv")
        if not os.path.exists(path):
            continue
        _, _, d = read_csv(path)
        t = d["t"]
        for a, col, scale in ((ax[0], "impact_force", 1e-3), (ax[1], "slab_force", 1e-3)):
            try:
                y = low_pass(t, d[col])
            except ValueError:
                y = d[col]
            a.plot(1e3 * t, y * scale, color=f"C{k % 10}", lw=1.0, label=name)
        ax[2].plot(1e3 * t, 1e3 * d["penetration"], color=f"C{k % 10}", lw=1.0, label=name)
    for a, what in zip(ax, (f"force on the boulder [kN] ({CUTOFF_HZ:g} Hz low-pass)", f"force on the slab [kN] ({CUTOFF_HZ:g} Hz low-pass)",
                            "penetration [mm]")):
        a.set(xlabel="t [ms]", ylabel=what)
        a.set_ylim(bottom=0)
        a.grid(True, lw=0.3)
    ax[0].legend(fontsize=7)
    fig.suptitle("the same configuration on fills built alike (seeds)", fontsize=10)
    fig.tight_layout()
    path = os.path.join(out, "scatter.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
