"""The tables of a parametric study (yadeflex.module.study): each run's row of results.csv with
its units, and each configuration's scatter over its seeds with the design formulas beside it
(configurations.csv, summary.json).

A configuration is one row of the study file: its runs share every input but the seed (the
fill's grain sizes and wire slack draws), so their spread is the fill-to-fill scatter. For every
QUANTITY it gives n, mean, standard deviation, coefficient of variation, min, max and the
characteristic value (yadeflex.scatter.CHARACTERISTIC); and the peak force of the three design
formulas (yadeflex.module.cushion) at the fill's measured properties.
"""
import csv
import io
import math
import re

from ..constants import G
from ..files import write_atomic, write_json
from ..scatter import CHARACTERISTIC, describe
from . import cushion

# the results a configuration's scatter is given for: (summary key, unit, what it is)
QUANTITIES = (
    ("peak_impact_force_filtered", "N", "peak force on the boulder, low-pass filtered"),
    ("peak_impact_force", "N", "peak force on the boulder, raw"),
    ("slab_force_max_filtered", "N", "peak force on the slab, low-pass filtered"),
    ("slab_force_max", "N", "peak force on the slab, raw"),
    ("slab_pressure_peak_filtered", "Pa", "peak pressure on the slab, low-pass filtered"),
    ("slab_pressure_peak", "Pa", "peak pressure on the slab, raw"),
    ("slab_loaded_radius", "m", "loaded radius on the slab"),
    ("penetration_max", "m", "boulder penetration"),
    ("impact_duration", "s", "impact duration"),
    ("energy_absorbed", "J", "energy taken by the module"),
    ("broken_elements_total", "-", "broken elements"),
)
STATS = ("mean", "std", "cv", "min", "max", "characteristic")
FORMULAS = tuple(cushion.SOURCES)  # the design formulas' names
UNIT_RE = re.compile(r"^(.*)\[([^\]]*)\]$")

# unit of each summary value results.csv carries (the others: energy_* J, the inputs' own)
SUMMARY_UNITS = dict(
    impact_energy="J", peak_impact_force="N", peak_impact_force_filtered="N", peak_deceleration="m/s2", penetration_max="m",
    impact_duration="s", rebound="-", released="-", slab_force_max="N", slab_force_max_filtered="N", slab_pressure_peak="Pa", slab_pressure_peak_filtered="Pa",
    slab_loaded_radius="m", bulge_max="m", ring_top_force_max="N", ring_bottom_force_max="N", rope_force_max="N",
    broken_wire_legs="-", broken_ring_segments="-", broken_rope_segments="-", broken_lining_facets="-", broken_other_elements="-",
    broken_elements_total="-", energy_absorbed="J", gravity_work_after_contact="J", boulder_energy_end="J",
    energy_residual_max_fraction="-", impact_steps="-", run_time_s="s", fill_time_s="s", wall_time_s="s", exit_status="-",
    seed="-", row="-", n_runs="-", n_done="-", k_n="-")


def formula_column(name):
    """results.csv's column of a design formula: 'Labiouse 1996' -> formula_labiouse_1996."""
    return "formula_" + re.sub(r"\W+", "_", name.lower()).strip("_")


def unit_of(column, param_units):
    """The unit of a results.csv column ('' if it has none: a text)."""
    if column in SUMMARY_UNITS:
        return SUMMARY_UNITS[column]
    if column in param_units:
        return param_units[column]
    if column.startswith("energy_"):
        return "J"
    if column.startswith("formula_"):
        return "N"
    if column.endswith(("_mean", "_std", "_min", "_max", "_characteristic")):
        return unit_of(column.rsplit("_", 1)[0], param_units)
    if column.endswith("_cv"):
        return "-"
    return param_units.get(column, "")


def header(column, param_units):
    """'peak_impact_force' -> 'peak_impact_force[N]' (a text column keeps its bare name)."""
    u = unit_of(column, param_units)
    return f"{column}[{u}]" if u else column


def bare(name):
    """A header without its unit: 'peak_impact_force[N]' -> 'peak_impact_force'."""
    m = UNIT_RE.match(name)
    return m.group(1) if m else name


def cell(v):
    if v is None:
        return ""
    if isinstance(v, float):
        return repr(v)  # shortest text that reads back to the same float
    if isinstance(v, (list, tuple)):
        return " ".join(cell(x) for x in v)
    return v


