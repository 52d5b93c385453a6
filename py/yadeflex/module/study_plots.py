"""The plots of a parametric study (yadeflex.module.study), from the rows of its results.csv, for
comparing designs:

- response.png: peak impact force and penetration against the impact energy, a line per
  configuration (the runs sharing every input but the boulder's mass, drop height, impact speed,
  seed and name);
- energy_shares.png: where the impact energy goes, a stacked bar per run grouped by
  configuration (the energy terms at the end of the run, as fractions of the impact energy);
- surface.png, when exactly two inputs vary and both are numbers: peak force and penetration over
  those two (filled contours, or coloured points where they do not span an area).

Only runs whose status is done are drawn.
"""
import os

ENERGY_INPUTS = ("boulder_mass", "drop_height", "impact_velocity")  # the inputs that set the impact energy
NOT_CONFIGURATION = ENERGY_INPUTS + ("seed", "name", "row", "repeat")
# energy terms that are not where the impact energy went: gravity's work (it adds to the energy
# brought in) and the kinetic energy left (in the boulder and the grains, at the run's end)
ENERGY_SOURCES = ("energy_gravWork",)


def _number(v):
    try:
        return float(v)
    except (TypeError, ValueError):
        return None


def varying_inputs(rows, runs):
    """The input columns whose cell differs between runs, in the study's order."""
    cols = list(dict.fromkeys(k for r in runs for k in r["inputs"]))
    return [c for c in cols if len({r["inputs"].get(c, "") for r in runs}) > 1]


def configuration(run, columns):
    """A configuration's label: its values of columns (empty cells: 'default')."""
    return ", ".join(f"{c}={run['inputs'].get(c) or 'default'}" for c in columns) or "all runs"


def write_study_plots(rows, runs, folder):
    """The plots above into folder; returns their paths (none when no run is done)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    by_name = {r["name"]: r for r in runs}
    done = [r for r in rows if r["status"] == "done"]
    if not done:
        return []
    vary = varying_inputs(rows, runs)
    config_cols = [c for c in vary if c not in NOT_CONFIGURATION]
    groups = {}
    for r in done:
        groups.setdefault(configuration(by_name[r["name"]], config_cols), []).append(r)
    paths = []

    fig, ax = plt.subplots(1, 2, figsize=(12, 5))
    for label, rs in groups.items():
        rs = sorted(rs, key=lambda r: r["impact_energy"])
        e = [r["impact_energy"] / 1e3 for r in rs]
        ax[0].plot(e, [r["peak_impact_force"] / 1e3 for r in rs], "o-", label=label)
        ax[1].plot(e, [1e3 * r["penetration_max"] for r in rs], "o-", label=label)
    ax[0].set(xlabel="impact energy [kJ]", ylabel="peak impact force [kN]", title="peak force on the boulder")
    ax[1].set(xlabel="impact energy [kJ]", ylabel="penetration [mm]", title="boulder penetration")
    ax[0].legend(fontsize=7)
    fig.tight_layout()
    paths.append(os.path.join(folder, "response.png"))
    fig.savefig(paths[-1], dpi=110)
    plt.close(fig)

    terms = sorted({k for r in done for k in r if k.startswith("energy_") and k not in ENERGY_SOURCES
                    and k != "energy_residual_max_fraction"})
    order = [r for rs in groups.values() for r in sorted(rs, key=lambda r: r["impact_energy"])]
    fig, ax = plt.subplots(figsize=(max(8, 0.45 * len(order) + 3), 6))
    bottom_pos, bottom_neg = [0.0] * len(order), [0.0] * len(order)
    cmap = plt.get_cmap("tab20")
    for k, term in enumerate(terms):
        share = [(r.get(term) or 0.0) / r["impact_energy"] for r in order]
        base = [bn if s < 0 else bp for s, bp, bn in zip(share, bottom_pos, bottom_neg)]
        ax.bar(range(len(order)), share, bottom=base, color=cmap(k % 20), label=term[len("energy_"):])
        bottom_pos = [bp + max(s, 0.0) for s, bp in zip(share, bottom_pos)]
        bottom_neg = [bn + min(s, 0.0) for s, bn in zip(share, bottom_neg)]
    ax.set_xticks(range(len(order)))
    ax.set_xticklabels([f"{r['name']}\n{r['impact_energy'] / 1e3:.2g} kJ" for r in order], rotation=90, fontsize=7)
    ax.axhline(1.0, color="k", lw=0.8, ls="--")
    ax.set(ylabel="fraction of the impact energy [-]",
           title="energy by mechanism at the end of each run (gravity's work during the impact not drawn)")
    ax.legend(fontsize=7, ncol=2, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    fig.tight_layout()
    paths.append(os.path.join(folder, "energy_shares.png"))
    fig.savefig(paths[-1], dpi=110)
    plt.close(fig)

    two = [c for c in vary if c not in ("name", "row")]
    if len(two) == 2:
        pts = [(_number(by_name[r["name"]]["inputs"].get(two[0])), _number(by_name[r["name"]]["inputs"].get(two[1])), r) for r in done]
        pts = [p for p in pts if p[0] is not None and p[1] is not None]
        if len(pts) >= 3:
            paths.append(_surface(plt, pts, two, os.path.join(folder, "surface.png")))
    return paths


def _surface(plt, pts, names, path):
    import numpy as np
    x = np.array([p[0] for p in pts])
    y = np.array([p[1] for p in pts])
    fig, ax = plt.subplots(1, 2, figsize=(12, 5))
    for a, (key, scale, what) in zip(ax, (("peak_impact_force", 1e-3, "peak impact force [kN]"),
                                           ("penetration_max", 1e3, "penetration [mm]"))):
        z = np.array([p[2][key] * scale for p in pts])
        spans_area = len(set(x)) > 1 and len(set(y)) > 1 and np.linalg.matrix_rank(np.c_[x - x.mean(), y - y.mean()]) == 2
        if spans_area:
            c = a.tricontourf(x, y, z, levels=12, cmap="viridis")
        else:
            c = a.scatter(x, y, c=z, cmap="viridis", s=80)
        a.plot(x, y, "k.", ms=4)
        fig.colorbar(c, ax=a, label=what)
        a.set(xlabel=names[0], ylabel=names[1], title=what)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
