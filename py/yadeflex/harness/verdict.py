"""A validation case's verdict: a measured value against its reference with a tolerance fixed in
code before the run (validation/run.py grades every case with it and writes the report).

A verdict is computed, never set: PASS when the measured value is finite and within the
tolerance, FAIL otherwise (NOT MEASURED when the run gave no finite value). A case with a known
open gap (a model still missing) keeps its FAIL and says so in `open`."""
import math
from dataclasses import dataclass, field, asdict

from .. import checks as C

KINDS = ("relative", "absolute", "band")


@dataclass
class Case:
    name: str                 # identifier, also the key in summary.json
    group: str                # section of the report
    quantity: str             # what is measured, with its unit
    reference: object         # a number, or (lo, hi) for kind 'band'
    source: str               # where the reference comes from (paper, datasheet, formula)
    tolerance: float          # relative or absolute (in the quantity's unit); ignored for 'band'
    kind: str                 # 'relative', 'absolute' or 'band'
    justification: str        # why this tolerance (physics, the reference's scatter)
    measured: float = math.nan
    verdict: str = ""
    open: str = ""            # a known gap that keeps this case failing
    details: dict = field(default_factory=dict)

    def __post_init__(self):
        C.choice("kind", self.kind, KINDS)


def error(case):
    """The deviation that the tolerance bounds: relative |m/r - 1|, absolute |m - r|, or for a
    band the distance outside it (0 inside)."""
    m, r = case.measured, case.reference
    if case.kind == "band":
        lo, hi = r
        return max(0.0, lo - m, m - hi)
    if case.kind == "absolute":
        return abs(m - r)
    return abs(m / r - 1) if r != 0 else math.inf


def grade(case, measured, **details):
    """Set the measured value (and details) and compute the verdict from them."""
    case.measured = float(measured) if measured is not None else math.nan
    case.details.update(details)
    if not math.isfinite(case.measured):
        case.verdict = "NOT MEASURED"
    elif case.kind == "band":
        case.verdict = "PASS" if error(case) == 0.0 else "FAIL"
    else:
        case.verdict = "PASS" if error(case) <= case.tolerance else "FAIL"
    return case


def as_dict(case):
    d = asdict(case)
    d["error"] = error(case) if math.isfinite(case.measured) else None
    if not math.isfinite(case.measured):
        d["measured"] = None
    return d
