"""Bad input raises an exception that names the problem; nothing half-built stays behind."""
import math

import pytest
from yade import O
from yade.wrapper import Body, FlexCylinder, FrictMat

import yadeflex as yf
from yadeflex.harness.scenes import sphere


@pytest.mark.parametrize("radius", [0, -1e-3, math.nan, math.inf])
def test_bad_radius(scene, radius):
    n0, n1 = yf.node((0, 0, 0), 0.01), yf.node((1, 0, 0), 0.01)
    with pytest.raises(ValueError, match="radius"):
        yf.cylinder(n0, n1, radius, yf.steel())
    with pytest.raises(ValueError, match="radius"):
        yf.node((0, 0, 0), radius)


def test_nan_position(scene):
    with pytest.raises(ValueError, match="finite"):
        yf.node((0, math.nan, 0), 0.01)


def test_coincident_nodes(scene):
    mat = yf.steel()
    n0, n1 = yf.node((0, 0, 0), 0.01), yf.node((0, 0, 0), 0.01)
    nb = len(O.bodies)
    with pytest.raises(ValueError, match="coincide"):
        yf.cylinder(n0, n1, 0.01, mat)
    assert len([b for b in O.bodies if b is not None]) == nb  # nothing left behind
    with pytest.raises(ValueError, match="same node"):
        yf.cylinder(n0, n0, 0.01, mat)
    with pytest.raises(ValueError, match="coincide"):
        yf.chain([(0, 0, 0), (0, 0, 0)], 0.01, mat)


def test_end_not_a_flexnode(scene):
    s = sphere((0, 0, 0), 0.1)
    n = yf.node((1, 0, 0), 0.01)
    with pytest.raises(ValueError, match="not a FlexNode"):
        yf.cylinder(s, n, 0.01, yf.steel())
    # the C++ check, without the Python builder in front
    b = Body()
    b.shape = FlexCylinder(node1=s, node2=n, radius=0.01)
    b.material = yf.steel()
    i = O.bodies.append(b)
    with pytest.raises(ValueError, match="not a FlexNode"):
        b.shape.attach(i)


def test_bad_materials(scene):
    with pytest.raises(ValueError, match="density"):
        yf.steel(density=0)
    with pytest.raises(ValueError, match="young"):
        yf.flex_material(young=-1, density=1000)
    n0, n1 = yf.node((0, 0, 0), 0.01), yf.node((1, 0, 0), 0.01)
    with pytest.raises(ValueError, match="unknown material"):
        yf.cylinder(n0, n1, 0.01, "no-such-material")
    m = FrictMat(density=1000, young=1e9)
    O.materials.append(m)
    m.label = "plain"
    with pytest.raises(ValueError, match="not a FlexMat"):
        yf.cylinder(n0, n1, 0.01, "plain")


def test_a_zero_contact_ratio_is_refused_by_name(scene):
    """ks/kn 0 (FrictMat.poisson) gives two such bodies a shear stiffness of 0 / 0 in YADE's
    Ip2_FrictMat_FrictMat_FrictPhys: NaN forces. The builders refuse it, and so does the first step
    of a scene whose material was set by hand, naming the material and the field, before any NaN."""
    with pytest.raises(ValueError, match="contact_ratio"):
        yf.flex_material(young=1e9, density=1000, contact_ratio=0)
    with pytest.raises(ValueError, match="contact_ratio"):
        yf.membrane_material(250e3, 0.3, contact_ratio=0)
    m = FrictMat(density=2650, young=1e8, poisson=0.0, frictionAngle=0.5, label="slick")
    O.materials.append(m)
    a, b = sphere((0, 0, 0), 0.01), sphere((0.005, 0, 0.019), 0.01)
    for i in (a, b):
        O.bodies[i].material = m
    O.bodies[a].state.blockedDOFs = "xyzXYZ"
    O.bodies[b].state.vel = (0, 0, -0.1)
    for grains in (None, "slick"):
        O.engines = yf.engines(grains=grains)
        with pytest.raises(ValueError, match=r"material 'slick' \(FrictMat\)\.poisson must be finite and positive \(ks/kn of its contacts\), got 0"):
            O.step()
        assert all(math.isfinite(x) for i in (a, b) for x in O.bodies[i].state.vel)


def test_massless_free_node_rejected_before_running(scene):
    yf.node((0, 0, 0), 0.01)
    with pytest.raises(ValueError, match="no mass"):
        yf.engines()


@pytest.mark.parametrize("label, cls, attr, value", [("newton", "FlexNewtonIntegrator", "damping", 1.5),
                                                     ("flexDt", "FlexTimeStepper", "safety", 2.0),
                                                     ("guard", "FlexGuard", "interval", 0),
                                                     ("flexLaw", "Law2_FlexContactGeom_FrictPhys_CundallStrack", "onsetFactor", -1.0)])
def test_an_engine_attribute_out_of_range_is_named_in_one_wording(scene, label, cls, attr, value):
    """Whether refused when set (FlexTimeStepper, FlexGuard) or at the next step (the integrator and
    the contact law, which YADE defines): one wording, naming the class, the attribute, the range,
    the value and the label."""
    from yade.wrapper import FlexGuard
    sphere((0, 0, 0), 0.01)
    O.engines = yf.engines() + [FlexGuard(label="guard")]
    eng = yf.contact_law() if label == "flexLaw" else next(e for e in O.engines if e.label == label)
    want = rf"^{cls}\.{attr} must be .+, got {value:g} \(the one labelled '{label}'\)$"
    with pytest.raises(ValueError, match=want):
        setattr(eng, attr, value)
        O.step()
