# The damping module rebuilt from YADE's BUILT-IN classes (GPL-2.0-or-later), from the geometry of a
# filled yade-flex module (the cache file of yadeflex.module.filled_module), for bench_module.py.
#
#     import sys; sys.path.insert(0, 'bench'); import builtin_module as bm
#     geo = bm.extract(cache_file)        # plain Python data (loads the cache on O)
#     info = bm.build(geo)                # fresh O: the same module with built-in classes
#     bm.settle(info); bid = bm.add_boulder(geo, info, params)
#
# What is built (every element of the yade-flex module has a counterpart at the same place):
#   fill     FrictMat spheres at the grains' settled positions, same radii and material (the
#            module's fill preset, read from the cache: E, nu, rho, friction);
#   slab     a Wall at z = 0 (fill material, as ours);
#   mesh     WireMat spheres at the mesh nodes + one WirePM link per wire leg (the same legs), as
#            bench/builtin_wire.py: TECCO wire curve (yadeflex.wire.TECCO_WIRE_*), d = 3 mm, WirePM
#            type 2 with lambda_u = the module's wireSlackScale (0.036) and lambda_F = wireForceRatio
#            (1): the same distortion as ours (not the same draws: WirePM's generator is its own);
#   rings    WirePM links along the ring segments, between the mesh's edge nodes (the rings share
#            their nodes with the mesh, in ours as here). The edge nodes carry a second WireMat
#            (d = 10 mm, linear steel curve, E = 200 GPa, never breaks: ours is elastic and
#            unbreakable too); a link between an edge node and an inner node takes the thinner
#            wire's curve (WirePM's rule), so the legs stay TECCO wire. Why not GridNode/
#            GridConnection + CohFrict: a body has one material, a WirePM link needs WireMat at
#            both ends and a CohFrict bond CohFrictMat at both ends, so a node cannot be both a
#            mesh knot and a ring GridNode. The price: the built-in rings are tension-only bars
#            with no bending (ours: co-rotational beams, EI of the 10 mm bar);
#   lining   PFacets over GridNodes/GridConnections at the lining's nodes and triangles, as
#            bench/builtin_pfacet.py: PFacet radius = ours (half the thickness), the bars' modulus
#            E_c = Et h/(1.261 pi r^2) so that the truss has the geotextile's E t along the mesh
#            lines (Et = the module's FlexMembraneMat.stiffness; see builtin_pfacet's header: a
#            truss, anisotropic, Poisson fixed at 0.26, tension and compression, no rupture),
#            contact modulus = ours;
#   masses   every node gets the mass and inertia of its yade-flex twin (mesh and ring nodes: the
#            lumped wire and ring mass; lining nodes: the lumped fabric mass), so both structures
#            weigh the same; blocked DOFs as ours (base nodes pinned, lining bottom clamped);
#   boulder  as yadeflex.module.add_boulder: a cube is a clump of 4x4x4 spheres with the mass and
#            inertia of the solid cube (or a sphere), lowest point 5 mm above the module's highest
#            point, moving at sqrt(v_top^2 - 2 g gap).
# Masks: grains and boulder collide with grains, the lining surface and the mesh nodes; the
# lining's GridNodes collide with nothing (their bonds are explicit), so a grain at a lining vertex
# gets the PFacet's vertex contact and not a second, sphere-GridNode one.
# Engines: those of YADE's pfacet and WirePM examples together (no time stepper: dt from the
# stiffnesses, stable_dt()). All links are created before the first step (linkThresholdIteration 1).
#
# Energy (O.trackEnergy): the built-in laws book kinetic, gravWork, nonviscDamp (NewtonIntegrator),
# plastDissip and elastPotential (CundallStrack: grain, wall, PFacet contacts), shearDissip
# (CohFrict bonds, only when a bond slides). WirePM books nothing (wire elastic, plastic and rupture
# energy) and CohFrict bonds book no elastic energy, so the built-in balance cannot close.

import json
import math

