"""The plots of a damping-module impact (yadeflex.impact.run_impact) from its recorded rows:
impact.png (forces on the boulder and the slab, penetration, bulging, ring and rope forces) and
energy.png (the energy terms and the balance residual)."""
import os

from .plots import term_colors


def term_styles(n):
    """Line styles: solid for the first ten, dashed for the light shades after them."""
    return ["-" if k < 10 else "--" for k in range(n)]


def _save(fig, path):
    """fig to path; OSError naming path (a full disk), with no part of the file left."""
    try:
        fig.savefig(path, dpi=110)
    except OSError as e:
        if os.path.exists(path):
            os.unlink(path)
        raise OSError(e.errno, e.strerror, path) from None


def write_plots(folder, rows, erows, keys):
    """impact.png and energy.png into folder; rows: timeseries.csv's, erows: energy.csv's, keys:
    the energy terms to draw."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    t = [1e3 * r["t"] for r in rows]
    fig, ax = plt.subplots(2, 2, figsize=(11, 7))
    ax[0, 0].plot(t, [r["impact_force"] / 1e3 for r in rows], label="on the boulder")
    ax[0, 0].plot(t, [r["slab_force"] / 1e3 for r in rows], label="on the slab")
    ax[0, 0].set(xlabel="t [ms]", ylabel="force [kN]", title="impact and slab forces")
    ax[0, 0].legend()
    ax[0, 1].plot(t, [1e3 * r["penetration"] for r in rows])
    ax[0, 1].set(xlabel="t [ms]", ylabel="penetration [mm]", title="boulder penetration")
    ax[1, 0].plot(t, [1e3 * r["bulge_max"] for r in rows], label="max")
    ax[1, 0].plot(t, [1e3 * r["bulge_mean"] for r in rows], label="mean")
    ax[1, 0].set(xlabel="t [ms]", ylabel="radial bulging [mm]", title="mesh at mid-height")
    ax[1, 0].legend()
    ax[1, 1].plot(t, [r["ring_top_force"] / 1e3 for r in rows], label="top ring")
    if any(r["ring_bottom_force"] for r in rows):
        ax[1, 1].plot(t, [r["ring_bottom_force"] / 1e3 for r in rows], label="bottom ring")
    else:  # its nodes are pinned to the slab: it cannot stretch, so it carries nothing
        ax[1, 1].plot([], [], " ", label="bottom ring: 0 (its nodes are pinned to the slab)")
    if any(r["rope_force"] for r in rows):
        ax[1, 1].plot(t, [r["rope_force"] / 1e3 for r in rows], label="boundary rope")
    ax[1, 1].set(xlabel="t [ms]", ylabel="largest axial force [kN] (tension > 0)", title="rings and rope")
    ax[1, 1].legend(fontsize=8)
    fig.tight_layout()
    _save(fig, os.path.join(folder, "impact.png"))
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(10, 6))
    te = [1e3 * e["t"] for e in erows]
    for k, c, ls in zip(keys, term_colors(len(keys)), term_styles(len(keys))):
        ax.plot(te, [e.get(k, 0.0) for e in erows], color=c, ls=ls, label=k)
    ax.plot(te, [e["residual"] for e in erows], "k--", label="balance residual")
    ax.set(xlabel="t [ms]", ylabel="energy [J]", title="energy budget (work terms with YADE's signs)")
    ax.legend(fontsize=8, ncol=2)
    fig.tight_layout()
    _save(fig, os.path.join(folder, "energy.png"))
    plt.close(fig)
