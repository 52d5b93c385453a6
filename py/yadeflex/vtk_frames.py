"""VTK time series for ParaView: the frames of a scene and their files.

VTK. Each frame writes one VTK XML unstructured grid (.vtu) per group of bodies and rewrites
the collection file PREFIX.pvd, which ParaView opens as ONE time series (a multiblock, one
block per group, named after it). The .pvd is replaced atomically after the frame's files are
complete (with VtkRecorder's workers > 1: after each batch of frames), so an interrupted run still
opens, up to its last frame written. yadeflex/paraview/open_run.py
opens it with colours, tubes and glyphs set.

    group            cells                     data (SI units)
    nodes            one vertex per FlexNode   point: id, part, radius [m], mass [kg], velocity [m/s],
                                               speed [m/s], angularVelocity [rad/s], blockedDOFs [-]
    cylinders        line node1-node2          cell: id, part, broken, radius [m], axialForce [N]
                                               (tension > 0), strain [-], plasticStrain [-],
                                               maxStrain [-], hardeningVar [-], wireSlack [-],
                                               elasticEnergy [J], L0 [m]; point: id (node),
                                               velocity [m/s]
    facets           triangle node1-2-3        cell: id, part, broken, radius [m] (half thickness),
                                               n1, n2 [N/m] (principal membrane forces), e1, e2 [-],
                                               elasticEnergy [J], pressure [Pa], area0 [m2];
                                               point: id (node), velocity [m/s]
    spheres          one vertex per Sphere     point: as nodes (Glyph > Sphere, Scale Array
                                               radius, Scale Factor 2 draws them to size); a
                                               clump's member spheres too (part: boulder)
    clumps           hexahedron per clump      cell: id, part, velocity [m/s], speed [m/s], mass
                                               [kg]; the box around its members in its own frame
                                               (the cube boulder: the cube)
    boxes            hexahedron per Box        cell: id, part, extents [m], velocity [m/s], speed [m/s]
    rigid_facets     triangle per YADE Facet   cell: id, part, velocity [m/s], speed [m/s]
    contacts         line per contact, from    cell: id1, id2, part1, part2, kind, contactPoint [m],
                     the centre of side 1 to   normal [-] (from 1 to 2), normalForce [N], shearForce
                     side 2's (force chains)   [N] (vectors, on body 2), fn, fs, force [N] (their
                                               magnitudes, |normal + shear|), penetrationDepth [m],
                                               plasticOverlap [m] (the crushed part of the overlap:
                                               grain crushing, engines' crushing_is50; else 0)

part: which part of the structure the body is, yadeflex.parts.PARTS (0 other, 1 mesh, 2 ring,
3 rope, 4 lining, 5 slab, 6 grain, 7 boulder), then the groups named with
yadeflex.parts.name_parts (8, 9, ...); every file's field data part_names gives the name of each
id. kind: 10 x the smaller standard part id of the two bodies + the larger (16 mesh-grain, 46
lining-grain, 66 grain-grain, 67 grain-boulder, ...; a named group's body counts as the standard
part its shape gives). A side's centre is a
sphere's centre, the closest point on a cylinder's axis or a facet's midplane, the contact point
on a wall, YADE facet or box. Contacts are the
real interactions with a normal force (handed-over FlexContactGeom contacts left out).
broken: 1 for an element FlexElementEngine erased as ruptured (VtkRecorder only): it is kept in
every later frame between its nodes' current positions, with its load fields (axialForce, n1,
n2, elasticEnergy, pressure) 0 and the others as in the last frame that held it alive (an
element that ruptures between two frames keeps the values of the frame before).

Cylinder and facet files hold only the nodes their elements use, at their current positions.
Erased bodies (None) are skipped; other shapes (walls) are not written.
Every file carries field data TimeValue [s] (the series' time: O.time - the recorder's
time_origin), SceneTime [s] (O.time) and Iteration [-].

Empty groups: a group with no bodies at a frame writes no file for that frame. Once a group has
appeared in the series, frames where it has no bodies (before it appeared, or after its bodies
were erased) point to one shared empty file PREFIX_GROUP_empty.vtu, so that every frame lists
the same blocks in the same order (VTK's collection reader numbers blocks by their order in a
frame). A group that never had a body has no file at all.

The frame is stamped with O.time and O.iter. Called from a PyRunner after the integrator,
positions are already advanced by one step while O.time is not: negligible for display.
"""
import contextlib
import json
import math
import os
import re
from xml.sax.saxutils import quoteattr

