"""Membranes of deformable facets: the geotextile lining, sheets, any triangle mesh.

A FlexFacet is a thick triangle (thickness = 2 x its radius, rounded edges and corners) over
three FlexNodes; its membrane law is a constant-strain triangle (St. Venant-Kirchhoff, plane
stress, optional tension-field wrinkling). Each builder validates its input and raises
ValueError naming the problem before anything is added to the scene.
"""
import math
import os
import struct

from yade import O
from yade.wrapper import Body, FlexNode, FlexFacet, FlexMembraneMat
from yade.minieigenHP import Vector3

from . import builders as B
from . import checks as C
from .builders import _positive, check_finite, fix, lookup_material, _section
from .materials import MODULUS, FRICTION_DEG, CONTACT_RATIO


def membrane_material(stiffness, areal_density, poisson=0.3, tension_only=True, strength=math.inf,
                      young=1e9, friction_deg=30.0, contact_ratio=0.25, label=""):
    """A FlexMembraneMat, validated.

    stiffness [N/m]: tensile stiffness E t of the membrane; areal_density [kg/m2]; poisson [-];
    tension_only: the fabric wrinkles instead of taking compression; strength [N/m]: a facet
    ruptures when its larger principal membrane force reaches it (inf: never);
    young [Pa]: contact modulus, FlexMembraneMat.young (contact kn = 2 E1 r1 E2 r2 / (E1 r1 + E2 r2) with r the
    facet's half thickness); friction_deg [deg]; contact_ratio [-] ks/kn of contacts.
    """
    C.number("membrane stiffness", stiffness, C.Range(0.0, 1e9, "N/m", lo_open=True, note="E t; steel sheet 1 mm: 2e8"))
    C.number("areal_density", areal_density, C.Range(0.0, 1e3, "kg/m2", lo_open=True))
    C.number("young", young, MODULUS)
    # the time step's stretch bound (membraneStretchFactor) needs nu >= 0
    C.number("poisson", poisson, C.Range(0.0, 0.5, hi_open=True))
    if strength != math.inf:
        C.number("strength", strength, C.Range(0.0, unit="N/m", lo_open=True, note="or inf: none"))
    C.number("friction_deg", friction_deg, FRICTION_DEG)
    C.number("contact_ratio", contact_ratio, CONTACT_RATIO)
    tension_only = C.boolean("tension_only", tension_only)
    if not isinstance(label, str):
        raise C.BadValue("label", label, "a string")
    return FlexMembraneMat(stiffness=stiffness, arealDensity=areal_density, membranePoisson=poisson,
                           tensionOnly=bool(tension_only), strength=strength, young=young,
                           poisson=contact_ratio, frictionAngle=math.radians(friction_deg),
                           density=areal_density / 0.002, label=label)


def geotextile(label="geotextile", **kw):
    """Woven polypropylene geotextile, typical catalogue class (not a specific product):
    tensile strength 40 kN/m at about 15% strain, secant stiffness E t = 250 kN/m, areal mass
    0.3 kg/m2, thickness about 2 mm (use thickness=0.002 in the builders), Poisson 0.3,
    tension-only (fabrics wrinkle). Override any value by keyword."""
    args = dict(stiffness=250e3, areal_density=0.3, poisson=0.3, tension_only=True, strength=40e3,
                friction_deg=30.0, label=label)
    args.update(kw)
    return membrane_material(**args)


def _membrane_material(material):
    return lookup_material(material, FlexMembraneMat)


def _node(pos, radius, mat):
    b = Body()
    b.shape = FlexNode(radius=radius)
    B._place(b, pos)
    b.bounded = False
    b.material = mat
    return O.bodies.append(b)


def facet(node1, node2, node3, material, thickness):
    """A deformable facet over three existing FlexNode bodies; thickness [m] (= 2 x contact
    radius). Returns its id."""
    t = _section("facet thickness", thickness)
    mat = _membrane_material(material)
    ids = (node1, node2, node3)
    for n in ids:
        if isinstance(n, bool) or not isinstance(n, int) or n < 0 or n >= len(O.bodies) or O.bodies[n] is None:
            raise ValueError(f"facet corner {n!r} is not the id of an existing body")
        if not isinstance(O.bodies[n].shape, FlexNode):
            raise ValueError(f"facet corner #{n} is a {type(O.bodies[n].shape).__name__}, not a FlexNode")
    if len(set(ids)) < 3:
        raise C.BadValue("facet corners", ids, "three different nodes (two corners are the same node)")
    C.body_budget("facet", ids, 1)
    b = Body()
    b.shape = FlexFacet(node1=node1, node2=node2, node3=node3, radius=0.5 * t)
    b.material = mat
    b.state.pos = (O.bodies[node1].state.pos + O.bodies[node2].state.pos + O.bodies[node3].state.pos) / 3
    i = O.bodies.append(b)
    try:
        b.shape.attach(i)
    except Exception:
        O.bodies.erase(i)
        raise
    return i


