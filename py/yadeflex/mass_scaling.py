"""Mass scaling of light nodes: every dynamic node of a mesh or membrane gets at least a given
mass, its rotational inertia scaled by the same factor.

A geotextile's or a fine mesh's own nodes weigh grams. Pressed between grains and wires they set
the time step of the whole run (FlexTimeStepper's stiffest body), while their inertia is small
beside that of the grains and the boulder that load them. Scaling them up lengthens the step. The
mass added weighs (gravity acts on it) and moves: its kinetic and potential energy are in the
balance as any body's, and how much was added is returned so that a run can state it.
"""
from yade import O
from yade.minieigenHP import Vector3

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