import numpy as np
from yade import O
from yade.wrapper import FlexSnapshot, Sphere

from . import parts as P
from .files import clear_matching, write_atomic
from .recording import Periodic
from .vtk_writers import write_jobs


GROUPS = ("nodes", "cylinders", "facets", "spheres", "clumps", "boxes", "rigid_facets", "contacts")

# cell arrays written for cylinders and facets (FlexSnapshot.elements gives them)
CYLINDER_FIELDS = ("radius", "axialForce", "strain", "plasticStrain", "maxStrain", "hardeningVar", "wireSlack",
                   "elasticEnergy", "L0")
FACET_FIELDS = ("radius", "n1", "n2", "e1", "e2", "elasticEnergy", "pressure", "area0")
# fields a broken element no longer carries: written as 0 on it (the others keep their last values)
_LOAD_FIELDS = ("axialForce", "n1", "n2", "elasticEnergy", "pressure")

# VTK cell types (vtkCellType.h)
_VTK_VERTEX, _VTK_LINE, _VTK_TRIANGLE, _VTK_HEXAHEDRON = 1, 3, 5, 12
# element groups: (FlexSnapshot.elements' group code, node attributes, cell type, fields)
_ELEMENT_GROUPS = {"cylinders": (2, ("node1", "node2"), _VTK_LINE, CYLINDER_FIELDS),
                   "facets": (3, ("node1", "node2", "node3"), _VTK_TRIANGLE, FACET_FIELDS)}
# Box corners in the order of VTK_HEXAHEDRON: bottom face counter-clockwise, then top face.
_HEX_CORNERS = ((-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1), (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1))


def _vtk():
    try:
        from vtkmodules.util import numpy_support
        from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkIntArray, vtkLogger, vtkPoints, vtkStringArray
        from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkUnstructuredGrid
        from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter
    except ImportError as err:
        raise ImportError(f"VTK output needs VTK's Python bindings (Debian: apt-get install python3-vtk9): {err}") from None
    # VTK's log stays off stderr (a writer that fails dumps its pipeline there: _write_vtu raises
    # naming the file instead)
    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)
    return dict(ns=numpy_support, vtkDoubleArray=vtkDoubleArray, vtkIntArray=vtkIntArray, vtkPoints=vtkPoints, vtkStringArray=vtkStringArray,
                vtkCellArray=vtkCellArray, vtkUnstructuredGrid=vtkUnstructuredGrid, writer=vtkXMLUnstructuredGridWriter)


# written as Int64; all others as Float64 (fixed, so an empty file has the same types)
_INT_ARRAYS = ("id", "blockedDOFs", "part", "broken", "id1", "id2", "part1", "part2", "kind")


def _array(vtk, name, values, components=1):
    a = np.ascontiguousarray(values, dtype=np.int64 if name in _INT_ARRAYS else np.float64)
    a = a.reshape(-1, components) if components > 1 else a.reshape(-1)
    arr = vtk["ns"].numpy_to_vtk(a, deep=True)
    arr.SetName(name)
    return arr


def _grid(vtk, points, cell_type, conn, nper, point_data=(), cell_data=()):
    """vtkUnstructuredGrid of one cell type; conn: flat point indices, nper per cell; *_data:
    (name, values, components)."""
    ug = vtk["vtkUnstructuredGrid"]()
    pts = vtk["vtkPoints"]()
    pts.SetDataTypeToDouble()
    pts.SetData(vtk["ns"].numpy_to_vtk(np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 3), deep=True))
    ug.SetPoints(pts)
    conn = np.ascontiguousarray(conn, dtype=np.int64).reshape(-1)
    ncell = len(conn) // nper
    cells = vtk["vtkCellArray"]()
    cells.SetData(vtk["ns"].numpy_to_vtkIdTypeArray(np.arange(0, nper * ncell + 1, nper, dtype=np.int64), deep=True),
                  vtk["ns"].numpy_to_vtkIdTypeArray(conn, deep=True))
    ug.SetCells(cell_type, cells)
    for name, values, comp in point_data:
        ug.GetPointData().AddArray(_array(vtk, name, values, comp))
    for name, values, comp in cell_data:
        ug.GetCellData().AddArray(_array(vtk, name, values, comp))
    return ug


# FlexSnapshot's group codes: a body group's position in GROUPS + 1, walls 8 (no group; part slab)
_GROUP_CODE = {g: k + 1 for k, g in enumerate(GROUPS[:-1])}
_WALL_CODE = len(GROUPS)


