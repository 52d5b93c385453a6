"""Bookkeeping of the damping-module impact (scripts/damping_module.py): which part of the module a
body is, what broke by kind, when the run ends and when it is expected to end, the progress line.
"""
import bisect
import time

from yade import O

# (key of the module's ids, name of one such body), in the order a body is looked up
PARTS = (("grains", "grain"), ("mesh_cylinders", "wire leg"), ("lining", "lining facet"), ("mesh_nodes", "mesh node"),
         ("ring_top", "top ring"), ("ring_bottom", "bottom ring"), ("rope", "rope"), ("lining_nodes", "lining node"),
         ("rope_nodes", "rope node"))
# summary key of broken elements -> keys of the module's ids holding such elements
BROKEN_KINDS = (("broken_wire_legs", ("mesh_cylinders",)), ("broken_ring_segments", ("ring_top", "ring_bottom")),
                ("broken_rope_segments", ("rope",)), ("broken_lining_facets", ("lining",)))


def bodies_of(ids, key):
    """Set of the body ids under key in the module's ids (module.build_filled): the whole
    scene's (grains, rope) and every module's (mesh, rings, lining), not the first module's only."""
    out = set(ids.get(key, ()))
    for m in ids.get("modules", ()):
        out.update(m.get(key, ()))
    return out


def part_names(ids):
    """dict body id -> part name ('wire leg', 'lining facet', ...) over all modules."""
    names = {}
    for key, name in reversed(PARTS):  # the first of PARTS wins
        names.update(dict.fromkeys(bodies_of(ids, key), name))
    return names


def part_name(bid, names):
    """'grain #12', 'wire leg #300', ...: which part of the module a body is (names: part_names)."""
    if bid is None or bid < 0 or bid >= len(O.bodies):
        return "no body"
    if bid in names:
        return f"{names[bid]} #{bid}"
    b = O.bodies[bid]
    if b is not None and b.isClumpMember:
        return f"boulder (clump member #{bid})"
    return f"{type(b.shape).__name__ if b is not None else 'erased body'} #{bid}"


class BrokenElements:
    """Counts of ruptured elements by kind (FlexElementEngine.rupturedIds: every element it
    erased, of any kind): the BROKEN_KINDS keys, broken_other_elements (an element of none of
    those kinds) and broken_elements_total, their sum."""

    def __init__(self, ids):
        self.kind = {}
        for name, keys in BROKEN_KINDS:
            for k in keys:
                self.kind.update(dict.fromkeys(bodies_of(ids, k), name))

    def counts(self, ruptured_ids):
        c = dict.fromkeys([name for name, _ in BROKEN_KINDS] + ["broken_other_elements"], 0)
        for i in ruptured_ids:
            c[self.kind.get(i, "broken_other_elements")] += 1
        c["broken_elements_total"] = len(ruptured_ids)
        return c


class ImpactTimes:
    """When the impact run stops (simulated time [s]) and when it is expected to stop.

    The run lasts `duration` [s] after the first contact if given; otherwise until the rebound
    (the boulder moving up again) plus REBOUND_MARGIN of the contact time (at least MIN_MARGIN),
    and at most MAX_AFTER_CONTACT after the first contact. Before the first contact, the same
    bounds count from the start. Feed it every record (observe); .end is the stop time known so
    far (a bound until the rebound), expected_end() the best estimate."""
    MAX_AFTER_CONTACT = 0.3
    REBOUND_MARGIN = 0.2
    MIN_MARGIN = 0.01
    WINDOW = 0.5  # deceleration over this latest fraction of the contact so far

    def __init__(self, start, duration=None):
        self.start, self.duration = start, duration
        self.t_contact = self.t_rebound = None
        self.end = start + (duration if duration else self.MAX_AFTER_CONTACT)
        self._t, self._vz = [], []  # the records since the first contact

    def observe(self, t, vz, touching):
        """A record at t: the boulder's vertical velocity vz [m/s] (< 0: down); touching: the
        module pushes on it (the first such record is the first contact)."""
        if self.t_contact is None and touching:
            self.t_contact = t
            self.end = t + (self.duration if self.duration else self.MAX_AFTER_CONTACT)
        if self.t_contact is None:
            return
        self._t.append(t)
        self._vz.append(vz)
        if self.t_rebound is None and vz > 0:
            self.t_rebound = t
            if not self.duration:
                self.end = min(self.end, self._after_rebound(t))

    def _after_rebound(self, t_rebound):
        return t_rebound + max(self.REBOUND_MARGIN * (t_rebound - self.t_contact), self.MIN_MARGIN)

    def expected_end(self):
        """The expected stop time after the last record: .end once it is fixed (a given duration,
        or after the rebound); during the contact, the rebound extrapolated from the boulder's
        deceleration over the latest WINDOW of the contact so far (its speed falling linearly to
        zero; exact for a constant force, an overestimate early in a stiffening contact) plus the
        margin, within .end; before the first contact or while the boulder is not slowing down,
        .end (the most it can last)."""
        if self.duration or self.t_rebound is not None or len(self._t) < 2:
            return self.end
        t, vz = self._t[-1], self._vz[-1]
        k = bisect.bisect_left(self._t, t - self.WINDOW * (t - self.t_contact))
        t0, v0 = self._t[k], self._vz[k]
        if t0 >= t or vz >= 0 or vz <= v0:
            return self.end
        return min(self.end, self._after_rebound(t - vz * (t - t0) / (vz - v0)))


class Progress:
    """The impact's progress line: simulated time done of the expected total, steps, wall time
    elapsed and left. The time left is the wall time per simulated second so far times the
    simulated time left to the expected end (ImpactTimes.expected_end). Prints at most every
    `every` wall seconds, and at the end. clock: wall-clock function (tests pass a fake one)."""

    def __init__(self, start, every=5.0, clock=time.time, out=None):
        self.start, self.every, self.clock = start, every, clock
        self.out = out or (lambda line: print(line, flush=True))
        self.t0 = clock()
        self.last = None

    def eta(self, t, expected_end):
        """Wall time left [s] at simulated time t."""
        done = max(1e-12, t - self.start)
        return (self.clock() - self.t0) / done * max(0.0, expected_end - t)

    def __call__(self, t, steps, expected_end, extra=""):
        """Print the line if due; returns it (None if not due)."""
        now = self.clock()
        if self.last is not None and now - self.last < self.every and t < expected_end:
            return None
        self.last = now
        line = (f"  t = {1e3 * (t - self.start):7.2f} ms of {1e3 * (expected_end - self.start):.0f} ms, {steps} steps, "
                f"{now - self.t0:6.0f} s elapsed, ~{self.eta(t, expected_end):.0f} s left {extra}")
        self.out(line)
        return line
