"""Would the fill's grains break? A screen of the grains' contact forces against the failure load
of rock lumps in the point-load test (no YADE needed).

The grains of the model are elastic and never break. A real gravel grain splits when the force
between two of its contacts passes its strength. The point-load test (ISRM 1985, "Suggested
method for determining point load strength", Int J Rock Mech Min Sci 22(2): 51-60) measures that
force P for a lump of size D pressed between two conical points: the index Is = P / D^2, reduced
to the size D = 50 mm by Is(50) = (D / 50 mm)^0.45 Is. A sphere of diameter d pressed across its
diameter therefore fails at

    P = Is(50) d^2 (50 mm / d)^0.45,

so a grain with a contact force of P or more would split. Is(50) of rock: 1.5-4 MPa moderately
strong (sandstone, shale), 4-10 MPa strong (marble, granite, gneiss), over 10 MPa very strong
(quartzite, dolerite, basalt) (Selby 1993, Hillslope materials and processes, 2nd ed., Table 5.3).

It is a screen, not a crushing model: a grain in a fill has several contacts, which spread the load
and raise its strength above the point-load test's two points, and a broken grain would change
what the fill does after it breaks. What it measures: how many grains would break, where, and
how far the boulder had penetrated when they did.

PeakGrainForces keeps, for each grain, the largest contact normal force seen so far, and for each
strength the penetration at which the grain first reached its failure load; feed it the contacts
of the scene (ids and normal forces: scene_contacts() reads them from YADE's scene) as often as
the forces change."""

import numpy as np

from . import checks as C

IS50_REFERENCE = 0.05  # [m] the point-load index's reference size
SIZE_EXPONENT = 0.45   # ISRM 1985's size correction


def failure_load(diameter, is50):
    """Point-load failure force [N] of a grain of diameter [m] (a number or an array) of rock of
    point-load index is50 [Pa]: is50 d^2 (0.05 m / d)^0.45."""
    is50 = C.number("is50", is50, C.Range(0.0, unit="Pa", lo_open=True))
    d = np.asarray(diameter, dtype=float)
    if not np.all(np.isfinite(d)) or np.any(d <= 0):
        raise ValueError(f"diameter: got {diameter!r}; allowed finite numbers > 0 m")
    return is50 * d ** 2 * (IS50_REFERENCE / d) ** SIZE_EXPONENT


class PeakGrainForces:
    """Largest contact normal force of each grain, and when it first reached its failure load.

    grains: body ids of the grains; diameters: theirs [m], in the same order; strengths: Is(50)
    values [Pa] to screen against. update(id1, id2, fn, penetration) takes one set of contacts (the
    two bodies' ids and the contact's normal force magnitude [N]; contacts with no grain are
    ignored, NaN forces are refused) and the boulder's penetration [m] at that moment."""

    def __init__(self, grains, diameters, strengths):
        self.ids = np.asarray(grains, dtype=np.int64)
        self.diameter = np.asarray(diameters, dtype=float)
        if self.ids.ndim != 1 or self.ids.shape != self.diameter.shape or self.ids.size == 0:
            raise ValueError(f"grains and diameters: got {self.ids.size} ids and {self.diameter.size} diameters; allowed the same number, at least one")
        if np.any(self.ids < 0) or np.unique(self.ids).size != self.ids.size:
            raise ValueError("grains: body ids must be distinct and >= 0")
        self.strengths = [C.number("strength", s, C.Range(0.0, unit="Pa", lo_open=True)) for s in strengths]
        self.load = np.array([failure_load(self.diameter, s) for s in self.strengths]).reshape(len(self.strengths), -1)
        self.row = np.full(int(self.ids.max()) + 1, -1, dtype=np.int64)  # body id -> grain row
        self.row[self.ids] = np.arange(self.ids.size)
        self.peak = np.zeros(self.ids.size)  # [N]
        self.first = np.full((len(self.strengths), self.ids.size), np.nan)  # penetration [m] at the failure load

    def _rows(self, ids):
        ids = np.asarray(ids, dtype=np.int64)
        inside = (ids >= 0) & (ids < self.row.size)
        r = np.full(ids.shape, -1, dtype=np.int64)
        r[inside] = self.row[ids[inside]]
        return r

    def update(self, id1, id2, fn, penetration):
        fn = np.abs(np.asarray(fn, dtype=float))
        if not np.all(np.isfinite(fn)):
            raise ValueError("fn: the contact forces must be finite")
        penetration = C.number("penetration", penetration)
        for r in (self._rows(id1), self._rows(id2)):
            if r.shape != fn.shape:
                raise ValueError(f"id1, id2 and fn: got {r.size} ids for {fn.size} forces")
            hit = r >= 0
            np.maximum.at(self.peak, r[hit], fn[hit])
        reached = (self.peak >= self.load) & np.isnan(self.first)
        self.first[reached] = penetration

    def broken(self, k):
        """Mask of the grains whose force reached the failure load at strengths[k]."""
        return ~np.isnan(self.first[k])


def scene_contacts():
    """(id1, id2, normal force magnitude [N]) of the current YADE scene's contacts that have a
    normal force (yade.wrapper.FlexSnapshot.contacts), as arrays."""
    from yade.wrapper import FlexSnapshot
    c = FlexSnapshot().contacts()
    fn = np.linalg.norm(np.frombuffer(c["normalForce"], dtype=np.float64).reshape(-1, 3), axis=1)
    ok = np.isfinite(fn)  # (geometries without a normal force)
    return np.frombuffer(c["id1"], dtype=np.int64)[ok], np.frombuffer(c["id2"], dtype=np.int64)[ok], fn[ok]
