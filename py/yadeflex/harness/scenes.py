"""Scenes defined once, reused by the tests and the benchmarks.

Each builder resets O, builds the scene with typed, unit-annotated parameters and returns a
dict with the ids that matter and the parameters used (saved with results).
"""
import math

from yade import O
from yade.minieigenHP import Vector3, Quaternion
from yade.wrapper import Body, Sphere, FrictMat, FlexCylinder

from .. import builders as B
from .. import checks as C
from ..constants import G
from ..materials import steel, flex_material, MODULUS, DENSITY, FRICTION_DEG, CONTACT_RATIO, _density
from ..scene import DEFAULT_TIMESTEP_SAFETY, engines, engine_args, step_until


def sphere(center, radius, density=2500.0, young=1e8, friction_deg=30.0, contact_ratio=0.25, velocity=(0, 0, 0)):
    """A rigid sphere (FrictMat) at center [m], radius [m]; returns its id."""
    c = B.check_finite("sphere center", center)
    r = B._positive("sphere radius", radius)
    _density("sphere density", density)
    C.number("sphere young", young, MODULUS)
    C.number("friction_deg", friction_deg, FRICTION_DEG)
    C.number("contact_ratio", contact_ratio, CONTACT_RATIO)
    v = B.check_finite("sphere velocity", velocity)
    C.body_budget("sphere", center, 1)
    mat = FrictMat(young=young, poisson=contact_ratio, density=density, frictionAngle=math.radians(friction_deg))
    O.materials.append(mat)
    b = Body()
    b.shape = Sphere(radius=r)
    b.material = mat
    b.state.pos = c
    b.state.vel = v
    m = density * 4.0 / 3.0 * math.pi * r ** 3
    b.state.mass = m
    b.state.inertia = Vector3(1, 1, 1) * (0.4 * m * r * r)
    return O.bodies.append(b)


def _check_chain(segments, length, radius, material=None, names=("segments", "length", "radius")):
    """The arguments of a chain that a scene builds after O.reset, checked before it: a count
    of segments, a length and a radius [m], a FlexMat (None: the scene's default); names: the
    scene's names of the first three."""
    B._segments(names[0], segments)
    B._positive(names[1], length)
    B._positive(names[2], radius)
    if material is not None:
        B._material(material, append=False)


def cantilever(segments=10, length=1.0, radius=0.01, load="tip", force=1.0, gravity=G, damping=0.8, material=None):
    """Horizontal cantilever along +x, clamped at x = 0.

    load: 'tip' (force [N] downwards at the free end), 'axial' (force [N] along +x at the
    free end) or 'self' (own weight, gravity [m/s2] along -z). Returns dict(nodes, cylinders,
    tip, params)."""
    C.choice("load", load, ("tip", "axial", "self"))
    _check_chain(segments, length, radius, material)
    C.number("force", force, C.Range(unit="N"))
    engine_args((0, 0, gravity), damping)
    O.reset()
    mat = material or steel()
    nodes, cyls = B.chain([(0, 0, 0), (length, 0, 0)], radius, mat, segments=segments, fixed=[0])
    g = (0, 0, -gravity) if load == "self" else (0, 0, 0)
    O.engines = engines(gravity=g, damping=damping)
    if load == "tip":
        O.forces.setPermF(nodes[-1], Vector3(0, 0, -force))
    elif load == "axial":
        O.forces.setPermF(nodes[-1], Vector3(force, 0, 0))
    return dict(nodes=nodes, cylinders=cyls, tip=nodes[-1], material=mat,
                params=dict(segments=segments, length=length, radius=radius, load=load, force=force, gravity=gravity))


def advance(n):
    """Advance n steps (yadeflex.step_until: O.run(n, True) waits in steps of 40 ms in YADE
    2023.02a; the engines run identically)."""
    step_until(math.inf, C.integer("n", n, 0))


