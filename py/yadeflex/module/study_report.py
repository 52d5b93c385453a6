"""The report of a parametric study (yadeflex.module.study): one self-contained HTML page (its
pictures inside it) from the study's folder, for a design file: the inputs and the fixed
parameters, each configuration's results with their scatter over the fills and the design
formulas beside them, the plots, the load on the slab, where the energy went, the broken
elements, the warnings and the software's version.

    scripts/report STUDY_OUT            (or scripts/study ... --report)
    from yadeflex.module.study_report import write_report; write_report("STUDY_OUT")
"""
import base64
import datetime
import html
import json
import os

from .study import read_results, DONE

REPORT_FILE = "report.html"
# the quantities of the results table: (key, scale, unit shown)
TABLE = (("peak_impact_force_filtered", 1e-3, "kN"), ("peak_impact_force", 1e-3, "kN"), ("slab_force_max_filtered", 1e-3, "kN"),
         ("slab_pressure_peak_filtered", 1e-3, "kPa"), ("slab_loaded_radius", 1.0, "m"), ("penetration_max", 1e3, "mm"),
         ("impact_duration", 1e3, "ms"), ("energy_absorbed", 1e-3, "kJ"), ("broken_elements_total", 1.0, "-"))
BROKEN = ("broken_wire_legs", "broken_ring_segments", "broken_rope_segments", "broken_lining_facets", "broken_other_elements")
MAX_RESIDUAL = 0.01  # [-] an energy residual above this is a warning (the main job refuses 5% by default)

CSS = """
body { font-family: sans-serif; max-width: 1200px; margin: 1.5em auto; color: #222; line-height: 1.35; }
h1 { font-size: 1.5em; } h2 { font-size: 1.2em; border-bottom: 1px solid #aaa; margin-top: 1.6em; }
table { border-collapse: collapse; font-size: 0.85em; margin: 0.5em 0; }
th, td { border: 1px solid #bbb; padding: 3px 7px; text-align: right; vertical-align: top; }
th { background: #eee; } td.l, th.l { text-align: left; }
.warn { color: #a40; } .note { font-size: 0.85em; color: #555; }
img { max-width: 100%; border: 1px solid #ddd; margin: 0.4em 0; }
"""


def _e(x):
    return html.escape(str(x))


def _num(v):
    try:
        return float(v)
    except (TypeError, ValueError):
        return None


def _fmt(v, scale=1.0, digits=3):
    v = _num(v)
    if v is None:
        return "-"
    x = v * scale
    return f"{x:.{digits}g}" if abs(x) < 10 ** digits else f"{x:.0f}"


def _img(path, alt):
    if not os.path.exists(path):
        return ""
    with open(path, "rb") as fh:
        data = base64.b64encode(fh.read()).decode("ascii")
    return f'<img alt="{_e(alt)}" src="data:image/png;base64,{data}">'


def _table(head, rows, left=1):
    out = ["<table><tr>" + "".join(f'<th class="{"l" if k < left else ""}">{h}</th>' for k, h in enumerate(head)) + "</tr>"]
    for r in rows:
        out.append("<tr>" + "".join(f'<td class="{"l" if k < left else ""}">{c}</td>' for k, c in enumerate(r)) + "</tr>")
    return "\n".join(out) + "</table>"


def write_report(out_dir):
    """OUT_DIR/report.html from the study's files (study.json, results.csv, configurations.csv,
    summary.json, the plots, each run's folder); returns its path. FileNotFoundError naming what
    is missing when the folder holds no finished study."""
    out_dir = os.path.abspath(out_dir)
    need = [os.path.join(out_dir, f) for f in ("study.json", "results.csv", "summary.json")]
    missing = [f for f in need if not os.path.exists(f)]
    if missing:
        raise FileNotFoundError(f"{out_dir} holds no finished study ({', '.join(os.path.basename(f) for f in missing)} missing): "
                                "run scripts/study STUDY.csv OUT_DIR first")
    with open(need[0]) as fh:
        study = json.load(fh)
    with open(need[2]) as fh:
        summary = json.load(fh)
    rows = read_results(need[1])
    confs = summary["configurations"]
    runs = study["runs"]
    parts = [f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>yade-flex study: {_e(os.path.basename(out_dir))}</title>"
             f"<style>{CSS}</style></head><body>"]
    parts += _head(out_dir, study, summary, rows)
    parts += _key_results(confs)
    parts += _inputs(runs, confs)
    parts += _results(confs, summary)
    parts += _plots(out_dir)
    parts += _slab(out_dir, runs, rows, confs)
    parts += _broken(confs, rows, runs)
    parts += _warnings(confs, rows)
    parts += _fixed(confs)
    parts += _definitions(summary)
    parts.append("</body></html>")
    path = os.path.join(out_dir, REPORT_FILE)
    from ..files import write_atomic
    write_atomic(path, "\n".join(parts))
    return path


