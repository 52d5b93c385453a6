"""The plots of a parametric study (yadeflex.module.study), for comparing designs without being
misled by one fill's answer:

- response.png: peak force on the boulder (low-pass filtered), peak force on the slab and
  penetration against the impact energy; each configuration's mean with an error bar of one
  standard deviation over its seeds and every seed as a dot; the design formulas' peak forces
  (yadeflex.module.cushion) as open markers; axes from zero; the inputs every configuration
  shares in a caption;
- energy_shares.png: where the energy went, per configuration (the mean over its seeds), as
  fractions of the energy brought in: the impact energy plus gravity's work on the boulder after
  its first contact;
- surface.png, when exactly two inputs vary and both are numbers: peak force and penetration over
  those two (filled contours, or coloured points where they do not span an area); when they are
  not both numbers the study says why there is none.

Only runs whose status is done are drawn.
"""
import os
import textwrap

ENERGY_INPUTS = ("boulder_mass", "drop_height", "impact_velocity")  # the inputs that set the impact energy
# results.csv inputs that never tell two configurations apart
NOT_CONFIGURATION = ENERGY_INPUTS + ("seed", "name", "row", "configuration", "repeat", "seeds", "boulder_size")
# the energy terms, by physical name (docs/model.md, "Energy"); gravity's work is the input, not a share
ENERGY_NAMES = {
    "kinetic": "kinetic energy left (boulder, grains)",
    "flexFriction": "friction between grains and steel",
    "plastDissip": "friction on the slab",
    "flexRolling": "rolling resistance of the grains",
    "flexContactElastic": "elastic energy in the contacts",
    "elastPotential": "elastic energy in the slab contacts",
    "flexBondElastic": "elastic energy in wires, rings, rope",
    "flexBondPlastic": "plastic work in wires, rings, rope",
    "flexRupture": "energy released by broken elements",
    "flexMembraneElastic": "elastic energy in the lining",
    "flexCrushing": "grain crushing",
    "flexHandover": "contact hand-overs (numerical loss)",
    "nonviscDamp": "numerical damping",
}
NOT_SHARES = ("energy_gravWork", "energy_residual_max_fraction", "energy_absorbed")
FORMULA_MARKERS = {"Labiouse 1996": "^", "JRA 2000": "s", "ASTRA 2008": "D"}


def _number(v):
    try:
        return float(v)
    except (TypeError, ValueError):
        return None


def varying_inputs(rows, runs):
    """The study file's columns whose cell differs between runs (seed included), in its order."""
    cols = list(dict.fromkeys(k for r in runs for k in r["inputs"]))
    return [c for c in cols if len({r["inputs"].get(c, "") for r in runs}) > 1]


def shared_inputs(runs, names=("n_modules", "diameter", "height", "fill", "grain_min", "grain_max", "boulder_mass", "boulder_shape",
                               "boulder_density", "drop_height", "rope", "damping")):
    """'name = value' of the inputs every run shares, for the plots' captions."""
    out = []
    for k in names:
        vals = {str(r["params"].get(k)) for r in runs if "params" in r}
        if len(vals) == 1:
            out.append(f"{k} = {vals.pop()}")
    return out


def configuration(run, columns):
    """A label of the values of columns (empty cells: 'default')."""
    vals = dict(run["inputs"], **run.get("params", {}))
    return ", ".join(f"{c}={vals.get(c) if vals.get(c) not in (None, '') else 'default'}" for c in columns) or "all runs"


def _caption(fig, lines, width=150):
    text = "\n".join(textwrap.fill(line, width) for line in lines)
    fig.text(0.01, 0.01, text, fontsize=7.5, va="bottom", ha="left", family="sans-serif")
    return 0.035 + 0.022 * text.count("\n")


