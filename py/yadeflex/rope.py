"""Boundary rope (6x7 FC, yadeflex.rope_6x7_8mm) around one or several modules."""
import math

from . import builders as B


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
    into segments of about segment_length [m]. Returns (node_ids, cylinder_ids)."""
    Rm = B._positive("module radius", module_radius) + B._positive("rope radius", rope_radius)
    h = B._positive("segment length", segment_length)
    cs = [(float(c[0]), float(c[1])) for c in centers]
    if not cs:
        raise ValueError("rope_around needs at least one module centre")
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
        pts.append((a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), float(z)))
    return B.chain(pts, rope_radius, material, closed=True, fixed=fixed)
