"""One tolerance helper and the reference values used by the YADE tests, named once."""
import math

G = 9.81  # [m/s2] gravity used in the test scenes
STEEL_E = 200e9  # [Pa]
STEEL_RHO = 7850.0  # [kg/m3]
STEEL_NU = 0.3  # [-]


def rel_err(value, reference):
    return abs(value - reference) / abs(reference)


def assert_rel(value, reference, tol, what=""):
    err = rel_err(value, reference)
    assert err <= tol, f"{what}: {value!r} vs reference {reference!r}: relative error {err:.3e} > {tol:.1e}"
    return err


def circle_I(r):
    """Second moment of area of a solid circle [m4]."""
    return math.pi * r ** 4 / 4
