"""The load on the slab as a pressure map (issue 57): the kernel (yadeflex.slab_load, no scene)
against known answers, and the main job's maps on the reduced module: every record's map sums to
the slab force, the files (slab_pressure.csv, .png, vtk/slab_pressure.pvd) agree with the maps,
and mapping only reads the scene (the time series are bit for bit those of a run without it)."""
import csv
import json
import math
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from yadeflex import slab_load as SL
from yadeflex.force_filter import low_pass


# --- the kernel

def test_the_cell_side_is_one_and_a_half_largest_grains_in_whole_centimetres():
    assert SL.cell_size(0.063) == pytest.approx(0.10)  # gravel 32-63 mm: the default module
    assert SL.cell_size(0.08) == pytest.approx(0.12)  # 60-80 mm: the reduced module
    assert SL.cell_size(0.06) == pytest.approx(0.09)  # (1.5 x 0.06 is 0.09 exactly, not rounded up after round-off)
    assert SL.cell_size(0.030) == pytest.approx(0.05)  # sand 20-30 mm
    for bad in (0.0, -0.01, math.nan, math.inf):
        with pytest.raises(ValueError, match="largest grain"):
            SL.cell_size(bad)


def test_the_grid_covers_every_footprint_with_the_first_axis_at_a_cell_centre():
    from yadeflex.module import ModuleParams
    for n in (1, 3, 7):
        p = ModuleParams(n_modules=n)
        R, m = 0.5 * p.diameter, 0.25 * p.diameter
        g = SL.Grid.covering(p.centers(), R, 0.1, m)
        x0, x1, y0, y1 = g.extent()
        for cx, cy in p.centers():
            assert x0 <= cx - R - m + 1e-12 and cx + R + m <= x1 + 1e-12 and y0 <= cy - R - m + 1e-12 and cy + R + m <= y1 + 1e-12
        X, Y = g.centres()
        i, j = g.cell_of(0.0, 0.0)
        assert X[i, j] == pytest.approx(0.0, abs=1e-12) and Y[i, j] == pytest.approx(0.0, abs=1e-12)
        # no cell beyond the covered range: it ends within a cell of it
        assert x0 > min(c[0] for c in p.centers()) - R - m - g.cell and x1 < max(c[0] for c in p.centers()) + R + m + g.cell
    # the single default module: 1 m + 2 x 0.25 m over 0.1 m cells, 15 x 15 (an end on an edge adds no cell)
    g = SL.Grid.covering([(0.0, 0.0)], 0.5, 0.1, 0.25)
    assert (g.nx, g.ny) == (15, 15) and g.x0 == pytest.approx(-0.75)
    g = SL.Grid.covering([(0.0, 0.0)], 0.2, 0.12, 0.1)  # the reduced module
    assert (g.nx, g.ny) == (5, 5) and g.x0 == pytest.approx(-0.3)
    with pytest.raises(ValueError, match="cell side"):
        SL.Grid(0.0, 0.0, 0.0, 3, 3)
    with pytest.raises(ValueError, match="at least one cell"):
        SL.Grid(0.0, 0.0, 0.1, 0, 3)


def test_a_point_force_in_one_cell_gives_force_over_area_there():
    g = SL.Grid(-0.5, -0.5, 0.1, 10, 10)
    forces, outside = g.bin([0.23], [-0.41], [1500.0])
    i, j = g.cell_of(0.23, -0.41)
    assert (i, j) == (7, 0) and outside == 0.0
    assert forces[i, j] == 1500.0 and np.count_nonzero(forces) == 1
    s = SL.PressureSeries(g)
    s.add(0.0, [0.23], [-0.41], [1500.0])
    p = s.pressures()[0]
    assert p[i, j] == pytest.approx(1500.0 / 0.01, rel=1e-14) and np.count_nonzero(p) == 1
    X, Y = g.centres()
    assert (X[i, j], Y[i, j]) == pytest.approx((0.25, -0.45))
    # a point on an edge belongs to the cell to its right and above
    forces, _ = g.bin([-0.3], [0.0], [1.0])
    assert forces[2, 5] == 1.0