def _arrays(raw, spec):
    """numpy views of FlexSnapshot's bytes: spec name -> (dtype, components)."""
    return {k: np.frombuffer(raw[k], dtype=dt).reshape(-1, c) if c > 1 else np.frombuffer(raw[k], dtype=dt)
            for k, (dt, c) in spec.items()}


_BODY_FIELDS = dict(group=(np.int64, 1), clumped=(np.int64, 1), pos=(np.float64, 3), vel=(np.float64, 3), angVel=(np.float64, 3),
                    mass=(np.float64, 1), radius=(np.float64, 1), blocked=(np.int64, 1))
_CONTACT_FIELDS = dict(id1=(np.int64, 1), id2=(np.int64, 1), end1=(np.float64, 3), end2=(np.float64, 3), contactPoint=(np.float64, 3),
                       normal=(np.float64, 3), normalForce=(np.float64, 3), shearForce=(np.float64, 3), penetrationDepth=(np.float64, 1),
                       plasticOverlap=(np.float64, 1))


class _Snapshot:
    """The scene's bodies (and, on first use, its contacts and each element group) as numpy arrays
    in id order, read in one pass each by FlexSnapshot."""

    def __init__(self):
        self._reader = FlexSnapshot()
        self.b = _arrays(self._reader.bodies(), _BODY_FIELDS)
        self._contacts = None
        self._elements = {}

    def ids(self, group):
        """Ids of the bodies of a body group, ascending."""
        return np.flatnonzero(self.b["group"] == _GROUP_CODE[group])

    def elements(self, group):
        """The bodies of an element group ('cylinders', 'facets') in id order: (ids, node ids
        (one row per element), field values (one column per field of the group))."""
        if group not in self._elements:
            code, attrs, _, fields = _ELEMENT_GROUPS[group]
            raw = self._reader.elements(code)
            ids = np.frombuffer(raw["id"], dtype=np.int64)
            nodes = np.frombuffer(raw["nodes"], dtype=np.int64).reshape(-1, len(attrs))
            vals = np.column_stack([np.frombuffer(raw[f], dtype=np.float64) for f in fields]).reshape(-1, len(fields))
            self._elements[group] = (ids, nodes, vals)
        return self._elements[group]

    def contacts(self):
        if self._contacts is None:
            self._contacts = _arrays(self._reader.contacts(), _CONTACT_FIELDS)
        return self._contacts

    def parts(self, table):
        """Part id of every body slot (yadeflex.parts.part_of, at once): table's, else boulder for
        clumps and their members, grain for spheres, slab for walls, other."""
        g = self.b["group"]
        out = np.full(len(g), P.PART["other"], dtype=np.int64)
        out[g == _GROUP_CODE["spheres"]] = P.PART["grain"]
        out[g == _WALL_CODE] = P.PART["slab"]
        out[self.b["clumped"] == 1] = P.PART["boulder"]
        if table:
            ids = np.fromiter(table.keys(), dtype=np.int64, count=len(table))
            vals = np.fromiter(table.values(), dtype=np.int64, count=len(table))
            inside = (ids >= 0) & (ids < len(g))
            out[ids[inside]] = vals[inside]
        return out


class _Drawn:
    """The elements of one group drawn so far, by id (ascending): node ids, field values and part
    id at the last frame that held each alive."""

    def __init__(self, nper, nfields):
        self.ids = np.zeros(0, dtype=np.int64)
        self.nodes = np.zeros((0, nper), dtype=np.int64)
        self.vals = np.zeros((0, nfields))
        self.part = np.zeros(0, dtype=np.int64)

    def update(self, ids, nodes, vals, part):
        """Rows of a frame's live elements (ids ascending) replace those remembered."""
        keep = ~np.isin(self.ids, ids)
        ids = np.concatenate([self.ids[keep], ids])
        order = np.argsort(ids, kind="stable")
        self.ids = ids[order]
        self.nodes = np.concatenate([self.nodes[keep], nodes])[order]
        self.vals = np.concatenate([self.vals[keep], vals])[order]
        self.part = np.concatenate([self.part[keep], part])[order]

    def rows(self, ids):
        """(ids, node ids, field values, part ids) of remembered ids."""
        k = np.searchsorted(self.ids, ids)
        return self.ids[k], self.nodes[k], self.vals[k], self.part[k]