def settle(ids, rel_tol=1e-9, chunk=2000, max_steps=2_000_000):
    """Run until the positions of `ids` change by less than rel_tol x their displacement
    from the start over one chunk. Returns the number of steps; raises if not converged."""
    ids = B._body_ids("ids", ids)
    C.positive("rel_tol", rel_tol)
    chunk, max_steps = C.integer("chunk", chunk, 1), C.integer("max_steps", max_steps, 1)
    start = [Vector3(O.bodies[i].state.pos) for i in ids]
    prev = None
    steps = 0
    while steps < max_steps:
        advance(chunk)
        steps += chunk
        cur = [O.bodies[i].state.pos - s for i, s in zip(ids, start)]
        if prev is not None:
            scale = max(c.norm() for c in cur)
            change = max((c - p).norm() for c, p in zip(cur, prev))
            if scale > 0 and change <= rel_tol * scale:
                return steps
        prev = cur
    raise RuntimeError(f"not settled after {max_steps} steps")


def rotate_rigidly(ids, axis, angle, center=(0, 0, 0)):
    """Rotate bodies (positions and orientations) rigidly by angle [rad] about axis through center."""
    ids = B._body_ids("ids", ids)
    ax = B.check_finite("axis", axis)
    if ax.norm() == 0:
        raise C.BadValue("axis", axis, "a non-zero vector")
    q = Quaternion(ax.normalized(), C.number("angle", angle, C.Range(unit="rad")))
    c = B.check_finite("center", center)
    for i in ids:
        s = O.bodies[i].state
        s.pos = c + q * (s.pos - c)
        s.ori = q * s.ori


def helix_scene(segments=200, coil_radius=0.05, pitch=0.01, wire_radius=0.002, gravity=G, damping=0.0):
    """Helical spring of `segments` cylinders hanging from its first node under gravity."""
    _check_chain(segments, coil_radius, wire_radius, names=("segments", "coil_radius", "wire_radius"))
    C.number("pitch", pitch, C.Range(unit="m"))
    engine_args((0, 0, gravity), damping)
    O.reset()
    mat = steel()
    nodes, cyls = B.helix(segments, coil_radius, pitch, wire_radius, mat)
    O.engines = engines(gravity=(0, 0, -gravity), damping=damping)
    return dict(nodes=nodes, cylinders=cyls, params=dict(segments=segments, coil_radius=coil_radius, pitch=pitch, wire_radius=wire_radius))


def net_impact(n=20, spacing=0.05, wire_radius=0.002, sphere_radius=0.1, speed=5.0, damping=0.0, gravity=G,
               sphere_young=5e9, sphere_density=2500.0, friction_deg=30.0, gap=1e-4, material=None):
    """Square net of n x n nodes (border clamped) hit at its centre by a sphere moving down
    at speed [m/s], starting gap [m] above the wires; sphere_young [Pa], sphere_density
    [kg/m3], friction_deg [deg] for wires and sphere; material: the wires' FlexMat (default
    steel with friction_deg)."""
    n = C.integer("n", n, 2, C.MAX_BODIES)
    C.body_budget("n", n, 3.0 * n * n)
    _check_chain(1, spacing, wire_radius, material, names=("n", "spacing", "wire_radius"))
    for name, v, rng in (("sphere_radius", sphere_radius, C.Range(0.0, unit="m", lo_open=True)), ("speed", speed, C.Range(unit="m/s")),
                         ("sphere_young", sphere_young, MODULUS), ("sphere_density", sphere_density, DENSITY),
                         ("friction_deg", friction_deg, FRICTION_DEG), ("gap", gap, C.Range(0.0, unit="m"))):
        C.number(name, v, rng)
    engine_args((0, 0, gravity), damping)
    O.reset()
    mat = material if material is not None else steel(friction_deg=friction_deg)
    grid, cyls = B.net(n, spacing, wire_radius, mat)
    c = (n - 1) * spacing / 2.0
    s = sphere((c, c, sphere_radius + wire_radius + gap), sphere_radius, density=sphere_density, young=sphere_young,
               friction_deg=friction_deg, velocity=(0, 0, -speed))
    O.engines = engines(gravity=(0, 0, -gravity), damping=damping)
    return dict(grid=grid, cylinders=cyls, sphere=s, params=dict(n=n, spacing=spacing, wire_radius=wire_radius, sphere_radius=sphere_radius,
                                                                speed=speed, sphere_young=sphere_young, sphere_density=sphere_density,
                                                                friction_deg=friction_deg, gap=gap))


