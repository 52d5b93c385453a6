"""The impact's start on a filled module: the lining's mass scaling and the boulder placed above
the fill with the speed of its drop."""
import math

from yade import O
from yade.minieigenHP import Vector3
from yade.wrapper import Body, Sphere, FrictMat

from .constants import G
from .scene import step_until
from .fill import fill_top, _sphere_body
from .fill_cache import filled_module
from .module_ids import ModuleIds
from .mass_scaling import scale_node_masses


def add_boulder(params, ids, gap=0.005):
    """The boulder, its lowest point `gap` [m] above the highest point of the module (fill,
    top ring), moving down with the free-fall speed of params (drop height reduced by the
    gap, so that it reaches the fill top at sqrt(2 g h)). Returns its body id."""
    params.validate()
    ids = ModuleIds.of(ids)
    top = max(fill_top(ids), max(O.bodies[n].state.pos[2] for n in ids["mesh_nodes"]) + 0.5 * params.ring_bar_diameter)
    s = params.boulder_size()
    v_top = params.impact_speed()
    v0 = math.sqrt(max(0.0, v_top * v_top - 2 * G * gap))
    mat = boulder_material(params.boulder_density)
    ox, oy = params.impact_offset
    return make_boulder(params.boulder_shape, s, params.boulder_mass, mat, ox, oy, top + gap, Vector3(0, 0, -v0))


def boulder_material(density, label="boulder"):
    """The boulder's material (concrete or rock against steel and grains): contact modulus 3 GPa,
    Poisson 0.2, friction 35 deg, `density` [kg/m3]; appended to O.materials."""
    mat = FrictMat(young=3e9, poisson=0.2, density=density, frictionAngle=math.radians(35), label=label)
    O.materials.append(mat)
    return mat


def make_boulder(shape, size, mass, mat, x, y, bottom, velocity):
    """A boulder of `shape` ('sphere': one sphere of diameter `size` [m], its mass from mat's
    density; 'cube': a clump of 4 x 4 x 4 spheres filling a cube of side `size`, of mass `mass`
    [kg] with a solid cube's inertia; or a list of (x, y, z, r) member spheres [m], relative to
    the boulder's centre, clumped, of mass `mass` with the inertia YADE computes for the
    members, scaled to that mass), centred on (x, y), its lowest point at z = bottom, moving at
    `velocity` [m/s]. Returns its body id (the clump's for a clump)."""
    if shape == "sphere":
        r = 0.5 * size
        bid = _sphere_body(Vector3(x, y, bottom + r), r, mat)
        O.bodies[bid].state.vel = velocity
        return bid
    if shape == "cube":
        n = 4  # member spheres per side: radius s/(2n), centres on a grid inset by that radius
        r = size / (2 * n)
        members = []
        for i in range(n):
            for j in range(n):
                for k in range(n):
                    c = Vector3(x - size / 2 + r + 2 * r * i, y - size / 2 + r + 2 * r * j, bottom + r + 2 * r * k)
                    b = Body()
                    b.shape = Sphere(radius=r * 1.0)
                    b.material = mat
                    b.state.pos = c
                    members.append(b)
        cid = O.bodies.appendClumped(members)[0]
        cl = O.bodies[cid]
        cl.state.mass = mass
        cl.state.inertia = Vector3(1, 1, 1) * mass * size * size / 6
        cl.aspherical = False  # isotropic inertia (a solid cube): the spherical rotation update is exact
        cl.state.vel = velocity
        return cid
    low = min(m[2] - m[3] for m in shape)
    members = []
    for mx, my, mz, mr in shape:
        b = Body()
        b.shape = Sphere(radius=mr)
        b.material = mat
        b.state.pos = Vector3(x + mx, y + my, bottom + (mz - low))
        members.append(b)
    cid = O.bodies.appendClumped(members)[0]
    cl = O.bodies[cid]
    scale = mass / cl.state.mass
    cl.state.mass = mass
    cl.state.inertia = cl.state.inertia * scale
    cl.state.vel = velocity
    return cid


def touches(bid):
    """Whether body bid (a clump: one of its members) has a real interaction."""
    b = O.bodies[bid]
    return any(i.isReal for m in (list(b.shape.members.keys()) if b.isClump else [bid]) for i in O.interactions.withBody(m))


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
