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
import math

from .. import checks as C
from ..constants import G



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