def wire_and_ring(wire_length=2.0, wire_segments=40, wire_radius=0.0015, ring_radius=0.3, ring_bar_radius=0.005,
                  ring_segments=36, ball_radius=0.08, drop_height=0.5, damping=0.0):
    """A wire clamped at both ends sagging under its weight, and a steel ring
    resting on it at mid-span, hit by a falling ball (drop_height [m] above the ring)."""
    _check_chain(wire_segments, wire_length, wire_radius, names=("wire_segments", "wire_length", "wire_radius"))
    _check_chain(C.integer("ring_segments", ring_segments, 3), ring_radius, ring_bar_radius,
                 names=("ring_segments", "ring_radius", "ring_bar_radius"))
    B._positive("ball_radius", ball_radius)
    C.number("drop_height", drop_height, C.Range(0.0, unit="m"))
    engine_args(damping=damping)
    O.reset()
    mat = steel(friction_deg=25.0)
    wn, wc = B.chain([(-wire_length / 2, 0, 0), (wire_length / 2, 0, 0)], wire_radius, mat, segments=wire_segments,
                     fixed=[0, wire_segments])
    # ring standing vertically in the x-z plane, its lowest point just above the wire
    rn, rc = B.ring((0, 0, ring_radius + wire_radius + ring_bar_radius + 1e-3), ring_radius, ring_bar_radius, mat,
                    segments=ring_segments, axis=(0, 1, 0))
    ball = sphere((0, 0, 2 * ring_radius + ring_bar_radius + ball_radius + drop_height), ball_radius, density=7850.0, young=50e9)
    O.engines = engines(damping=damping)
    return dict(wire_nodes=wn, wire_cylinders=wc, ring_nodes=rn, ring_cylinders=rc, ball=ball,
                params=dict(wire_length=wire_length, wire_segments=wire_segments, wire_radius=wire_radius, ring_radius=ring_radius,
                            ring_bar_radius=ring_bar_radius, ring_segments=ring_segments, ball_radius=ball_radius,
                            drop_height=drop_height, damping=damping))


def bouncing_bar(drop=1e-3, length=0.2, segments=1, radius=0.003, element_young=2e8, contact_young=200e9, support_radius=0.01,
                 friction_deg=0.0, timestep_safety=DEFAULT_TIMESTEP_SAFETY, timestep_interval=50):
    """A bar of FlexCylinders (length, radius [m], steel density) falling drop [m] onto two
    fixed steel spheres (support_radius [m]) under its ends, bouncing off them again and again:
    every bounce is a contact that separates and starts anew. element_young [Pa] is the bar's
    modulus, contact_young [Pa] its contacts': a softer element than contact makes the bonds'
    critical step far longer than the contacts'. No damping; friction_deg [deg] for both;
    timestep_safety [-] and timestep_interval [-] of the time stepper."""
    _check_chain(segments, length, radius, names=("segments", "length", "radius"))
    for name, v, rng in (("drop", drop, C.Range(0.0, 1.0, "m")), ("element_young", element_young, MODULUS), ("contact_young", contact_young, MODULUS),
                         ("support_radius", support_radius, C.Range(0.0, 1.0, "m", lo_open=True)), ("friction_deg", friction_deg, FRICTION_DEG)):
        C.number(name, v, rng)
    C.integer("timestep_interval", timestep_interval, 1, 10 ** 9)
    engine_args((0, 0, G), 0.0, timestep_safety)
    O.reset()
    mat = flex_material(young=contact_young, element_young=element_young, density=7850.0, friction_deg=friction_deg)
    half = 0.5 * length
    z = support_radius + radius + drop
    nodes, cyls = B.chain([(-half, 0, z), (half, 0, z)], radius, mat, segments=segments)
    supports = [sphere((x, 0, 0), support_radius, density=7850.0, young=200e9, friction_deg=friction_deg) for x in (-0.8 * half, 0.8 * half)]
    for s in supports:
        O.bodies[s].state.blockedDOFs = "xyzXYZ"
    O.engines = engines(damping=0.0, timestep_safety=timestep_safety, timestep_interval=timestep_interval)
    return dict(nodes=nodes, cylinders=cyls, supports=supports,
                params=dict(drop=drop, length=length, segments=segments, radius=radius, element_young=element_young,
                            contact_young=contact_young, support_radius=support_radius, friction_deg=friction_deg,
                            timestep_safety=timestep_safety, timestep_interval=timestep_interval))