def write_table(rows, columns, path, param_units):
    """A CSV of rows (dicts) under headers NAME[UNIT], written whole through a rename."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow([header(c, param_units) for c in columns])
    for r in rows:
        w.writerow([cell(r.get(c)) for c in columns])
    write_atomic(path, buf.getvalue())


def read_table(path):
    """The rows of a table write_table wrote, as dicts keyed by the bare column names (texts)."""
    with open(path, newline="") as fh:
        rd = csv.reader(fh)
        cols = [bare(c) for c in next(rd)]
        return [dict(zip(cols, r)) for r in rd]


def design_values(params):
    """The design formulas' peak forces [N] of a run's resolved parameters (ModuleParams.resolved()),
    by results.csv column, and the properties they took (or why there are none)."""
    height = params["impact_velocity"] ** 2 / (2 * G)  # (the drop height, or the height the impact speed is worth)
    d = cushion.design_forces(params["fill"], params["boulder_mass"], params["boulder_density"], height, params["height"])
    return {formula_column(k): v for k, v in d["forces"].items()}, d.get("inputs") or dict(missing=d.get("missing"))


def configurations(rows, runs, done="done"):
    """One dict per configuration (in the study's order): configuration, n_runs, n_done, the
    fixed inputs (the first run's resolved parameters, seed left out), the seeds, for each
    QUANTITY key_mean, key_std, ... (over the runs done), the formulas' forces and their inputs,
    and warnings (runs not done, residuals)."""
    by_conf = {}
    for run, row in zip(runs, rows):
        by_conf.setdefault(run["configuration"], []).append((run, row))
    out = []
    for conf, members in by_conf.items():
        ok = [row for _, row in members if row.get("status") == done]
        first = members[0][0]
        c = dict(configuration=conf, n_runs=len(members), n_done=len(ok), seeds=[run["params"].get("seed") for run, _ in members])
        c["inputs"] = {k: v for k, v in first["params"].items() if k != "seed"}
        for key, unit, _ in QUANTITIES:
            st = describe([row.get(key) for row in ok])
            for s in STATS:
                c[f"{key}_{s}"] = st[s]
        c["k_n"] = describe([row.get("peak_impact_force") for row in ok])["k_n"]
        forces, inputs = design_values(first["params"])
        c.update(forces)
        c["formula_inputs"] = inputs
        warnings = [f"{run['name']}: {row.get('status')} ({row.get('message') or 'no message'})" for run, row in members
                    if row.get("status") != done]
        warnings += [f"{run['name']}: energy residual {100 * row['energy_residual_max_fraction']:.2f}%" for run, row in members
                     if isinstance(row.get("energy_residual_max_fraction"), float) and row["energy_residual_max_fraction"] > 0.01]
        if len(ok) == 1:
            warnings.append("one run: no scatter (give the row seeds = 5 or more for a characteristic value)")
        c["warnings"] = warnings
        out.append(c)
    return out


def configuration_columns(confs):
    """configurations.csv's columns."""
    inputs = list(dict.fromkeys(k for c in confs for k in c["inputs"]))
    stats = [f"{key}_{s}" for key, _, _ in QUANTITIES for s in STATS]
    forms = [formula_column(f) for f in FORMULAS]
    return ["configuration", "n_runs", "n_done", "k_n"] + stats + forms + inputs + ["warnings"]


def write_configurations(confs, folder_csv, folder_json, param_units, study_info):
    """configurations.csv (a row per configuration: its statistics, the formulas, its fixed
    inputs) and summary.json (the same, with the definitions) of a study."""
    cols = configuration_columns(confs)
    flat = [dict(c, **c["inputs"], warnings="; ".join(c["warnings"])) for c in confs]
    write_table(flat, cols, folder_csv, param_units)
    write_json(folder_json, dict(study_info, characteristic_value=CHARACTERISTIC,
                                 quantities={k: dict(unit=u, meaning=m) for k, u, m in QUANTITIES},
                                 formulas={f: dict(source=cushion.SOURCES[f], column=formula_column(f), unit="N") for f in FORMULAS},
                                 configurations=[_finite(c) for c in confs]))


def _finite(obj):
    """obj with NaN and infinities as None (JSON has no NaN)."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: _finite(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_finite(v) for v in obj]
    return obj
