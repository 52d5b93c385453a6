"""Results output: VTK time series read back with VTK's own reader, energy CSV, plots."""
import csv
import math
import os
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkFiltersVerdict import vtkCellSizeFilter
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from yade import O
from yade.minieigenHP import Quaternion, Vector3
from yade.wrapper import Body, Box, FlexNode, FrictMat

import yadeflex as yf
import yadeflex.harness.membrane_scenes as MS
import yadeflex.harness.scenes as S


# ---- helpers ----------------------------------------------------------------------------------

def _read_pvd(path):
    """[(time, name, part, file)] in file order (the .pvd is plain XML)."""
    root = ET.parse(path).getroot()
    assert root.get("type") == "Collection"
    return [(float(d.get("timestep")), d.get("name"), int(d.get("part")), d.get("file")) for d in root.iter("DataSet")]


def _frames(path):
    """[(time, [(name, file), ...])] grouped by time, in file order."""
    out = []
    for t, name, part, f in _read_pvd(path):
        if not out or out[-1][0] != t:
            out.append((t, []))
        assert part == len(out[-1][1])
        out[-1][1].append((name, f))
    return out


def _read(path):
    r = vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    assert r.GetErrorCode() == 0, path
    return r.GetOutput()


def _pd(g, name):
    a = g.GetPointData().GetArray(name)
    assert a is not None, name
    return vtk_to_numpy(a)


def _cd(g, name):
    a = g.GetCellData().GetArray(name)
    assert a is not None, name
    return vtk_to_numpy(a)


def _points(g):
    return vtk_to_numpy(g.GetPoints().GetData()) if g.GetNumberOfPoints() else np.zeros((0, 3))


def _cell_point_ids(g, k):
    c = g.GetCell(k)
    return [c.GetPointId(j) for j in range(c.GetNumberOfPoints())]


def _vec(v):
    return np.array([v[0], v[1], v[2]])


def _mixed_scene():
    """A TECCO-wire chain clamped at both ends with its middle node pulled down (tension, per-link
    slack), a 2 x 2 geotextile sheet with its centre node lifted (membrane tension) and a
    falling sphere, far from each other."""
    nodes, cyls = yf.chain([(0, 0, 0), (1, 0, 0)], 0.0015, yf.tecco_wire(), segments=4, fixed=[0, 4])
    O.bodies[nodes[2]].state.pos += Vector3(0, 0, -0.02)
    sh = yf.sheet(2, 2, (1, 1), 0.002, yf.geotextile(), origin=(0, 2, 0))
    O.bodies[sh["grid"][1][1]].state.pos += Vector3(0, 0, 0.05)
    s = S.sphere((3, 0, 1), 0.05, velocity=(1, 2, -3))
    O.engines = yf.engines()
    return dict(nodes=nodes, cylinders=cyls, sheet=sh, sphere=s)


# ---- VTK time series ----------------------------------------------------------------------------

