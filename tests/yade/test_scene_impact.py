"""The impact runner on any scene (yadeflex.boulder_impact): a boulder onto a clamped net, its records
checked against statics, the energy balance and the free fall; the named parts in its outputs;
its inputs refused with their reasons."""
import json
import math

import numpy as np
import pytest
from yade import O

import yadeflex as yf
from yadeflex import checks as C

N = 7  # nodes per side of the test net, 0.1 m apart, its border clamped


def _net():
    grid, cyls = yf.net(N, 0.1, 0.003, yf.steel(), origin=(-0.3, -0.3, 0))
    border = [grid[i][j] for i in range(N) for j in range(N) if i in (0, N - 1) or j in (0, N - 1)]
    return grid, cyls, border


def test_a_boulder_come_to_rest_on_a_net_loads_its_supports_with_every_weight(scene, tmp_path):
    """Statics: once the boulder rests on the net (numerical damping 0.5 settles it), the clamped
    border's reaction is the weight of the boulder and of the whole net (the border nodes' own
    weight included: the supports hold it), and has no horizontal part."""
    grid, cyls, border = _net()
    s = yf.boulder_impact(str(tmp_path / "out"), yf.Boulder(mass=20.0, above=(0, 0), speed=1.0), parts={"net": cyls, "border": border},
                  reactions={"border": border}, damping=0.5, duration=1.0, no_vtk=True, progress=False)
    assert s["status"] == "done", s
    rows = yf.read_csv(str(tmp_path / "out" / "timeseries.csv"))[2]
    weight = (20.0 + sum(O.bodies[n].state.mass for row in grid for n in row)) * 9.81
    # the settling decays as exp(-t/tau): measured 7e-6 of the weight left after 1 s
    assert rows["reaction_border_z"][-1] == pytest.approx(weight, rel=1e-4)
    assert abs(rows["reaction_border_x"][-1]) < 1e-4 * weight and abs(rows["reaction_border_y"][-1]) < 1e-4 * weight
    assert abs(rows["boulder_vz"][-1]) < 1e-4
    assert s["reaction_border_max"] >= weight
    params = json.loads((tmp_path / "out" / "params.json").read_text())
    assert params["parts"] == {"net": len(cyls), "border": len(border), "boulder": 1}  # (the runner names its boulder)
    assert params["reactions"] == {"border": sorted(border)}


def test_the_surface_under_a_boulder_counts_each_element_by_its_own_radius(scene):
    """Where a boulder starts (Boulder.above): a wire or a membrane reaches its own radius above
    its nodes, whatever radius the nodes are drawn with, and a wire crossing under the boulder
    counts with both ends outside its footprint (a ring of 5 mm bar on 1 mm nodes made the
    reduced module's boulder touch 2 mm into its 5 mm gap)."""
    from yadeflex.scene_impact import surface_under
    a, b = yf.node((-1.0, 0, 0), 0.001), yf.node((1.0, 0, 0), 0.001)
    yf.cylinder(a, b, 0.005, yf.steel())
    assert surface_under(0, 0, 0.05) == 0.005
    assert surface_under(0, 0.05 + 0.005, 0.05) == 0.005  # (the disc's edge touches the wire's side)
    with pytest.raises(ValueError, match="no body under"):
        surface_under(0, 0.05 + 0.006, 0.05)
    n = [yf.node(p, 0.0005) for p in ((-0.1, -0.1, 0.1), (0.1, -0.1, 0.1), (0, 0.1, 0.1))]
    yf.facet(*n, yf.geotextile(), thickness=0.004)
    assert surface_under(0, 0, 0.05) == pytest.approx(0.102, rel=1e-12)