def test_forces_sum_exactly_and_those_outside_the_grid_are_counted():
    """map + outside = the total, to round-off, with points inside, on the edges and outside;
    the outside force is exactly that of the points outside (counted, not refused)."""
    rng = np.random.default_rng(57)
    g = SL.Grid(-0.75, -0.75, 0.1, 15, 15)
    x, y = rng.uniform(-1.0, 1.0, 2000), rng.uniform(-1.0, 1.0, 2000)
    x[:50] = -0.75 + 0.1 * rng.integers(0, 16, 50)  # on edges, the grid's far edge (outside) included
    f = rng.normal(200.0, 300.0, 2000)  # supports pulling up too
    forces, outside = g.bin(x, y, f)
    out = ~((x >= -0.75) & (x < 0.75) & (y >= -0.75) & (y < 0.75))
    assert out.sum() > 100
    assert outside == pytest.approx(math.fsum(f[out]), rel=1e-12)
    assert forces.sum() + outside == pytest.approx(math.fsum(f), rel=1e-12, abs=1e-9)
    assert forces.sum() == pytest.approx(math.fsum(f[~out]), rel=1e-12)
    for bad in ([math.nan], [math.inf]):
        with pytest.raises(ValueError, match="finite"):
            g.bin([0.0], bad, [1.0])
    with pytest.raises(ValueError, match="one length"):
        g.bin([0.0, 0.1], [0.0], [1.0])
    forces, outside = g.bin([], [], [])
    assert forces.shape == (15, 15) and not forces.any() and outside == 0.0


def _uniform_disc(R, h, centre=(0.0, 0.0), p0=1e5):
    """A uniform pressure p0 [Pa] on a disc of radius R [m] as point forces on a square lattice of pitch h [m]."""
    k = np.arange(-math.ceil(R / h), math.ceil(R / h) + 1) * h
    X, Y = np.meshgrid(k, k, indexing="ij")
    inside = np.hypot(X, Y) <= R
    return X[inside] + centre[0], Y[inside] + centre[1], np.full(inside.sum(), p0 * h * h)


def test_a_uniform_load_on_a_disc_has_its_loaded_radius_at_sqrt_090_r():
    R, h = 0.4, 0.002
    x, y, f = _uniform_disc(R, h, centre=(0.13, -0.07))
    c = SL.load_centre(x, y, f)
    assert c == pytest.approx((0.13, -0.07), abs=1e-12)
    assert SL.loaded_radius(x, y, f) == pytest.approx(math.sqrt(0.9) * R, abs=h)
    assert SL.loaded_radius(x, y, f, fraction=0.5) == pytest.approx(math.sqrt(0.5) * R, abs=h)
    assert SL.loaded_radius(x, y, f, fraction=1.0) == pytest.approx(R, abs=h)
    # its radial profile: the pressure in each ring is p0; the share within r is (r / R)^2
    r_in, p, share = SL.radial_profile(x, y, f, c, 0.05, R)
    assert np.allclose(p, 1e5, rtol=0.02)
    assert np.allclose(share, ((r_in + 0.05) / R) ** 2, atol=0.01)
    # one point force: radius 0; no downward load: no centre, no radius
    assert SL.loaded_radius([0.3], [0.2], [10.0]) == 0.0
    assert SL.load_centre([0.0, 1.0], [0.0, 0.0], [1.0, -1.0]) is None and SL.loaded_radius([0.0], [0.0], [0.0]) is None
    # two equal forces 1 m apart: the centre between them, 90% needs both: 0.5 m
    assert SL.loaded_radius([0.0, 1.0], [0.0, 0.0], [5.0, 5.0]) == pytest.approx(0.5)
    with pytest.raises(ValueError, match="fraction"):
        SL.loaded_radius(x, y, f, fraction=0.0)