def write_study_plots(rows, runs, folder, confs=None, say=None):
    """The plots above into folder; returns their paths (none when no run is done). confs: the
    configurations' statistics (yadeflex.module.study_results.configurations)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from . import study_results as SR
    say = say or (lambda line: None)
    confs = confs if confs is not None else SR.configurations(rows, runs)
    by_name = {r["name"]: r for r in runs}
    done = [r for r in rows if r["status"] == "done"]
    if not done:
        return []
    vary = varying_inputs(rows, runs)
    line_cols = [c for c in vary if c not in NOT_CONFIGURATION]
    paths = [_response(plt, rows, runs, confs, line_cols, by_name, os.path.join(folder, "response.png"))]
    paths.append(_energy_shares(plt, done, runs, confs, os.path.join(folder, "energy_shares.png")))
    two = [c for c in vary if c not in ("name", "row", "configuration", "seed")]
    if len(two) == 2:
        pts = [(_number(dict(by_name[r["name"]]["inputs"], **by_name[r["name"]]["params"]).get(two[0])),
                _number(dict(by_name[r["name"]]["inputs"], **by_name[r["name"]]["params"]).get(two[1])), r) for r in done]
        pts = [p for p in pts if p[0] is not None and p[1] is not None]
        if len(pts) >= 3:
            paths.append(_surface(plt, pts, two, os.path.join(folder, "surface.png")))
        else:
            say(f"study: no surface.png: the two inputs that vary ({', '.join(two)}) are not both numbers")
    elif len(two) > 2:
        say(f"study: no surface.png: {len(two)} inputs vary ({', '.join(two)}); it is drawn when exactly two do")
    return paths


def _response(plt, rows, runs, confs, line_cols, by_name, path):
    from . import study_results as SR
    import numpy as np
    conf_runs = {}
    for run, row in zip(runs, rows):
        conf_runs.setdefault(run["configuration"], []).append((run, row))
    lines = {}
    for c in confs:
        if c["n_done"]:
            first = conf_runs[c["configuration"]][0][0]
            lines.setdefault(configuration(first, line_cols), []).append(c)
    fig, ax = plt.subplots(1, 3, figsize=(15, 5.6))
    panels = (("peak_impact_force_filtered", 1e-3, "peak force on the boulder [kN]\n(low-pass filtered)"),
              ("slab_force_max_filtered", 1e-3, "peak force on the slab [kN]\n(low-pass filtered)"),
              ("penetration_max", 1e3, "boulder penetration [mm]"))
    shown_formula = set()
    e_max = max(0.5 * c["inputs"]["boulder_mass"] * c["inputs"]["impact_velocity"] ** 2 / 1e3 for cs in lines.values() for c in cs)
    for k, (label, cs) in enumerate(lines.items()):
        colour = f"C{k % 10}"
        cs = sorted(cs, key=lambda c: c["inputs"]["impact_velocity"])
        # (lines side by side, 1.5% of the energy axis apart, so that configurations at one energy do not hide each other)
        shift = (k - 0.5 * (len(lines) - 1)) * 0.015 * e_max
        e = [0.5 * c["inputs"]["boulder_mass"] * c["inputs"]["impact_velocity"] ** 2 / 1e3 + shift for c in cs]
        for a, (key, scale, _) in zip(ax, panels):
            m = [c[f"{key}_mean"] * scale if c[f"{key}_mean"] is not None else np.nan for c in cs]
            sd = [c[f"{key}_std"] * scale if c[f"{key}_std"] is not None else 0.0 for c in cs]
            a.errorbar(e, m, yerr=sd, fmt="o-" if len(cs) > 1 else "o", color=colour, capsize=4, lw=1.2, ms=6,
                       label=f"{label} (mean +- 1 s.d.)")
            for c, x in zip(cs, e):  # every seed
                ys = [row.get(key) for _, row in conf_runs[c["configuration"]] if row["status"] == "done" and row.get(key) is not None]
                a.plot([x] * len(ys), [y * scale for y in ys], ".", color=colour, alpha=0.45, ms=5)
        for name, marker in FORMULA_MARKERS.items():
            col = SR.formula_column(name)
            fx = [(x, c[col] / 1e3) for x, c in zip(e, cs) if c.get(col)]
            if fx:
                ax[0].plot(*zip(*fx), marker=marker, ls=":", mfc="none", color=colour, ms=7,
                           label=name if name not in shown_formula else None)
                shown_formula.add(name)
    for a, (_, _, what) in zip(ax, panels):
        a.set(xlabel="impact energy [kJ]", ylabel=what)
        a.set_xlim(left=0)
        a.set_ylim(bottom=0)
        a.grid(True, lw=0.3)
    ax[0].set_title("force on the boulder", fontsize=10)
    ax[1].set_title("load on the slab", fontsize=10)
    ax[2].set_title("penetration", fontsize=10)
    ax[0].legend(fontsize=7, loc="lower right")
    if len(lines) > 1:
        ax[2].legend(*ax[2].get_legend_handles_labels(), fontsize=7, loc="lower right")
    n = sorted({c["n_done"] for c in confs if c["n_done"]})
    cap = [f"Every configuration shares: {', '.join(shared_inputs(runs)) or '-'} (SI units).",
           f"Dots: each fill (seed); error bars: one standard deviation over the {'/'.join(map(str, n))} fill(s) of a configuration; "
           "configurations at one energy are drawn side by side. "
           "Forces low-pass filtered (zero-phase Butterworth, order 4, 300 Hz); raw peaks in results.csv.",
           "Open markers: design formulas at the fill's measured M_E, lambda, phi (Labiouse et al. 1996; JRA 2000; ASTRA 2008)."]
    bottom = _caption(fig, cap)
    fig.tight_layout(rect=(0, bottom, 1, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _energy_shares(plt, done, runs, confs, path):
    """Each configuration's mean energy shares (over its seeds) of impact energy + gravity's work after contact."""
    by_conf = {}
    names = {r["name"]: r["configuration"] for r in runs}
    for r in done:
        by_conf.setdefault(names[r["name"]], []).append(r)
    order = [c["configuration"] for c in confs if c["configuration"] in by_conf]
    terms = sorted({k for r in done for k in r if k.startswith("energy_") and k not in NOT_SHARES and isinstance(r.get(k), float)},
                   key=lambda k: list(ENERGY_NAMES).index(k[7:]) if k[7:] in ENERGY_NAMES else 99)
    fig, ax = plt.subplots(figsize=(max(8.0, 0.9 * len(order) + 6.0), 6.2))
    cmap = plt.get_cmap("tab20")
    base_pos = [0.0] * len(order)
    base_neg = [0.0] * len(order)
    for k, term in enumerate(terms):
        share = []
        for conf in order:
            rs = by_conf[conf]
            share.append(sum((r.get(term) or 0.0) / _brought_in(r) for r in rs) / len(rs))
        base = [bn if s < 0 else bp for s, bp, bn in zip(share, base_pos, base_neg)]
        ax.bar(range(len(order)), share, bottom=base, color=cmap(k % 20), label=ENERGY_NAMES.get(term[7:], term[7:]))
        base_pos = [bp + max(s, 0.0) for s, bp in zip(share, base_pos)]
        base_neg = [bn + min(s, 0.0) for s, bn in zip(share, base_neg)]
    ax.set_xticks(range(len(order)))
    ax.set_xticklabels([f"{conf}\n({len(by_conf[conf])} fill{'s' if len(by_conf[conf]) > 1 else ''})" for conf in order],
                       rotation=30 if len(order) > 6 else 0, fontsize=8)
    ax.axhline(1.0, color="k", lw=0.8, ls="--")
    ax.set(ylabel="share of the energy brought in [-]", ylim=(min(0.0, min(base_neg)) - 0.02, max(1.1, max(base_pos) + 0.05)))
    ax.set_title("where the energy went (end of the run, mean over the fills)", fontsize=10)
    ax.legend(fontsize=7.5, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    bottom = _caption(fig, ["Energy brought in = the boulder's impact energy + gravity's work on the boulder after its first contact. "
                            "The bars sum to 1 within the energy balance residual and gravity's work on the grains as they sink."], 110)
    fig.tight_layout(rect=(0, bottom, 1, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _brought_in(row):
    e = row["impact_energy"]
    w = row.get("gravity_work_after_contact")
    return e + (w if isinstance(w, float) else 0.0)


def _surface(plt, pts, names, path):
    import numpy as np
    at = {}  # (x, y) -> runs there (a configuration's seeds: their mean is drawn)
    for x, y, r in pts:
        at.setdefault((x, y), []).append(r)
    x = np.array([k[0] for k in at])
    y = np.array([k[1] for k in at])
    fig, ax = plt.subplots(1, 2, figsize=(12, 5))
    for a, (key, scale, what) in zip(ax, (("peak_impact_force_filtered", 1e-3, "peak force on the boulder [kN] (filtered, mean)"),
                                           ("penetration_max", 1e3, "penetration [mm] (mean)"))):
        z = np.array([np.mean([r[key] if r.get(key) is not None else np.nan for r in rs]) * scale for rs in at.values()])
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