def test_vtk_series_matches_scene(scene, tmp_path):
    sc = _mixed_scene()
    rec = yf.VtkRecorder(str(tmp_path), prefix="run", every=2)
    written = [rec() is not None]
    for _ in range(4):
        O.step()
        written.append(rec() is not None)
    assert written == [True, False, True, False, True]  # iterations 0, 2, 4

    frames = _frames(rec.pvd)
    assert [len(fr) for _, fr in frames] == [4, 4, 4]
    times = [t for t, _ in frames]
    assert times[0] == 0.0 and all(b > a for a, b in zip(times, times[1:]))
    assert times[-1] == O.time
    assert [n for n, _ in frames[-1][1]] == ["nodes", "cylinders", "facets", "spheres"]
    files = {n: os.path.join(str(tmp_path), f) for n, f in frames[-1][1]}
    assert all(os.path.basename(f).endswith("_000002.vtu") for f in files.values())

    all_nodes = [b for b in O.bodies if b is not None and isinstance(b.shape, FlexNode)]
    g = _read(files["nodes"])
    assert g.GetNumberOfPoints() == g.GetNumberOfCells() == len(all_nodes) == 5 + 9
    assert vtk_to_numpy(g.GetFieldData().GetArray("TimeValue"))[0] == O.time
    assert vtk_to_numpy(g.GetFieldData().GetArray("Iteration"))[0] == O.iter == 4
    ids = _pd(g, "id")
    assert list(ids) == [b.id for b in all_nodes]
    for k, b in enumerate(all_nodes):
        assert np.array_equal(_points(g)[k], _vec(b.state.pos))
        assert np.array_equal(_pd(g, "velocity")[k], _vec(b.state.vel))
        assert _pd(g, "mass")[k] == b.state.mass
        assert _pd(g, "blockedDOFs")[k] == len(b.state.blockedDOFs)
    assert np.max(np.abs(_pd(g, "velocity"))) > 0  # the comparison is not between zeros

    g = _read(files["cylinders"])
    cyls = sc["cylinders"]
    assert g.GetNumberOfCells() == len(cyls) == 4 and g.GetNumberOfPoints() == 5
    pid, pos = _pd(g, "id"), _points(g)
    assert list(_cd(g, "id")) == cyls
    for k, c in enumerate(cyls):
        sh = O.bodies[c].shape
        assert [pid[j] for j in _cell_point_ids(g, k)] == [sh.node1, sh.node2]
        for j, n in zip(_cell_point_ids(g, k), (sh.node1, sh.node2)):
            assert np.array_equal(pos[j], _vec(O.bodies[n].state.pos))
        for f in ("radius", "axialForce", "strain", "plasticStrain", "wireSlack", "elasticEnergy"):
            assert _cd(g, f)[k] == getattr(sh, f), f
    assert np.max(np.abs(_cd(g, "axialForce"))) > 1.0
    assert len(set(_cd(g, "wireSlack"))) == 4  # per-link values, so a mix-up of cells would show

    g = _read(files["facets"])
    fac = sc["sheet"]["facets"]
    assert g.GetNumberOfCells() == len(fac) == 8 and g.GetNumberOfPoints() == 9
    pid, pos = _pd(g, "id"), _points(g)
    for k, f in enumerate(fac):
        sh = O.bodies[f].shape
        assert _cd(g, "id")[k] == f
        assert [pid[j] for j in _cell_point_ids(g, k)] == [sh.node1, sh.node2, sh.node3]
        for j, n in zip(_cell_point_ids(g, k), (sh.node1, sh.node2, sh.node3)):
            assert np.array_equal(pos[j], _vec(O.bodies[n].state.pos))
        for name in ("n1", "n2", "e1", "e2", "elasticEnergy", "radius"):
            assert _cd(g, name)[k] == getattr(sh, name), name
    assert np.min(_cd(g, "n1")) > 0

    g = _read(files["spheres"])
    b = O.bodies[sc["sphere"]]
    assert g.GetNumberOfPoints() == g.GetNumberOfCells() == 1
    assert np.array_equal(_points(g)[0], _vec(b.state.pos))
    assert _pd(g, "radius")[0] == 0.05 and _pd(g, "id")[0] == b.id
    assert np.array_equal(_pd(g, "velocity")[0], _vec(b.state.vel))
    assert _pd(g, "speed")[0] == pytest.approx(b.state.vel.norm(), rel=1e-15)


def test_vtk_groups_appearing_and_vanishing_keep_the_blocks(scene, tmp_path):
    """A sphere added after the first frame and erased before the last: every frame lists the same
    blocks; the frames without it point to one empty file; the erased body is skipped."""
    yf.chain([(0, 0, 0), (1, 0, 0)], 0.002, yf.steel(), segments=3, fixed=[0])
    O.engines = yf.engines()
    rec = yf.VtkRecorder(str(tmp_path / "out"))
    rec()
    s = S.sphere((3, 0, 1), 0.05)
    O.step()
    rec()
    O.bodies.erase(s)
    O.step()
    rec()
    frames = _frames(rec.pvd)
    assert [[n for n, _ in fr] for _, fr in frames] == [["nodes", "cylinders", "spheres"]] * 3
    sph = [dict(fr)["spheres"] for _, fr in frames]
    assert sph[0] == sph[2] == "flex_spheres_empty.vtu" and sph[1] == "flex_spheres_000001.vtu"
    empty, full = (_read(str(tmp_path / "out" / f)) for f in sph[:2])
    assert empty.GetNumberOfPoints() == empty.GetNumberOfCells() == 0
    assert full.GetNumberOfPoints() == 1
    names = lambda g: sorted(g.GetPointData().GetArrayName(i) for i in range(g.GetPointData().GetNumberOfArrays()))
    assert names(empty) == names(full)
    assert not os.path.exists(tmp_path / "out" / "flex_facets_empty.vtu")  # never had a body: no file


def test_vtk_runner_every_and_pvd_valid_after_each_frame(scene, tmp_path):
    yf.chain([(0, 0, 0), (1, 0, 0)], 0.002, yf.steel(), segments=2, fixed=[0])
    O.engines = yf.engines()
    rec = yf.VtkRecorder(str(tmp_path), every=3)
    O.engines = O.engines + [rec.runner()]
    counts = []
    for _ in range(7):
        O.step()
        counts.append(len(_frames(rec.pvd)))  # parses after every step: the .pvd is always complete XML
    assert counts == [1, 1, 1, 2, 2, 2, 3]
    its = [rec.frames[k][1] for k in range(3)]
    assert its == [0, 3, 6]
    for k, (_, fr) in enumerate(_frames(rec.pvd)):
        g = _read(os.path.join(str(tmp_path), dict(fr)["cylinders"]))
        assert vtk_to_numpy(g.GetFieldData().GetArray("Iteration"))[0] == its[k]
    assert not [f for f in os.listdir(tmp_path) if f.startswith(".tmp")]