def test_an_undamped_drop_closes_its_energy_and_checks_its_free_fall(scene, tmp_path):
    """No damping: the energy balance closes (the impact's energy against every term O.energy
    books) and the speed at the first contact is that of the fall; the filtered peak force lies
    below the raw one and the run ends by itself after the rebound."""
    _, cyls, border = _net()
    s = yf.boulder_impact(str(tmp_path / "out"), yf.Boulder(mass=20.0, above=(0, 0), drop_height=0.5), parts={"net": cyls, "border": border},
                  no_vtk=True, progress=False)
    assert s["status"] == "done" and s["exit_status"] == 0, s
    ff = s["free_fall_check"]
    assert abs(ff["v_measured"] / ff["v_expected"] - 1) < 1e-3
    assert s["impact_speed_expected"] == pytest.approx(math.sqrt(2 * 9.81 * 0.5))
    assert s["rebound"] and not s["released"]
    # the same scenes of the exactness bench close to 0.3% and better (bench/punch_energy.py)
    assert s["energy_residual_max_fraction"] < 0.01
    assert 0 < s["peak_impact_force_filtered"] <= s["peak_impact_force"]
    assert "Butterworth" in s["force_filter"]
    # the default reaction groups: the named part's supported bodies
    assert "reaction_border_max" in s and s["broken_elements_total"] == 0
    for f in ("impact.png", "energy.png", "energy.csv"):
        assert (tmp_path / "out" / f).stat().st_size > 0


