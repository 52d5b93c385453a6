"""CSV files with NAME[UNIT] headers: the energy budget over time (EnergyRecorder) and reading any
such file back (read_csv)."""
import csv
import math
import os
import re

import numpy as np
from yade import O

from .recording import Periodic


class EnergyRecorder(Periodic):
    """Energy budget over time in CSV: columns time[s], iter[-], one column [J] per O.energy term
    (the union of the terms seen so far, in order of appearance, 0 where a term did not exist
    yet) and total[J], their sum. Needs O.trackEnergy = True. Call it like VtkRecorder; the file
    is complete after every call (rewritten when a new term appears, else appended to)."""

    def __init__(self, csv_path, every=1):
        super().__init__(every)
        self.path = csv_path
        self.terms = []
        self.rows = []  # (time, iter, {term: value})
        folder = os.path.dirname(csv_path)
        if folder:
            os.makedirs(folder, exist_ok=True)

    def header(self):
        return ["time[s]", "iter[-]"] + [f"{k}[J]" for k in self.terms] + ["total[J]"]

    def _line(self, row):
        t, it, e = row
        vals = [e.get(k, 0.0) for k in self.terms]
        return [repr(float(t)), str(it)] + [repr(float(v)) for v in vals] + [repr(math.fsum(vals))]

    def __call__(self):
        if not O.trackEnergy:
            raise RuntimeError("EnergyRecorder: O.trackEnergy is False, so O.energy is not tracked; set O.trackEnergy = True "
                               "before the first step")
        if not self._due():
            return None
        e = {k: float(O.energy[k]) for k in O.energy.keys()}
        new = [k for k in e if k not in self.terms]
        self.terms += new
        row = (float(O.time), O.iter, e)
        self.rows.append(row)
        self.last_iter = O.iter
        if new or len(self.rows) == 1:
            with open(self.path, "w", newline="") as fh:
                w = csv.writer(fh)
                w.writerow(self.header())
                w.writerows(self._line(r) for r in self.rows)
        else:
            with open(self.path, "a", newline="") as fh:
                csv.writer(fh).writerow(self._line(row))
        return row


HEADER = re.compile(r"^\s*(.*?)\s*\[([^\]]*)\]\s*$")
_KNOWN_UNITS = {"time": "s", "t": "s", "iter": "-", "iteration": "-", "dt": "s"}


def read_csv(path):
    """(names, units, columns) of a CSV with a header row: names without units, units from
    'NAME[UNIT]' headers ('' if none), columns: dict name -> numpy array (NaN for empty cells)."""
    if not os.path.isfile(path):
        raise ValueError(f"CSV file {path!r} does not exist")
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    if not rows:
        raise ValueError(f"{path}: empty CSV file")
    names, units = [], {}
    for h in rows[0]:
        m = HEADER.match(h)
        name, unit = (m.group(1), m.group(2)) if m else (h.strip(), "")
        names.append(name)
        units[name] = unit or _KNOWN_UNITS.get(name, "")
    try:
        data = np.array([[float(v) if v.strip() else np.nan for v in r] for r in rows[1:] if r], dtype=float)
    except ValueError as err:
        raise ValueError(f"{path}: a value is not a number ({err})") from None
    data = data.reshape(-1, len(names))
    return names, units, {n: data[:, k] for k, n in enumerate(names)}
