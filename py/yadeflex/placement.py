"""Placement of a structure: every builder inside `with placed(origin, axis, angle):` builds its
structure as it would at the origin, then moved rigidly: each node's position p becomes
origin + R p and its orientation R q, R the rotation of `angle` [deg] about `axis`. A panel
built in the x-y plane becomes a drapery on a slope, a module stands on a tilted slab, two
panels meet at an edge. Placements nest (the inner one is applied first).

What is not turned: gravity, and the degrees of freedom a builder blocks by axis letter (`fix(ids,
"z")` blocks the global z); fixing every translation ("xyz") or every DOF is the same in any
placement.
"""
import contextlib
import math

from yade.minieigenHP import Quaternion, Vector3

from . import checks as C


class Placement:
    """A rigid motion: origin (Vector3) and rotation (Quaternion)."""

    def __init__(self, origin=Vector3(0, 0, 0), rotation=Quaternion.Identity):
        self.origin, self.rotation = Vector3(origin), Quaternion(rotation)

    def is_identity(self):
        return self.origin == Vector3(0, 0, 0) and self.rotation == Quaternion.Identity

    def point(self, p):
        """Position p [m] placed."""
        return self.origin + self.rotation * Vector3(p)

    def orientation(self, q):
        """Orientation q placed."""
        return self.rotation * q

    def local(self, p):
        """The position whose placement is p (the inverse motion)."""
        return self.rotation.conjugate() * (Vector3(p) - self.origin)

    def then(self, outer):
        """This placement followed by `outer`."""
        return Placement(outer.point(self.origin), outer.rotation * self.rotation)


_stack = [Placement()]


def current():
    """The placement the builders apply now (identity outside any `placed`)."""
    return _stack[-1]


@contextlib.contextmanager
def placed(origin=(0, 0, 0), axis=(0, 0, 1), angle=0.0):
    """Builders inside are placed: rotated by `angle` [deg] about `axis` (through the local
    origin), then moved to `origin` [m]. Yields the Placement."""
    o = C.vector("origin", origin, 3)
    a = C.vector("axis", axis, 3)
    n = math.sqrt(sum(x * x for x in a))
    if not n > 0:
        raise C.BadValue("axis", axis, "a non-zero direction")
    ang = C.number("angle", angle, C.Range(-360.0, 360.0, "deg"))
    p = Placement(Vector3(*o), Quaternion(Vector3(*(x / n for x in a)), math.radians(ang)))
    _stack.append(p.then(current()))
    try:
        yield _stack[-1]
    finally:
        _stack.pop()
