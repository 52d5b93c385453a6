"""Filling the damping module (stages 1-2 of yadeflex.module): the grains settled in a container,
then the mesh, rings and lining built around them and settled with them."""
import math
import random

from yade import O
from yade.minieigenHP import Vector3
from yade.wrapper import FrictMat, Sphere

from .. import builders as B
from .. import membrane as M
from ..mesh import chain_link_cylinder, edge_ring, TECCO_G65_WIRE_RADIUS as TECCO_WIRE_RADIUS
from .ids import ModuleIds, ModuleStructureIds
from ..grains import FILL_TIMESTEP_SAFETY, UNBALANCED_TOL, _grain_material, _sphere_body, fill_preset
from ..mass_scaling import _heavier_nodes, _restore_nodes
from ..scene import grain_engine, step_until
from .params import MAX_NODE_MASS_SCALING, PLACED_HEIGHT, ModuleParams, fill_radii, lining_cells_around


def _placement(r, z0, z1, a):
    """Centres of a hexagonal close-packed lattice of spacing a (layers ABAB) inside the
    vertical cylinder of radius r about the axis, from z0 up to z1."""
    dz, dy = a * math.sqrt(2.0 / 3.0), a * math.sqrt(3.0) / 2
    m = int(r / a) + 2
    out = []
    for k in range(int((z1 - z0) / dz) + 1):
        ox, oy = (0.5 * a, a / (2 * math.sqrt(3.0))) if k % 2 else (0.0, 0.0)
        for j in range(-m, m + 1):
            for i in range(-m, m + 1):
                x, y = i * a + (0.5 * a if j % 2 else 0.0) + ox, j * dy + oy
                if math.hypot(x, y) <= r:
                    out.append((x, y, z0 + k * dz))
    return out


def _container(radius, height, n=48, center=(0.0, 0.0)):
    """Rigid frictionless cylinder of YADE facets (only while the grains settle)."""
    from yade import geom
    mat = FrictMat(young=1e8, poisson=0.3, density=1000, frictionAngle=0.0, label="container")
    O.materials.append(mat)
    fs = geom.facetCylinder((center[0], center[1], height / 2), radius, height, segmentsNumber=n, wallMask=4, material=mat)
    return O.bodies.append(fs)


def _settle(ke_tol, max_steps, chunk=500, progress=None, unbalanced_tol=None):
    """Run until the kinetic energy of the spheres falls below ke_tol [J] and, if unbalanced_tol
    is given, YADE's unbalanced force (mean resultant on the dynamic bodies over the mean contact
    force) below it too: a packing at rest, not one creeping slowly under heavy damping (a loose
    fill met the kinetic-energy test while still compacting at an unbalanced force of 0.19).
    progress(steps, kinetic energy, ke_tol) after every chunk."""
    from yade import utils
    steps = 0
    ubf = float("nan")
    while steps < max_steps:
        step_until(math.inf, chunk)
        steps += chunk
        ke = sum(0.5 * b.state.mass * b.state.vel.squaredNorm() for b in O.bodies if b is not None and isinstance(b.shape, Sphere))
        if progress:
            progress(steps, ke, ke_tol)
        if ke < ke_tol:
            if unbalanced_tol is None:
                return steps
            ubf = utils.unbalancedForce()
            if ubf < unbalanced_tol:
                return steps
    raise RuntimeError(f"the fill did not settle in {max_steps} steps (kinetic energy {ke:.3g} J, limit {ke_tol:.3g} J"
                       + (f"; unbalanced force {ubf:.3g}, limit {unbalanced_tol:.3g})" if unbalanced_tol is not None else ")"))


def _relayout():
    """Save O to memory and load it back: the bodies and interactions, created in the order the
    grains met while they fell, come back side by side in memory, in the order the loops visit
    them (the steps that follow wait less on memory)."""
    O.saveTmp("yadeflex_fill")
    O.loadTmp("yadeflex_fill")


def settle_fill(params, r_in, rnd, progress=None):
    """Stage 1 on an empty O: the module's grains settled in their container of radius r_in
    (settle_grains with the module's preset, height, centres and settle damping), the container
    removed. Returns (wall id, grain ids, the kinetic-energy tolerance used)."""
    wall, grains, ke_tol, _ = settle_grains(params.preset(), params.height, r_in, rnd, centers=params.centers(),
                                            damping=params.settle_damping, progress=progress,
                                            deposition_friction_deg=params.fill_deposition_friction_deg)
    return wall, grains, ke_tol