def mesh_punch(size=1.0, boulder_mass=100.0, boulder_radius=0.2, velocity=(0, 0, -4.0), contact_young=1e8, edge="held",
               friction_deg=30.0, gap=0.004, timestep_safety=None, wire=None):
    """A TECCO G65/3 chain-link panel size x size m (yadeflex.tecco_wire, shared-node knots) in
    the plane z = 0, hit at its centre by a rigid sphere of boulder_mass [kg] and boulder_radius
    [m] (contact modulus contact_young [Pa], friction_deg [deg]) moving at velocity [m/s] from
    gap [m] above the wires; no damping, gravity. edge 'held': every edge node clamped; 'rope':
    the edge nodes joined in order by a 6x7 8 mm steel rope (yadeflex.rope_6x7_8mm) held at the
    panel's four corners. timestep_safety: the engines' (None: their default); wire: the mesh's
    wire material (None: tecco_wire())."""
    from ..materials import rope_6x7_8mm
    from ..mesh import chain_link_panel, panel_counts
    from ..wire import tecco_wire
    panel_counts(B._positive("size", size), size)  # (the panel's own checks, before O is reset)
    for name, v, rng in (("boulder_mass", boulder_mass, C.Range(0.0, unit="kg", lo_open=True)),
                         ("boulder_radius", boulder_radius, C.Range(0.0, unit="m", lo_open=True)),
                         ("contact_young", contact_young, MODULUS), ("friction_deg", friction_deg, FRICTION_DEG), ("gap", gap, C.Range(0.0, unit="m"))):
        C.number(name, v, rng)
    C.choice("edge", edge, ("held", "rope"))
    v = B.check_finite("velocity", velocity)
    args = engine_args(damping=0.0) if timestep_safety is None else engine_args(damping=0.0, timestep_safety=timestep_safety)
    O.reset()
    p = chain_link_panel(size, size, tecco_wire() if wire is None else wire)
    W, H = p["params"]["width"], p["params"]["height"]
    e = p["edges"]
    rope = []
    if edge == "held":
        B.fix(sorted({n for side in e.values() for n in side}))
    else:
        ring = list(dict.fromkeys(e["bottom"] + e["right"] + e["top"][::-1] + e["left"][::-1]))  # around, each node once
        mat = rope_6x7_8mm()
        rope = [B.cylinder(a, b, 0.004, mat) for a, b in zip(ring, ring[1:] + ring[:1])]
        B.fix([n for n in ring if O.bodies[n].state.pos[0] in (0.0, W) and O.bodies[n].state.pos[1] in (0.0, H)])
    density = boulder_mass / (4.0 / 3.0 * math.pi * boulder_radius ** 3)
    s = sphere((0.5 * W, 0.5 * H, boulder_radius + p["params"]["wire_radius"] + gap), boulder_radius, density=density, young=contact_young,
               friction_deg=friction_deg, velocity=v)
    O.engines = engines(gravity=args[0], damping=0.0, timestep_safety=args[2])
    return dict(panel=p, rope=rope, boulder=s, params=dict(size=size, boulder_mass=boulder_mass, boulder_radius=boulder_radius,
                                                           velocity=tuple(v), contact_young=contact_young, edge=edge,
                                                           friction_deg=friction_deg, gap=gap))