class _Frame:
    """What the builders of one frame share: the snapshot of the scene, the part id of every body
    (from parts: body id -> part id, yadeflex.parts), the broken elements to draw (group -> (ids,
    node ids, field values, part ids), as _Drawn.rows gives) and the memory of the group's
    elements drawn (a _Drawn, updated if not None)."""

    def __init__(self, snap, parts=None, broken=None, memory=None):
        self.snap = snap
        table = P.scene_parts() if parts is None else parts
        self.part_ids = snap.parts(table)
        self.names = P.part_names()
        # the contact kinds: of the standard parts (a named group's body: the one its shape gives)
        n = len(P.PARTS)
        self.kind_ids = self.part_ids if all(v < n for v in table.values()) else snap.parts({k: v for k, v in table.items() if v < n})
        self.broken = broken or {}
        self.memory = memory

    def part(self, b):
        return int(self.part_ids[b.id])


def _norms(v):
    return np.sqrt(np.einsum("ij,ij->i", v, v))


def _particles(vtk, ids, fr):
    """Nodes or spheres (ids, ascending): one vertex each, data on the points."""
    ids = np.asarray(ids, dtype=np.int64)
    b = fr.snap.b
    vel = b["vel"][ids]
    return _grid(vtk, b["pos"][ids], _VTK_VERTEX, np.arange(len(ids)), 1, point_data=[
        ("id", ids, 1), ("part", fr.part_ids[ids], 1), ("radius", b["radius"][ids], 1), ("mass", b["mass"][ids], 1),
        ("velocity", vel, 3), ("speed", _norms(vel), 1), ("angularVelocity", b["angVel"][ids], 3), ("blockedDOFs", b["blocked"][ids], 1)])


def _element_rows(ids, fr, group):
    """(ids, node ids, field values, part ids) of the group's elements ids (ascending) in the frame."""
    all_ids, all_nodes, all_vals = fr.snap.elements(group)
    ids = np.asarray(ids, dtype=np.int64)
    k = np.searchsorted(all_ids, ids)
    if len(ids) and (k.max() >= len(all_ids) or not np.array_equal(all_ids[k], ids)):
        raise ValueError(f"{group}: ids that are not bodies of the group in the scene: "
                         f"{sorted(set(ids.tolist()) - set(all_ids.tolist()))[:10]}")
    return ids, all_nodes[k], all_vals[k], fr.part_ids[ids]


def _elements(vtk, ids, fr, group):
    """Cylinders or facets (ids, ascending): cells over their nodes (only the nodes they use, in
    the order the cells first use them), shape fields as cell data, node id and velocity as point
    data. The group's broken elements of fr follow the live ones, between their nodes' current
    positions (skipped if a node is gone), with broken = 1, the load fields 0 and the other fields
    as last recorded."""
    _, attrs, cell_type, fields = _ELEMENT_GROUPS[group]
    ids, nodes, vals, part = _element_rows(ids, fr, group)
    if fr.memory is not None:
        fr.memory.update(ids, nodes, vals, part)
    d_ids, d_nodes, d_vals, d_part = fr.broken.get(group, _NO_ROWS[group])
    gone = fr.snap.b["group"] < 0
    ok = (d_nodes >= 0) & (d_nodes < len(gone))
    ok[ok] = ~gone[d_nodes[ok]]
    ok = ok.all(axis=1)
    d_vals = d_vals[ok].copy()
    d_vals[:, [c for c, f in enumerate(fields) if f in _LOAD_FIELDS]] = 0.0
    conn = np.concatenate([nodes, d_nodes[ok]]).reshape(-1)
    used, first, inverse = np.unique(conn, return_index=True, return_inverse=True)
    order = np.argsort(first, kind="stable")  # the nodes in the order the cells first use them
    rank = np.empty(len(used), dtype=np.int64)
    rank[order] = np.arange(len(used))
    points = used[order]
    n_dead = int(ok.sum())
    values = np.concatenate([vals, d_vals])
    return _grid(vtk, fr.snap.b["pos"][points], cell_type, rank[inverse.reshape(-1)], len(attrs),
                 point_data=[("id", points, 1), ("velocity", fr.snap.b["vel"][points], 3)],
                 cell_data=[("id", np.concatenate([ids, d_ids[ok]]), 1), ("part", np.concatenate([part, d_part[ok]]), 1),
                            ("broken", np.repeat([0, 1], [len(ids), n_dead]), 1)] + [(f, values[:, c], 1) for c, f in enumerate(fields)])


def _v3(v):
    """(x, y, z) of a Vector3 (tuple(v) would end its iteration on an IndexError: slower)."""
    return (v[0], v[1], v[2])


def _norm(v):
    return math.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2)