def test_vtk_an_earlier_series_does_not_survive(scene, tmp_path):
    """A new recorder removes the series an earlier one wrote with its prefix (a longer run's
    frames would stand next to the new ones, outside the new .pvd), not other files."""
    yf.chain([(0, 0, 0), (1, 0, 0)], 0.002, yf.steel(), segments=2, fixed=[0])
    O.engines = yf.engines()
    first = yf.VtkRecorder(str(tmp_path))
    for _ in range(3):
        first()
        O.step()
    (tmp_path / "notes.txt").write_text("the user's\n")
    (tmp_path / "other.pvd").write_text("another series\n")
    second = yf.VtkRecorder(str(tmp_path))
    assert sorted(os.listdir(tmp_path)) == ["notes.txt", "other.pvd"]
    second()
    named = {f for _, fr in _frames(second.pvd) for _, f in fr}
    assert {f for f in os.listdir(tmp_path) if f.endswith(".vtu")} == named | {f"flex_{g}_empty.vtu" for g in second.groups}


def test_vtk_boxes_and_rigid_facets(scene, tmp_path):
    """Hexahedra in VTK's corner order (a wrong order gives a wrong or negative volume)."""
    from yade import utils
    mat = FrictMat()
    O.materials.append(mat)
    b = Body()
    b.shape = Box(extents=(0.1, 0.2, 0.3))
    b.material = mat
    b.state.pos = (1, 2, 3)
    b.state.ori = Quaternion(Vector3(1, 2, 3).normalized(), 0.7)
    b.state.vel = (0.5, 0, 0)
    box = O.bodies.append(b)
    fct = O.bodies.append(utils.facet([(0, 0, 0), (1, 0, 0), (0, 1, 1)]))
    paths = yf.write_vtk_snapshot(str(tmp_path), "snap")
    assert sorted(paths) == ["boxes", "pvd", "rigid_facets"]
    assert [(n, f) for _, n, _, f in _read_pvd(paths["pvd"])] == [("boxes", "snap_boxes.vtu"), ("rigid_facets", "snap_rigid_facets.vtu")]

    g = _read(paths["boxes"])
    assert g.GetNumberOfCells() == 1 and g.GetCellType(0) == 12
    f = vtkCellSizeFilter()
    f.SetInputData(g)
    f.Update()
    vol = vtk_to_numpy(f.GetOutput().GetCellData().GetArray("Volume"))[0]
    assert vol == pytest.approx(8 * 0.1 * 0.2 * 0.3, rel=1e-12)
    assert np.allclose(_points(g).mean(axis=0), [1, 2, 3], atol=1e-14)
    assert np.array_equal(_cd(g, "velocity")[0], [0.5, 0, 0]) and _cd(g, "id")[0] == box
    assert np.allclose(_cd(g, "extents")[0], [0.1, 0.2, 0.3])

    g = _read(paths["rigid_facets"])
    assert g.GetNumberOfCells() == 1 and g.GetCellType(0) == 5 and _cd(g, "id")[0] == fct
    assert np.allclose(_points(g), [[0, 0, 0], [1, 0, 0], [0, 1, 1]], atol=1e-14)


def test_vtk_bad_arguments(scene, tmp_path):
    with pytest.raises(ValueError, match="every"):
        yf.VtkRecorder(str(tmp_path), every=0)
    with pytest.raises(ValueError, match="prefix"):
        yf.VtkRecorder(str(tmp_path), prefix="a/b")


def _contact_scene():
    """A sphere touching a clamped steel chain, a second sphere on the first, a clump of two
    spheres on the second, each 10 um into the one below: contacts of three kinds, with forces,
    after two steps."""
    from yade import utils
    nodes, cyls = yf.chain([(-0.5, 0, 0), (0.5, 0, 0)], 0.005, yf.steel(), segments=4, fixed=[0, 4])
    a = S.sphere((0, 0, 0.05499), 0.05)  # each 10 um into the one below
    b = S.sphere((0, 0, 0.15498), 0.05)
    mat = O.bodies[a].material
    zc = 0.15498 + math.sqrt(0.08 ** 2 - 0.02 ** 2) - 1e-5
    clump = O.bodies.appendClumped([utils.sphere((-0.02, 0, zc), 0.03, material=mat), utils.sphere((0.02, 0, zc), 0.03, material=mat)])[0]
    O.engines = yf.engines()
    O.run(2, True)
    return dict(nodes=nodes, cylinders=cyls, a=a, b=b, clump=clump, members=sorted(O.bodies[clump].shape.members.keys()))