SURFACES = ("wall", "facets", "box")
STRUCTURES = ("net", "sheet")


def drop_on_surface(structure="net", surface="wall", drop=0.02, size=0.4, cells=4, contact_young=1e8, friction_deg=30.0, damping=0.0,
                    velocity=(0, 0, 0)):
    """A free square structure of size [m] (structure 'net': yadeflex.net of (cells + 1)^2 steel
    nodes, wire radius 3 mm, element modulus 2e11 Pa; 'sheet': yadeflex.sheet of cells x cells
    geotextile, 2 mm thick) held flat drop [m] above a rigid floor z = 0 and released under
    gravity with velocity [m/s]. surface 'wall': a YADE Wall (two-sided); 'facets': a 1 m square
    of two YADE Facets whose shared diagonal runs under the structure; 'box': a fixed YADE Box
    1 x 1 x 0.1 m. The floor's material: FrictMat of contact_young [Pa], friction_deg [deg]; the
    elements' contact modulus is contact_young too. Returns dict(nodes, elements, floor (ids),
    params)."""
    from yade import utils
    C.choice("structure", structure, STRUCTURES)
    C.choice("surface", surface, SURFACES)
    C.number("drop", drop, C.Range(0.0, unit="m"))
    B._positive("size", size)
    cells = C.integer("cells", cells, 1, 100)
    C.number("contact_young", contact_young, MODULUS)
    C.number("friction_deg", friction_deg, FRICTION_DEG)
    v = B.check_finite("velocity", velocity)
    args = engine_args(damping=damping)
    O.reset()
    floor_mat = _rigid_material("floor", contact_young, friction_deg)
    lo = 0.5 - 0.5 * size  # the structure's corner, over the middle of the 1 m floor
    r = 0.003 if structure == "net" else 0.001
    nodes, elements = _free_structure(structure, cells, size / cells, contact_young, friction_deg, (lo, lo, r + drop))
    for n in nodes:
        O.bodies[n].state.vel = v
    if surface == "wall":
        floor = [O.bodies.append(utils.wall(0.0, axis=2, sense=0, material=floor_mat))]
    elif surface == "facets":
        a, b, c, d = (0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)
        floor = [O.bodies.append(utils.facet(t, fixed=True, material=floor_mat)) for t in ((a, b, c), (a, c, d))]
    else:
        floor = [O.bodies.append(utils.box((0.5, 0.5, -0.05), (0.5, 0.5, 0.05), fixed=True, material=floor_mat))]
    O.engines = engines(gravity=args[0], damping=args[1])
    return dict(nodes=nodes, elements=elements, floor=floor,
                params=dict(structure=structure, surface=surface, drop=drop, size=size, cells=cells, contact_young=contact_young,
                            friction_deg=friction_deg, damping=damping, velocity=tuple(v)))