def test_the_series_gives_the_peak_the_slab_peak_and_the_filtered_peak():
    """A moving, growing then fading load: the peak pressure is the largest cell pressure at any
    record (its cell, its time); the map at the slab force's peak is that record's; the filtered
    maps are each cell's history filtered, so they sum to the filtered total force (the filter is
    linear)."""
    g = SL.Grid(-0.55, -0.55, 0.1, 11, 11)
    s = SL.PressureSeries(g)
    t = np.arange(0, 0.04, 2e-4)
    F = 1e5 * np.sin(np.pi * t / 0.04) ** 2
    for k, tk in enumerate(t):
        x, y, f = _uniform_disc(0.3, 0.02)
        # most of the load spread, a concentrated part under a point that moves along x
        s.add(tk, np.append(x, 0.2 * tk / 0.04 - 0.1), np.append(y, 0.02), np.append(0.7 * F[k] * f / f.sum(), 0.3 * F[k]))
    res = s.results(low_pass=low_pass)
    p = s.pressures()
    kmax = int(np.argmax(F))
    assert res["at_peak_time"] == t[kmax] and res["at_peak_force"] == pytest.approx(F[kmax], rel=1e-12)
    assert np.array_equal(res["at_peak"], p[kmax])
    assert res["peak"] == p.max() and res["peak_time"] == t[int(np.argmax(p.max(axis=(1, 2))))]
    i, j = g.cell_of(*res["peak_at"])
    assert res["peak_map"][i, j] == res["peak"] and np.array_equal(res["peak_map"], p.max(axis=0))
    assert res["peak_map_time"][i, j] == res["peak_time"] and np.isnan(res["peak_map_time"][0, 0])  # (a corner: never loaded)
    assert res["outside_max"] == 0.0 and res["cell"] == 0.1 and res["records"] == len(t)
    # the concentrated part moves off the centre: the load centre follows 30% of it
    assert res["centre"] == pytest.approx((0.3 * (0.2 * t[kmax] / 0.04 - 0.1), 0.3 * 0.02), abs=1e-9)
    assert 0 < res["loaded_radius"] < 0.3
    filtered_total = res["filtered"].sum(axis=(1, 2)) * g.area
    assert np.allclose(filtered_total, low_pass(t, s.total), rtol=0, atol=1e-9 * F.max())
    assert res["filtered_peak"] == pytest.approx(res["filtered"].max()) and res["filtered_peak"] <= 1.05 * res["peak"]
    # too few records to filter: said, the raw results kept
    short = SL.PressureSeries(g)
    for k in range(5):
        short.add(k * 2e-4, [0.0], [0.0], [1.0])
    r = short.results(low_pass=low_pass)
    assert r["filtered_peak"] is None and "too few" in r["filter_error"] and r["peak"] == pytest.approx(100.0)
    assert SL.PressureSeries(g).results() == dict(cell=0.1, fraction=0.9, records=0)


# --- the main job's maps, reduced module

@pytest.fixture(scope="module")
def mapped_run(module_cache, tmp_path_factory):
    """The reduced module's impact in this process with VTK output, its SlabMap kept."""
    from yade import O
    from yadeflex.module import ModuleParams
    from yadeflex.module import impact as I
    made = []
    init = I.SlabMap.__init__

    def keep(self, *a, **kw):
        init(self, *a, **kw)
        made.append(self)
    out = tmp_path_factory.mktemp("slab") / "run"
    O.reset()
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(I.SlabMap, "__init__", keep)
        s = I.run_impact(ModuleParams.small(), str(out), cache_dir=module_cache, progress=False)
    O.reset()
    assert s["status"] == "done", s
    rows = [{k.split("[")[0]: float(v) for k, v in r.items()} for r in csv.DictReader(open(out / "timeseries.csv"))]
    return out, s, rows, made[-1]


def test_every_records_map_sums_to_the_slab_force(mapped_run):
    out, s, rows, sm = mapped_run
    series = sm.series
    assert len(series) == len(rows) > 50 and [r["t"] for r in rows] == series.t
    slab = np.array([r["slab_force"] for r in rows])
    mapped = series.pressures().sum(axis=(1, 2)) * sm.grid.area + np.array(series.outside)
    assert np.max(np.abs(mapped - slab)) <= 1e-9 * np.max(np.abs(slab)), np.max(np.abs(mapped - slab) / np.max(np.abs(slab)))
    assert np.max(np.abs(np.array(series.total) - slab)) <= 1e-9 * np.max(np.abs(slab))
    assert s["slab_force_outside_grid_max"] == 0.0  # the grid holds the whole load
    assert s["slab_force_peak_time"] == rows[int(np.argmax(slab))]["t"]


def test_the_summary_gives_the_peak_pressure_and_the_loaded_radius(mapped_run):
    out, s, rows, sm = mapped_run
    R = 0.2
    assert s["slab_pressure_cell"] == pytest.approx(0.12)
    assert s == json.loads((out / "summary.json").read_text())
    # the peak pressure: at least the mean pressure of the peak slab force over the footprint
    assert s["slab_pressure_peak"] > s["slab_force_max"] / (math.pi * R * R)
    assert 0 < s["slab_pressure_peak_filtered"] <= s["slab_pressure_peak"]
    assert all(abs(v) <= R + 0.12 for v in s["slab_pressure_peak_at"])
    assert 0 < s["slab_loaded_radius"] < R + 0.05
    assert math.hypot(*s["slab_load_centre"]) < 0.5 * R
    d = s["slab_pressure_definitions"]
    assert {"slab_pressure", "slab_pressure_peak", "slab_loaded_radius", "slab_pressure_cell"} <= set(d) and "90%" in d["slab_loaded_radius"]