def test_vtk_contacts_parts_and_clumps(scene, tmp_path):
    sc = _contact_scene()
    P = yf.parts
    parts = dict.fromkeys(sc["cylinders"] + sc["nodes"], P.PART["mesh"])
    rec = yf.VtkRecorder(str(tmp_path), parts=parts)
    files = rec()
    g = _read(files["contacts"])
    inters = yf.output.real_contacts()
    pairs = {tuple(sorted((i.id1, i.id2))) for i in inters}
    # the sphere on the chain (one owned contact), sphere on sphere, clump members on the sphere
    assert any(sc["a"] in p and set(p) & set(sc["cylinders"]) for p in pairs)
    assert (sc["a"], sc["b"]) in pairs and any(sc["b"] in p and set(p) & set(sc["members"]) for p in pairs)
    assert g.GetNumberOfCells() == len(inters) and g.GetNumberOfPoints() == 2 * len(inters)
    pts = _points(g)
    kinds = {}
    for k, i in enumerate(inters):
        assert (_cd(g, "id1")[k], _cd(g, "id2")[k]) == (i.id1, i.id2)
        assert np.array_equal(_cd(g, "normalForce")[k], _vec(i.phys.normalForce))
        assert np.array_equal(_cd(g, "shearForce")[k], _vec(i.phys.shearForce))
        assert np.array_equal(_cd(g, "contactPoint")[k], _vec(i.geom.contactPoint))
        assert np.array_equal(_cd(g, "normal")[k], _vec(i.geom.normal))
        assert _cd(g, "fn")[k] == pytest.approx(i.phys.normalForce.norm(), rel=1e-14)
        assert _cd(g, "force")[k] == pytest.approx((i.phys.normalForce + i.phys.shearForce).norm(), rel=1e-14)
        # the force-chain line joins the two sides' centres, which hold the contact point between them
        assert np.array_equal(pts[2 * k], _vec(i.geom.axis1)) and np.array_equal(pts[2 * k + 1], _vec(i.geom.axis2))
        c = _vec(i.geom.contactPoint)
        seg = pts[2 * k + 1] - pts[2 * k]
        u = np.dot(c - pts[2 * k], seg) / np.dot(seg, seg)
        assert -1e-9 < u < 1 + 1e-9 and np.linalg.norm(pts[2 * k] + u * seg - c) < 1e-9
        kinds[tuple(sorted((i.id1, i.id2)))] = int(_cd(g, "kind")[k])
    # they press on each other: the forces are not zeros, except on a contact that started unloaded
    # (the sphere on the chain's middle node, as the chain bends under it, touches the second
    # segment beside the first: a new contact at the first one's overlap, which takes no force
    # until it goes deeper; see FlexContactGeom.plasticOverlap)
    for k, i in enumerate(inters):
        if getattr(i.geom, "plasticOverlap", 0.0) < i.geom.penetrationDepth:
            assert _cd(g, "fn")[k] > 1.0, (i.id1, i.id2)
    names = {P.contact_kind_name(k) for k in kinds.values()}
    assert names == {"mesh-grain", "grain-grain", "grain-boulder"}, names
    assert kinds[(sc["a"], sc["b"])] == 66

    # part ids: given ones, then by shape (clump members: boulder, spheres: grain)
    sp = _read(files["spheres"])
    part = dict(zip(_pd(sp, "id"), _pd(sp, "part")))
    assert part[sc["a"]] == part[sc["b"]] == P.PART["grain"]
    assert all(part[m] == P.PART["boulder"] for m in sc["members"])
    cy = _read(files["cylinders"])
    assert set(_cd(cy, "part")) == {P.PART["mesh"]} and set(_cd(cy, "broken")) == {0}
    assert set(_pd(_read(files["nodes"]), "part")) == {P.PART["mesh"]}
    # the clump as the box around its members, in its own frame: 0.1 x 0.06 x 0.06 m
    cl = _read(files["clumps"])
    assert cl.GetNumberOfCells() == 1 and cl.GetCellType(0) == 12 and _cd(cl, "id")[0] == sc["clump"]
    assert _cd(cl, "part")[0] == P.PART["boulder"]
    f = vtkCellSizeFilter()
    f.SetInputData(cl)
    f.Update()
    assert vtk_to_numpy(f.GetOutput().GetCellData().GetArray("Volume"))[0] == pytest.approx(0.1 * 0.06 * 0.06, rel=1e-9)
    assert np.allclose(_points(cl).mean(axis=0), _vec(O.bodies[sc["clump"]].state.pos), atol=1e-12)


