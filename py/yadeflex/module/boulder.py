"""The impact's start on a filled module: the lining's mass scaling and the boulder placed above
the fill with the speed of its drop."""
import math

from yade import O
from yade.minieigenHP import Vector3

from ..boulder import boulder_material, make_boulder, touches
from ..constants import G
from ..drop import lower_onto
from ..scene import step_until
from ..scene_impact import Boulder, surface_under
from ..mass_scaling import scale_node_masses
from .fill import fill_top
from .fill_cache import filled_module
from .ids import ModuleIds


def add_boulder(params, ids, gap=0.005):
    """The boulder over the module, placed so that it first touches it (fill, rings, wires or
    lining: yadeflex.drop) after a fall of `gap` [m], moving down with the free-fall speed of
    params less that fall's (it touches at sqrt(2 g h)). Returns its body id."""
    params.validate()
    ids = ModuleIds.of(ids)
    top = max(fill_top(ids), max(O.bodies[n].state.pos[2] for n in ids["mesh_nodes"]) + 0.5 * params.ring_bar_diameter)
    s = params.boulder_size()
    v_top = params.impact_speed()
    v0 = math.sqrt(max(0.0, v_top * v_top - 2 * G * gap))
    mat = boulder_material(params.boulder_density)
    ox, oy = params.impact_offset
    # (placed clear above everything under it first, then lowered onto its first touch)
    clear = max(top, surface_under(ox, oy, Boulder(mass=params.boulder_mass, shape=params.boulder_shape, density=params.boulder_density,
                                                   above=(ox, oy), speed=v_top).half_width()))
    bid = make_boulder(params.boulder_shape, s, params.boulder_mass, mat, ox, oy, clear + gap, Vector3(0, 0, -v0))
    lower_onto(bid, gap)
    return bid


def scale_lining_nodes(ids, m_min):
    """Mass scaling of every module's lining for the impact (yadeflex.mass_scaling): every dynamic
    lining node gets at least the mass m_min [kg]. The geotextile's own nodes weigh about a gram;
    pressed between grains and wires they would set the time step of the whole impact. Returns
    (mass added, the lining's own mass) [kg]; m_min = 0 changes nothing."""
    added = own = 0.0
    for m in ModuleIds.of(ids).modules:
        a, o = scale_node_masses(m.lining_nodes, m_min)
        added, own = added + a, own + o
    return added, own


def impact_start(params, cache_dir=None, max_fall=0.5):
    """The main job's impact up to the boulder's first contact: loads (or fills) the module,
    adds the boulder and the impact engines, and steps until the boulder touches something (for
    benchmarks and diagnostics that look at the impact itself). Returns (ids, boulder id, the
    boulder's member body ids), with the lining's nodes scaled as the main job scales them
    (scale_lining_nodes). Raises RuntimeError if no contact within max_fall [s]."""
    ids, _, _ = filled_module(params, cache_dir=cache_dir)
    scale_lining_nodes(ids, params.lining_node_mass)
    bid = add_boulder(params, ids)
    O.engines = params.engines(params.damping)
    boulder = O.bodies[bid]
    members = set(boulder.shape.members.keys()) if boulder.isClump else {bid}
    t0 = O.time
    while not touches(bid):
        if O.time - t0 > max_fall:
            raise RuntimeError("the boulder never touched the module")
        step_until(math.inf, 50)
    return ids, bid, members
