"""Chain-link wire law materials (FlexMat with a stress-strain curve; see pkg/kernel/WireLaw.hpp).

The wire law is tension-only and piecewise linear through the given stress-strain points
(the origin implied); unloading and reloading follow the first slope stress[0]/strain[0]
with a plastic-elongation memory; a link ruptures past the last point. Each link may carry a
stochastic slack (Thoeni et al. 2013, Computers and Geotechnics 49:158-169): slack strain
slack_scale * xi, xi symmetric triangular on [0, 1], drawn once per link from `seed` and the
link's two node ids (reproducible, independent of thread count and O.reset()), reached
through a soft initial branch ending at force_ratio x the first point's force.
"""
from . import checks as C
from .materials import flex_material

# High-tensile steel wire, tensile strength 1770 N/mm2 (TECCO wire, Geobrugg; docs/model.md).
# E = 200 GPa up to the proportional limit 1400 N/mm2 (0.79 fu), 0.2% proof stress about
# 1600 N/mm2 (0.90 fu), tensile strength 1770 N/mm2 at 5% elongation after fracture: typical of
# cold-drawn, patented wire (EN 10264-2 class; an assumption, not a measured curve of this wire).
TECCO_WIRE_STRAIN = (0.0070, 0.0100, 0.0200, 0.0500)  # [-]
TECCO_WIRE_STRESS = (1.400e9, 1.600e9, 1.720e9, 1.770e9)  # [Pa]
TECCO_WIRE_DIAMETER = 0.003  # [m]


def wire_material(strain, stress, young=None, density=7850.0, slack_scale=0.0, force_ratio=1.0, seed=12345,
                  friction_deg=30.0, contact_ratio=0.25, beam_poisson=0.3, bending_factor=1.0, label="", contact_young=None):
    """FlexMat with the wire law. strain [-], stress [Pa]: the curve's points (origin implied);
    young [Pa]: bending stiffness, and contact stiffness unless contact_young [Pa] is given
    (default: the curve's first slope); density
    [kg/m3]; slack_scale [-], force_ratio [-], seed: distortion (see module doc);
    bending_factor [-]: bending and twist stiffness relative to a solid wire. 1 (default): beam
    links, so a knot transmits moments; 0: bar links, axial only, the knot a hinge (the model
    class of YADE's WirePM, with the cylinder contacts added); a bar link skips the rotations
    and makes the TECCO panel's step about 1.8x cheaper (bench/bench_wire.py).
    Raises ValueError naming the problem for a bad curve or distortion parameters."""
    try:
        e = [float(x) for x in strain]
        s = [float(x) for x in stress]
    except (TypeError, ValueError):
        raise ValueError(f"wire curve: strain and stress must be sequences of numbers, got {strain!r}, {stress!r}") from None
    if young is None:
        young = s[0] / e[0] if e and s and e[0] > 0 and s[0] > 0 else 200e9
    C.integer("seed", seed, -2 ** 31, 2 ** 31 - 1)
    m = flex_material(young=young, density=density, friction_deg=friction_deg, beam_poisson=beam_poisson,
                      contact_ratio=contact_ratio, tension_only=True, bending_factor=bending_factor, label=label,
                      contact_young=contact_young)
    m.wireStrain = e
    m.wireStress = s
    m.wireSlackScale = C.number("slack_scale", slack_scale, C.Range(0.0, 1.0, hi_open=True, note="slack strain of a link"))
    m.wireForceRatio = C.number("force_ratio", force_ratio, C.Range(0.0, 1.0, lo_open=True))
    m.wireSeed = seed
    err = m.wireError()
    if err:
        raise ValueError(err)
    return m


def tecco_wire(label="tecco_wire", slack_scale=None, force_ratio=None, seed=12345, **kw):
    """TECCO G65/3 wire: d = 3 mm high-tensile steel, 1770 N/mm2 (curve TECCO_WIRE_*).

    Distortion defaults (slack_scale, force_ratio) are the mesh calibration of
    TECCO_MESH_CALIBRATION (see yadeflex.mesh); pass 0 and 1 for a straight single wire."""
    from .mesh import TECCO_MESH_CALIBRATION
    cal = TECCO_MESH_CALIBRATION
    return wire_material(TECCO_WIRE_STRAIN, TECCO_WIRE_STRESS, density=7850.0,
                         slack_scale=cal["slack_scale"] if slack_scale is None else slack_scale,
                         force_ratio=cal["force_ratio"] if force_ratio is None else force_ratio,
                         seed=seed, label=label, **kw)

