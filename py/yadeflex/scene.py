"""Engine list, time step, energy and force read-outs for scenes with yade-flex elements."""
import math

from yade import O
from yade.wrapper import (ForceResetter, InsertionSortCollider, FlexInteractionLoop, NewtonIntegrator,
                          Bo1_Sphere_Aabb, Bo1_Facet_Aabb, Bo1_Box_Aabb, Bo1_Wall_Aabb, Bo1_FlexCylinder_Aabb, Bo1_FlexFacet_Aabb,
                          Ig2_Sphere_Sphere_ScGeom, Ig2_Facet_Sphere_ScGeom, Ig2_Box_Sphere_ScGeom, Ig2_Wall_Sphere_ScGeom,
                          Ig2_Sphere_FlexCylinder_FlexContactGeom, Ig2_FlexCylinder_FlexCylinder_FlexContactGeom,
                          Ig2_Sphere_FlexFacet_FlexContactGeom, Ig2_FlexCylinder_FlexFacet_FlexContactGeom,
                          Ig2_FlexFacet_FlexFacet_FlexContactGeom, Ig2_Sphere_Sphere_FlexContactGeom,
                          Ig2_Wall_FlexNode_FlexContactGeom, Ig2_Box_FlexNode_FlexContactGeom, Ig2_Facet_FlexNode_FlexContactGeom,
                          Ig2_Box_FlexCylinder_FlexContactGeom, Ig2_Facet_FlexCylinder_FlexContactGeom,
                          Ig2_Box_FlexFacet_FlexContactGeom, Ig2_Facet_FlexFacet_FlexContactGeom,
                          Ip2_FrictMat_FrictMat_FrictPhys, Law2_ScGeom_FrictPhys_CundallStrack,
                          Law2_FlexContactGeom_FrictPhys_CundallStrack, FlexElementEngine, FlexTimeStepper, FlexNewtonIntegrator, FlexGuard,
                          FlexCylinder, FlexNode, Sphere, FlexRun, FlexGrainEngine, FrictMat)

from . import checks as C
from .constants import G
from .builders import check_finite, lookup_material


def _min_contact_radius():
    r = math.inf
    for b in O.bodies:
        if b is None:
            continue
        if isinstance(b.shape, (FlexCylinder, Sphere)):
            r = min(r, b.shape.radius)
    return r


DAMPING = C.Range(0.0, 1.0, hi_open=True, note="local damping")
TIMESTEP_SAFETY = C.Range(0.0, 1.0, lo_open=True, note="x the critical step")
# the one default of the time-step safety: FlexTimeStepper.safety's (scenes and engines() use it;
# the damping module states its own, ModuleParams.timestep_safety, with its measured margin)
DEFAULT_TIMESTEP_SAFETY = FlexTimeStepper().safety
ROLLING_FRICTION = C.Range(0.0, 1.0, note="rolling moment / (normal force x radius)")
CRUSHING_IS50 = C.Range(1e4, 1e9, "Pa", note="in Pa, not MPa: rock 1.5e6-1e7 Pa (Selby 1993)")


def engine_args(gravity=(0, 0, -G), damping=0.0, timestep_safety=DEFAULT_TIMESTEP_SAFETY):
    """(gravity Vector3, damping, timestep_safety) checked as engines() checks them: scenes
    check them before they build anything."""
    return (check_finite("gravity", gravity), C.number("damping", damping, DAMPING),
            C.number("timestep_safety", timestep_safety, TIMESTEP_SAFETY))