def test_the_peak_maps_csv_and_png(mapped_run):
    out, s, rows, sm = mapped_run
    assert (out / "slab_pressure.png").stat().st_size > 20000
    with open(out / "slab_pressure.csv", newline="") as fh:
        r = csv.reader(fh)
        header = next(r)
        table = np.array([[float(v) for v in row] for row in r])
    assert header == ["x[m]", "y[m]", "pressure_peak[Pa]", "t_peak[s]", "pressure_at_slab_peak[Pa]", "pressure_peak_filtered[Pa]"]
    g = sm.grid
    assert len(table) == g.nx * g.ny
    assert table[:, 2].max() == s["slab_pressure_peak"]
    k = int(np.argmax(table[:, 2]))
    assert list(table[k, :2]) == pytest.approx(s["slab_pressure_peak_at"]) and table[k, 3] == s["slab_pressure_peak_time"]
    assert math.fsum(table[:, 4]) * g.area == pytest.approx(s["slab_force_max"], rel=1e-9)
    assert table[:, 5].max() == pytest.approx(s["slab_pressure_peak_filtered"], rel=1e-12)


def test_the_vtk_series_holds_the_maps(mapped_run):
    """vtk/slab_pressure.pvd: an image per VTK frame interval from the first contact, on the
    clock of vtk/flex.pvd, each the map of its record (cells in VTK's order: x fastest); the
    peak maps in slab_pressure_peak.vti."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOXML import vtkXMLImageDataReader
    out, s, rows, sm = mapped_run
    vtk = out / "vtk"
    sets = [(float(d.get("timestep")), d.get("file")) for d in ET.parse(vtk / "slab_pressure.pvd").getroot().iter("DataSet")]
    flex = sorted({float(d.get("timestep")) for d in ET.parse(vtk / "flex.pvd").getroot().iter("DataSet")})
    times = [t for t, _ in sets]
    assert len(sets) >= 10 and times == sorted(times) and times[0] == pytest.approx(0.0, abs=2e-4)
    assert times[-1] == pytest.approx(flex[-1], abs=1e-3)  # the same clock, to the end
    g, series = sm.grid, sm.series
    t0 = s["free_fall_check"]["t"]

    def read(path):
        r = vtkXMLImageDataReader()
        r.SetFileName(str(path))
        r.Update()
        return r.GetOutput()
    for t, f in sets[::5] + sets[-1:]:
        img = read(vtk / f)
        assert img.GetDimensions() == (g.nx + 1, g.ny + 1, 1) and img.GetSpacing()[:2] == pytest.approx((g.cell, g.cell))
        k = series.t.index(min(series.t, key=lambda v: abs(v - t0 - t)))
        assert series.t[k] - t0 == pytest.approx(t, abs=1e-12)
        p = vtk_to_numpy(img.GetCellData().GetArray("pressure"))
        assert np.array_equal(p.reshape(g.ny, g.nx).T, series.pressures()[k])
        assert img.GetCellData().GetArray("pressure_filtered") is not None
        assert vtk_to_numpy(img.GetFieldData().GetArray("TimeValue"))[0] == pytest.approx(t)
    peak = read(vtk / "slab_pressure_peak.vti")
    assert vtk_to_numpy(peak.GetCellData().GetArray("pressure_peak")).max() == s["slab_pressure_peak"]


def test_mapping_only_reads_and_an_earlier_runs_maps_are_removed(mapped_run, module_cache, tmp_path):
    """Into the folder of the VTK run, a --no-vtk run removes its maps' VTK files (and the
    runner its frames); its time series are bit for bit those of a run whose map records nothing."""
    from yade import O
    from yadeflex.module import ModuleParams
    from yadeflex.module import impact as I
    out = mapped_run[0]
    O.reset()
    s = I.run_impact(ModuleParams.small(), str(out), cache_dir=module_cache, progress=False, no_vtk=True)
    assert s["status"] == "done" and not (out / "vtk").exists()
    assert (out / "slab_pressure.csv").exists()
    O.reset()
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(I.SlabMap, "record", lambda self, t, supports: None)
        bare = I.run_impact(ModuleParams.small(), str(tmp_path / "bare"), cache_dir=module_cache, progress=False, no_vtk=True)
    O.reset()
    assert bare["status"] == "done" and bare["slab_pressure_peak"] is None and not (tmp_path / "bare" / "slab_pressure.csv").exists()
    for f in ("timeseries.csv", "energy.csv"):
        assert (out / f).read_bytes() == (tmp_path / "bare" / f).read_bytes(), f
