"""How far a boulder falls straight down before it first touches the scene: from its spheres (one,
or a clump's members) against every body it can meet: spheres, yade-flex wires and membranes
(capsules and thick triangles about their nodes), YADE facets, boxes and walls normal to z.

Each body's distance to a falling sphere is a convex function of the fall, so the first touch
along the fall is found exactly: the fall of least distance (ternary search), then the first
fall within reach before it (bisection), both to well below a micrometre; numpy over the bodies
near each sphere."""
import math

import numpy as np
from yade import O

_ITER = 60  # steps of each search: (2/3)^60 = 3e-11 of the range for the ternary one


def _point_segment(p, a, b):
    """Distances from points p (n, 3) to segments a-b (n, 3 each)."""
    ab = b - a
    L2 = np.einsum("ij,ij->i", ab, ab)
    t = np.where(L2 > 0, np.einsum("ij,ij->i", p - a, ab) / np.where(L2 > 0, L2, 1.0), 0.0)
    t = np.clip(t, 0.0, 1.0)
    return np.linalg.norm(p - (a + t[:, None] * ab), axis=1)


def _point_triangle(p, a, b, c):
    """Distances from points p to triangles abc (n, 3 each): to the face where p projects inside
    it, else to the nearest edge."""
    n = np.cross(b - a, c - a)
    nn = np.linalg.norm(n, axis=1)
    unit = n / np.where(nn > 0, nn, 1.0)[:, None]
    h = np.einsum("ij,ij->i", p - a, unit)
    q = p - h[:, None] * unit
    inside = nn > 0
    for u, v in ((a, b), (b, c), (c, a)):
        inside &= np.einsum("ij,ij->i", np.cross(v - u, q - u), n) >= 0
    face = np.where(inside, np.abs(h), np.inf)
    edges = np.minimum(np.minimum(_point_segment(p, a, b), _point_segment(p, b, c)), _point_segment(p, c, a))
    return np.minimum(face, edges)


class _Targets:
    """What a falling sphere can meet: (kind, reach, points) arrays, kind 0 sphere (points: the
    centre), 1 segment (2 points), 2 triangle (3 points), 3 plane z = const (points: any)."""

    def __init__(self, skip):
        from yade.wrapper import Box, Facet, FlexCylinder, FlexFacet, Sphere, Wall
        rows = []  # (kind, reach, p0, p1, p2)
        for b in O.bodies:
            if b is None or b.isClump or b.id in skip:
                continue
            sh, pos = b.shape, b.state.pos
            if isinstance(sh, Sphere):
                rows.append((0, sh.radius, pos, pos, pos))
            elif isinstance(sh, FlexCylinder):
                x = [O.bodies[i].state.pos for i in (sh.node1, sh.node2)]
                rows.append((1, sh.radius, x[0], x[1], x[1]))
            elif isinstance(sh, FlexFacet):
                x = [O.bodies[i].state.pos for i in (sh.node1, sh.node2, sh.node3)]
                rows.append((2, sh.radius, x[0], x[1], x[2]))
            elif isinstance(sh, Facet):
                x = [pos + b.state.ori * v for v in sh.vertices]
                rows.append((2, 0.0, x[0], x[1], x[2]))
            elif isinstance(sh, Box):  # (its six faces, two triangles each)
                e = sh.extents

                def corner(v):
                    return pos + b.state.ori * type(pos)(v[0] * e[0], v[1] * e[1], v[2] * e[2])
                for axis in range(3):
                    u, w = [k for k in range(3) if k != axis]
                    for s in (-1, 1):
                        quad = []
                        for su, sw in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                            v = [0, 0, 0]
                            v[axis], v[u], v[w] = s, su, sw
                            quad.append(corner(v))
                        rows.append((2, 0.0, quad[0], quad[1], quad[2]))
                        rows.append((2, 0.0, quad[0], quad[2], quad[3]))
            elif isinstance(sh, Wall) and sh.axis == 2:
                rows.append((3, 0.0, pos, pos, pos))
        self.kind = np.array([r[0] for r in rows], dtype=int)
        self.reach = np.array([r[1] for r in rows], dtype=float)
        self.p = np.array([[[float(r[k][i]) for i in range(3)] for k in (2, 3, 4)] for r in rows], dtype=float).reshape(len(rows), 3, 3)

    def near(self, c, r):
        """Indices of the targets whose horizontal extent comes within reach of the vertical line
        through c for a sphere of radius r (every plane)."""
        lo = self.p[:, :, :2].min(axis=1) - (self.reach + r)[:, None]
        hi = self.p[:, :, :2].max(axis=1) + (self.reach + r)[:, None]
        ok = (lo[:, 0] <= c[0]) & (c[0] <= hi[:, 0]) & (lo[:, 1] <= c[1]) & (c[1] <= hi[:, 1])
        return np.nonzero(ok | (self.kind == 3))[0]