def test_module_parts_from_the_module_ids(scene):
    P = yf.parts
    ids = dict(grains=[1, 2], wall=0, rope=[30], rope_nodes=[31], modules=[
        dict(mesh_cylinders=[10], mesh_nodes=[11, 12], ring_top=[13], ring_bottom=[14], lining=[20], lining_nodes=[21]),
        dict(mesh_cylinders=[40], mesh_nodes=[41], ring_top=[42], ring_bottom=[43], lining=[44], lining_nodes=[45])])
    from yadeflex.module.ids import module_parts
    got = module_parts(ids)
    want = {0: "slab", 1: "grain", 2: "grain", 30: "rope", 31: "rope", 10: "mesh", 11: "mesh", 12: "mesh", 13: "ring", 14: "ring",
            20: "lining", 21: "lining", 40: "mesh", 41: "mesh", 42: "ring", 43: "ring", 44: "lining", 45: "lining"}
    assert {k: P.PARTS[v] for k, v in got.items()} == want
    assert P.contact_kind_name(P.contact_kind(P.PART["boulder"], P.PART["grain"])) == "grain-boulder"
    with pytest.raises(ValueError, match="contact kind"):
        P.contact_kind_name(76)


def test_module_ids_are_typed_and_read_as_their_stored_dictionary():
    """ModuleIds (yadeflex.module.ids): made from the stored dictionary, it reads as it (the top
    level also as the first module), stores back the same, gathers a key over every module, and
    names a body by the first key it is under; anything else is refused with its reason."""
    from yadeflex.module.ids import ModuleIds, ModuleStructureIds
    m0 = dict(center=[0.0, 0.0], mesh_cylinders=[10], mesh_nodes=[11, 12], ring_top=[13], ring_bottom=[14], lining=[20],
              lining_nodes=[21], base_nodes=[11], mesh_params=dict(opening=0.083))
    m1 = dict(center=[1.0, 0.0], mesh_cylinders=[40], mesh_nodes=[41], ring_top=[42], ring_bottom=[43], lining=[44],
              lining_nodes=[45], base_nodes=[41], mesh_params=dict(opening=0.083))
    stored = dict(m0, wall=0, grains=[1, 2], modules=[m0, m1], rope=[30], rope_nodes=[31], base_nodes=[11, 41])
    ids = ModuleIds.of(stored)
    assert isinstance(ids.modules[1], ModuleStructureIds) and ids.modules[1].center == (1.0, 0.0)
    assert ids.to_dict() == stored and ModuleIds.from_json(ids.to_json()) == ids
    assert ids["mesh_nodes"] == [11, 12] and ids["grains"] == [1, 2] and ids.get("rope") == [30] and "lining" in ids
    assert dict(ids)["modules"][1]["lining"] == [44]
    assert ids.bodies("mesh_nodes") == {11, 12, 41} and ids.bodies("wall") == {0} and ids.bodies("rope") == {30}
    assert ids.names()[13] == "top ring" and ids.names()[44] == "lining facet" and 0 not in ids.names()
    assert ids.parts()[0] == "slab" and ids.parts()[45] == "lining" and ids.parts()[31] == "rope"
    assert ids.broken_kinds() == {10: "broken_wire_legs", 40: "broken_wire_legs", 13: "broken_ring_segments", 14: "broken_ring_segments",
                                  42: "broken_ring_segments", 43: "broken_ring_segments", 20: "broken_lining_facets",
                                  44: "broken_lining_facets", 30: "broken_rope_segments"}
    with pytest.raises(TypeError, match="no 'modules' key"):
        ModuleIds.of({"lining_nodes": [21]})
    with pytest.raises(TypeError, match="lining must be a list of body ids"):
        ModuleIds.of(dict(modules=[dict(lining=7)]))
    with pytest.raises(KeyError, match="no key 'meshnodes'"):
        ids.bodies("meshnodes")


def test_vtk_broken_elements_stay_as_broken(scene, tmp_path):
    """An element erased as ruptured stays in the later frames, between its nodes, broken = 1,
    with no force; the series time counts from time_origin and SceneTime is O.time."""
    mat = yf.steel(tensile_strength=400e6)
    s = S.cantilever(segments=3, length=0.3, radius=0.002, load="axial", force=0.0, material=mat)
    O.forces.setPermF(s["tip"], Vector3(1.2 * 400e6 * math.pi * 0.002 ** 2, 0, 0))
    el = next(e for e in O.engines if type(e).__name__ == "FlexElementEngine")
    dt0 = O.dt
    t0 = O.time + 5 * dt0
    rec = yf.VtkRecorder(str(tmp_path), time_origin=t0)
    rec()
    for _ in range(20000):
        O.step()
        if el.nRuptured:
            break
    assert el.nRuptured == 1
    broken = el.rupturedIds[0]
    rec()
    O.step()
    last = rec()
    g = _read(last["cylinders"])
    ids, br = list(_cd(g, "id")), _cd(g, "broken")
    assert sorted(ids) == sorted(s["cylinders"]) and O.bodies[broken] is None
    k = ids.index(broken)
    assert br[k] == 1 and sum(br) == 1 and _cd(g, "axialForce")[k] == 0.0 and _cd(g, "radius")[k] == 0.002
    n1, n2 = (O.bodies[s["nodes"][j]] for j in (s["cylinders"].index(broken), s["cylinders"].index(broken) + 1))
    pid, pos = _pd(g, "id"), _points(g)
    ends = _cell_point_ids(g, k)
    assert [pid[j] for j in ends] == [n1.id, n2.id]
    assert np.array_equal(pos[ends[0]], _vec(n1.state.pos)) and np.array_equal(pos[ends[1]], _vec(n2.state.pos))
    times = [t for t, _ in _frames(rec.pvd)]
    assert times[0] == pytest.approx(-5 * dt0, rel=1e-12) and times[-1] == O.time - t0
    fd = g.GetFieldData()
    assert vtk_to_numpy(fd.GetArray("TimeValue"))[0] == O.time - t0 and vtk_to_numpy(fd.GetArray("SceneTime"))[0] == O.time
    with pytest.raises(ValueError, match="time_origin"):
        yf.VtkRecorder(str(tmp_path / "x"), time_origin=float("nan"))