def _floor_grains(radius, r_floor, mat):
    """A fixed monolayer of spheres of radius r_floor on a square lattice of spacing 2 r_floor,
    touching z = 0, out to `radius` about the axis: a floor as rough as the largest grains."""
    n = int(radius / (2 * r_floor))
    out = []
    for i in range(-n, n + 1):
        for j in range(-n, n + 1):
            x, y = 2 * r_floor * i, 2 * r_floor * j
            if math.hypot(x, y) <= radius:
                bid = _sphere_body(Vector3(x, y, r_floor), r_floor, mat)
                O.bodies[bid].state.blockedDOFs = "xyzXYZ"
                O.bodies[bid].dynamic = False
                out.append(bid)
    return out


def settle_grains(p, H, r_in, rnd, centers=((0.0, 0.0),), damping=ModuleParams.settle_damping, rough_floor=0.0, keep_container=False, progress=None,
                  deposition_friction_deg=0.0):
    """Grains of fill preset p settled as the module's fill is, on an empty O (yadeflex.deposition's
    deposition, a CylinderRegion about each centre): placed on a close-packed lattice up to
    PLACED_HEIGHT x H (solid fraction about 0.33: enough for a dense fill above H) in a rigid
    frictionless container of radius r_in about each centre, on a wall at z = 0, settled without
    rolling resistance and frictionless (or at deposition_friction_deg [deg]: a looser fill),
    then with the fill's friction and rolling resistance (until at rest: kinetic energy and
    unbalanced force, local damping `damping`), and trimmed to the height H.
    rough_floor > 0: a fixed monolayer of the largest grains covers the floor out to that
    radius, and the fill starts on it. keep_container: the container stays (else removed).
    p: a ModuleParams, a preset's name or a preset dict (fill_preset). progress, if given, is
    called as progress(stage, steps, kinetic energy [J], its tolerance [J]) while settling (steps
    0: a stage starts). Returns (wall id, grain ids, the kinetic-energy tolerance used, the
    container's facet ids)."""
    from ..deposition import CylinderRegion, GrainSizes, place_grains, settle_deposit, trim_grains
    p = fill_preset(p)
    gmat = _grain_material(p)
    from yade import utils
    wall = O.bodies.append(utils.wall(0, axis=2, sense=1, material=gmat))
    floor = 0.0
    if rough_floor > 0:
        r_floor = 0.5 * p["grain_max"]
        _floor_grains(rough_floor, r_floor, gmat)
        floor = 2 * r_floor
    sizes = GrainSizes.of(p)
    grains, container = [], []
    for cx, cy in centers:  # each centre's container, then its grains (the bodies' order sets the round-off of the contact sums)
        container += _container(r_in, 3.6 * H, center=(cx, cy))
        grains += place_grains(CylinderRegion((cx, cy), r_in, floor, 3.6 * H), sizes, rnd, gmat, top=PLACED_HEIGHT * H)[0]
    _, ke_tol, _ = settle_deposit(grains, gmat, p, H, damping, deposition_friction_deg, progress)
    grains = trim_grains(grains, H)  # the grains wholly below the height
    if not keep_container:
        for f in container:
            O.bodies.erase(f)
        container = []
    for g in grains:
        O.bodies[g].state.vel = Vector3(0, 0, 0)
        O.bodies[g].state.angVel = Vector3(0, 0, 0)
    return wall, grains, ke_tol, container


