"""Checks of user input, shared by every builder, scene and the main job.

Each check returns the value converted (float, int, bool, Vector3) or raises BadValue, a
ValueError that names the argument, the value it got and the values allowed, in one line:

    diameter: got -1.0; allowed >= 0.2 m

Builders run all their checks, including the body budget, before they add anything to the
scene, so a refused call leaves the scene as it was.
"""
import math
import numbers
from dataclasses import dataclass

# Largest scene a builder agrees to make. A body with its contacts takes about 8.5 kB (measured:
# 64,000 touching spheres in YADE 2023.02a, 6 contacts each, after one step), so this limit keeps
# a scene near 4 GB; the default damping module has under 10,000 bodies, seven tied modules under
# 70,000 (ModuleParams.body_estimate). A call that would pass it is refused before anything is built.
MAX_BODIES = 500_000
BYTES_PER_BODY = 8.5e3


class BadValue(ValueError):
    """A refused argument: .name, .value (as given) and .allowed (text)."""

    def __init__(self, name, value, allowed):
        self.name, self.value, self.allowed = name, value, allowed
        super().__init__(f"{name}: got {show(value)}; allowed {allowed}")


def show(v):
    """A value as the user wrote it (floats in their shortest form)."""
    if isinstance(v, float):
        return repr(v)
    if isinstance(v, (tuple, list)):
        return "(" + ", ".join(show(x) for x in v) + ")"
    return repr(v)


def _fmt(x):
    return f"{x:g}"


@dataclass(frozen=True)
class Range:
    """Allowed values of a number: lo..hi (open or closed ends), unit, an optional note."""
    lo: float = -math.inf
    hi: float = math.inf
    unit: str = ""
    lo_open: bool = False
    hi_open: bool = False
    note: str = ""

    def text(self):
        u = f" {self.unit}" if self.unit else ""
        if self.hi == math.inf and self.lo == -math.inf:
            t = "any finite value" + u
        elif self.hi == math.inf:
            t = ("> " if self.lo_open else ">= ") + _fmt(self.lo) + u
        elif self.lo == -math.inf:
            t = ("< " if self.hi_open else "<= ") + _fmt(self.hi) + u
        else:
            t = ("(" if self.lo_open else "[") + f"{_fmt(self.lo)}, {_fmt(self.hi)}" + (")" if self.hi_open else "]") + u
        return t + (f" ({self.note})" if self.note else "")

    def check(self, name, v):
        return number(name, v, self)


def number(name, v, rng=Range()):
    """float(v) if v is a finite real number (not a bool, not a string) in rng, else BadValue."""
    if isinstance(v, bool) or not isinstance(v, numbers.Real):
        raise BadValue(name, v, "a finite number " + rng.text())
    x = float(v)
    inside = (math.isfinite(x) and (x > rng.lo if rng.lo_open else x >= rng.lo) and (x < rng.hi if rng.hi_open else x <= rng.hi))
    if not inside:
        raise BadValue(name, v, rng.text())
    return x


def positive(name, v, unit="", hi=math.inf):
    """float(v) if finite and > 0 (and <= hi), else BadValue."""
    return number(name, v, Range(0.0, hi, unit, lo_open=True))


def integer(name, v, lo=-2 ** 63, hi=2 ** 63 - 1):
    """int(v) if v is an integer (not a bool, not a float) in [lo, hi], else BadValue."""
    if isinstance(v, bool) or not isinstance(v, numbers.Integral) or not lo <= v <= hi:
        raise BadValue(name, v, f"a whole number in [{lo}, {hi}]")
    return int(v)


TRUE_WORDS, FALSE_WORDS = ("true", "yes", "1"), ("false", "no", "0")


def boolean(name, v):
    """True/False from a bool, the integers 0 and 1 or the words true/false/yes/no/1/0 (any case)."""
    if isinstance(v, bool):
        return v
    if isinstance(v, numbers.Integral) and v in (0, 1):
        return bool(v)
    if isinstance(v, str) and v.strip().lower() in TRUE_WORDS + FALSE_WORDS:
        return v.strip().lower() in TRUE_WORDS
    raise BadValue(name, v, "true/false/yes/no/1/0")


def choice(name, v, options):
    """v if it is one of options, else BadValue listing them."""
    if not any(v == o and type(v) is type(o) for o in options):
        raise BadValue(name, v, "one of " + ", ".join(show(o) for o in options))
    return v


def vector(name, p, n=3):
    """Tuple of n finite floats from a sequence, else BadValue."""
    try:
        vals = [number(name, x) for x in p]
    except (TypeError, BadValue):
        vals = None
    if vals is None or len(vals) != n:
        raise BadValue(name, p, f"{n} finite numbers")
    return tuple(vals)


def point(name, p):
    """Vector3 from a sequence of 3 finite numbers, else BadValue."""
    from yade.minieigenHP import Vector3
    return Vector3(*vector(name, p, 3))


def indices(name, seq, n):
    """List of ints, each in [0, n), else BadValue."""
    try:
        items = list(seq)
    except TypeError:
        raise BadValue(name, seq, f"a sequence of indices in [0, {n - 1}]") from None
    for i in items:
        if isinstance(i, bool) or not isinstance(i, numbers.Integral) or not 0 <= i < n:
            raise BadValue(name, seq, f"indices in [0, {n - 1}]")
    return [int(i) for i in items]


def _count(n):
    return f"{float(n):.3g}" if n < 1e300 else "over 1e300"


def body_budget(name, value, count):
    """BadValue naming `name` if adding `count` bodies (a float estimate is fine) to the scene
    would pass MAX_BODIES."""
    from yade import O
    room = MAX_BODIES - len(O.bodies)
    if not count <= room:
        raise BadValue(name, value, f"a value that needs at most {room} more bodies (this one {_count(count)}; "
                       f"yadeflex.checks.MAX_BODIES = {MAX_BODIES}, about {MAX_BODIES * BYTES_PER_BODY / 1e9:.0f} GB)")
