"""Boundary rope (6x7 FC, yadeflex.rope_6x7_8mm) around one or several modules."""
import math

from . import builders as B
from . import checks as C


def _hull(points):
    """Convex hull (counter-clockwise) of 2D points, Andrew's monotone chain."""
    pts = sorted(set(points))
    if len(pts) < 3:
        return pts

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]


def rope_around(centers, module_radius, z, material, rope_radius=0.004, segment_length=0.1, fixed=()):
    """Closed rope at height z [m] around vertical cylindrical modules of radius module_radius
    [m] centred at centers [(x, y), ...], touching them (its axis at module_radius +
    rope_radius): the convex hull of the circles, straight between modules, discretised
    into segments of about segment_length [m] whose chords touch the circles without cutting
    into them (the nodes on the arcs lie slightly outside). Returns (node_ids, cylinder_ids)."""
    Rm = B._positive("module radius", module_radius) + B._section("rope radius", rope_radius)
    h = B._positive("segment length", segment_length)
    z = C.number("z", z, C.Range(unit="m"))
    try:
        cs = [C.vector("centers", c, 2) for c in centers]
    except TypeError:
        raise C.BadValue("centers", centers, "a sequence of (x, y) points") from None
    if not cs:
        raise C.BadValue("centers", centers, "at least one module centre")
    B._material(material)
    span = sum(max(c[i] for c in cs) - min(c[i] for c in cs) for i in (0, 1))
    C.body_budget("segment length", segment_length, 2 * (2 * math.pi * Rm + 2 * span) / h)
    # fine samples on every circle; the hull of the samples follows arcs and tangents
    n = max(64, int(2 * math.pi * Rm / (0.25 * h)))
    hull = _hull([(x + Rm * math.cos(2 * math.pi * k / n), y + Rm * math.sin(2 * math.pi * k / n)) for x, y in cs for k in range(n)])
    # resample the closed polyline at (about) equal arc length
    seg = [math.dist(hull[k], hull[(k + 1) % len(hull)]) for k in range(len(hull))]
    total = sum(seg)
    m = max(3, int(round(total / h)))
    pts, k, acc = [], 0, 0.0
    for j in range(m):
        s = j * total / m
        while acc + seg[k] < s:
            acc += seg[k]
            k += 1
        t = (s - acc) / seg[k]
        a, b = hull[k], hull[(k + 1) % len(hull)]
        pts.append((a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])))
    pts = _clear_of_circles(pts, cs, Rm)
    return B.chain([(x, y, z) for x, y in pts], rope_radius, material, closed=True, fixed=fixed)


def _segment_distance(c, a, b):
    """Distance from point c to segment a-b (2D)."""
    ab = (b[0] - a[0], b[1] - a[1])
    L2 = ab[0] * ab[0] + ab[1] * ab[1]
    t = 0.0 if L2 == 0 else max(0.0, min(1.0, ((c[0] - a[0]) * ab[0] + (c[1] - a[1]) * ab[1]) / L2))
    return math.hypot(a[0] + t * ab[0] - c[0], a[1] + t * ab[1] - c[1])


def _clear_of_circles(pts, centers, R, rel_tol=1e-9):
    """Move the vertices of the closed polygon pts outward, each from its nearest centre, until
    no chord comes closer than R to any centre. Vertices on the arcs of the hull leave chords
    that cut into the circle by their sagitta, R (1 - cos(h / 2R)): 6 mm for 0.1 m segments on
    a 0.2 m module, and a rope built there would start by pushing the mesh wires away with
    forces of the order of 100 kN (mesh nodes thrown at 100 m/s in the first steps of a
    three-module fill). Pushed out, the chords touch the circles at their middles (a circumscribed polygon)
    and stay straight along the tangents between modules."""
    pts = [list(p) for p in pts]
    m = len(pts)
    for _ in range(200):
        deficit = [max(0.0, R - min(_segment_distance(c, pts[j], pts[(j + 1) % m]) for c in centers)) for j in range(m)]
        if max(deficit) <= rel_tol * R:
            return [tuple(p) for p in pts]
        moved = []
        for j in range(m):
            d = max(deficit[j - 1], deficit[j])
            if d > 0:
                c = min(centers, key=lambda c: math.dist(c, pts[j]))
                r = math.dist(c, pts[j])
                moved.append((j, (pts[j][0] + d * (pts[j][0] - c[0]) / r, pts[j][1] + d * (pts[j][1] - c[1]) / r)))
        for j, q in moved:
            pts[j] = list(q)
    raise RuntimeError(f"rope_around: could not place the rope clear of the modules (chord {max(deficit):.3g} m inside)")
