"""The plots of an impact from its recorded rows: impact.png of any scene (yadeflex.boulder_impact:
the force raw and filtered, the penetration, the force against the penetration, the supports'
reactions; the damping module's is yadeflex.module.impact_plots) and energy.png (the energy terms
and the balance residual)."""
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


def write_energy_plot(folder, erows, keys):
    """energy.png into folder: the energy terms keys of erows (energy.csv's rows) and the residual."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
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


def write_scene_plots(folder, rows, filtered, filter_text, reactions):
    """impact.png of any scene's impact into folder: rows (timeseries.csv's), filtered (the
    filtered impact force of each row [N], or None), filter_text (the filter in words), reactions
    (the names of the reaction groups)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    t = [1e3 * r["t"] for r in rows]
    f = [r["impact_force"] / 1e3 for r in rows]
    pen = [1e3 * r["penetration"] for r in rows]
    fig, ax = plt.subplots(2, 2, figsize=(11, 7))
    ax[0, 0].plot(t, f, color="0.7", lw=0.8, label="raw")
    if filtered is not None:
        ax[0, 0].plot(t, [x / 1e3 for x in filtered], color="C0", label="filtered")
        ax[0, 0].annotate(filter_text, (0.01, -0.16), xycoords="axes fraction", fontsize=7, color="0.3")
    ax[0, 0].set(xlabel="t [ms]", ylabel="force [kN]", title="force on the boulder (against its travel)")
    ax[0, 0].set_ylim(bottom=min(0.0, min(f)))
    ax[0, 0].legend(fontsize=7)
    ax[0, 1].plot(t, pen)
    ax[0, 1].set(xlabel="t [ms]", ylabel="penetration [mm]", title="boulder travel since its first contact")
    ax[0, 1].set_ylim(bottom=0.0)
    ax[1, 0].plot(pen, [x / 1e3 for x in filtered] if filtered is not None else f)
    ax[1, 0].set(xlabel="penetration [mm]", ylabel="force [kN]", title="force against penetration" + (" (filtered)" if filtered is not None else ""))
    for n in reactions:
        ax[1, 1].plot(t, [r[f"reaction_{n}"] / 1e3 for r in rows], label=n)
    ax[1, 1].set(xlabel="t [ms]", ylabel="|reaction| [kN]", title="supports' reactions")
    ax[1, 1].set_ylim(bottom=0.0)
    if reactions:
        ax[1, 1].legend(fontsize=8)
    fig.tight_layout()
    _save(fig, os.path.join(folder, "impact.png"))
    plt.close(fig)