def _rigid(vtk, bodies, cell_type, local_corners, extra, fr):
    """Rigid bodies drawn from corners in their local frame (pos + ori * corner)."""
    pts = [_v3(b.state.pos + b.state.ori * c) for b in bodies for c in local_corners(b)]
    vel = [_v3(b.state.vel) for b in bodies]
    nper = len(pts) // len(bodies) if bodies else {_VTK_HEXAHEDRON: 8, _VTK_TRIANGLE: 3}[cell_type]
    return _grid(vtk, pts, cell_type, range(len(pts)), nper, cell_data=[
        ("id", [b.id for b in bodies], 1), ("part", [fr.part(b) for b in bodies], 1), ("velocity", vel, 3),
        ("speed", [_norm(v) for v in vel], 1)] + extra(bodies))


def _box_corners(b):
    e = b.shape.extents
    return [type(e)(sx * e[0], sy * e[1], sz * e[2]) for sx, sy, sz in _HEX_CORNERS]


def _clump_box(b):
    """(centre, half extents) in the clump's frame of the box around its members (spheres with
    their radius, other members by their centre)."""
    lo, hi = [math.inf] * 3, [-math.inf] * 3
    for mid, (rel, _) in b.shape.members.items():
        m = O.bodies[mid]
        r = m.shape.radius if m is not None and isinstance(m.shape, Sphere) else 0.0
        for k in range(3):
            lo[k], hi[k] = min(lo[k], rel[k] - r), max(hi[k], rel[k] + r)
    if not b.shape.members:
        lo = hi = [0.0] * 3
    return [0.5 * (a + c) for a, c in zip(lo, hi)], [0.5 * (c - a) for a, c in zip(lo, hi)]


def _clump_corners(b):
    c, e = _clump_box(b)
    v = type(b.state.pos)
    return [v(c[0] + sx * e[0], c[1] + sy * e[1], c[2] + sz * e[2]) for sx, sy, sz in _HEX_CORNERS]


def real_contacts():
    """The scene's real interactions that carry a contact force (FrictPhys-like physics; a
    FlexContactGeom contact handed over to a neighbour is left out), in O.interactions' order."""
    return [i for i in O.interactions if i.isReal and hasattr(i.phys, "normalForce") and getattr(i.geom, "active", True)]


def _contacts(vtk, c, fr):
    """One line per contact (FlexSnapshot.contacts' arrays) from the centre of body 1's side to
    body 2's (force chains), contact data on the cells."""
    n = len(c["id1"])
    pts = np.stack([c["end1"], c["end2"]], axis=1).reshape(-1, 3)
    p1, p2 = fr.part_ids[c["id1"]], fr.part_ids[c["id2"]]
    k1, k2 = fr.kind_ids[c["id1"]], fr.kind_ids[c["id2"]]
    fn, fs = c["normalForce"], c["shearForce"]
    data = [("id1", c["id1"], 1), ("id2", c["id2"], 1), ("part1", p1, 1), ("part2", p2, 1),
            ("kind", 10 * np.minimum(k1, k2) + np.maximum(k1, k2), 1), ("contactPoint", c["contactPoint"], 3), ("normal", c["normal"], 3),
            ("normalForce", fn, 3), ("shearForce", fs, 3), ("fn", _norms(fn), 1), ("fs", _norms(fs), 1), ("force", _norms(fn + fs), 1),
            ("penetrationDepth", c["penetrationDepth"], 1), ("plasticOverlap", c["plasticOverlap"], 1)]
    return _grid(vtk, pts, _VTK_LINE, np.arange(2 * n), 2, cell_data=data)


_NO_CONTACTS = {k: np.zeros((0, comp) if comp > 1 else 0, dtype=dt) for k, (dt, comp) in _CONTACT_FIELDS.items()}
_NO_ROWS = {g: (np.zeros(0, dtype=np.int64), np.zeros((0, len(a)), dtype=np.int64), np.zeros((0, len(f))), np.zeros(0, dtype=np.int64))
            for g, (_, a, _, f) in _ELEMENT_GROUPS.items()}
_BODY_LISTS = ("clumps", "boxes", "rigid_facets")  # builders that read the bodies themselves