def triangle_mesh(points, triangles, material, thickness, fixed=()):
    """Membrane from a triangle mesh: points [(x, y, z)] [m], triangles [(i, j, k)] indices into
    points; fixed: indices of points to clamp. Returns (node_ids, facet_ids). Every triangle is
    checked (indices, area) before anything is added."""
    try:
        pts = [check_finite(f"point {k}", p) for k, p in enumerate(points)]
        triangles = list(triangles)
    except TypeError:
        raise C.BadValue("points, triangles", (points, triangles), "sequences of points and of index triples") from None
    C.body_budget("triangles", f"{len(triangles)} triangles", len(pts) + len(triangles))
    tris = []
    for k, t in enumerate(triangles):
        try:
            tri = tuple(int(i) for i in t)
        except (TypeError, ValueError):
            raise ValueError(f"triangle {k} must be 3 point indices, got {t!r}") from None
        if len(tri) != 3 or any(i < 0 or i >= len(pts) for i in tri):
            raise ValueError(f"triangle {k} = {t!r}: indices must be 3 values in [0, {len(pts) - 1}]")
        a, b, c = (pts[i] for i in tri)
        area2 = (b - a).cross(c - a).norm()
        scale = max((b - a).norm(), (c - a).norm(), (c - b).norm())
        if not area2 > 1e-12 * scale * scale:
            raise ValueError(f"triangle {k} = {tri} is degenerate (collinear or coincident points)")
        tris.append(tri)
    if not tris:
        raise ValueError("a membrane needs at least one triangle")
    fixed = C.indices("fixed", fixed, len(pts))
    t = _section("membrane thickness", thickness)
    mat = _membrane_material(material)
    used = sorted({i for tri in tris for i in tri})
    nid = {i: _node(pts[i], 0.5 * t, mat) for i in used}
    facets = [facet(nid[a], nid[b], nid[c], mat, t) for a, b, c in tris]
    fix([nid[i] for i in fixed if i in nid])
    return [nid.get(i, -1) for i in range(len(pts))], facets


def sheet(nx, ny, size, thickness, material, origin=(0, 0, 0), fix_border=True, pattern="crossed"):
    """Rectangular sheet in the plane z = origin.z, size = (lx, ly) [m], with nx x ny cells.
    pattern 'crossed' splits cells along alternating diagonals (no preferred direction),
    'right' along one diagonal. Returns dict(grid=node ids [i][j], facets, border)."""
    nx, ny = C.integer("nx", nx, 1, C.MAX_BODIES), C.integer("ny", ny, 1, C.MAX_BODIES)
    C.body_budget("nx" if nx > ny else "ny", nx if nx > ny else ny, (nx + 1) * (ny + 1) + 2 * nx * ny)
    C.choice("pattern", pattern, ("crossed", "right"))
    lx, ly = (_positive("sheet size", s) for s in C.vector("sheet size", size, 2))
    o = check_finite("sheet origin", origin)
    fix_border = C.boolean("fix_border", fix_border)
    pts = [o + Vector3(lx * i / nx, ly * j / ny, 0) for i in range(nx + 1) for j in range(ny + 1)]
    idx = lambda i, j: i * (ny + 1) + j
    tris = []
    for i in range(nx):
        for j in range(ny):
            a, b, c, d = idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)
            if pattern == "right" or (i + j) % 2 == 0:
                tris += [(a, b, c), (a, c, d)]
            else:
                tris += [(a, b, d), (b, c, d)]
    border = [idx(i, j) for i in range(nx + 1) for j in range(ny + 1) if i in (0, nx) or j in (0, ny)]
    nodes, facets = triangle_mesh(pts, tris, material, thickness, fixed=border if fix_border else ())
    grid = [[nodes[idx(i, j)] for j in range(ny + 1)] for i in range(nx + 1)]
    return dict(grid=grid, facets=facets, border=[nodes[k] for k in border])


def lining(radius, height, n_around, n_height, thickness, material, center=(0, 0, 0), fix_bottom=False):
    """Cylindrical lining (open tube, axis along z from center.z to center.z + height), radius
    [m], n_around x n_height cells, crossed diagonals. Facet normals point outwards, so a
    positive FlexFacet.pressure pushes the lining outwards (a fill's pressure). Returns
    dict(rings=node ids [k][i] (k along the height), facets, bottom, top)."""
    R = _positive("lining radius", radius)
    H = _positive("lining height", height)
    n_around, n_height = C.integer("n_around", n_around, 3, C.MAX_BODIES), C.integer("n_height", n_height, 1, C.MAX_BODIES)
    C.body_budget("n_around" if n_around > n_height else "n_height", max(n_around, n_height), 3 * n_around * (n_height + 1))
    c = check_finite("lining center", center)
    fix_bottom = C.boolean("fix_bottom", fix_bottom)
    pts = [c + Vector3(R * math.cos(2 * math.pi * i / n_around), R * math.sin(2 * math.pi * i / n_around), H * k / n_height)
           for k in range(n_height + 1) for i in range(n_around)]
    idx = lambda k, i: k * n_around + (i % n_around)
    tris = []
    for k in range(n_height):
        for i in range(n_around):
            a, b, cc, d = idx(k, i), idx(k, i + 1), idx(k + 1, i + 1), idx(k + 1, i)
            if (i + k) % 2 == 0:
                tris += [(a, b, cc), (a, cc, d)]
            else:
                tris += [(a, b, d), (b, cc, d)]
    bottom = [idx(0, i) for i in range(n_around)]
    nodes, facets = triangle_mesh(pts, tris, material, thickness, fixed=bottom if fix_bottom else ())
    rings = [[nodes[idx(k, i)] for i in range(n_around)] for k in range(n_height + 1)]
    return dict(rings=rings, facets=facets, bottom=rings[0], top=rings[-1])


