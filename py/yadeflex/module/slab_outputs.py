"""The files of the load on the slab (yadeflex.slab_load's maps of a run of
yadeflex.module.impact): slab_pressure.csv (the peak maps, cell by cell), slab_pressure.png (the
map at the slab force's peak, the largest pressure of each cell, the slab force over time, the
radial profile) and, with VTK output, vtk/slab_pressure.pvd (the maps over time for ParaView:
one image, vtkImageData, per VTK frame interval) with vtk/slab_pressure_peak.vti (the peak
maps).

    file                      cells             data (SI units)
    slab_pressure_NNNNNN.vti  one per grid      cell: pressure [Pa] (the record's),
                              cell, in the      pressure_filtered [Pa] (each cell's pressure
                              slab's plane      over time low-pass filtered, if it could be)
    slab_pressure_peak.vti    as above          cell: pressure_peak [Pa] (each cell's largest
                                                over the records), pressure_at_slab_peak [Pa],
                                                pressure_peak_filtered [Pa]

Every .vti carries field data TimeValue [s] on the clock of vtk/flex.pvd (from the first contact).
"""
import csv
import io
import math
import os
import re

import numpy as np

from ..files import clear_matching, write_atomic
from ..impact_plots import _save
from ..vtk_frames import write_xml

CSV_FILE, PNG_FILE = "slab_pressure.csv", "slab_pressure.png"
VTK_PREFIX = "slab_pressure"
RESULT_FILES = (CSV_FILE, PNG_FILE)


def vtk_files_pattern(prefix=VTK_PREFIX):
    """The names of the VTK files write_vtk writes (a regular expression, whole names)."""
    return re.escape(prefix) + r"(\.pvd|_peak\.vti|_\d{6,}\.vti)"


def clear_vtk(folder, prefix=VTK_PREFIX):
    """Removes an earlier run's maps from the VTK folder (the folder too if that empties it)."""
    clear_matching(folder, vtk_files_pattern(prefix))


def write_csv(path, grid, res):
    """The peak maps, one row per cell: its centre x, y [m], its largest pressure over the records
    pressure_peak [Pa] and when t_peak [s] (timeseries.csv's clock; nan: never loaded), the pressure at the record
    of the slab force's peak pressure_at_slab_peak [Pa], and (if the records could be filtered)
    the largest filtered pressure pressure_peak_filtered [Pa]."""
    X, Y = grid.centres()
    cols = [("x", "m", X), ("y", "m", Y), ("pressure_peak", "Pa", res["peak_map"]), ("t_peak", "s", res["peak_map_time"]),
            ("pressure_at_slab_peak", "Pa", res["at_peak"])]
    if res.get("filtered_peak_map") is not None:
        cols.append(("pressure_peak_filtered", "Pa", res["filtered_peak_map"]))
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow([f"{n}[{u}]" for n, u, _ in cols])
    flat = [np.asarray(v, dtype=float).reshape(-1) for _, _, v in cols]
    for k in range(len(flat[0])):
        w.writerow([repr(float(v[k])) for v in flat])
    write_atomic(path, buf.getvalue())


def frame_records(t, t_origin, every):
    """The records a VTK series shows: from t_origin [s] on (the first contact), the record
    nearest to each multiple of every [s] after it, and the last one; indices into t (increasing)."""
    t = np.asarray(t, dtype=float)
    first = int(np.searchsorted(t, t_origin - 1e-12))
    if first >= len(t):
        return []
    want = t_origin + every * np.arange(int(math.floor((t[-1] - t_origin) / every + 1e-9)) + 1)
    k = np.clip(np.searchsorted(t, want), first, len(t) - 1)
    nearer = np.where((k > first) & (np.abs(t[np.maximum(k - 1, first)] - want) < np.abs(t[k] - want)), k - 1, k)
    return sorted(set(int(v) for v in nearer) | {len(t) - 1})


def _vtk():
    try:
        from vtkmodules.util import numpy_support
        from vtkmodules.vtkCommonDataModel import vtkImageData
        from vtkmodules.vtkIOXML import vtkXMLImageDataWriter
    except ImportError as err:
        raise ImportError(f"VTK output needs VTK's Python bindings (Debian: apt-get install python3-vtk9): {err}") from None
    return numpy_support, vtkImageData, vtkXMLImageDataWriter