_BUILD = {
    "nodes": lambda vtk, ids, fr: _particles(vtk, ids, fr),
    "cylinders": lambda vtk, ids, fr: _elements(vtk, ids, fr, "cylinders"),
    "facets": lambda vtk, ids, fr: _elements(vtk, ids, fr, "facets"),
    "spheres": lambda vtk, ids, fr: _particles(vtk, ids, fr),
    "clumps": lambda vtk, bs, fr: _rigid(vtk, bs, _VTK_HEXAHEDRON, _clump_corners,
                                         lambda bs_: [("mass", [b.state.mass for b in bs_], 1)], fr),
    "boxes": lambda vtk, bs, fr: _rigid(vtk, bs, _VTK_HEXAHEDRON, _box_corners,
                                        lambda bs_: [("extents", [_v3(b.shape.extents) for b in bs_], 3)], fr),
    "rigid_facets": lambda vtk, bs, fr: _rigid(vtk, bs, _VTK_TRIANGLE, lambda b: list(b.shape.vertices), lambda bs_: [], fr),
    "contacts": lambda vtk, c, fr: _contacts(vtk, c, fr),
}


def _named(build):
    """build, with the part names (field data part_names: the name of each part id) in its grid."""
    def named(vtk, what, fr):
        grid = build(vtk, what, fr)
        names = vtk["vtkStringArray"]()
        names.SetName("part_names")
        for n in fr.names:
            names.InsertNextValue(n)
        grid.GetFieldData().AddArray(names)
        return grid
    return named


_BUILD = {g: _named(f) for g, f in _BUILD.items()}


def _empty(g):
    """What a group's builder takes for no bodies (or no contacts)."""
    return _NO_CONTACTS if g == "contacts" else []


def _cost(g, what):
    """Rough cost of building and writing a group's file: its rows times the arrays written."""
    rows = len(what["id1"]) if g == "contacts" else len(what)
    return rows * {"contacts": 16, "nodes": 9, "spheres": 9, "cylinders": 15, "facets": 14}.get(g, 4)


def _job(vtk, cost, build, path, time, stamp):
    """(cost, write) for _write_jobs: the grid build() returns, to path."""
    return cost, lambda: _write_vtu(vtk, build(), path, time, stamp)


def scene_groups(snap=None):
    """dict group -> what its builder takes, for the non-empty groups of the current scene (in id
    order): the ids of nodes, spheres and elements, the bodies of the other body groups, and 'contacts' ->
    FlexSnapshot.contacts' arrays (the contacts of real_contacts(), in its order)."""
    snap = snap or _Snapshot()
    out = {}
    for g in GROUPS[:-1]:
        ids = snap.ids(g)
        if len(ids):
            out[g] = [O.bodies[int(i)] for i in ids] if g in _BODY_LISTS else ids
    c = snap.contacts()
    if len(c["id1"]):
        out["contacts"] = c
    return out


def _write_vtu(vtk, grid, path, time, stamp=None):
    """The grid to path with its field data: TimeValue (time), SceneTime and Iteration (stamp:
    (O.time, O.iter) of its frame; default the current ones)."""
    scene_time, iteration = (O.time, O.iter) if stamp is None else stamp
    fd = grid.GetFieldData()
    fd.AddArray(_array(vtk, "TimeValue", [time]))
    fd.AddArray(_array(vtk, "SceneTime", [scene_time]))
    it = vtk["vtkIntArray"]()
    it.SetName("Iteration")
    it.InsertNextValue(iteration)
    fd.AddArray(it)
    write_xml(vtk["writer"](), grid, path)


def write_xml(w, data, path):
    """data through the VTK XML writer w to path, as every VTK file of a run is written: inline
    binary, LZ4, built in memory, then written from Python (OSError naming the file)."""
    w.SetFileName(path)
    w.SetInputData(data)
    # inline (base64 in each array), not appended: ParaView 5.11's reader (Debian bookworm) stops
    # its XML parser at an appended block, which fails with the expat of Debian's security updates
    # (reparse deferral), and then shows nothing of the file
    w.SetDataModeToBinary()
    w.SetCompressorTypeToLZ4()  # (zlib's compression took longer than building the frame)
    w.SetHeaderTypeToUInt64()
    # into memory, then to the file from Python: VTK 9.1's writer can crash when the disk fills
    # under it (a segfault, reproduced on a 200 kB disk), where Python raises OSError naming it
    w.WriteToOutputStringOn()
    if w.Write() != 1 or w.GetErrorCode() != 0:
        raise OSError(f"VTK could not build {path}")
    text = w.GetOutputString()
    try:
        with open(path, "w", encoding="ascii") as fh:  # (inline binary data is base64: ASCII)
            fh.write(text)
    except OSError as e:
        with contextlib.suppress(OSError):
            os.unlink(path)
        raise OSError(e.errno, f"VTK could not write {path}: {e.strerror}", path) from None