from yade import O, utils
from yade.minieigenHP import Vector2, Vector3
from yade.wrapper import (Bo1_GridConnection_Aabb, Bo1_PFacet_Aabb, Bo1_Sphere_Aabb, Bo1_Wall_Aabb, CohFrictMat, CohFrictPhys,
                          ForceResetter, FrictMat, FrictPhys, GridConnection, Ig2_GridConnection_GridConnection_GridCoGridCoGeom,
                          Ig2_GridConnection_PFacet_ScGeom, Ig2_GridNode_GridNode_GridNodeGeom6D, Ig2_PFacet_PFacet_ScGeom,
                          Ig2_Sphere_PFacet_ScGridCoGeom, Ig2_Sphere_Sphere_ScGeom, Ig2_Wall_Sphere_ScGeom, InsertionSortCollider,
                          InteractionLoop, Ip2_CohFrictMat_CohFrictMat_CohFrictPhys, Ip2_FrictMat_FrictMat_FrictPhys,
                          Ip2_WireMat_WireMat_WirePhys, Law2_GridCoGridCoGeom_FrictPhys_CundallStrack, Law2_ScGeom6D_CohFrictPhys_CohesionMoment,
                          Law2_ScGeom_FrictPhys_CundallStrack, Law2_ScGeom_WirePhys_WirePM, Law2_ScGridCoGeom_FrictPhys_CundallStrack,
                          NewtonIntegrator, PFacet, WireMat, WirePhys)
from yade.gridpfacet import gridConnection, gridNode, pfacet

import builtin_pfacet as bp  # _edges: the mesh edges of a triangle list
from yadeflex import module as flex_module

G = 9.81
HUGE = 1e30  # [Pa] cohesion of the lining bonds: never break
TRUSS_UNIAXIAL = 1.0 + math.sqrt(2.0) / 4.0 - (math.sqrt(2.0) / 4.0)**2 / (1.0 + math.sqrt(2.0) / 4.0)  # 1.261, builtin_pfacet
RING_CURVE = [(0.01, 2.0e9), (10.0, 2.0e12)]  # linear, E = 200 GPa, unbreakable in practice
MASK_GRAIN, MASK_LINING, MASK_MESH, MASK_LNODE = 1, 2, 4, 8
GRAIN_MASK = MASK_GRAIN | MASK_LINING | MASK_MESH
DT_FACTOR = 0.5  # [-] O.dt = DT_FACTOR x min sqrt(m/K) (stable_dt)


def _v(x):
    return [float(x[0]), float(x[1]), float(x[2])]


def extract(cache_file):
    """Loads a filled yade-flex module (O.load) and returns its geometry and materials as plain
    data: positions [m], radii [m], masses [kg], inertias [kg m2], blocked DOFs, connectivity."""
    O.load(cache_file)
    ids = json.loads(O.tags["yadeflex_module"])
    B = O.bodies

    def node(i):
        s = B[i].state
        return dict(pos=_v(s.pos), mass=s.mass, inertia=_v(s.inertia), blocked=s.blockedDOFs, radius=B[i].shape.radius)

    gm = B[ids["grains"][0]].material
    wire = B[ids["mesh_cylinders"][0]].material
    ring_c = B[ids["ring_top"][0]]
    geo = dict(
        cache_file=cache_file,
        grains=[(_v(B[g].state.pos), B[g].shape.radius) for g in ids["grains"] if B[g] is not None],
        fill=dict(young=gm.young, poisson=gm.poisson, density=gm.density, friction=gm.frictionAngle),
        nodes={i: node(i) for i in ids["mesh_nodes"]},
        legs=[(B[c].shape.node1, B[c].shape.node2) for c in ids["mesh_cylinders"] if B[c] is not None],
        ring=[(B[c].shape.node1, B[c].shape.node2) for c in ids["ring_top"] + ids["ring_bottom"] if B[c] is not None],
        ring_radius=ring_c.shape.radius,
        wire=dict(radius=B[ids["mesh_cylinders"][0]].shape.radius, strain=list(wire.wireStrain), stress=list(wire.wireStress),
                  slack=wire.wireSlackScale, force_ratio=wire.wireForceRatio, seed=wire.wireSeed, contact_young=wire.young,
                  friction=wire.frictionAngle, density=wire.density),
        ring_mat=dict(contact_young=ring_c.material.young, friction=ring_c.material.frictionAngle),
        lining_nodes={i: node(i) for i in ids["lining_nodes"]},
        lining=[(B[f].shape.node1, B[f].shape.node2, B[f].shape.node3) for f in ids["lining"] if B[f] is not None],
        mesh_params=ids["mesh_params"],
    )
    if ids["lining"]:
        f = B[ids["lining"][0]]
        geo["lining_radius"] = f.shape.radius
        geo["lining_mat"] = dict(Et=f.material.stiffness, contact_young=f.material.young, friction=f.material.frictionAngle)
    w = B[ids["wall"]]
    geo["wall_z"] = float(w.state.pos[2])
    return geo