def engines(gravity=(0, 0, -G), damping=0.0, timestep_safety=DEFAULT_TIMESTEP_SAFETY, timestep_interval=50, verlet=None, flex_sphere_contacts=True,
            rolling_stiffness=0.0, rolling_friction=0.0, crushing_is50=0.0, guard=False, grains=None):
    """Standard engine list for scenes with yade-flex cylinders and facets, spheres, YADE facets, boxes, walls.

    damping [-]: NewtonIntegrator's non-viscous (local) damping; 0 by default, so that every
    joule goes to a physical mechanism unless the user asks otherwise (O.energy books it as
    'nonviscDamp'). verlet [m]: collider sweep distance (default: half the smallest
    cylinder or sphere radius in the scene; 0.25 r runs the collider 60% more often on a
    net impact, 1-2 r gains nothing more, measured). The time step is set by FlexTimeStepper
    to timestep_safety x the critical step: stability needs < 1, accuracy of stiff, short
    contacts needs less (the energy residual of scenes.wire_and_ring falls tenfold from 0.8 to
    0.5), hence DEFAULT_TIMESTEP_SAFETY = 0.5, FlexTimeStepper.safety's default. flex_sphere_contacts: sphere-sphere contacts use
    yade-flex's contact geometry and law (friction dissipation consistent with the leap-frog
    integrator, see pkg/kernel/Contact.cpp) instead of YADE's ScGeom + CundallStrack.
    The loop over interactions is FlexInteractionLoop: YADE's InteractionLoop with the same
    functor calls in the same order (same results) that asks for each interaction's data a few
    iterations ahead (pkg/yade/speed/FlexLoop.hpp; .prefetch = False runs InteractionLoop's own loop),
    and leaves out the sphere pairs whose spheres are apart, and the spheres apart from YADE facets
    and walls, from a table of their centres before reading their bodies (.quickReject; same results).
    crushing_is50 [Pa]: the point-load strength index Is(50) of the spheres' rock: the normal force
    of a sphere-sphere contact never passes the point-load failure load of the smaller sphere
    (yadeflex.crushing.failure_load); past it the contact yields, a stand-in for the grains'
    crushing ('flexCrushing' in O.energy; the yielded overlap is the contact's plasticOverlap,
    lost when the spheres part). 0 or None (the default): spheres do not crush.
    guard (opt-in, off by default): True puts a FlexGuard (label 'guard') first, which stops the run with yadeflex.Unstable
    naming the bodies at the first non-finite value, step longer than half a contact radius or
    (with O.trackEnergy) energy created without external work; it costs one pass over the
    bodies per step. Or a FlexGuard to use. Off by default: it still raises false alarms on
    driven scenes (tensile tests booking energy before their first external work).
    grains (opt-in): the grains' material (a FrictMat in O.materials, or its label): contacts
    between standalone spheres of that material then run in a FlexGrainEngine (label
    'grainEngine') on a neighbour list of its own (pairs within r1 + r2 + half the smallest grain's radius), with the same law,
    instead of through O.interactions (their contacts with everything else stay there). Not
    with crushing_is50.
    """
    g, damping, timestep_safety = engine_args(gravity, damping, timestep_safety)
    timestep_interval = C.integer("timestep_interval", timestep_interval, 1)
    if verlet is not None:
        verlet = C.number("verlet", verlet, C.Range(0.0, unit="m"))
    flex_sphere_contacts = C.boolean("flex_sphere_contacts", flex_sphere_contacts)
    rolling_stiffness = C.number("rolling_stiffness", rolling_stiffness, C.Range(0.0))
    rolling_friction = C.number("rolling_friction", rolling_friction, ROLLING_FRICTION)
    if crushing_is50 is None or crushing_is50 == 0:
        crushing_is50 = 0.0
    else:
        crushing_is50 = C.number("crushing_is50", crushing_is50, CRUSHING_IS50)
        if not flex_sphere_contacts:
            raise ValueError("crushing_is50: sphere contacts crush only with yade-flex's sphere-sphere law (flex_sphere_contacts=True)")
    for b in O.bodies:
        if b is not None and isinstance(b.shape, FlexNode) and b.state.mass <= 0 and b.state.blockedDOFs != "xyzXYZ":
            raise ValueError(f"FlexNode #{b.id} has no mass: attach cylinders to it or fix it")
    if verlet is None:
        r = _min_contact_radius()
        verlet = 0.5 * r if math.isfinite(r) else 0.0
    grain_engine = []
    if grains is not None:
        if not flex_sphere_contacts:
            raise ValueError("grains: the grain engine runs yade-flex's sphere-sphere law (flex_sphere_contacts=True)")
        if crushing_is50:
            raise ValueError("grains: the grain engine does not crush grains (crushing_is50 must be 0)")
        m = lookup_material(grains, FrictMat)
        grain_engine = [FlexGrainEngine(material=m.id, label="grainEngine")]
    if guard is True:
        guard = FlexGuard(label="guard")
    elif guard is not False and not isinstance(guard, FlexGuard):
        raise ValueError(f"guard must be True, False or a FlexGuard, got {guard!r}")
    return ([guard] if guard else []) + [
        ForceResetter(),
        InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_FlexCylinder_Aabb(), Bo1_FlexFacet_Aabb(), Bo1_Facet_Aabb(), Bo1_Box_Aabb(), Bo1_Wall_Aabb()],
                              verletDist=verlet, label="collider"),
    ] + grain_engine + [
        FlexInteractionLoop(
            [Ig2_Sphere_Sphere_FlexContactGeom() if flex_sphere_contacts else Ig2_Sphere_Sphere_ScGeom(), Ig2_Sphere_FlexCylinder_FlexContactGeom(), Ig2_FlexCylinder_FlexCylinder_FlexContactGeom(),
             Ig2_Sphere_FlexFacet_FlexContactGeom(), Ig2_FlexCylinder_FlexFacet_FlexContactGeom(), Ig2_FlexFacet_FlexFacet_FlexContactGeom(),
             Ig2_Facet_Sphere_ScGeom(), Ig2_Box_Sphere_ScGeom(), Ig2_Wall_Sphere_ScGeom(),
             Ig2_Wall_FlexNode_FlexContactGeom(), Ig2_Box_FlexNode_FlexContactGeom(), Ig2_Facet_FlexNode_FlexContactGeom(),
             Ig2_Box_FlexCylinder_FlexContactGeom(), Ig2_Facet_FlexCylinder_FlexContactGeom(),
             Ig2_Box_FlexFacet_FlexContactGeom(), Ig2_Facet_FlexFacet_FlexContactGeom()],
            [Ip2_FrictMat_FrictMat_FrictPhys()],
            [Law2_ScGeom_FrictPhys_CundallStrack(), Law2_FlexContactGeom_FrictPhys_CundallStrack(label="flexLaw", rollingStiffness=rolling_stiffness,
                                                                                        rollingFriction=rolling_friction, crushingIs50=crushing_is50)],
            label="interactionLoop"),
        FlexElementEngine(label="flexElements"),
        FlexTimeStepper(safety=timestep_safety, interval=timestep_interval, label="flexDt"),
        FlexNewtonIntegrator(gravity=g, damping=damping, label="newton"),
    ]