def _write_vti(path, grid, z, fields, time, scene_time):
    """The grid as vtkImageData in the plane z [m] to path, cell data fields (name -> map [i, j]),
    field data TimeValue (time [s]) and SceneTime (scene_time [s]), written as vtk/flex's frames
    are (inline binary, LZ4)."""
    ns, vtkImageData, writer = _vtk()
    img = vtkImageData()
    img.SetDimensions(grid.nx + 1, grid.ny + 1, 1)
    img.SetOrigin(grid.x0, grid.y0, z)
    img.SetSpacing(grid.cell, grid.cell, 1.0)

    def array(name, values):
        a = ns.numpy_to_vtk(np.ascontiguousarray(values, dtype=np.float64).reshape(-1), deep=True)
        a.SetName(name)
        return a
    for name, m in fields.items():
        img.GetCellData().AddArray(array(name, np.asarray(m).T))  # (VTK's cells: x fastest)
    fd = img.GetFieldData()
    fd.AddArray(array("TimeValue", [time]))
    fd.AddArray(array("SceneTime", [scene_time]))
    write_xml(writer(), img, path)


def write_vtk(folder, series, res, z, t_origin, every, filtered=None, scene_origin=0.0, prefix=VTK_PREFIX):
    """folder/PREFIX.pvd and its images: the maps of series (yadeflex.slab_load.PressureSeries)
    at frame_records(series.t, t_origin, every), stamped with TimeValue = t - t_origin [s] (t_origin:
    the first contact on timeseries.csv's clock, the clock of vtk/flex.pvd then), SceneTime = t +
    scene_origin [s]; filtered: the filtered pressures (records, nx, ny) or None; and
    folder/PREFIX_peak.vti with res's peak maps. Returns the .pvd's path."""
    from ..vtk_frames import _write_pvd
    os.makedirs(folder, exist_ok=True)
    grid, p = series.grid, series.pressures()
    datasets = []
    for n, k in enumerate(frame_records(series.t, t_origin, every)):
        fields = dict(pressure=p[k])
        if filtered is not None:
            fields["pressure_filtered"] = filtered[k]
        name = f"{prefix}_{n:06d}.vti"
        time = series.t[k] - t_origin
        _write_vti(os.path.join(folder, name), grid, z, fields, time, series.t[k] + scene_origin)
        datasets.append((time, 0, "slab_pressure", name))
    peak = dict(pressure_peak=res["peak_map"], pressure_at_slab_peak=res["at_peak"])
    if res.get("filtered_peak_map") is not None:
        peak["pressure_peak_filtered"] = res["filtered_peak_map"]
    _write_vti(os.path.join(folder, f"{prefix}_peak.vti"), grid, z, peak, res["at_peak_time"] - t_origin, res["at_peak_time"] + scene_origin)
    pvd = os.path.join(folder, prefix + ".pvd")
    _write_pvd(pvd, datasets)
    return pvd


def _map(ax, fig, grid, m, title, outlines, marks=()):
    """The map m [Pa] (nx, ny) in kPa with the footprints outlines ((x, y), r) [m] and marks."""
    import matplotlib.colors as mcolors
    lo, hi = float(np.min(m)) / 1e3, float(np.max(m)) / 1e3
    # white at zero, red above; supports pulling up (below zero) in blue, on the same scale
    if lo < 0:
        top = max(hi, -lo, 1e-9)
        norm, cmap = mcolors.Normalize(vmin=-top, vmax=top), "RdBu_r"
    else:
        norm, cmap = mcolors.Normalize(vmin=0.0, vmax=max(hi, 1e-9)), "Reds"
    xe, ye = grid.edges()
    im = ax.pcolormesh(xe, ye, np.asarray(m).T / 1e3, cmap=cmap, norm=norm, shading="flat")
    fig.colorbar(im, ax=ax, label="pressure [kPa]")
    for k, ((cx, cy), r) in enumerate(outlines):
        a = np.linspace(0, 2 * np.pi, 181)
        ax.plot(cx + r * np.cos(a), cy + r * np.sin(a), color="0.3", lw=1.0, ls="-", label="module" if not k else None)
    for x, y, r, style, label in marks:
        if r:
            a = np.linspace(0, 2 * np.pi, 181)
            ax.plot(x + r * np.cos(a), y + r * np.sin(a), style, color="k", lw=1.2, label=label)
        else:
            ax.plot([x], [y], style, color="k", ms=9, mew=2, label=label)
    x0, x1, y0, y1 = grid.extent()
    ax.set(xlim=(x0, x1), ylim=(y0, y1), xlabel="x [m]", ylabel="y [m]", title=title, aspect="equal")
    ax.legend(fontsize=7, loc="upper right", framealpha=0.8)