def engines(damping):
    """YADE's pfacet + WirePM + sphere engines (order as in YADE's examples)."""
    return [
        ForceResetter(),
        InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_GridConnection_Aabb(), Bo1_PFacet_Aabb(), Bo1_Wall_Aabb()], label="collider"),
        InteractionLoop(
            [Ig2_Sphere_Sphere_ScGeom(), Ig2_GridNode_GridNode_GridNodeGeom6D(), Ig2_GridConnection_GridConnection_GridCoGridCoGeom(),
             Ig2_Sphere_PFacet_ScGridCoGeom(), Ig2_GridConnection_PFacet_ScGeom(), Ig2_PFacet_PFacet_ScGeom(), Ig2_Wall_Sphere_ScGeom()],
            [Ip2_WireMat_WireMat_WirePhys(linkThresholdIteration=1),
             Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(setCohesionNow=True, setCohesionOnNewContacts=False),
             Ip2_FrictMat_FrictMat_FrictPhys()],
            [Law2_ScGeom_WirePhys_WirePM(linkThresholdIteration=1), Law2_ScGeom6D_CohFrictPhys_CohesionMoment(),
             Law2_ScGeom_FrictPhys_CundallStrack(), Law2_ScGridCoGeom_FrictPhys_CundallStrack(), Law2_GridCoGridCoGeom_FrictPhys_CundallStrack()],
            label="iloop"),
        NewtonIntegrator(gravity=(0, 0, -G), damping=damping, label="newton"),
    ]


