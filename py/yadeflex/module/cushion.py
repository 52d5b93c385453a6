"""Empirical formulas for the peak force of a boulder falling on a granular cushion layer (rock
sheds), and the power-law fit that compares a model's peak forces with them.

All three rest on Hertz's elastic impact, peak force ~ (mass x height)^(3/5):

- Labiouse, Descoeudres & Montani (1996), "Experimental study of rock sheds impacted by rock
  blocks", Structural Engineering International 6(3): F = 1.765 M_E^0.4 R^0.2 (W H)^0.6 [kN],
  M_E the cushion's modulus from a plate-load test [kN/m2], R the block's radius [m], W its
  weight [kN], H the drop height [m].
- Japan Road Association (2000), Rockfall countermeasures handbook: F = 2.108 W^(2/3) lambda^0.4
  H^0.6 [kN], lambda the cushion's Lame constant [kN/m2] (1000 kN/m2 for the usual sand cushion).
- ASTRA (2008), Einwirkungen infolge Steinschlags auf Schutzgalerien, guideline 12 006 of the
  Swiss Federal Roads Office: F = 2.8 e^-0.5 R^0.7 M_E^0.4 tan(phi)^0.5 E^0.6 [kN], e the cushion
  thickness [m], phi its friction angle, E = m v^2 / 2 the impact energy [kJ].
"""
import json
import math
import os

from .. import checks as C
from ..constants import G

SOURCES = {"Labiouse 1996": "Labiouse, Descoeudres & Montani (1996), Structural Engineering International 6(3), 171-175",
           "JRA 2000": "Japan Road Association (2000), Rockfall countermeasures handbook",
           "ASTRA 2008": "ASTRA (2008), Einwirkungen infolge Steinschlags auf Schutzgalerien, guideline 12 006, Swiss Federal Roads Office"}
# The cushion's properties the formulas take are the model fill's own, measured in the laboratory
# tests of validation/fill_calibration.py (validation/calibration/summary.json): the plate-load
# modulus M_E from its plate-load test, over the range of plate pressure every run reached; the
# Lame constant from its oedometer, over the range of the pressure under the boulder at the peak
# force; the angle of repose for the friction angle. The contacts are linear (kn = E r), so the
# moduli do not depend on the grains' size: the presets' grains measure them for other sizes too.
CALIBRATION = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))),
                           "validation", "calibration", "summary.json")
PLATE_RANGE = "50-100kPa"
LAME_RANGE = "100-200kPa"



def labiouse_1996(mass, height, radius, M_E):
    """Peak force [N] of a block of mass [kg] and radius [m] dropped from height [m] on a cushion
    of plate-load modulus M_E [Pa]."""
    W = mass * G / 1e3
    return 1e3 * 1.765 * (M_E / 1e3) ** 0.4 * radius ** 0.2 * (W * height) ** 0.6


def jra_2000(mass, height, lame):
    """Peak force [N] of a block of mass [kg] dropped from height [m] on a cushion of Lame
    constant lame [Pa]."""
    W = mass * G / 1e3
    return 1e3 * 2.108 * W ** (2 / 3) * (lame / 1e3) ** 0.4 * height ** 0.6


def astra_2008(mass, height, radius, M_E, thickness, friction_deg):
    """Peak force [N] of a block of mass [kg] and radius [m] dropped from height [m] on a cushion
    of plate-load modulus M_E [Pa], thickness [m] and friction angle [deg]."""
    E = mass * G * height / 1e3
    return 1e3 * 2.8 * thickness ** -0.5 * radius ** 0.7 * (M_E / 1e3) ** 0.4 * math.tan(math.radians(friction_deg)) ** 0.5 * E ** 0.6


def formulas(mass, height, radius, M_E, lame, thickness, friction_deg):
    """The three formulas' peak forces [N], by name."""
    return {"Labiouse 1996": labiouse_1996(mass, height, radius, M_E), "JRA 2000": jra_2000(mass, height, lame),
            "ASTRA 2008": astra_2008(mass, height, radius, M_E, thickness, friction_deg)}


def power_fit(x, y):
    """Least-squares fit of log y = log a + b log x; returns (a, b). Needs two distinct positive x."""
    if len(x) != len(y) or len(x) < 2:
        raise C.BadValue("x, y", (x, y), "two sequences of equal length, at least 2 points")
    if min(x) <= 0 or min(y) <= 0:
        raise C.BadValue("x, y", (x, y), "positive values (a power law is fitted on logarithms)")
    lx, ly = [math.log(v) for v in x], [math.log(v) for v in y]
    mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
    sxx = sum((a - mx) ** 2 for a in lx)
    if sxx == 0:
        raise C.BadValue("x", x, "at least two distinct values")
    b = sum((a - mx) * (c - my) for a, c in zip(lx, ly)) / sxx
    return math.exp(my - b * mx), b


def fill_properties(fill, path=CALIBRATION):
    """dict(M_E, lame [Pa], friction_deg, M_E_std, lame_std, M_E_from) of the preset fill `fill`
    measured by validation/fill_calibration.py (its summary.json at path): M_E from its plate-load
    test, or, for a fill that test was not run on, from its oedometer (M_E = 4E / (pi (1 - nu^2)),
    a rigid plate on an elastic half-space of the oedometer's E and nu); M_E_from says which.
    RuntimeError naming what is missing."""
    try:
        with open(path) as f:
            s = json.load(f)[fill]
        key, src = f"plate_test_{PLATE_RANGE}", f"plate-load test, {PLATE_RANGE}"
        if key not in s:
            key, src = f"plate_load_{PLATE_RANGE}", f"oedometer, {PLATE_RANGE}, as a rigid plate on an elastic half-space (no plate-load test of this fill)"
        out = dict(M_E=float(s[key][0]), lame=float(s[f"lame_{LAME_RANGE}"][0]), friction_deg=float(s["repose_deg"][0]))
        if not all(math.isfinite(v) and v > 0 for v in out.values()):
            raise ValueError(f"not measured: {out}")
        out.update(M_E_std=float(s[key][1]), lame_std=float(s[f"lame_{LAME_RANGE}"][1]), M_E_from=src)
        return out
    except (OSError, KeyError, ValueError, IndexError, TypeError) as e:
        raise RuntimeError(f"the {fill} fill's measured moduli are missing from {path} ({e!r}): run validation/fill_calibration.py "
                           f"with --to validation/calibration") from e


def equivalent_radius(mass, density):
    """The radius of the sphere of the boulder's volume [m] (the formulas' R)."""
    return (3 * mass / density / (4 * math.pi)) ** (1 / 3)


def design_forces(fill, mass, density, height, thickness):
    """The three formulas' peak forces [N] for a boulder of mass [kg] and density [kg/m3] dropped
    from height [m] onto a cushion of the preset fill `fill`, thickness [m]: dict(forces={name:
    N}, inputs: the cushion's properties used, with their source), or dict(forces={}, missing=why)
    when the fill was not measured."""
    try:
        f = fill_properties(fill)
    except RuntimeError as e:
        return dict(forces={}, missing=str(e))
    R = equivalent_radius(mass, density)
    inputs = dict(M_E=f["M_E"], lame=f["lame"], friction_deg=f["friction_deg"], radius=R, thickness=thickness,
                  source=f"the {fill} fill's M_E ({f['M_E_from']}), lambda (oedometer, {LAME_RANGE}), phi (angle of repose), measured "
                         "by validation/fill_calibration.py; R: the sphere of the boulder's volume; e: the module's height")
    return dict(forces=formulas(mass, height, R, f["M_E"], f["lame"], thickness, f["friction_deg"]), inputs=inputs)