def _head(out_dir, study, summary, rows):
    done = sum(1 for r in rows if r.get("status") == DONE)
    sw = summary.get("software", {})
    return [f"<h1>Damping-module study: {_e(os.path.basename(out_dir))}</h1>",
            f"<p>Study file <code>{_e(study.get('study_file'))}</code>; results in <code>{_e(out_dir)}</code>. "
            f"{done} of {len(rows)} runs done. Report written {datetime.datetime.now().strftime('%Y-%m-%d %H:%M')}; "
            f"yade-flex {_e(sw.get('yadeflex', 'unknown'))}, YADE {_e(sw.get('yade', 'unknown'))}.</p>"]


def _inputs(runs, confs):
    out = ["<h2>Inputs</h2>"]
    cols = list(dict.fromkeys(k for r in runs for k in r["inputs"] if k != "name"))
    given = {}
    for r in runs:
        given.setdefault(r["configuration"], r)
    out.append("<p>The study file's rows (an empty cell: the main job's default); each configuration runs on the fills (seeds) listed.</p>")
    head = ["configuration"] + [_e(c) for c in cols if c != "seed"] + ["seeds"]
    body = []
    for c in confs:
        r = given[c["configuration"]]
        body.append([_e(c["configuration"])] + [_e(r["inputs"].get(k) or "default") for k in cols if k != "seed"]
                    + [_e(", ".join(str(s) for s in c["seeds"]))])
    out.append(_table(head, body))
    keys = list(dict.fromkeys(k for c in confs for k in c["inputs"]))
    differ = [k for k in keys if len({json.dumps(c["inputs"].get(k)) for c in confs}) > 1]
    units = _param_units()
    if differ:
        out.append("<p>The parameters that differ between configurations (the values the runs used; those they share: "
                   "<a href='#fixed'>fixed parameters</a>):</p>")
        out.append(_table(["configuration"] + [_e(k) + (f" [{_e(units[k])}]" if units.get(k) else "") for k in differ],
                          [[_e(c["configuration"])] + [_val(c["inputs"].get(k)) for k in differ] for c in confs]))
    out.append("<p>Grain sizes of each fill:</p>")
    from ..grains import FILLS
    rows = []
    for c in confs:
        p = c["inputs"]
        preset = FILLS.get(p["fill"], {})
        note = ""
        if preset and (abs(preset["grain_min"] - p["grain_min"]) > 1e-12 or abs(preset["grain_max"] - p["grain_max"]) > 1e-12):
            note = (f"not the {p['fill']} preset's {1e3 * preset['grain_min']:g}-{1e3 * preset['grain_max']:g} mm"
                    + (" (the reduced module's grains, whatever the fill)" if p["diameter"] < 0.5 else ""))
        rows.append([_e(c["configuration"]), _e(p["fill"]), f"{1e3 * p['grain_min']:g}-{1e3 * p['grain_max']:g} mm",
                     _val(p.get("fill_density")), f'<span class="warn">{_e(note)}</span>' if note else ""])
    out.append(_table(["configuration", "fill", "grain diameters", "grain density [kg/m3]", "note"], rows, left=5))
    return out


def _val(v):
    """A parameter's value for a table: numbers to 4 significant digits."""
    if isinstance(v, bool) or v is None:
        return _e(v)
    if isinstance(v, float):
        return f"{v:.4g}"
    if isinstance(v, list):
        return " ".join(_val(x) for x in v)
    return _e(v)