def _write_part_names(pvd):
    """PREFIX_parts.json beside the .pvd: the name of each part id (yadeflex.parts.part_names),
    for readers that do not read the files' field data (the ParaView macro)."""
    write_atomic(pvd[:-len(".pvd")] + "_parts.json", json.dumps(P.part_names()))


def _write_pvd(path, datasets):
    """Collection file; datasets: (time, part, name, file). Written to a temporary file and
    renamed, so the .pvd on disk is always complete."""
    lines = ['<?xml version="1.0"?>',
             '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
             "  <Collection>"]
    lines += [f'    <DataSet timestep="{t!r}" group="" part="{p}" name={quoteattr(n)} file={quoteattr(f)}/>'
              for t, p, n, f in datasets]
    lines += ["  </Collection>", "</VTKFile>", ""]
    write_atomic(path, "\n".join(lines))


def _check_name(what, name):
    if not isinstance(name, str) or not name or os.sep in name or name in (".", ".."):
        raise ValueError(f"{what} must be a non-empty file name without '{os.sep}', got {name!r}")
    return name


def write_vtk_snapshot(folder, name, parts=None):
    """One frame: FOLDER/NAME_GROUP.vtu for each non-empty group and FOLDER/NAME.pvd listing them
    at O.time. parts: body id -> part id (default yadeflex.parts.scene_parts()). No broken
    elements (they need the history a VtkRecorder keeps). Returns dict group -> path, plus 'pvd'."""
    vtk = _vtk()
    _check_name("snapshot name", name)
    os.makedirs(folder, exist_ok=True)
    paths, datasets = {}, []
    snap = _Snapshot()
    groups = scene_groups(snap)
    fr = _Frame(snap, parts)
    for part, g in enumerate(x for x in GROUPS if x in groups):
        fn = f"{name}_{g}.vtu"
        _write_vtu(vtk, _BUILD[g](vtk, groups[g], fr), os.path.join(folder, fn), float(O.time))
        paths[g] = os.path.join(folder, fn)
        datasets.append((float(O.time), part, g, fn))
    paths["pvd"] = os.path.join(folder, name + ".pvd")
    _write_part_names(paths["pvd"])
    _write_pvd(paths["pvd"], datasets)
    return paths


def _ruptured_ids():
    """Ids of the elements FlexElementEngine erased as ruptured (empty without the engine)."""
    for e in O.engines:
        if type(e).__name__ == "FlexElementEngine":
            return set(e.rupturedIds)
    return set()