def write_png(path, series, res, outlines, slab=None, fraction=0.9):
    """slab_pressure.png: the map at the slab force's peak (the load centre and the loaded radius
    marked), each cell's largest pressure (filtered if it could be, else raw; the peak cell
    marked), the slab force over time (slab: (t [s], raw [N], filtered [N] or None, filter
    label) from timeseries.csv, else the maps' totals) and the radial profile about the load
    centre at the slab force's peak. outlines: the modules' footprints ((x, y), r) [m]."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from ..slab_load import cumulative_share, radial_profile
    grid = series.grid
    fig, ax = plt.subplots(2, 2, figsize=(12, 10))
    tp = res["at_peak_time"]
    marks = []
    if res.get("centre") is not None:
        cx, cy = res["centre"]
        marks = [(cx, cy, 0, "+", "load centre"),
                 (cx, cy, res["loaded_radius"], "--", f"loaded radius {res['loaded_radius']:.2f} m ({100 * fraction:g}%)")]
    _map(ax[0, 0], fig, grid, res["at_peak"], f"pressure at the slab force's peak ({res['at_peak_force'] / 1e3:.1f} kN, "
         f"t = {1e3 * tp:.1f} ms)\ncells {grid.cell:g} m", outlines, marks)
    filtered = res.get("filtered_peak_map") is not None
    pm = res["filtered_peak_map"] if filtered else res["peak_map"]
    at = res["filtered_peak_at"] if filtered else res["peak_at"]
    peak = res["filtered_peak"] if filtered else res["peak"]
    _map(ax[0, 1], fig, grid, pm, f"largest pressure of each cell over the run\n({'low-pass filtered' if filtered else 'raw records'}; "
         f"peak {peak / 1e3:.0f} kPa" + (f", raw {res['peak'] / 1e3:.0f} kPa)" if filtered else ")"),
         outlines, [(at[0], at[1], 0, "x", "peak cell")])
    a = ax[1, 0]
    if slab is not None:
        t, raw, filt, label = slab
        a.plot(1e3 * np.asarray(t), np.asarray(raw) / 1e3, color="C1", lw=0.6, alpha=0.4 if filt is not None else 1.0, label="raw records")
        if filt is not None:
            a.plot(1e3 * np.asarray(t), np.asarray(filt) / 1e3, color="C1", label=label)
    else:
        a.plot(1e3 * np.asarray(series.t), np.asarray(series.total) / 1e3, color="C1", label="raw records")
    a.axvline(1e3 * tp, color="0.4", ls=":", lw=1, label=f"peak: {res['at_peak_force'] / 1e3:.1f} kN at {1e3 * tp:.1f} ms")
    a.set(xlabel="t [ms]", ylabel="force on the slab [kN]", title="slab force (the map's total)")
    a.set_ylim(bottom=min(0.0, a.get_ylim()[0]))
    a.legend(fontsize=8)
    a = ax[1, 1]
    if res.get("centre") is not None:
        x, y, f = series.peak_points
        r_max = max(np.max(np.hypot(x - res["centre"][0], y - res["centre"][1])), grid.cell) + 1e-9
        r_in, p, _ = radial_profile(x, y, f, res["centre"], grid.cell, r_max)
        a.bar(r_in, p / 1e3, width=grid.cell, align="edge", color="C0", alpha=0.6, edgecolor="C0",
              label=f"mean pressure in {grid.cell:g} m rings")
        a.set(xlabel="distance from the load centre [m]", ylabel="mean pressure [kPa]",
              title="radial profile at the slab force's peak")
        a.set_ylim(bottom=min(0.0, a.get_ylim()[0]))
        b = a.twinx()
        d, within = cumulative_share(x, y, f, res["centre"])
        b.step(np.concatenate([[0.0], d, [r_in[-1] + grid.cell]]), 100 * np.concatenate([[0.0], within, within[-1:]]), where="post",
               color="C3", label="share of the slab force within r")
        b.axvline(res["loaded_radius"], color="k", ls="--", lw=1.2, label=f"loaded radius {res['loaded_radius']:.2f} m")
        b.set_ylabel("share of the slab force within r [%]")
        b.set_ylim(0, 105)
        h1, l1 = a.get_legend_handles_labels()
        h2, l2 = b.get_legend_handles_labels()
        a.legend(h1 + h2, l1 + l2, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2)
    else:
        a.set_axis_off()
        a.text(0.5, 0.5, "no downward load on the slab", ha="center", va="center", transform=a.transAxes)
    fig.suptitle("load on the slab (vertical, downward > 0)", fontsize=13)
    fig.tight_layout(rect=(0, 0, 1, 0.975))
    _save(fig, path)
    plt.close(fig)