def build(geo, damping=0.7):
    """The module of `geo` with built-in classes on a fresh O (links made by one first step).
    Returns a dict of ids and derived parameters."""
    O.reset()
    O.engines = engines(damping)  # before gridConnection(): it runs the InteractionLoop's functors
    f = geo["fill"]
    fill = O.materials.append(FrictMat(young=f["young"], poisson=f["poisson"], density=f["density"], frictionAngle=f["friction"], label="fill"))
    wall = O.bodies.append(utils.wall(geo["wall_z"], axis=2, sense=1, material=fill, mask=MASK_GRAIN | MASK_MESH))
    grains = [O.bodies.append(utils.sphere(Vector3(*p), r, material=fill, mask=GRAIN_MASK)) for p, r in geo["grains"]]
    # mesh and rings: WireMat spheres + WirePM links
    w = geo["wire"]
    curve = list(zip(w["strain"], w["stress"]))
    wmat = WireMat(young=w["contact_young"], poisson=0.3, frictionAngle=w["friction"], density=w["density"], diameter=2 * w["radius"],
                   isDoubleTwist=False, type=2, lambdau=w["slack"], lambdaF=w["force_ratio"], seed=max(1, int(w["seed"])), label="wire")
    wmat.strainStressValues = [Vector2(e, s) for e, s in curve]
    wmat = O.materials.append(wmat)
    rmat = WireMat(young=geo["ring_mat"]["contact_young"], poisson=0.3, frictionAngle=geo["ring_mat"]["friction"], density=w["density"],
                   diameter=2 * geo["ring_radius"], isDoubleTwist=False, type=2, lambdau=0.0, lambdaF=1.0, seed=-1, label="ring")
    # type 2 with lambdau = 0, seed -1: no slack; type 2 so that a mixed ring-wire link takes the wire's
    # distortion whichever material WirePM reads first
    rmat.strainStressValues = [Vector2(e, s) for e, s in RING_CURVE]
    rmat = O.materials.append(rmat)
    ring_nodes = {n for leg in geo["ring"] for n in leg}
    nid = {}
    for i, nd in geo["nodes"].items():
        i = int(i)
        is_ring = i in ring_nodes
        r = max(nd["radius"], geo["ring_radius"]) if is_ring else nd["radius"]
        nid[i] = O.bodies.append(utils.sphere(Vector3(*nd["pos"]), r, material=(rmat if is_ring else wmat), mask=MASK_MESH | MASK_GRAIN))
    legs = [(nid[int(a)], nid[int(b)]) for a, b in geo["legs"]]
    rings = [(nid[int(a)], nid[int(b)]) for a, b in geo["ring"]]
    pairs = {}
    for a, b in legs + rings:
        pairs.setdefault((min(a, b), max(a, b)), 0)
    for a, b in pairs:
        utils.createInteraction(a, b)
    # lining: GridNodes, GridConnections, PFacets
    lin = dict(nodes=[], conns=[], facets=[])
    if geo["lining"]:
        lm = geo["lining_mat"]
        r = geo["lining_radius"]
        lid = {}
        edges = bp._edges(geo["lining"])
        P = {int(i): Vector3(*nd["pos"]) for i, nd in geo["lining_nodes"].items()}
        # h: mean bar length of the two mesh directions (the diagonals are longer by sqrt2)
        lens = sorted((P[int(a)] - P[int(b)]).norm() for a, b in edges)
        h = sum(lens[:2 * len(lens) // 3]) / (2 * len(lens) // 3)
        young_bar = lm["Et"] * h / (TRUSS_UNIAXIAL * math.pi * r * r)
        nmat = O.materials.append(CohFrictMat(young=young_bar, poisson=0.3, density=1000.0, frictionAngle=lm["friction"], isCohesive=True,
                                              momentRotationLaw=True, normalCohesion=HUGE, shearCohesion=HUGE, label="liningNode"))
        emat = O.materials.append(FrictMat(young=lm["contact_young"], poisson=0.3, density=1000.0, frictionAngle=lm["friction"], label="liningSurface"))
        for i, p in P.items():
            gn = gridNode(p, r, material=nmat)
            gn.mask = MASK_LNODE
            lid[i] = O.bodies.append(gn)
        for a, b in edges:
            lin["conns"].append(O.bodies.append(gridConnection(lid[int(a)], lid[int(b)], r, material=emat, mask=MASK_LINING | MASK_MESH)))
        for a, b, c in geo["lining"]:
            lin["facets"].append(O.bodies.append(pfacet(lid[int(a)], lid[int(b)], lid[int(c)], material=emat, mask=MASK_LINING | MASK_MESH)))
        lin["nodes"] = list(lid.values())
        lin.update(young_bar=young_bar, h=h)
    else:
        lid = {}
    # the yade-flex twins' masses, inertias and supports
    for src, m in ((geo["nodes"], nid), (geo["lining_nodes"], lid)):
        for i, nd in src.items():
            st = O.bodies[m[int(i)]].state
            st.mass = nd["mass"]
            j = nd["inertia"]
            if min(j) <= 0:
                rr = O.bodies[m[int(i)]].shape.radius
                j = [0.4 * nd["mass"] * rr * rr] * 3
            st.inertia = Vector3(*j)
            st.blockedDOFs = nd["blocked"]
    O.dt = 1e-9
    O.step()  # Ip2 marks the WirePM links linked during the first step
    nlinked = sum(1 for i in O.interactions if isinstance(i.phys, WirePhys) and i.phys.isLinked)
    info = dict(wall=wall, grains=grains, mesh_nodes=list(nid.values()), links_planned=len(pairs), links=nlinked, ring_links=len(rings),
                lining_nodes=lin["nodes"], lining_conns=lin["conns"], lining_facets=lin["facets"], lining_young_bar=lin.get("young_bar"),
                lining_h=lin.get("h"), node_of=nid)
    if nlinked != len(pairs):
        raise RuntimeError(f"builtin_module: {nlinked} WirePM links made, {len(pairs)} planned")
    set_dt()
    return info


def _body_of(i):
    """Dynamic body that moves for body id i (a clump member's clump), or the nodes of an element."""
    b = O.bodies[i]
    if b is None:
        return []
    if isinstance(b.shape, PFacet):
        return [b.shape.node1.id, b.shape.node2.id, b.shape.node3.id]
    if isinstance(b.shape, GridConnection):
        return [b.shape.node1.id, b.shape.node2.id]
    if b.isClumpMember:
        return [b.clumpId]
    return [i]


def stable_dt(factor=None):
    """factor x min over dynamic bodies of sqrt(m / K), K the sum of the largest stiffness of each of
    its interactions (WirePM: largest slope of the link's curve; CohFrict: max(kn, ks); contacts: kn;
    a PFacet or GridConnection contact counted in full on each of its nodes), and the rotational bound
    of the lining bonds (builtin_grid.stiffness_dt). Gershgorin: omega_max^2 <= 2 max K/m, so the
    critical step 2/omega_max >= sqrt2 min sqrt(m/K)."""
    K, Kr = {}, {}
    for i in O.interactions:
        p = i.phys
        if isinstance(p, WirePhys):
            if not p.isLinked:
                continue
            k = max([p.kn] + [abs(x) for x in p.stiffnessValues])
        elif isinstance(p, CohFrictPhys):
            k = max(p.kn, p.ks)
            half = 0.5 * (O.bodies[i.id2].state.pos - O.bodies[i.id1].state.pos).norm()
            for bid in (i.id1, i.id2):
                Kr[bid] = Kr.get(bid, 0.0) + max(p.kr, p.ktw) + p.ks * half * half
        elif isinstance(p, FrictPhys):
            k = p.kn
        else:
            continue
        for bid in _body_of(i.id1) + _body_of(i.id2):
            K[bid] = K.get(bid, 0.0) + k
    dt = float("inf")
    for bid, k in K.items():
        st = O.bodies[bid].state
        if st.blockedDOFs == "xyzXYZ" or k <= 0 or st.mass <= 0:
            continue
        dt = min(dt, math.sqrt(st.mass / k))
    for bid, k in Kr.items():
        st = O.bodies[bid].state
        j = min(st.inertia)
        if st.blockedDOFs != "xyzXYZ" and j > 0 and k > 0:
            dt = min(dt, math.sqrt(j / k))
    return (DT_FACTOR if factor is None else factor) * dt


def set_dt(factor=None, only_decrease=False):
    dt = stable_dt(factor)
    O.dt = min(O.dt, dt) if only_decrease else dt
    return O.dt


def grain_kinetic(info):
    return sum(0.5 * O.bodies[g].state.mass * O.bodies[g].state.vel.squaredNorm() for g in info["grains"])


def settle(info, damping=0.7, min_time=0.05, max_time=0.3, ke_tol=None, chunk=500, progress=None):
    """Runs the built-in module under gravity with local damping until the grains' kinetic energy is
    below ke_tol [J] (default: 1e-3 M g H, the criterion of ours' structure stage) after min_time [s],
    or max_time [s]; then zero velocities. Returns (simulated time [s], final grain kinetic energy [J])."""
    for e in O.engines:
        if isinstance(e, NewtonIntegrator):
            e.damping = damping
    if ke_tol is None:
        H = max(O.bodies[g].state.pos[2] for g in info["grains"])
        ke_tol = 1e-3 * sum(O.bodies[g].state.mass for g in info["grains"]) * G * H
    t0 = O.time
    ke = float("inf")
    while O.time - t0 < max_time:
        for _ in range(chunk):
            O.step()
        set_dt(only_decrease=True)
        ke = grain_kinetic(info)
        if progress:
            progress(O.time - t0, ke)
        if not math.isfinite(ke):
            raise RuntimeError("builtin_module.settle: non-finite kinetic energy")
        if O.time - t0 >= min_time and ke < ke_tol:
            break
    for b in O.bodies:
        if b is not None:
            b.state.vel = Vector3(0, 0, 0)
            b.state.angVel = Vector3(0, 0, 0)
    return O.time - t0, ke


def fill_top(info):
    return max(O.bodies[g].state.pos[2] + O.bodies[g].shape.radius for g in info["grains"])


def add_boulder(info, params, gap=0.005):
    """The boulder of yadeflex.module.add_boulder (same shape, mass, inertia, material, speed, and the
    same rule: lowest point `gap` [m] above the highest grain or mesh node + half the ring bar),
    with the grains' collision mask. Returns its body id."""
    bid = flex_module.add_boulder(params, dict(grains=info["grains"], modules=[dict(mesh_nodes=info["mesh_nodes"])]), gap=gap)
    b = O.bodies[bid]
    for m in (list(b.shape.members.keys()) if b.isClump else [bid]):
        O.bodies[m].mask = GRAIN_MASK
    return bid