def _gap(c, r, t, idx, fall):
    """Distance from the sphere (centre c, radius r) lowered by `fall` (array by target) to the
    targets idx, less their reach and r: > 0 apart."""
    p = np.repeat(c[None, :], len(idx), axis=0)
    p[:, 2] -= fall
    k, P = t.kind[idx], t.p[idx]
    d = np.empty(len(idx))
    m = k == 0
    d[m] = np.linalg.norm(p[m] - P[m, 0], axis=1)
    m = k == 1
    d[m] = _point_segment(p[m], P[m, 0], P[m, 1])
    m = k == 2
    d[m] = _point_triangle(p[m], P[m, 0], P[m, 1], P[m, 2])
    m = k == 3
    d[m] = np.where(p[m, 2] >= P[m, 0, 2], p[m, 2] - P[m, 0, 2], 0.0)  # (a wall: from above only)
    return d - t.reach[idx] - r


def first_touch(spheres, skip=()):
    """How far [m] the rigid set of spheres [(centre (x, y, z), radius)] can fall straight down
    (along -z) before one first touches a body of the scene (skip: ids left out, e.g. the
    boulder's own); inf if it meets nothing; 0 if one already touches."""
    t = _Targets(set(skip))
    top = t.p[:, :, 2].max(axis=1) + t.reach  # (a plane: its height)
    best = math.inf
    spheres = [(np.array([float(c[0]), float(c[1]), float(c[2])]), float(r)) for c, r in spheres]
    # a sphere straight above another as large or larger touches nothing before it (the lower one
    # holds it lowered): only the lowest of each column counts (a cube's bottom layer)
    spheres = [(c, r) for k, (c, r) in enumerate(spheres)
               if not any(j != k and c2[0] == c[0] and c2[1] == c[1] and r2 >= r and (c2[2] < c[2] or (c2[2] == c[2] and j < k))
                          for j, (c2, r2) in enumerate(spheres))]
    spheres.sort(key=lambda s: s[0][2] - s[1])  # (the lowest first: the others then meet fewer targets within the best fall)
    for c, r in spheres:
        idx = t.near(c, r)
        if math.isfinite(best):  # only what it could reach within the best fall so far
            idx = idx[top[idx] >= c[2] - r - best]
        if not len(idx):
            continue
        if (_gap(c, r, t, idx, np.zeros(len(idx))) <= 0).any():
            return 0.0
        # the least distance: somewhere between no fall and the fall that takes the sphere's
        # centre below the target's lowest point by its reach (distance only grows past it)
        P = t.p[idx]
        lo = np.zeros(len(idx))
        hi = np.maximum(0.0, c[2] - (P[:, :, 2].min(axis=1) - t.reach[idx] - r)) + 1e-9
        for _ in range(_ITER):
            m1, m2 = lo + (hi - lo) / 3, hi - (hi - lo) / 3
            left = _gap(c, r, t, idx, m1) <= _gap(c, r, t, idx, m2)
            hi = np.where(left, m2, hi)
            lo = np.where(left, lo, m1)
        at_min = 0.5 * (lo + hi)
        hit = _gap(c, r, t, idx, at_min) <= 0
        if not hit.any():
            continue
        idx, at_min = idx[hit], at_min[hit]
        lo, hi = np.zeros(len(idx)), at_min  # gap > 0 at lo, <= 0 at hi
        for _ in range(_ITER):
            mid = 0.5 * (lo + hi)
            inside = _gap(c, r, t, idx, mid) <= 0
            hi = np.where(inside, mid, hi)
            lo = np.where(inside, lo, mid)
        best = min(best, float(lo.min()))
    return best


def lower_onto(bid, gap):
    """Lower body bid (a sphere or a clump, placed clear above what it falls onto) straight down
    until it would first touch the scene after a fall of exactly `gap` [m]; returns how far it was
    moved [m] (0 if its first touch was within gap already, or it meets nothing below)."""
    b = O.bodies[bid]
    ids = [bid] + (list(b.shape.members.keys()) if b.isClump else [])
    spheres = [(O.bodies[i].state.pos, O.bodies[i].shape.radius) for i in ids if not O.bodies[i].isClump]
    fall = first_touch(spheres, skip=ids)
    if not (math.isfinite(fall) and fall > gap):
        return 0.0
    shift = fall - gap
    for i in ids:
        p = O.bodies[i].state.pos
        p[2] -= shift
        O.bodies[i].state.pos = p
    return shift