def test_the_vtk_part_field_names_the_groups(scene, tmp_path):
    """The named groups get the part ids after the standard parts; every file says so
    (part_names beside the series); a contact's kind stays that of the standard parts."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
    from yadeflex import parts as P

    def read(path):
        r = vtkXMLUnstructuredGridReader()
        r.SetFileName(str(path))
        r.Update()
        g = r.GetOutput()
        names = g.GetFieldData().GetAbstractArray("part_names")
        return dict(point={k: vtk_to_numpy(g.GetPointData().GetArray(k)) for k in ("id", "part") if g.GetPointData().GetArray(k)},
                    cell={k: vtk_to_numpy(g.GetCellData().GetArray(k)) for k in ("part", "kind") if g.GetCellData().GetArray(k)},
                    names=[names.GetValue(k) for k in range(names.GetNumberOfValues())])
    _, cyls, border = _net()
    s = yf.boulder_impact(str(tmp_path / "out"), yf.Boulder(mass=20.0, above=(0, 0), speed=2.0), parts={"net": cyls, "border": border},
                  duration=0.004, vtk_every=1e-3, progress=False)
    assert s["status"] == "done", s
    names = json.loads((tmp_path / "out" / "vtk" / "flex_parts.json").read_text())
    assert names == list(P.PARTS) + ["net", "border"]
    vtk = tmp_path / "out" / "vtk"
    cyl = read(sorted(vtk.glob("flex_cylinders_0*.vtu"))[-1])
    assert set(cyl["cell"]["part"]) == {names.index("net")}
    nodes = read(sorted(vtk.glob("flex_nodes_0*.vtu"))[-1])
    part = dict(zip(nodes["point"]["id"], nodes["point"]["part"]))
    assert {part[b] for b in border} == {names.index("border")}
    assert cyl["names"] == names
    con = read(sorted(vtk.glob("flex_contacts_0*.vtu"))[-1])
    assert len(con["cell"]["kind"]) > 0 and max(con["cell"]["kind"]) <= 77


def test_inputs_are_refused_with_their_reasons(scene, tmp_path):
    with pytest.raises(C.BadValue, match="Boulder.mass"):
        yf.Boulder(mass=0.0, above=(0, 0), speed=1.0)
    with pytest.raises(ValueError, match="either at="):
        yf.Boulder(mass=1.0, speed=1.0)
    with pytest.raises(ValueError, match="either speed"):
        yf.Boulder(mass=1.0, above=(0, 0), speed=1.0, drop_height=1.0)
    with pytest.raises(C.BadValue, match="Boulder.speed"):
        yf.Boulder(mass=1.0, above=(0, 0), speed=math.nan)
    with pytest.raises(C.BadValue, match="Boulder.direction"):
        yf.Boulder(mass=1.0, above=(0, 0), speed=1.0, direction=(0, 0, 0))
    bad = tmp_path / "clump.txt"
    bad.write_text("0 0 0 0.1\n0 0 0.1 x\n")
    with pytest.raises(ValueError, match="line 2"):
        yf.Boulder(mass=1.0, above=(0, 0), speed=1.0, shape=str(bad))
    with pytest.raises(C.BadValue, match="Boulder.shape"):
        yf.Boulder(mass=1.0, above=(0, 0), speed=1.0, shape="pyramid")
    _, cyls, border = _net()
    with pytest.raises(ValueError, match="in two parts"):
        yf.name_parts({"a": cyls[:3], "b": cyls[2:5]})
    with pytest.raises(ValueError, match="part name"):
        yf.name_parts({"two words": cyls})
    with pytest.raises(C.BadValue, match="ids of existing bodies"):
        yf.name_parts({"net": [len(O.bodies) + 5]})
    with pytest.raises(TypeError, match="Boulder"):
        yf.boulder_impact(str(tmp_path / "x"), "boulder")
    with pytest.raises(C.BadValue, match="record_every"):  # (a run setting out of its declared range)
        yf.boulder_impact(str(tmp_path / "x"), yf.Boulder(mass=1.0, above=(0, 0), speed=1.0), record_every=0.5)
    # found while the run prepares: the run fails, its summary names the problem
    s = yf.boulder_impact(str(tmp_path / "free"), yf.Boulder(mass=1.0, above=(0, 0), speed=1.0), reactions={"net": cyls}, no_vtk=True, progress=False)
    assert s["status"] == "failed" and s["exit_status"] == 1 and "none of its" in s["message"] and "supported" in s["message"], s
    s = yf.boulder_impact(str(tmp_path / "far"), yf.Boulder(mass=1.0, above=(50, 50), speed=1.0), no_vtk=True, progress=False)
    assert s["status"] == "failed" and "no body under" in s["message"], s


def test_the_force_filter_keeps_a_pulse_and_removes_the_chatter():
    """A 30 ms half-sine pulse (the boulder's deceleration) with a 2 kHz ripple of half its height
    (contact chatter), sampled every 0.2 ms: the 300 Hz filter keeps the pulse's peak to 1% (its
    spectrum lies below 100 Hz) and leaves under 1% of the ripple away from the ends (within
    about 1/cutoff of either end a zero-phase filter has too few samples on one side)."""
    from yadeflex.force_filter import low_pass
    t = np.arange(0, 0.06, 2e-4)
    pulse = np.where(t < 0.03, np.sin(np.pi * t / 0.03), 0.0)
    f = low_pass(t, pulse + 0.5 * np.sin(2 * np.pi * 2000 * t))
    assert abs(f.max() - 1.0) < 0.01
    inner = (t > 0.005) & (t < t[-1] - 0.005)
    assert np.max(np.abs(f - low_pass(t, pulse))[inner]) < 0.005
    with pytest.raises(ValueError, match="Nyquist"):
        low_pass(t, pulse, cutoff_hz=3000)
    with pytest.raises(ValueError, match="too few"):
        low_pass(t[:5], pulse[:5])


def test_a_boulder_that_passes_through_ends_the_run():
    """ImpactTimes' release: no force on the boulder for `release` after its first contact ends
    the run there (it broke through, or left), not at the longest run."""
    from yadeflex.runner import ImpactTimes
    tm = ImpactTimes(0.0, release=0.02)
    for k in range(100):
        t = 1e-3 * k
        tm.observe(t, -5.0, touching=10 <= k < 30)
    assert tm.t_contact == pytest.approx(0.010) and tm.t_released == pytest.approx(0.049) and tm.end == pytest.approx(0.049)
    assert ImpactTimes(0.0).end == ImpactTimes.MAX_AFTER_CONTACT