def build_filled(params, progress=None):
    """Stages 1-2 on a fresh O. Returns the dict of ids (also stored in O.tags['yadeflex_module'])."""
    params.validate()
    rnd = random.Random(params.seed)
    O.reset()
    H = params.height
    r_lin, r_in = fill_radii(params)
    wall, grains, ke_tol = settle_fill(params, r_in, rnd, progress)
    # --- stage 2: the structure around the fill
    from ..wire import TECCO_WIRE_YOUNG, tecco_wire
    wire = tecco_wire(seed=params.seed, young=params.steel_contact_young, element_young=TECCO_WIRE_YOUNG)
    O.materials.append(wire)
    from ..materials import STEEL_YOUNG, steel
    ring_mat = steel(label="ring_steel", friction_deg=30.0, young=params.steel_contact_young, element_young=STEEL_YOUNG)
    # contact modulus 3e9 Pa: kn = E r = 3e6 N/m for the 1 mm half thickness, so that the
    # lining pressed by grains against the wires and rings stays out of them (at 1e9 three modules
    # closed their energy balance to 35% only; 1e10 costs 2.4x in time step)
    gtx = M.geotextile(friction_deg=30.0, young=3e9) if params.lining else None
    per = []
    for cx, cy in params.centers():
        mesh = chain_link_cylinder(params.diameter, H, wire, center=(cx, cy, 0))
        rings = dict(bottom=edge_ring(mesh["edges"]["bottom"], 0.5 * params.ring_bar_diameter, ring_mat),
                     top=edge_ring(mesh["edges"]["top"], 0.5 * params.ring_bar_diameter, ring_mat))
        lin = None
        if params.lining:
            n_around = lining_cells_around(r_lin)
            n_height = max(2, int(round(H / 0.08)))
            lin = M.lining(r_lin, H, n_around, n_height, params.lining_thickness, gtx, center=(cx, cy, 0.5 * params.lining_thickness),
                           fix_bottom=True)
        B.fix(mesh["edges"]["bottom"], "xyz")
        per.append(dict(center=(cx, cy), mesh_nodes=sorted(mesh["nodes"].values()), mesh_cylinders=mesh["cylinders"],
                        ring_bottom=rings["bottom"], ring_top=rings["top"], lining=(lin["facets"] if lin else []),
                        lining_nodes=(sorted({n for row in lin["rings"] for n in row}) if lin else []),
                        base_nodes=sorted(set(mesh["edges"]["bottom"]) | set(lin["bottom"] if lin else [])), mesh_params=mesh["params"]))
    rope = dict(nodes=[], cylinders=[])
    if params.with_rope():
        from ..materials import ROPE_6X7_YOUNG, rope_6x7_8mm
        from ..rope import rope_around
        rn, rc = rope_around(params.centers(), 0.5 * params.diameter + TECCO_WIRE_RADIUS, 0.5 * H, rope_6x7_8mm(young=params.steel_contact_young, element_young=ROPE_6X7_YOUNG))
        rope = dict(nodes=rn, cylinders=rc)
    O.engines = params.engines(params.settle_damping, FILL_TIMESTEP_SAFETY, crushing=False)
    # the structure settles onto the fill: the mesh takes up its slack, a creep that local
    # damping slows down; 1e-3 of the fill's potential energy scale is "negligible" here. The
    # kinetic energy alone is not enough: the grains released by the container stand just clear
    # of the lining (they settled inside its flat facets) and creep out onto it, slowly, under
    # this damping; stopped on the kinetic energy the cached fill had no grain touching the
    # lining and sank once released without damping (bench/fill_equilibrium.py). The
    # unbalanced force holds it until the fill bears on the lining.
    if progress:
        progress("structure (mesh, rings, lining) on the fill", 0, float("nan"), 10 * ke_tol)
    _relayout()
    # the grains alone ran at dt_fill; the structure's light nodes shorten the step: heavier
    # nodes (their weight kept) settle to the same equilibrium at the grains' step
    dt_fill = O.dt
    # every bound swept by the collider's full distance: at the grains' step, the adaptive sweep
    # of slow bodies (InsertionSortCollider.targetInterv) re-ran the collider on many steps
    next(e for e in O.engines if e.label == "collider").targetInterv = -1
    O.step()
    heavier = _heavier_nodes(min(MAX_NODE_MASS_SCALING, (dt_fill / O.dt) ** 2))
    _settle(10 * ke_tol, 300000, progress=progress and (lambda s, ke, tol: progress("structure", s, ke, tol)), unbalanced_tol=UNBALANCED_TOL)
    _restore_nodes(heavier)
    ids = ModuleIds(wall=wall, grains=list(grains), modules=[ModuleStructureIds.from_dict(m) for m in per], rope=list(rope["cylinders"]),
                    rope_nodes=list(rope["nodes"]), base_nodes=sorted({n for m in per for n in m["base_nodes"]}))
    O.tags["yadeflex_module"] = ids.to_json()
    return ids


def fill_contacts(ids):
    """The filled module's active contacts: dict of grain_grain (count), grain_lining (count) and
    grain_lining_force (their total normal force [N])."""
    gs, lining = set(g for g in ids["grains"] if O.bodies[g] is not None), set(ids["lining"])
    out = dict(grain_grain=0, grain_lining=0, grain_lining_force=0.0)
    for i in O.interactions:
        if not i.isReal or (hasattr(i.geom, "active") and not i.geom.active):
            continue
        if i.id1 in gs and i.id2 in gs:
            out["grain_grain"] += 1
        elif (i.id1 in gs and i.id2 in lining) or (i.id2 in gs and i.id1 in lining):
            out["grain_lining"] += 1
            out["grain_lining_force"] += i.phys.normalForce.norm()
    ge = grain_engine()  # (the grains' contacts it keeps out of O.interactions)
    out["grain_grain"] += sum(1 for a, b, _, _ in (ge.contactList() if ge else ()) if a in gs and b in gs)
    return out


def fill_top(ids):
    """Height of the highest grain surface [m]."""
    return max(O.bodies[g].state.pos[2] + O.bodies[g].shape.radius for g in ids["grains"] if O.bodies[g] is not None)
