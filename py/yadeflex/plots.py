"""Plots of CSV time series (PNG, matplotlib): chosen columns against time, and an energy budget
with its balance residual."""
import os

import numpy as np

from .energy_csv import HEADER, read_csv


def term_colors(n):
    """n colours, no two alike: matplotlib's tab10, then tab20's light shades (up to 20), then
    hues around the circle."""
    import matplotlib
    base = list(matplotlib.colormaps["tab10"].colors) + list(matplotlib.colormaps["tab20"].colors[1::2])
    if n <= len(base):
        return base[:n]
    return [matplotlib.colors.hsv_to_rgb((k / n, 0.8, 0.8)) for k in range(n)]


def _label(name, unit):
    return f"{name} [{unit}]" if unit else name


def _pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _save(fig, png_path):
    folder = os.path.dirname(png_path)
    if folder:
        os.makedirs(folder, exist_ok=True)
    fig.savefig(png_path, dpi=110)


def plot_timeseries(csv_path, columns, png_path, x=None, title=None, ylabel=None, units=None, logy=False):
    """Plot `columns` (names, with or without their '[unit]') of a time-series CSV against its
    first column (or x) into png_path. units: dict name -> unit for headers without one. The
    y label is the common unit; the legend gives each column with its unit. Returns png_path."""
    names, hunits, data = read_csv(csv_path)
    hunits.update(units or {})
    strip = lambda c: HEADER.match(c).group(1) if HEADER.match(c) else c.strip()
    xs = strip(x) if x is not None else names[0]
    cols = [strip(c) for c in ([columns] if isinstance(columns, str) else columns)]
    for c in [xs] + cols:
        if c not in data:
            raise ValueError(f"{csv_path}: no column {c!r} (columns: {names})")
    if not cols:
        raise ValueError("plot_timeseries needs at least one column")
    if len(data[xs]) == 0:
        raise ValueError(f"{csv_path}: no data rows")
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7, 4))
    for c in cols:
        ax.plot(data[xs], data[c], lw=1.2, label=_label(c, hunits[c]))
    ax.set_xlabel(_label(xs, hunits[xs]))
    common = {hunits[c] for c in cols}
    ax.set_ylabel(ylabel or (_label(cols[0] if len(cols) == 1 else "value", common.pop()) if len(common) == 1 else "value"))
    if logy:
        ax.set_yscale("log")
    if title:
        ax.set_title(title)
    ax.grid(True, lw=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    _save(fig, png_path)
    plt.close(fig)
    return png_path


ENERGY_ALPHA = 0.75  # fill opacity of the energy terms in plot_energy


def plot_energy(csv_path, png_path, title="Energy budget"):
    """Energy budget of an EnergyRecorder CSV (or any CSV: time first, terms in [J], optional
    total[J]) into png_path. Top: the terms stacked, positive parts upwards and negative parts
    (e.g. gravWork) downwards, with the total (their sum) as a line. Bottom: the residual,
    total(t) - total(t0) [J]. Returns dict(terms, total_start, max_abs_residual [J],
    max_abs_residual_rel [-] (relative to the largest |term|), colors: term -> fill colour, drawn
    with opacity ENERGY_ALPHA)."""
    names, units, data = read_csv(csv_path)
    t = data[names[0]]
    if len(t) == 0:
        raise ValueError(f"{csv_path}: no data rows")
    skip = {names[0], "iter", "iteration", "total"}
    terms = [n for n in names if n not in skip and not n.startswith("residual") and units[n] in ("J", "")]
    if not terms:
        raise ValueError(f"{csv_path}: no energy columns (expected NAME[J]; columns: {names})")
    vals = np.nan_to_num(np.array([data[n] for n in terms]))
    total = data["total"] if "total" in data else vals.sum(axis=0)
    residual = total - total[0]
    scale = float(np.max(np.abs(vals))) if vals.size else 0.0
    plt = _pyplot()
    fig, (ax, axr) = plt.subplots(2, 1, figsize=(8, 6), sharex=True, gridspec_kw=dict(height_ratios=(3, 1)))
    cols = list(term_colors(len(terms)))
    ax.stackplot(t, np.clip(vals, 0, None), labels=terms, colors=cols, alpha=ENERGY_ALPHA)
    ax.stackplot(t, np.clip(vals, None, 0), colors=cols, alpha=ENERGY_ALPHA)
    ax.plot(t, total, "k-", lw=1.5, label="total (sum)")
    ax.axhline(0, color="k", lw=0.5)
    ax.set_ylabel("energy [J]")
    ax.set_title(title)
    ax.grid(True, lw=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    axr.plot(t, residual, "r-", lw=1.2)
    axr.axhline(0, color="k", lw=0.5)
    axr.set_ylabel("total - total(t0) [J]")
    axr.set_xlabel(_label(names[0], units[names[0]]))
    axr.grid(True, lw=0.3)
    fig.tight_layout()
    _save(fig, png_path)
    plt.close(fig)
    res = float(np.max(np.abs(residual)))
    return dict(terms=terms, colors=dict(zip(terms, cols)), total_start=float(total[0]), max_abs_residual=res,
                max_abs_residual_rel=res / scale if scale > 0 else 0.0)
