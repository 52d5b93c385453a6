"""Mass scaling of light nodes: every dynamic node of a mesh or membrane gets at least a given
mass, its rotational inertia scaled by the same factor.

A geotextile's or a fine mesh's own nodes weigh grams. Pressed between grains and wires they set
the time step of the whole run (FlexTimeStepper's stiffest body), while their inertia is small
beside that of the grains and the boulder that load them. Scaling them up lengthens the step. The
mass added weighs (gravity acts on it) and moves: its kinetic and potential energy are in the
balance as any body's, and how much was added is returned so that a run can state it.

_heavier_nodes and _restore_nodes scale every node for a quasi-static settle only (their weight
held at m g, the same equilibrium at a longer step), and undo it.
"""
from yade import O
from yade.minieigenHP import Vector3
from yade.wrapper import FlexNode, NewtonIntegrator

from . import builders as B
from . import checks as C


def scale_node_masses(node_ids, m_min):
    """Every dynamic node of node_ids (FlexNode bodies) gets at least the mass m_min [kg], its
    rotational inertia scaled by the same factor; nodes fixed in every direction are left as they
    are. Returns (mass added, the nodes' own mass) [kg]; m_min = 0 changes nothing."""
    m_min = C.number("m_min", m_min, C.Range(0.0, unit="kg"))
    from yade.wrapper import FlexNode
    ids = B._body_ids("node_ids", node_ids)
    for n in ids:
        if not isinstance(O.bodies[n].shape, FlexNode):
            raise C.BadValue("node_ids", node_ids, f"ids of FlexNode bodies (body #{n} is a {type(O.bodies[n].shape).__name__})")
    added = own = 0.0
    for n in ids:
        b = O.bodies[n]
        if not b.dynamic:
            continue
        own += b.state.mass
        if b.state.mass < m_min:
            f = m_min / b.state.mass
            added += m_min - b.state.mass
            b.state.mass = m_min
            b.state.inertia = Vector3(b.state.inertia) * f
    return added, own


def _heavier_nodes(factor):
    """Mass scaling for a quasi-static settle: the dynamic FlexNodes' mass and rotational inertia
    x factor (>= 1), their weight held at m g by a permanent force (factor - 1) m g upwards. The
    static equilibrium is the same; FlexTimeStepper's step for the elements grows as
    sqrt(factor). Returns what _restore_nodes needs."""
    if factor <= 1.0:
        return []
    g = next(e for e in O.engines if isinstance(e, NewtonIntegrator)).gravity
    out = []
    for b in O.bodies:
        if b is not None and isinstance(b.shape, FlexNode) and b.dynamic:
            m, inertia = b.state.mass, Vector3(b.state.inertia)
            out.append((b.id, m, inertia))
            b.state.mass = m * factor
            b.state.inertia = inertia * factor
            O.forces.setPermF(b.id, -(factor - 1.0) * m * g)
    return out


def _restore_nodes(heavier):
    """Undo _heavier_nodes: the nodes' own mass and inertia, no permanent force, everything at rest."""
    for bid, m, inertia in heavier:
        b = O.bodies[bid]
        b.state.mass, b.state.inertia = m, inertia
    if heavier:
        O.forces.reset()
    for b in O.bodies:
        if b is not None and b.dynamic:
            b.state.vel = Vector3(0, 0, 0)
            b.state.angVel = Vector3(0, 0, 0)