def read_mesh(path):
    """(points, triangles) from a GTS or STL (ASCII or binary) file; STL vertices are merged."""
    if not isinstance(path, (str, os.PathLike)) or not os.path.isfile(path):
        raise ValueError(f"mesh file {path!r} does not exist")
    ext = os.path.splitext(path)[1].lower()
    if ext == ".gts":
        return _read_gts(path)
    if ext == ".stl":
        return _read_stl(path)
    raise ValueError(f"mesh file {path!r}: unknown format (use .gts or .stl)")


def _read_gts(path):
    with open(path) as f:
        lines = [ln.split() for ln in f if ln.strip() and not ln.lstrip().startswith("#")]
    try:
        nv, ne, nf = (int(x) for x in lines[0][:3])
        pts = [tuple(float(x) for x in ln[:3]) for ln in lines[1:1 + nv]]
        edges = [tuple(int(x) - 1 for x in ln[:2]) for ln in lines[1 + nv:1 + nv + ne]]
        tris = []
        for ln in lines[1 + nv + ne:1 + nv + ne + nf]:
            e = [edges[int(x) - 1] for x in ln[:3]]
            v = [e[0][0], e[0][1]]
            v.append(next(x for x in e[1] + e[2] if x not in v))
            tris.append(tuple(v))
    except (ValueError, IndexError, StopIteration) as err:
        raise ValueError(f"{path}: not a valid GTS file ({err})") from None
    if len(pts) != nv or len(tris) != nf:
        raise ValueError(f"{path}: truncated GTS file")
    return pts, tris


def _read_stl(path):
    with open(path, "rb") as f:
        data = f.read()
    raw = []
    text = data[:5].lower() == b"solid" and b"facet" in data[:1000]
    if text:
        verts = [tuple(float(x) for x in ln.split()[1:4]) for ln in data.decode(errors="replace").splitlines()
                 if ln.strip().startswith("vertex")]
        if len(verts) % 3:
            raise ValueError(f"{path}: ASCII STL with {len(verts)} vertices (not a multiple of 3)")
        raw = [verts[k:k + 3] for k in range(0, len(verts), 3)]
    else:
        if len(data) < 84:
            raise ValueError(f"{path}: too short for a binary STL")
        n = struct.unpack("<I", data[80:84])[0]
        if len(data) < 84 + 50 * n:
            raise ValueError(f"{path}: binary STL announces {n} triangles but is truncated")
        for k in range(n):
            v = struct.unpack("<12f", data[84 + 50 * k:84 + 50 * k + 48])
            raw.append([v[3:6], v[6:9], v[9:12]])
    if not raw:
        raise ValueError(f"{path}: no triangles")
    allv = [p for tri in raw for p in tri]
    span = max(max(p[i] for p in allv) - min(p[i] for p in allv) for i in range(3)) or 1.0
    tol = 1e-9 * span
    index, pts, tris = {}, [], []
    for tri in raw:
        ids = []
        for p in tri:
            key = tuple(round(x / tol) for x in p)
            if key not in index:
                index[key] = len(pts)
                pts.append(p)
            ids.append(index[key])
        tris.append(tuple(ids))
    return pts, tris


def mesh_file(path, material, thickness, scale=1.0, shift=(0, 0, 0), fixed=()):
    """Membrane from a GTS or STL file (coordinates x scale + shift [m]). Returns (node_ids, facet_ids)."""
    pts, tris = read_mesh(path)
    s = _positive("scale", scale)
    d = check_finite("shift", shift)
    return triangle_mesh([Vector3(*p) * s + d for p in pts], tris, material, thickness, fixed=fixed)


def membrane_state(facet_ids):
    """Per-facet dict(n1, n2 [N/m], e1, e2 [-], energy [J]) (None for ruptured facets)."""
    out = []
    for i in facet_ids:
        b = O.bodies[i]
        out.append(None if b is None else dict(n1=b.shape.n1, n2=b.shape.n2, e1=b.shape.e1, e2=b.shape.e2, energy=b.shape.elasticEnergy))
    return out