def critical_timestep():
    """Critical time step of the current scene [s] from bonds and contacts (no change to O.dt)."""
    return FlexTimeStepper().critical()


def step_until(time, max_steps):
    """Step the scene until O.time >= time [s] (inf: no limit) or max_steps steps were taken, with no Python
    between the steps (as O.run; a PyRunner still runs); returns the number of steps taken. For
    loops that record between steps: O.step() in a loop makes every step check the whole scene
    for what the script may have changed, this checks it once. Raises what O.step() raises."""
    max_steps = C.integer("max_steps", max_steps, 0)
    return FlexRun.until(math.inf if time == math.inf else C.number("time", time), max_steps)


def energy_budget():
    """dict of O.energy terms plus 'total' (requires O.trackEnergy = True)."""
    d = {k: O.energy[k] for k in O.energy.keys()}
    d["total"] = O.energy.total()
    return d


def bond_forces(ids):
    """Axial forces [N] of the given cylinders (None for ruptured/erased ones)."""
    return [O.bodies[i].shape.axialForce if O.bodies[i] is not None else None for i in ids]


def contact_law():
    """The yade-flex contact law of the current engines (Law2_FlexContactGeom_FrictPhys_CundallStrack),
    e.g. to read its hand-over ledger (deepOnsets, deepOnsetEnergy, deepEndings, deepEndingEnergy)."""
    for e in O.engines:
        for f in (e.lawDispatcher.functors if hasattr(e, "lawDispatcher") else ()):
            if type(f).__name__ == "Law2_FlexContactGeom_FrictPhys_CundallStrack":
                return f
    raise ValueError("no Law2_FlexContactGeom_FrictPhys_CundallStrack in O.engines (set them with yadeflex.engines())")


def grain_engine():
    """The scene's FlexGrainEngine (yadeflex.engines(grains=...)), or None."""
    return next((e for e in O.engines if isinstance(e, FlexGrainEngine)), None)


def contacts_on(body_id, active_only=True):
    """Real contacts of a body; FlexContactGeom contacts that are inactive (handed over to
    a neighbour) are skipped unless active_only is False."""
    out = []
    for i in O.interactions.withBody(body_id):
        if not i.isReal:
            continue
        if active_only and hasattr(i.geom, "active") and not i.geom.active:
            continue
        out.append(i)
    return out
