"""The fill's laboratory tests (yadeflex.harness.calibration): the read-outs against exact geometry and
elasticity, and the oedometer against the force balance of a quasi-static compression."""
import math
import random

import numpy as np
import pytest

from yadeflex.harness import calibration as K
from yadeflex.checks import BadValue


@pytest.mark.parametrize("angle", [25.0, 33.0, 41.0])
def test_heap_angle_of_a_cone_of_spheres(angle):
    """Spheres filling a cone of the given flank angle (centres drawn uniformly inside it, one
    radius) give that angle: the profile of the highest tops is the cone raised by the radius."""
    rnd = np.random.default_rng(3)
    R, r, z_floor = 0.5, 0.01, 0.02
    h = R * math.tan(math.radians(angle))
    pts = rnd.uniform((-R, -R, 0.0), (R, R, h), size=(400000, 3))
    inside = pts[:, 2] <= h * (1 - np.hypot(pts[:, 0], pts[:, 1]) / R)
    c = pts[inside] + (0, 0, z_floor)
    got = K.heap_angle(c, np.full(len(c), r), z_floor=z_floor, axis=(0.0, 0.0))
    # the bins' outer edge is where their highest sphere lies: half a bin of play in r, over
    # the flank's 60% of R, a few tenths of a degree
    assert got["angle_deg"] == pytest.approx(angle, abs=0.5)
    assert got["n_fit"] >= 10


def test_heap_angle_refuses_what_it_cannot_measure():
    with pytest.raises(ValueError, match="at least 10 spheres"):
        K.heap_angle([(0, 0, 0)] * 3, [0.01] * 3)
    with pytest.raises(ValueError, match="non-finite"):
        K.heap_angle([(0, 0, float("nan"))] * 12, [0.01] * 12)


def test_solid_fraction_of_a_sphere_in_a_cylinder():
    r, R, z0, z1 = 0.05, 0.1, 0.0, 0.2
    exact = 4 / 3 * math.pi * r ** 3 / (math.pi * R * R * (z1 - z0))
    got = K.solid_fraction([(0.01, -0.02, 0.1)], [r], R, z0, z1, voxel=0.002)
    assert got == pytest.approx(exact, rel=0.01)
    # a sphere half above z1 counts half
    half = K.solid_fraction([(0.0, 0.0, z1)], [r], R, z0, z1, voxel=0.002)
    assert half == pytest.approx(0.5 * exact, rel=0.02)


def test_elastic_moduli_from_an_oedometer_are_exact_for_an_elastic_solid():
    E, nu = 30e6, 0.27
    lame = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    M, K0 = lame + 2 * mu, lame / (lame + 2 * mu)
    got = K.elastic_from_oedometer(M, K0)
    assert got["young"] == pytest.approx(E, rel=1e-12)
    assert got["nu"] == pytest.approx(nu, rel=1e-12)
    assert got["lame"] == pytest.approx(lame, rel=1e-12)
    assert got["shear"] == pytest.approx(mu, rel=1e-12)
    # a rigid circular plate of diameter D on an elastic half-space settles s = pi (1 - nu^2) p D / (4 E)
    assert got["plate_load"] == pytest.approx(4 * E / (math.pi * (1 - nu * nu)), rel=1e-12)


def test_secant_of_a_sampled_straight_line_is_its_slope():
    x = np.linspace(0.0, 0.1, 37)
    y = 5e6 * x - 1e3
    assert K.secant(x, y, 50e3, 300e3) == pytest.approx(5e6, rel=1e-12)
    assert math.isnan(K.secant(x, y, 50e3, 1e9))


def test_bad_calibration_input_is_refused_by_name():
    with pytest.raises(BadValue, match="radius"):
        K.oedometer_test(radius=-1.0)
    with pytest.raises(BadValue, match="fill"):
        K.repose_test(fill="cellular_glass")
    with pytest.raises(BadValue, match="rolling_friction"):
        K.repose_test(rolling_friction=float("nan"))


def test_oedometer_is_quasi_static(scene):
    """With a frictionless cylinder, the floor carries the plate's load plus the sample's weight
    when the compression is quasi-static. The grains' momentum changes in bursts as they
    rearrange, which average out over the loading: averaged over the samples above 10 kPa the
    imbalance is below 1% of the stress (the usual quasi-static criterion of DEM element tests),
    and no single sample is out by more than 5%."""
    r = K.oedometer_test(max_stress=60e3, ranges=((20e3, 60e3),))
    c = r["curve"]
    on = c["sigma_top"] > 10e3
    assert on.sum() > 20
    gap = c["sigma_bottom"][on] - c["sigma_top"][on] - r["weight_stress"]
    rel = np.abs(gap) / c["sigma_v"][on]
    assert rel.mean() < 0.01 and rel.max() < 0.05, (rel.mean(), rel.max())
    row = r["ranges"][0]
    # a frictional packing: stiffer than nothing and the radial stress a fraction of the vertical
    assert row["M"] > 0 and 0 < row["K0"] < 1, row
    assert 0.45 < r["core_solid_fraction"] < 0.70


def test_plate_load_test_is_quasi_static(scene):
    """The container is frictionless, so the floor carries the plate's load plus the sample's
    weight when the plate is pressed in quasi-statically: averaged over the samples above 10 kPa
    the imbalance is below 1% of the plate's load (the oedometer's criterion). The plate seats on
    a few grains first, with bursts of up to about 13% at 10 kPa; 95% of the samples are within 5%."""
    r = K.plate_load_test(plate_diameter=0.26, radius=0.26, height=0.26, max_stress=40e3, ranges=((10e3, 40e3),))
    c = r["curve"]
    assert r["reached"]
    floor_area = math.pi * r["radius"] ** 2
    on = c["p"] > 10e3
    assert on.sum() > 20
    F = c["p"][on] * r["plate_area"]
    gap = c["sigma_bottom"][on] * floor_area - r["weight_stress"] * floor_area - F
    rel = np.abs(gap) / F
    assert rel.mean() < 0.01 and np.percentile(rel, 95) < 0.05, (rel.mean(), np.percentile(rel, 95))
    assert r["imbalance"] == pytest.approx(rel.mean(), rel=1e-9)
    # a 36-sided polygon inscribed in the plate's circle
    assert r["plate_area"] == pytest.approx(18 * 0.13 ** 2 * math.sin(math.pi / 18), rel=1e-12)
    assert 0 < r["ranges"][0]["M_E"] < math.inf


def test_plate_load_test_refuses_a_plate_it_cannot_hold():
    with pytest.raises(BadValue, match="radius"):
        K.plate_load_test(plate_diameter=0.4, radius=0.3)
    with pytest.raises(BadValue, match="plate_diameter"):
        K.plate_load_test(plate_diameter=0.1)
    with pytest.raises(BadValue, match="max_settlement"):
        K.plate_load_test(max_settlement=0.2)