def _recorded_run(folder, workers, batch):
    """The contact scene (contacts, a clump, a chain) with a bar pulled apart (a rupture) and a
    sphere that appears and is erased, recorded at 7 frames; returns the recorder, flushed."""
    bar, _ = yf.chain([(0, 3, 0), (0.3, 3, 0)], 0.002, yf.steel(tensile_strength=400e6), segments=3, fixed=[0])
    sc = _contact_scene()
    O.forces.setPermF(bar[-1], Vector3(1.2 * 400e6 * math.pi * 0.002 ** 2, 0, 0))
    el = next(e for e in O.engines if type(e).__name__ == "FlexElementEngine")
    rec = yf.VtkRecorder(folder, workers=workers, batch=batch)
    extra = None
    for frame in range(7):
        rec()
        if frame == 1:
            extra = S.sphere((3, 3, 1), 0.05)
        if frame == 4:
            O.bodies.erase(extra)
        for _ in range(20000 if frame == 2 else 3):  # (the bar ruptures after the third frame)
            O.step()
            if frame == 2 and el.nRuptured:
                break
    rec.flush()
    assert el.nRuptured == 1 and sc["clump"] >= 0
    return rec


def test_vtk_frames_written_by_several_processes_are_the_same_files(scene, tmp_path, monkeypatch):
    """workers > 1: the frames are taken at each call and written a batch at a time by that many
    processes; the files (every group, the empty ones, the broken element, also when the frame
    that last held it whole was still waiting, the .pvd) are those one process writes at each
    call, byte for byte. Until a batch is written the .pvd lists only
    the frames written; a child's failure raises."""
    one = _recorded_run(str(tmp_path / "one"), 1, 1)
    O.reset()
    two = _recorded_run(str(tmp_path / "two"), 2, 4)  # (frame 2, the bar still whole, waits while it ruptures)
    files = sorted(os.listdir(tmp_path / "one"))
    assert files == sorted(os.listdir(tmp_path / "two")) and len(files) > 30
    assert {f.split("_")[1] for f in files if f.endswith(".vtu")} >= {"nodes", "cylinders", "spheres", "clumps", "contacts"}
    for f in files:
        with open(tmp_path / "one" / f, "rb") as a, open(tmp_path / "two" / f, "rb") as b:
            assert a.read() == b.read(), f
    assert one.frames == two.frames and not two.pending
    g = _read(str(tmp_path / "two" / "flex_cylinders_000006.vtu"))
    assert sum(_cd(g, "broken")) == 1
    # the .pvd before and after a batch; a batch that cannot be written
    O.reset()
    yf.chain([(0, 0, 0), (1, 0, 0)], 0.002, yf.steel(), segments=2, fixed=[0])
    O.engines = yf.engines()
    out = tmp_path / "three"
    rec = yf.VtkRecorder(str(out), workers=2, batch=2)
    rec()
    assert len(rec.pending) == 1 and not os.path.exists(rec.pvd) and not os.path.exists(out / "flex_cylinders_000000.vtu")
    O.step()
    rec()
    assert not rec.pending and len(_frames(rec.pvd)) == 2 and os.path.exists(out / "flex_cylinders_000001.vtu")
    O.step()
    rec()
    for f in os.listdir(out):
        os.remove(out / f)
    os.rmdir(out)
    with pytest.raises(OSError, match="VTK could not write .*No such file"):
        rec.flush()
    one = yf.VtkRecorder(str(out))  # (one process: the same error)
    os.rmdir(out)
    with pytest.raises(OSError, match="VTK could not write .*No such file"):
        one()
    # a child that fails: its message reaches this process
    import yadeflex.vtk_frames as frames
    parent, write = os.getpid(), frames._write_vtu

    def fails_in_a_child(*args):
        if os.getpid() != parent:
            raise RuntimeError("disk gone in the child")
        write(*args)

    monkeypatch.setattr(frames, "_write_vtu", fails_in_a_child)
    rec = yf.VtkRecorder(str(out), workers=2, batch=10)
    rec()
    with pytest.raises(OSError, match="child process failed: RuntimeError: disk gone in the child"):
        rec.flush()
    with pytest.raises(ValueError, match="workers"):
        yf.VtkRecorder(str(tmp_path / "x"), workers=0)