def _key_results(confs):
    """The design values first: per configuration, the characteristic peak forces and penetration."""
    out = ["<h2>Design values</h2>",
           "<p>Per configuration: the mean over its fills and, in bold, the characteristic value (the upper 95% fractile, "
           "<a href='#definitions'>definitions</a>); forces low-pass filtered.</p>"]
    body = []
    for c in confs:
        row = [_e(c["configuration"]), str(c["n_done"])]
        for k, scale in (("peak_impact_force_filtered", 1e-3), ("slab_force_max_filtered", 1e-3), ("slab_pressure_peak_filtered", 1e-3),
                         ("penetration_max", 1e3)):
            m, ch = c.get(f"{k}_mean"), c.get(f"{k}_characteristic")
            row.append("-" if m is None else _fmt(m, scale) + (f" / <b>{_fmt(ch, scale)}</b>" if ch is not None else ""))
        body.append(row)
    out.append(_table(["configuration", "fills", "force on the boulder [kN]", "force on the slab [kN]", "peak slab pressure [kPa]",
                       "penetration [mm]"], body))
    return out


def _fixed(confs):
    keys = list(dict.fromkeys(k for c in confs for k in c["inputs"]))
    same = [k for k in keys if len({json.dumps(c["inputs"].get(k)) for c in confs}) == 1]
    units = _param_units()
    cells = [[_e(k), _val(confs[0]["inputs"].get(k)), _e(units.get(k, ""))] for k in same]
    third = (len(cells) + 2) // 3
    cols = [cells[i * third:(i + 1) * third] for i in range(3)]
    body = [sum((col[r] if r < len(col) else ["", "", ""] for col in cols), []) for r in range(third)]
    return ["<h2 id='fixed'>Fixed parameters</h2><p>The values every configuration's runs used (presets resolved).</p>",
            _table(["parameter", "value", "unit"] * 3, body, left=0)]


def _param_units():
    from .study import param_units
    return param_units()


def _results(confs, summary):
    out = ["<h2>Results with their scatter over the fills</h2>",
           "<p>Each cell: mean &plusmn; standard deviation [min-max] over the fills of the configuration; <b>char.</b>: the "
           f"characteristic value, {_e(summary.get('characteristic_value', ''))}. Forces low-pass filtered unless marked raw.</p>"]
    names = {k: m for k, m in ((q, dict(summary["quantities"]).get(q, {}).get("meaning", q)) for q, _, _ in TABLE)}
    head = ["configuration", "fills"] + [f"{_e(names[k])} [{u}]" for k, _, u in TABLE]
    body = []
    for c in confs:
        cells = [_e(c["configuration"]), f"{c['n_done']} of {c['n_runs']}"]
        for k, scale, _ in TABLE:
            m, sd, lo, hi, ch = (c.get(f"{k}_{s}") for s in ("mean", "std", "min", "max", "characteristic"))
            if m is None:
                cells.append("-")
                continue
            t = _fmt(m, scale) + (f" &plusmn; {_fmt(sd, scale, 2)}" if sd is not None else "")
            if lo is not None and hi is not None and c["n_done"] > 1:
                t += f"<br>[{_fmt(lo, scale)}-{_fmt(hi, scale)}]"
            if ch is not None:
                t += f"<br><b>char. {_fmt(ch, scale)}</b>"
            cells.append(t)
        body.append(cells)
    out.append(_table(head, body, left=1))
    out.append("<h2>Against the design formulas</h2>")
    forms = list(summary.get("formulas", {}))
    out.append("<p>The peak force on the boulder from the cushion formulas at the fill's measured properties, beside the model's "
               "(filtered, mean over the fills). Sources: " + "; ".join(f"{_e(f)}: {_e(v['source'])}" for f, v in summary.get("formulas", {}).items())
               + ".</p>")
    body = []
    for c in confs:
        m = c.get("peak_impact_force_filtered_mean")
        row = [_e(c["configuration"]), _fmt(m, 1e-3)]
        for f in forms:
            v = c.get(summary["formulas"][f]["column"])
            row.append(f"{_fmt(v, 1e-3)}" + (f" ({m / v:.2f}x)" if v and m else ""))
        inp = c.get("formula_inputs") or {}
        row.append(_e(inp.get("missing")) if inp.get("missing") else
                   _e(f"M_E {_fmt(inp.get('M_E'), 1e-6)} MPa, lambda {_fmt(inp.get('lame'), 1e-6)} MPa, phi {_fmt(inp.get('friction_deg'))} deg, "
                      f"R {_fmt(inp.get('radius'))} m, e {_fmt(inp.get('thickness'))} m: {inp.get('source', '')}"))
        body.append(row)
    out.append(_table(["configuration", "model [kN]"] + [f"{_e(f)} [kN] (model / formula)" for f in forms] + ["formula inputs"], body))
    return out