def block_on_net(clump=False, speed=1.0, contact_young=1e8):
    """A rigid block smaller than the cell of the net it falls on: a net of 5 x 5 steel nodes
    0.1 m apart (wire radius 3 mm, element modulus 2e11 Pa, border clamped) in the plane z = 0,
    hit at the centre of a cell by a YADE Box of 0.06 m (clump: a clump of two Boxes of the same
    outline) moving down at speed [m/s] from 7 mm above the wires; no damping. The block meets
    the wires between their nodes, at its edges (Ig2_Box_FlexCylinder_FlexContactGeom). Returns
    dict(nodes, cylinders, block (the clump's id if clump), members, params)."""
    from yade import utils
    clump = C.boolean("clump", clump)
    C.number("speed", speed, C.Range(0.0, unit="m/s"))
    C.number("contact_young", contact_young, MODULUS)
    O.reset()
    mat = steel(young=contact_young, element_young=2e11)
    grid, cyls = B.net(5, 0.1, 0.003, mat, origin=(0.3, 0.3, 0.0), fix_border=True)
    bm = FrictMat(young=contact_young, poisson=0.25, density=2500.0, frictionAngle=math.radians(30.0), label="block")
    O.materials.append(bm)
    if clump:
        block, members = O.bodies.appendClumped([utils.box((0.5, 0.5 + dy, 0.04), (0.03, 0.015, 0.03), material=bm) for dy in (-0.015, 0.015)])
    else:
        block = O.bodies.append(utils.box((0.5, 0.5, 0.04), (0.03, 0.03, 0.03), material=bm))
        members = [block]
    O.bodies[block].state.vel = Vector3(0, 0, -speed)
    O.engines = engines(damping=0.0)
    return dict(nodes=[n for col in grid for n in col], cylinders=cyls, block=block, members=list(members),
                params=dict(clump=clump, speed=speed, contact_young=contact_young))


def _rigid_material(label, young, friction_deg):
    """A FrictMat for the scenes' rigid bodies (density 2500 kg/m3, Poisson 0.25), added to O.materials."""
    mat = FrictMat(young=young, poisson=0.25, density=2500.0, frictionAngle=math.radians(friction_deg), label=label)
    O.materials.append(mat)
    return mat


def _free_structure(structure, cells, spacing, contact_young, friction_deg, origin):
    """A free square structure of cells x cells cells of spacing [m] with its corner node at origin:
    'net' (yadeflex.net, steel nodes, wire radius 3 mm, element modulus 2e11 Pa) or 'sheet'
    (yadeflex.sheet of geotextile, 2 mm thick, crossed diagonals). Returns (nodes, elements)."""
    from .. import membrane as M
    if structure == "net":
        mat = steel(young=contact_young, element_young=2e11, friction_deg=friction_deg)
        grid, elements = B.net(cells + 1, spacing, 0.003, mat, origin=origin, fix_border=False)
        return [n for col in grid for n in col], elements
    mat = M.geotextile(young=contact_young, friction_deg=friction_deg)
    sh = M.sheet(cells, cells, (cells * spacing, cells * spacing), 0.002, mat, origin=origin, fix_border=False)
    return [n for col in sh["grid"] for n in col], sh["facets"]