class VtkRecorder(Periodic):
    """VTK time series of the scene: FOLDER/PREFIX.pvd and per frame FOLDER/PREFIX_GROUP_NNNNNN.vtu.

    Call it (from a loop, or via runner() from a PyRunner) to write a frame; it writes at most
    one frame per `every` steps [-] and none twice at one iteration. Returns the dict group ->
    path of the frame written (the shared empty file for groups without bodies), or None if it
    did not write. An earlier series with the same prefix in the folder (its .pvd and frames,
    files_pattern(prefix)) is removed when the recorder is made, so that no frame of it stays next
    to the new ones. time_origin [s]: the series' time (the .pvd's timesteps, TimeValue) is
    O.time - time_origin; SceneTime holds O.time. parts: body id -> part id (yadeflex.parts; default
    scene_parts() at each frame). Elements erased as ruptured (FlexElementEngine.rupturedIds) stay
    in later frames with broken = 1. See the module docstring for the groups and their data.

    workers: processes that write the files (default 1: each frame is written when it is called).
    With more (a run on several threads and CPUs), a call takes the frame's data and builds what
    reads the bodies themselves, and the files of `batch` frames at a time are then built and
    written by that many processes (this one and children forked for them) while the scene waits:
    the same files, the .pvd updated after each batch; the paths a call returns then exist once
    its batch is written. Call flush() at the end (and before reading the files); the frames still
    waiting are listed in `pending`. A batch that fails raises; its frames are lost (their numbers
    are not used again)."""

    def __init__(self, folder, prefix="flex", every=1, time_origin=0.0, parts=None, workers=1, batch=8):
        super().__init__(every)
        if not (isinstance(time_origin, (int, float)) and math.isfinite(time_origin)):
            raise ValueError(f"time_origin must be a finite time [s], got {time_origin!r}")
        for what, v in (("workers", workers), ("batch", batch)):
            if not (isinstance(v, int) and not isinstance(v, bool) and v >= 1):
                raise ValueError(f"{what} must be a positive whole number, got {v!r}")
        self.workers, self.batch = workers, batch
        self.pending = []  # frames taken, not written yet: (scene time [s], iteration, {group: file name}, [(cost, write)])
        self._taken = 0  # frames taken (written, waiting or lost in a batch that failed)
        self.folder = folder
        self.prefix = _check_name("prefix", prefix)
        self.time_origin = float(time_origin)
        self.parts = parts
        self.pvd = os.path.join(folder, prefix + ".pvd")
        self.frames = []  # (scene time [s], iteration, {group: file name}) of the frames written
        self.groups = []  # groups seen so far, in GROUPS order
        self._memory = {g: _Drawn(len(a), len(f)) for g, (_, a, _, f) in _ELEMENT_GROUPS.items()}  # elements drawn so far
        clear_matching(folder, self.files_pattern(prefix))
        os.makedirs(folder, exist_ok=True)

    @staticmethod
    def files_pattern(prefix="flex"):
        """Regular expression of the names of the files a recorder with this prefix writes."""
        return re.escape(prefix) + r"(\.pvd|_parts\.json|_(" + "|".join(GROUPS) + r")_(\d{6,}|empty)\.vtu)|\.tmp-.*\.(pvd|json)"

    def _empty_file(self, g):
        return f"{self.prefix}_{g}_empty.vtu"

    def _broken(self):
        """group -> (ids, node ids, field values, part ids) of the remembered elements erased as ruptured."""
        ruptured = np.fromiter(_ruptured_ids(), dtype=np.int64)
        out = {}
        for g, mem in self._memory.items():
            gone = [i for i in mem.ids[np.isin(mem.ids, ruptured)].tolist() if i >= len(O.bodies) or O.bodies[i] is None]
            if gone:
                out[g] = mem.rows(np.asarray(gone, dtype=np.int64))
        return out

    def __call__(self):
        if not self._due():
            return None
        vtk = _vtk()
        snap = _Snapshot()
        groups = scene_groups(snap)
        broken = self._broken()
        for g in broken:
            groups.setdefault(g, [])
        k = self._taken
        self._taken += 1
        files = {}
        t = float(O.time) - self.time_origin
        stamp = (float(O.time), O.iter)
        fr = _Frame(snap, P.scene_parts() if self.parts is None else self.parts, broken)
        none = _Frame(snap, {})  # (the shared empty files: no bodies, no broken elements)
        later = self.workers > 1
        jobs = []
        for g in GROUPS:
            if g not in groups:
                continue
            files[g] = f"{self.prefix}_{g}_{k:06d}.vtu"
            path = os.path.join(self.folder, files[g])
            fr.memory = self._memory.get(g)
            if not later:
                _write_vtu(vtk, _BUILD[g](vtk, groups[g], fr), path, t, stamp)
            elif g in _BODY_LISTS:  # (built now: the builder reads the bodies)
                built = _BUILD[g](vtk, groups[g], fr)
                jobs.append(_job(vtk, 1, lambda built=built: built, path, t, stamp))
            else:  # (the frame's data is taken: the snapshot's arrays, the elements remembered now)
                if fr.memory is not None:
                    fr.memory.update(*_element_rows(groups[g], fr, g))
                jobs.append(_job(vtk, _cost(g, groups[g]), lambda g=g: _BUILD[g](vtk, groups[g], fr), path, t, stamp))
            if g not in self.groups:
                _write_vtu(vtk, _BUILD[g](vtk, _empty(g), none), os.path.join(self.folder, self._empty_file(g)), t, stamp)
                self.groups = [x for x in GROUPS if x in self.groups or x == g]
        fr.memory = None  # (the later builds: the elements are remembered)
        self.last_iter = O.iter
        if later:
            self.pending.append((stamp[0], stamp[1], files, jobs))
            if len(self.pending) >= self.batch:
                self.flush()
        else:
            self.frames.append((stamp[0], stamp[1], files))
            self._write_pvd()
        return {g: os.path.join(self.folder, files.get(g, self._empty_file(g))) for g in self.groups}

    def flush(self):
        """Writes the frames taken and not written yet (workers > 1), then the .pvd."""
        if not self.pending:
            return
        pending, self.pending = self.pending, []
        write_jobs([j for *_, jobs in pending for j in jobs], self.workers)
        self.frames += [(ts, it, files) for ts, it, files, _ in pending]
        self._write_pvd()

    def _write_pvd(self):
        datasets = [(ts - self.time_origin, part, g, fr_.get(g, self._empty_file(g)))
                    for ts, _, fr_ in self.frames for part, g in enumerate(self.groups)]
        _write_part_names(self.pvd)
        _write_pvd(self.pvd, datasets)
