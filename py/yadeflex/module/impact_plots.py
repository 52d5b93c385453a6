"""The damping module's impact plot (yadeflex.module.impact.run_impact): impact.png (forces on the
boulder and the slab, penetration, bulging, ring and rope forces), with energy.png."""
import os

from ..impact_plots import _save, write_energy_plot


def write_plots(folder, rows, erows, keys, filtered=None, cutoff_hz=None):
    """impact.png and energy.png into folder; rows: timeseries.csv's, erows: energy.csv's, keys:
    the energy terms to draw; filtered: column -> its low-pass filtered series (drawn over the
    raw one), cutoff_hz: that filter's cut-off [Hz]."""
    filtered = filtered or {}
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    t = [1e3 * r["t"] for r in rows]
    fig, ax = plt.subplots(2, 2, figsize=(11, 7))
    for col, label, colour in (("impact_force", "on the boulder", "C0"), ("slab_force", "on the slab", "C1")):
        raw = [r[col] / 1e3 for r in rows]
        if col in filtered:
            ax[0, 0].plot(t, raw, color=colour, lw=0.6, alpha=0.35, label=f"{label} (raw)")
            ax[0, 0].plot(t, [f / 1e3 for f in filtered[col]], color=colour, label=f"{label} ({cutoff_hz:g} Hz low-pass)")
        else:
            ax[0, 0].plot(t, raw, color=colour, label=label)
    ax[0, 0].set(xlabel="t [ms]", ylabel="force [kN]", title="impact and slab forces")
    ax[0, 0].set_ylim(bottom=min(0.0, ax[0, 0].get_ylim()[0]))
    ax[0, 0].legend(fontsize=8)
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
    write_energy_plot(folder, erows, keys)