def _plots(out_dir):
    out = ["<h2>Plots</h2>"]
    for f, alt in (("response.png", "peak forces and penetration against the impact energy"),
                   ("energy_shares.png", "where the energy went"), ("surface.png", "response surface")):
        out.append(_img(os.path.join(out_dir, f), alt))
    return out


def _slab(out_dir, runs, rows, confs):
    out = ["<h2>Load on the slab</h2>",
           "<p>The pressure under the module at the slab force's peak and its largest value over the run, for the first fill "
           "of each configuration (every run's map: <code>runs/NAME/slab_pressure.png</code>, <code>.csv</code>, and in ParaView "
           "<code>runs/NAME/vtk/</code>).</p>"]
    seen = set()
    status = {r["name"]: r.get("status") for r in rows}
    for r in runs:
        if r["configuration"] in seen or status.get(r["name"]) != DONE:
            continue
        seen.add(r["configuration"])
        img = _img(os.path.join(out_dir, "runs", r["name"], "slab_pressure.png"), f"slab pressure, {r['name']}")
        out.append(f"<h3>{_e(r['configuration'])} (run {_e(r['name'])})</h3>" + (img or "<p class='note'>no slab map in this run's folder</p>"))
    return out


def _broken(confs, rows, runs):
    conf_of = {r["name"]: r["configuration"] for r in runs}
    out = ["<h2>Broken elements</h2>", "<p>Mean over the fills of each configuration (min-max).</p>"]
    body = []
    for c in confs:
        rs = [r for r in rows if conf_of.get(r["name"]) == c["configuration"] and r.get("status") == DONE]
        cells = [_e(c["configuration"])]
        for k in BROKEN:
            v = [x for x in (_num(r.get(k)) for r in rs) if x is not None]
            cells.append(f"{sum(v) / len(v):.3g} ({min(v):.0f}-{max(v):.0f})" if v else "-")
        body.append(cells)
    out.append(_table(["configuration"] + [k.replace("broken_", "").replace("_", " ") for k in BROKEN], body))
    return out


def _warnings(confs, rows):
    w = [f"{_e(c['configuration'])}: {_e(x)}" for c in confs for x in c.get("warnings", [])]
    for r in rows:
        res = _num(r.get("energy_residual_max_fraction"))
        if res is not None and res > MAX_RESIDUAL and not any(r["name"] in x for x in w):
            w.append(f"{_e(r['name'])}: energy residual {100 * res:.2f}%")
    for c in confs:
        inp = c.get("formula_inputs") or {}
        if inp.get("missing"):
            w.append(f"{_e(c['configuration'])}: no design formulas: {_e(inp['missing'])}")
    out = ["<h2>Warnings</h2>"]
    out.append("<ul>" + "".join(f'<li class="warn">{x}</li>' for x in w) + "</ul>" if w else
               f"<p>None: every run done, every energy residual below {100 * MAX_RESIDUAL:g}%, every configuration on several fills.</p>")
    return out


def _definitions(summary):
    return ["<h2 id='definitions'>Definitions</h2><ul>",
            f"<li>Characteristic value: {_e(summary.get('characteristic_value'))}.</li>",
            "<li>Forces: the force on the boulder against its travel (from its deceleration) and the force on the slab (the slab's "
            "contacts plus the base nodes' supports), recorded every 0.2 ms; peaks reported after a zero-phase 4th-order Butterworth "
            "low-pass filter at 300 Hz, the raw peaks beside them in results.csv.</li>",
            "<li>Energy shares: fractions of the energy brought in, the impact energy plus gravity's work on the boulder after its "
            "first contact.</li>",
            "<li>A configuration is one row of the study file; its runs differ only in the seed of the fill (grain sizes, positions, "
            "wire slack): their spread is the fill-to-fill scatter.</li></ul>"]