def net_on_ridge(drop=0.005, slope_deg=30.0, cells=5, contact_young=1e8, friction_deg=30.0, damping=0.0, structure="net"):
    """A free square net (structure 'net': yadeflex.net of (cells + 1)^2 steel nodes 0.1 m apart,
    wire radius 3 mm, element modulus 2e11 Pa; 'sheet': a geotextile sheet of the same outline, 2 mm
    thick) held flat drop [m] above the ridge of a fixed roof of four YADE Facets and released under
    gravity. The ridge runs along y at x = 0.5 m, z = 0, between two columns of nodes (cells odd), so
    that the wires (the sheet's facets) crossing it meet it between their nodes
    (Ig2_Facet_FlexCylinder_FlexContactGeom, Ig2_Facet_FlexFacet_FlexContactGeom); each slope falls
    at slope_deg [deg] to x = 0 and x = 1 m and is a rectangle of two facets, one of them on the
    ridge. Materials as in drop_on_surface. Returns dict(nodes, elements, roof (facet ids),
    ridge_facets, params)."""
    from yade import utils
    C.number("drop", drop, C.Range(0.0, unit="m"))
    C.number("slope_deg", slope_deg, C.Range(0.0, 80.0, lo_open=True, unit="deg"))
    cells = C.integer("cells", cells, 1, 99)
    if cells % 2 == 0:
        raise ValueError(f"cells must be odd (the ridge runs between two columns of nodes), got {cells}")
    C.number("contact_young", contact_young, MODULUS)
    C.number("friction_deg", friction_deg, FRICTION_DEG)
    C.choice("structure", structure, STRUCTURES)
    args = engine_args(damping=damping)
    O.reset()
    roof_mat = _rigid_material("roof", contact_young, friction_deg)
    r, spacing = (0.003 if structure == "net" else 0.001), 0.1
    lo = 0.5 - 0.5 * cells * spacing
    nodes, elements = _free_structure(structure, cells, spacing, contact_young, friction_deg, (lo, lo, r + drop))
    h = 0.5 * math.tan(math.radians(slope_deg))
    r0, r1, a0, a1, b0, b1 = (0.5, 0, 0), (0.5, 1, 0), (0, 0, -h), (0, 1, -h), (1, 0, -h), (1, 1, -h)
    roof = [O.bodies.append(utils.facet(t, fixed=True, material=roof_mat)) for t in ((r0, r1, a1), (r0, a1, a0), (r1, r0, b0), (r1, b0, b1))]
    O.engines = engines(gravity=args[0], damping=args[1])
    return dict(nodes=nodes, elements=elements, roof=roof, ridge_facets=[roof[0], roof[2]],
                params=dict(drop=drop, slope_deg=slope_deg, cells=cells, contact_young=contact_young, friction_deg=friction_deg, damping=damping,
                            structure=structure))


def sheet_on_corner(drop=0.005, cells=5, contact_young=1e8, friction_deg=30.0, damping=0.0, box_half=0.1):
    """A free geotextile sheet (yadeflex.sheet, cells x cells cells 0.12 m wide, 2 mm thick, crossed
    diagonals) held flat drop [m] above a corner of a fixed YADE Box (half-size box_half [m]) that
    points straight up at (0.5, 0.5, 0), under the middle of the sheet's central cell (cells odd: on
    the diagonal two of its facets share), and released under gravity. The sheet meets the corner
    between its nodes (Ig2_Box_FlexFacet_FlexContactGeom). Materials as in drop_on_surface. Returns
    dict(nodes, elements, box, corner, params)."""
    from yade import utils
    C.number("drop", drop, C.Range(0.0, unit="m"))
    cells = C.integer("cells", cells, 1, 99)
    if cells % 2 == 0:
        raise ValueError(f"cells must be odd (the corner lies under the middle of a cell), got {cells}")
    C.number("contact_young", contact_young, MODULUS)
    C.number("friction_deg", friction_deg, FRICTION_DEG)
    a = B._positive("box_half", box_half)
    args = engine_args(damping=damping)
    O.reset()
    box_mat = _rigid_material("box", contact_young, friction_deg)
    spacing = 0.12
    lo = 0.5 - 0.5 * cells * spacing
    nodes, elements = _free_structure("sheet", cells, spacing, contact_young, friction_deg, (lo, lo, 0.001 + drop))
    diag = Vector3(1, 1, 1).normalized()  # the box's corner (a, a, a) turned to point up
    q = Quaternion(diag.cross(Vector3(0, 0, 1)).normalized(), math.acos(1 / math.sqrt(3)))
    box = O.bodies.append(utils.box((0.5, 0.5, -a * math.sqrt(3)), (a, a, a), orientation=q, fixed=True, material=box_mat))
    O.engines = engines(gravity=args[0], damping=args[1])
    return dict(nodes=nodes, elements=elements, box=box, corner=Vector3(0.5, 0.5, 0),
                params=dict(drop=drop, cells=cells, contact_young=contact_young, friction_deg=friction_deg, damping=damping, box_half=a))
