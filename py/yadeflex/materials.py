"""Material presets for deformable elements (FlexMat). Each value carries its unit and source."""
import math

from yade.wrapper import FlexMat

from . import checks as C

# ranges shared by the material presets: moduli up to 10x steel's (a stiffer contact only
# shortens the time step), densities from an aerogel's up (above 5x steel's, MASS_SCALING: mass
# scaling, with a warning), friction below 90 deg, ks/kn in [0, 1]
MODULUS = C.Range(0.0, 2e12, "Pa", lo_open=True)
MASS_SCALING = 4e4  # [kg/m3] densities above this are taken as mass scaling
DENSITY = C.Range(1.0, 1e9, "kg/m3", note=f"above {MASS_SCALING:g}: mass scaling, with a warning")


def _density(name, v):
    """A density [kg/m3], checked (DENSITY); above MASS_SCALING a UserWarning says it is taken as
    mass scaling: it lengthens the time step as its square root, for quasi-static loading only
    (inertia forces grow with it)."""
    v = C.number(name, v, DENSITY)
    if v > MASS_SCALING:
        import warnings
        warnings.warn(f"{name} {v:g} kg/m3 is {v / 7850:.3g}x steel's: taken as mass scaling (the time step grows as its square root, "
                      "inertia forces with it): for quasi-static loading only", stacklevel=3)
    return v
FRICTION_DEG = C.Range(0.0, 90.0, "deg", hi_open=True)
CONTACT_RATIO = C.Range(0.0, 1.0, lo_open=True, note="ks/kn")


def flex_material(young, density, friction_deg=30.0, beam_poisson=0.3, contact_ratio=0.25,
                  tension_only=False, yield_stress=math.inf, hardening=0.0,
                  tensile_strength=math.inf, rupture_strain=math.inf, bending_factor=1.0, label="", element_young=None):
    """A FlexMat, validated.

    young [Pa]: Young's modulus, FlexMat.young: of the contacts, and of the elements unless
    element_young [Pa] is given (FlexMat.elementYoung; a contact modulus below the elements'
    lengthens the time step of stiff wire contacts); density [kg/m3];
    friction_deg [deg] contact friction angle; beam_poisson [-] for G = E/(2(1+nu));
    contact_ratio [-] ks/kn of contacts (FrictMat.poisson); yield_stress, tensile_strength [Pa];
    hardening [-] post-yield stiffness / EA; rupture_strain [-]; bending_factor [-] scale of EI, GJ.
    """
    young = C.number("young", young, MODULUS)
    density = _density("density", density)
    for name, v, unit in (("yield_stress", yield_stress, "Pa"), ("tensile_strength", tensile_strength, "Pa"), ("rupture_strain", rupture_strain, "")):
        if v != math.inf:
            C.number(name, v, C.Range(0.0, unit=unit, lo_open=True, note="or inf: none"))
    C.number("friction_deg", friction_deg, FRICTION_DEG)
    C.number("beam_poisson", beam_poisson, C.Range(-1.0, 0.5, lo_open=True, hi_open=True))
    C.number("contact_ratio", contact_ratio, CONTACT_RATIO)
    C.number("hardening", hardening, C.Range(0.0))
    C.number("bending_factor", bending_factor, C.Range(0.0))
    tension_only = C.boolean("tension_only", tension_only)
    if not isinstance(label, str):
        raise C.BadValue("label", label, "a string")
    if element_young is not None:
        C.number("element_young", element_young, MODULUS)
    m = FlexMat(young=young, density=density, frictionAngle=math.radians(friction_deg),
                   beamPoisson=beam_poisson, poisson=contact_ratio, tensionOnly=tension_only,
                   yieldStress=yield_stress, hardening=hardening, tensileStrength=tensile_strength,
                   ruptureStrain=rupture_strain, bendingFactor=bending_factor, label=label)
    if element_young is not None:
        m.elementYoung = element_young
    return m


STEEL_YOUNG = 200e9  # [Pa] EN 1993-1-1, 3.2.6


def steel(label="steel", **kw):
    """Structural steel bar: E = STEEL_YOUNG, rho = 7850 kg/m3, nu = 0.3 (EN 1993-1-1, 3.2.6).
    Softer contacts on steel elements: steel(young=E_contact, element_young=STEEL_YOUNG)."""
    args = dict(young=STEEL_YOUNG, density=7850.0, beam_poisson=0.3, label=label)
    args.update(kw)
    return flex_material(**args)


ROPE_6X7_YOUNG = 96e9 * 24.32e-6 / (math.pi * 0.004 ** 2)  # [Pa] E x metallic / nominal area (below)


def rope_6x7_8mm(label="rope6x7", **kw):
    """Wire rope 6x7 FC, d = 8 mm, modelled as a tension-only bar of the nominal diameter.

    Rope data (docs/model.md): E = 96 GPa on the metallic area 24.32 mm2, minimum breaking force
    37.6 kN, 22.1 kg/100 m. The model's cross-section is the nominal circle (d = 8 mm, A =
    50.27 mm2), so E and density are scaled to keep EA, the breaking force and the mass per
    metre of the datasheet; bending stiffness is that of the metallic area spread over the
    strands (bending_factor 0.05, an assumption to revisit with a bending test).
    """
    a_nom = math.pi * 0.004 ** 2
    args = dict(young=ROPE_6X7_YOUNG, density=0.221 / a_nom, tension_only=True,
                tensile_strength=37.6e3 / a_nom, bending_factor=0.05, label=label)
    args.update(kw)
    return flex_material(**args)