# ---- energy CSV and plots ------------------------------------------------------------------------

def _energy_run(tmp_path, steps=400, every=20):
    """A sphere released touching a 4 x 4 geotextile sheet: kinetic, gravity, membrane and contact
    terms, none of them booked at iteration 0."""
    MS.sheet_impact(n=4, drop=0.0)
    O.trackEnergy = True
    rec = yf.EnergyRecorder(str(tmp_path / "energy.csv"), every=every)
    rec()  # iteration 0: no term booked yet
    seen = set()
    for _ in range(steps):
        O.step()
        seen |= set(O.energy.keys())
        rec()
    return rec, seen


def test_energy_recorder_columns_and_total(scene, tmp_path):
    rec, seen = _energy_run(tmp_path)
    with open(rec.path, newline="") as fh:
        rows = list(csv.reader(fh))
    head = rows[0]
    assert head[:2] == ["time[s]", "iter[-]"] and head[-1] == "total[J]"
    terms = [h[:-3] for h in head[2:-1]]
    assert all(h.endswith("[J]") for h in head[2:-1])
    assert set(terms) == seen and len(terms) == len(seen)
    assert {"kinetic", "gravWork", "flexMembraneElastic", "flexContactElastic"} <= seen
    data = [[float(v) for v in r] for r in rows[1:]]
    assert [int(r[1]) for r in data] == list(range(0, 401, 20))
    assert all(v == 0.0 for v in data[0][2:])  # zero-filled: nothing was booked at iteration 0
    for r in data:
        assert r[-1] == math.fsum(r[2:-1])
    assert data[-1][-1] == pytest.approx(O.energy.total(), rel=1e-12, abs=1e-15)
    assert max(abs(v) for v in data[-1][2:-1]) > 1e-3  # the sphere has fallen: real energies, not zeros


def test_energy_recorder_needs_tracking(scene, tmp_path):
    O.trackEnergy = False
    with pytest.raises(RuntimeError, match="trackEnergy"):
        yf.EnergyRecorder(str(tmp_path / "e.csv"))()


def _nonwhite_fraction(png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.image as mpimg
    img = mpimg.imread(png)
    return float(np.mean(np.any(img[..., :3] < 0.9, axis=-1))), float(img[..., :3].std())


def _colour_fraction(png, colour, alpha):
    """Fraction of the pixels showing `colour` filled with opacity alpha over white."""
    import matplotlib
    import matplotlib.image as mpimg
    img = mpimg.imread(png)[..., :3]
    want = alpha * np.array(matplotlib.colors.to_rgb(colour)) + (1 - alpha)
    return float(np.mean(np.all(np.abs(img - want) < 0.02, axis=-1)))


def matplotlib_rgb(c):
    import matplotlib.colors
    return matplotlib.colors.to_rgb(c)


def test_energy_term_colours_are_distinct():
    """The main job books 13 energy terms or more: no two share a colour (with the line style)."""
    from yadeflex.impact_plots import term_colors, term_styles
    for n in (3, 10, 13, 20, 27):
        styled = {(tuple(np.round(matplotlib_rgb(c), 6)), ls) for c, ls in zip(term_colors(n), term_styles(n))}
        colours = {tuple(np.round(matplotlib_rgb(c), 6)) for c in term_colors(n)}
        assert len(colours) == len(styled) == n, n


def test_csv_stream_headers_carry_units(tmp_path):
    from yadeflex.files import CsvStream
    s = CsvStream(str(tmp_path / "a.csv"), first=("t",), units=dict(t="s", f="N"))
    s.append(dict(t=0.0, f=1.0))
    s.append(dict(t=0.1, f=2.0, n=3))  # a new column: the header is rewritten, with units where known
    s.close()
    names, units, cols = yf.read_csv(str(tmp_path / "a.csv"))
    assert names == ["t", "f", "n"] and units == dict(t="s", f="N", n="") and list(cols["f"]) == [1.0, 2.0]


def test_plots(scene, tmp_path):
    rec, _ = _energy_run(tmp_path)
    info = yf.plot_energy(rec.path, str(tmp_path / "energy.png"))
    names, units, cols = yf.read_csv(rec.path)
    assert info["terms"] == names[2:-1] and units["total"] == "J" and units["time"] == "s"
    res = cols["total"] - cols["total"][0]
    assert info["max_abs_residual"] == np.max(np.abs(res))
    frac, std = _nonwhite_fraction(str(tmp_path / "energy.png"))
    assert os.path.getsize(tmp_path / "energy.png") > 20e3 and frac > 0.03 and std > 0.05
    # every term that matters has a visible area in its colour: kinetic above zero, gravWork below
    big = [n for n in info["terms"] if np.max(np.abs(cols[n])) > 0.1 * max(np.max(np.abs(cols[m])) for m in info["terms"])]
    assert set(big) == {"kinetic", "gravWork"}
    for n in big:
        assert _colour_fraction(str(tmp_path / "energy.png"), info["colors"][n], yf.output.ENERGY_ALPHA) > 0.02, n

    assert len({tuple(np.round(matplotlib_rgb(c), 6)) for c in info["colors"].values()}) == len(info["terms"])

    png = yf.plot_timeseries(rec.path, ["kinetic", "total[J]"], str(tmp_path / "ts.png"), title="t")
    assert os.path.getsize(png) > 15e3
    # one line per column, in matplotlib's first colours, and no third line
    line = [_colour_fraction(png, c, 1.0) for c in ("C0", "C1", "C2")]
    assert line[0] > 8e-4 and line[1] > 8e-4 and line[2] == 0.0, line
    with pytest.raises(ValueError, match="nosuch"):
        yf.plot_timeseries(rec.path, ["nosuch"], str(tmp_path / "x.png"))
    assert not os.path.exists(tmp_path / "x.png")


def test_snapshot_elements_are_the_shapes_fields(scene):
    """FlexSnapshot.elements (the VTK frames' element arrays) gives each element's id, node ids and
    fields as its shape's attributes, in id order; another group is refused by name."""
    from yade.wrapper import FlexSnapshot
    import yadeflex.vtk_frames as out
    mat = yf.steel(tensile_strength=400e6)
    for build, code, kind, attrs, fields, load in (
            (lambda: S.cantilever(segments=4, length=0.3, radius=0.002, load="axial", force=50.0, material=mat),
             2, "FlexCylinder", ("node1", "node2"), out.CYLINDER_FIELDS, "axialForce"),
            (lambda: MS.circular_membrane(rings=3, pressure=500.0), 3, "FlexFacet", ("node1", "node2", "node3"), out.FACET_FIELDS, "n1")):
        build()
        for _ in range(30):
            O.step()
        raw = FlexSnapshot().elements(code)
        bodies = [b for b in O.bodies if b is not None and type(b.shape).__name__ == kind]
        assert bodies
        assert np.frombuffer(raw["id"], dtype=np.int64).tolist() == [b.id for b in bodies]
        assert np.frombuffer(raw["nodes"], dtype=np.int64).tolist() == [getattr(b.shape, a) for b in bodies for a in attrs]
        assert set(raw.keys()) == {"id", "nodes", *fields}
        for f in fields:
            assert np.frombuffer(raw[f], dtype=np.float64).tolist() == [getattr(b.shape, f) for b in bodies], f
        assert np.frombuffer(raw[load], dtype=np.float64).any()  # loaded: the values are not all the defaults
        assert FlexSnapshot().elements(5 - code)["id"] == b""
    with pytest.raises(ValueError, match="group must be 2 .FlexCylinder. or 3 .FlexFacet., got 4"):
        FlexSnapshot().elements(4)


def test_vtk_group_of_broken_elements_only(scene, tmp_path):
    """A cantilever of one element that ruptures: the later frames still hold it, alone, broken = 1
    with no force, between its nodes; the frame before holds it alive."""
    mat = yf.steel(tensile_strength=400e6)
    s = S.cantilever(segments=1, length=0.1, radius=0.002, load="axial", force=0.0, material=mat)
    O.forces.setPermF(s["tip"], Vector3(1.2 * 400e6 * math.pi * 0.002 ** 2, 0, 0))
    el = next(e for e in O.engines if type(e).__name__ == "FlexElementEngine")
    rec = yf.VtkRecorder(str(tmp_path))
    first = rec()
    for _ in range(20000):
        O.step()
        if el.nRuptured:
            break
    assert el.nRuptured == 1 and O.bodies[s["cylinders"][0]] is None
    O.step()
    last = rec()
    g0, g = _read(first["cylinders"]), _read(last["cylinders"])
    assert list(_cd(g0, "broken")) == [0] and list(_cd(g0, "id")) == s["cylinders"]
    assert list(_cd(g, "broken")) == [1] and list(_cd(g, "id")) == s["cylinders"]
    assert _cd(g, "axialForce")[0] == 0.0 and _cd(g, "elasticEnergy")[0] == 0.0 and _cd(g, "radius")[0] == 0.002
    assert _cd(g, "L0")[0] == _cd(g0, "L0")[0]
    assert list(_pd(g, "id")) == s["nodes"]
    assert np.array_equal(_points(g)[1], _vec(O.bodies[s["nodes"][1]].state.pos))
