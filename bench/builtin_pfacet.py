# Reference scenes built from YADE's BUILT-IN PFacet classes (GPL-2.0-or-later).
#
# PFacet = a triangle over three GridNodes whose edges are three GridConnections; the in-plane
# stiffness of a PFacet mesh comes ONLY from the CohFrict bonds between GridNodes (one Euler-Bernoulli
# beam per GridConnection, stiffnesses set by yade.gridpfacet.gridConnection: kn = E pi r^2/L,
# ks = 12 E I/L^3, kr = E I/L, ktw = 2 G I/L, I = pi r^4/4).  The PFacet body itself carries no
# stiffness and no mass; it is only a contact surface.  Contacts with spheres go through
# Ig2_Sphere_PFacet_ScGridCoGeom + Law2_ScGridCoGeom_FrictPhys_CundallStrack, the force being spread
# on the three nodes with barycentric weights (face) or on two nodes linearly (edge).
#
# Use from a yade-double script:
#     import sys; sys.path.insert(0, '/path/to/bench')
#     import builtin_pfacet as bp
#     info = bp.sheet(n=12); print(bp.time_per_step(500, 5))
# or run the demo (prints tables, writes bench/results/builtin_pfacet_*.csv):
#     yade-double -n -j1 -x bench/builtin_pfacet.py
#
# Every builder calls O.reset() and builds on the global O.
#
# Membrane mapping (sheet).  A PFacet mesh cannot represent a membrane law (E t, nu): it is a
# pin-jointed-like truss of bars (plus weak beam shear/bending springs).  For the structured mesh
# used here (squares of side h, each split by ONE diagonal, all bars with the same E and radius r,
# as PFacet requires one radius), the small-strain stiffness tensor of the truss per unit area is
#     C_ijkl = (1/h^2) sum_bars(in one cell) EA L n_i n_j n_k n_l,   EA = E_c pi r^2,
# bars: x (L = h), y (L = h), diagonal (L = h sqrt2, n = (1,1)/sqrt2):
#     C1111 = C2222 = (EA/h)(1 + sqrt2/4) = 1.354 EA/h,   C1122 = C1212 = (sqrt2/4) EA/h = 0.354 EA/h,
#     C1112 = C2212 = 0.354 EA/h (Voigt matrix [[1.354, .354, .354], [.354, 1.354, .354], [.354, .354, .354]] EA/h).
# Uniaxial stiffness along x with free lateral contraction and zero shear strain:
#     (E t)_x = C1111 - C1122^2/C2222 = 1.261 EA/h.
# We choose the connection modulus E_c so that this equals the target membrane stiffness:
#     E_c = Et * h / (1.261 pi r^2),       r = thickness / 2 (the PFacet radius)
# so E_c is NOT a material modulus (for Et = 30 kN/m, h = 1/12 m, r = 2 mm: E_c = 0.16 GPa).
# What the built-in then has (a truss, not a membrane law; it cannot represent (E t, nu)):
#   * Poisson-like ratio C1122/C2222 = 0.26, fixed by the topology, not a parameter;
#   * strongly anisotropic: uniaxial stiffness with ALL other stresses zero (shear free too) is
#     1.00 EA/h along x or y (nu = 0: the cell shears and the diagonal unloads), 0.300 EA/h along the
#     diagonal direction (1,1) and 0.136 EA/h along (1,-1); C_nnnn = 1.914 vs 0.500 EA/h for the two
#     diagonals.  So the "E t" of this sheet is 30 kN/m only along x/y with the shear held, between
#     23.8 and 30 kN/m along x/y, and 3.2-7.1 kN/m along the diagonals;
#   * in-plane shear C1212 = 0.354 EA/h = 0.28 (E t)_x (isotropic with nu = 0.26 would give 0.40 E t).
# Each bar also has bending/shear springs (ks/kn = 3 r^2/L^2 ~ 2e-3 here): a small, mesh-dependent
# out-of-plane stiffness of rods, not of a plate.
#
# Masses.  PFacets get zero mass (yade.gridpfacet.pfacet); each gridConnection adds
# rho_n (L/2) pi r^2 to both of its nodes.  To get an areal mass mu [kg/m2] we set the node material
# density rho_n = mu * S^2 / (pi r^2 * sum of connection lengths), so the summed GridNode mass is
# exactly mu S^2 (border nodes included; clamped nodes' mass is irrelevant).  Nodes get an inertia
# 2/5 m r^2 (sphere of radius r) per connection.
#
# Time step (returned as 'dt', 'dt_pwave', 'dt_stiff', 'dt_contact'):
#   * dt_pwave  : yade.utils.PWaveTimeStep() (GridNodes are Spheres for YADE);
#   * dt_stiff  : builtin_grid.stiffness_dt(): per node sqrt(m / sum max(kn,ks)) and
#                 sqrt(J / sum(max(kr,ktw) + ks (L/2)^2)), Gershgorin bound (carries 1/sqrt2 margin);
#   * dt_contact: sqrt(m / kn_c) for the sphere and for the lightest free node, with
#                 kn_c = 2 E_s R E_p r / (E_s R + E_p r) (Ip2_FrictMat_FrictMat_FrictPhys with the
#                 radii of ScGridCoGeom: sphere radius R, PFacet radius r);
#   dt = dt_factor * min(dt_stiff, dt_contact), dt_factor = 0.5.  dt_pwave is reported only: for these
#   light nodes (a few grams, r = 2 mm) it is 5x below the stiffness bound (it sees each GridNode as a
#   sphere of radius r with an 'equivalent density' m/(4/3 pi r^3)) and would only make the runs longer;
#   checked for the sheet: sphere and centre-node heights at dt and dt/2 agree within 0.03 mm over the
#   first 0.3 s (impact and rebound).  (The bumpy scene's energy gain is not a time-step effect: see
#   BUILTIN_NOTES.md, it is the same at dt/5.)
#
# Interactions in a PFacet scene (measured by census()):
#   * real: node-node CohFrict bonds (one per GridConnection), sphere-PFacet contacts;
#   * virtual (never real): the collider pairs every PFacet with every PFacet whose Aabb overlaps
#     (all neighbours); Ig2_PFacet_PFacet_ScGeom returns False for facets sharing a node and, for the
#     others, INSERTS more potential interactions (node-PFacet, GridConnection-GridConnection) that
#     Ig2 functors then evaluate every step.  neighbour_pairs=False masks PFacet-PFacet pairs out at the
#     collider (collider.avoidSelfInteractionMask), which is what an implementation that knows the
#     mesh topology would do; the difference in time per step is the cost of the virtual pairs.

import csv
import math
import os
import statistics
import sys
import time

import yade
from yade import O, utils
from yade.wrapper import (Bo1_GridConnection_Aabb, Bo1_PFacet_Aabb, Bo1_Sphere_Aabb, CohFrictMat, ForceResetter, FrictMat,
                          GridConnection, GridNode, Ig2_GridConnection_GridConnection_GridCoGridCoGeom,
                          Ig2_GridConnection_PFacet_ScGeom, Ig2_GridNode_GridNode_GridNodeGeom6D, Ig2_PFacet_PFacet_ScGeom,
                          Ig2_Sphere_PFacet_ScGridCoGeom, InsertionSortCollider, InteractionLoop,
                          Ip2_CohFrictMat_CohFrictMat_CohFrictPhys, Ip2_FrictMat_FrictMat_FrictPhys,
                          Law2_GridCoGridCoGeom_FrictPhys_CundallStrack, Law2_ScGeom6D_CohFrictPhys_CohesionMoment,
                          Law2_ScGridCoGeom_FrictPhys_CundallStrack, NewtonIntegrator, PFacet, Sphere)
from yade.gridpfacet import gridConnection, gridNode, pfacet
from yade.minieigenHP import Vector3


def _here():
	"""Directory of this file (when run by yade -x, __file__ is yade's own script)."""
	f = globals().get('__file__', '')
	if f.endswith('builtin_pfacet.py'):
		return os.path.dirname(os.path.abspath(f))
	for a in sys.argv:
		if a.endswith('builtin_pfacet.py'):
			return os.path.dirname(os.path.abspath(a))
	return os.path.join(os.getcwd(), 'bench')


BENCH_DIR = _here()
if BENCH_DIR not in sys.path:
	sys.path.insert(0, BENCH_DIR)
import builtin_grid as bg  # noqa: E402  (stiffness_dt, run_steps)

G_ACC = 9.81
HUGE_COHESION = 1e30  # Pa; bonds never break
MESH_MASK = 2  # PFacets and GridConnections of a mesh
SPHERE_MASK = 3  # external spheres (share bit 2 with the mesh: they collide with it)
TRUSS_UNIAXIAL = 1.0 + math.sqrt(2.0) / 4.0 - (math.sqrt(2.0) / 4.0)**2 / (1.0 + math.sqrt(2.0) / 4.0)  # 1.261 (see header)


# ----------------------------------------------------------------------------------------------
# common helpers
# ----------------------------------------------------------------------------------------------
def _engines(gravity=(0, 0, -G_ACC), damping=0.0, neighbour_pairs=True):
	"""Engines as in YADE's examples/pfacet scripts.  Installed before the mesh is built:
	gridConnection() calls createInteraction, which needs the InteractionLoop functors."""
	collider = InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_GridConnection_Aabb(), Bo1_PFacet_Aabb()], label='collider')
	if not neighbour_pairs:
		collider.avoidSelfInteractionMask = MESH_MASK
	O.engines = [
	        ForceResetter(),
	        collider,
	        InteractionLoop(
	                [
	                        Ig2_GridNode_GridNode_GridNodeGeom6D(),
	                        Ig2_GridConnection_GridConnection_GridCoGridCoGeom(),
	                        Ig2_Sphere_PFacet_ScGridCoGeom(),
	                        Ig2_GridConnection_PFacet_ScGeom(),
	                        Ig2_PFacet_PFacet_ScGeom(),
	                ],
	                [Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(setCohesionNow=True, setCohesionOnNewContacts=False),
	                 Ip2_FrictMat_FrictMat_FrictPhys()],
	                [
	                        Law2_ScGeom6D_CohFrictPhys_CohesionMoment(),
	                        Law2_ScGridCoGeom_FrictPhys_CundallStrack(),
	                        Law2_GridCoGridCoGeom_FrictPhys_CundallStrack(),
	                ],
	                label='iloop'
	        ),
	        NewtonIntegrator(gravity=gravity, damping=damping, label='newton'),
	]


def _mesh_materials(young_bond, poisson, density_node, young_contact, friction_deg):
	"""(node material: CohFrictMat for the bonds, PFacet/GridConnection material: FrictMat for contacts)."""
	node_mat = O.materials.append(
	        CohFrictMat(
	                young=young_bond,
	                poisson=poisson,
	                density=density_node,
	                frictionAngle=math.radians(friction_deg),
	                isCohesive=True,
	                momentRotationLaw=True,
	                normalCohesion=HUGE_COHESION,
	                shearCohesion=HUGE_COHESION,
	                label='pfNodeMat'
	        )
	)
	ext_mat = O.materials.append(
	        FrictMat(young=young_contact, poisson=poisson, density=density_node, frictionAngle=math.radians(friction_deg), label='pfExtMat')
	)
	return node_mat, ext_mat


def _sphere_material(young, poisson, density, friction_deg):
	return O.materials.append(FrictMat(young=young, poisson=poisson, density=density, frictionAngle=math.radians(friction_deg), label='sphereMat'))


def _edges(triangles):
	seen = []
	s = set()
	for t in triangles:
		for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
			k = (min(a, b), max(a, b))
			if k not in s:
				s.add(k)
				seen.append(k)
	return seen


def build_mesh(points, triangles, radius, node_mat, ext_mat, fixed=()):
	"""GridNodes at points, one GridConnection per mesh edge, one PFacet per triangle (indices into
	points).  Nodes listed in `fixed` (indices) get blockedDOFs='xyzXYZ'.  Returns
	{'nodes': [ids], 'conns': [ids], 'facets': [ids]}."""
	nodes = [O.bodies.append(gridNode(Vector3(*p), radius, material=node_mat)) for p in points]
	conns = [O.bodies.append(gridConnection(nodes[a], nodes[b], radius, material=ext_mat, mask=MESH_MASK)) for a, b in _edges(triangles)]
	facets = [O.bodies.append(pfacet(nodes[a], nodes[b], nodes[c], material=ext_mat, mask=MESH_MASK)) for a, b, c in triangles]
	for k in fixed:
		O.bodies[nodes[k]].state.blockedDOFs = 'xyzXYZ'
	return {'nodes': nodes, 'conns': conns, 'facets': facets}


def grid_mesh(n, size, height=None):
	"""Square [0,size]^2 of n x n cells, each split along the diagonal (i,j)-(i+1,j+1); z = height(x, y)
	(0 if None).  Returns (points, triangles, border point indices)."""
	h = size / n
	pts, border = [], []
	for j in range(n + 1):
		for i in range(n + 1):
			x, y = i * h, j * h
			pts.append((x, y, 0.0 if height is None else height(x, y)))
			if i in (0, n) or j in (0, n):
				border.append(j * (n + 1) + i)
	tris = []
	for j in range(n):
		for i in range(n):
			a = j * (n + 1) + i
			b, c, d = a + 1, a + n + 2, a + n + 1
			tris.append((a, b, c))
			tris.append((a, c, d))
	return pts, tris, border


def contact_kn(young_sphere, sphere_radius, young_facet, facet_radius):
	"""Normal stiffness [N/m] Ip2_FrictMat_FrictMat_FrictPhys gives a sphere-PFacet (or sphere-edge) contact:
	harmonic mean 2 k1 k2/(k1+k2) of k1 = E_s R, k2 = E_p r."""
	k1, k2 = young_sphere * sphere_radius, young_facet * facet_radius
	return 2.0 * k1 * k2 / (k1 + k2)


def _set_dt(dt_factor, kn_c, sphere_id=None):
	dtp = utils.PWaveTimeStep()
	free = any(isinstance(b.shape, GridNode) and b.state.blockedDOFs != 'xyzXYZ' for b in O.bodies)
	dts = bg.stiffness_dt() if free else float('inf')  # a fully blocked mesh has no bond time step
	masses = [b.state.mass for b in O.bodies if isinstance(b.shape, GridNode) and b.state.blockedDOFs != 'xyzXYZ' and b.state.mass > 0]
	if sphere_id is not None:
		masses.append(O.bodies[sphere_id].state.mass)
	dtc = math.sqrt(min(masses) / kn_c) if masses else float('inf')
	O.dt = dt_factor * min(dts, dtc)
	return {'dt': O.dt, 'dt_pwave': dtp, 'dt_stiff': dts, 'dt_contact': dtc}


def _kind(b):
	if b is None:
		return 'none'
	s = b.shape
	if isinstance(s, GridNode):
		return 'GridNode'
	if isinstance(s, GridConnection):
		return 'GridConnection'
	if isinstance(s, PFacet):
		return 'PFacet'
	if isinstance(s, Sphere):
		return 'Sphere'
	return s.__class__.__name__


def census():
	"""Interactions of the current scene by (shape pair, real/virtual): {'GridNode-GridNode real': n, ...},
	plus totals 'total', 'real', 'virtual', 'virtual_mesh' (virtual pairs with no external sphere)."""
	c = {}
	tot = real = vm = 0
	for i in O.interactions.all(False):  # iterating O.interactions yields real ones only
		k1, k2 = sorted((_kind(O.bodies[i.id1]), _kind(O.bodies[i.id2])))
		key = '%s-%s %s' % (k1, k2, 'real' if i.isReal else 'virtual')
		c[key] = c.get(key, 0) + 1
		tot += 1
		if i.isReal:
			real += 1
		elif k1 != 'Sphere' and k2 != 'Sphere':
			vm += 1
	c.update({'total': tot, 'real': real, 'virtual': tot - real, 'virtual_mesh': vm})
	return c


def counts():
	kinds = {}
	for b in O.bodies:
		k = _kind(b)
		kinds[k] = kinds.get(k, 0) + 1
	return {
	        'bodies': len(O.bodies),
	        'nodes': kinds.get('GridNode', 0),
	        'connections': kinds.get('GridConnection', 0),
	        'facets': kinds.get('PFacet', 0),
	        'spheres': kinds.get('Sphere', 0),
	        'interactions': len(O.interactions),
	        'interactions_real': O.interactions.countReal(),
	}


def sphere_contacts(sid):
	"""Real interactions of body sid."""
	return sum(1 for i in O.interactions.withBody(sid) if i.isReal)


def _is_active(i, sid):
	"""Whether Law2_ScGridCoGeom_FrictPhys_CundallStrack applies a force for this real interaction: it skips
	a ScGridCoGeom flagged isDuplicate unless the other body is its trueInt."""
	g = i.geom
	other = i.id2 if i.id1 == sid else i.id1
	dup = getattr(g, 'isDuplicate', 0)
	return dup == 0 or other == getattr(g, 'trueInt', -1)


def active_contacts(sid):
	"""Real interactions of body sid that the law does not skip as duplicates (see _is_active)."""
	return sum(1 for i in O.interactions.withBody(sid) if i.isReal and _is_active(i, sid))


# ----------------------------------------------------------------------------------------------
# a. sheet: clamped geotextile-like membrane + sphere
# ----------------------------------------------------------------------------------------------
def sheet(
        n=12,
        size=1.0,
        thickness=0.004,
        membrane_Et=30e3,
        areal_mass=0.4,
        poisson=0.3,
        young=None,
        density=None,
        young_contact=None,
        sphere_radius=0.1,
        sphere_mass=5.0,
        sphere_young=1e9,
        drop_height=0.005,
        friction_deg=30.0,
        fix_border=True,
        damping=0.0,
        dt_factor=0.5,
        neighbour_pairs=True
):
	"""Square membrane [0,size]^2 (z = 0) of n x n cells split into 2 n^2 PFacets, border nodes clamped
	(fix_border), gravity -z, a FrictMat sphere whose surface starts drop_height above the membrane
	top surface (z = thickness/2) over the centre, at rest.

	size [m], thickness [m] (PFacet radius r = thickness/2), membrane_Et [N/m] target uniaxial
	membrane stiffness, areal_mass [kg/m2], poisson [-] (of the bonds' CohFrictMat: only sets the twist
	spring and the contact ks/kn ratio), young [Pa] bond modulus E_c (None: from membrane_Et by the
	truss mapping in the file header), density [kg/m3] node-material density (None: from areal_mass, see
	the header; if given, areal_mass is ignored), young_contact [Pa] modulus of the PFacets' FrictMat for contacts
	(None: = E_c), sphere_radius [m], sphere_mass [kg], sphere_young [Pa], drop_height [m], friction_deg [deg],
	damping [-] Newton local damping, dt_factor [-], neighbour_pairs: keep YADE's default collider
	behaviour (True) or mask PFacet-PFacet pairs out (False).

	Returns a dict: scene, n, facets/nodes/connections/bodies counts, sphere_id, centre_node,
	young_bond, young_contact, kn_contact [N/m], membrane_Et_model [N/m], mass_membrane [kg],
	density_node [kg/m3], dt, dt_pwave, dt_stiff, dt_contact [s]."""
	O.reset()
	h = size / n
	r = 0.5 * thickness
	if young is None:
		young = membrane_Et * h / (TRUSS_UNIAXIAL * math.pi * r * r)
	if young_contact is None:
		young_contact = young
	pts, tris, border = grid_mesh(n, size)
	total_len = sum(math.dist(pts[a], pts[b]) for a, b in _edges(tris))
	rho_node = areal_mass * size * size / (math.pi * r * r * total_len) if density is None else density
	_engines(gravity=(0, 0, -G_ACC), damping=damping, neighbour_pairs=neighbour_pairs)
	node_mat, ext_mat = _mesh_materials(young, poisson, rho_node, young_contact, friction_deg)
	sph_mat = _sphere_material(sphere_young, poisson, sphere_mass / (4.0 / 3.0 * math.pi * sphere_radius**3), friction_deg)
	m = build_mesh(pts, tris, r, node_mat, ext_mat, fixed=border if fix_border else ())
	c = 0.5 * size
	sid = O.bodies.append(utils.sphere(Vector3(c, c, r + sphere_radius + drop_height), sphere_radius, material=sph_mat, mask=SPHERE_MASK))
	kn_c = contact_kn(sphere_young, sphere_radius, young_contact, r)
	res = {
	        'scene': 'sheet',
	        'n': n,
	        'sphere_id': sid,
	        'centre_node': m['nodes'][(n // 2) * (n + 1) + n // 2],
	        'young_bond': young,
	        'young_contact': young_contact,
	        'kn_contact': kn_c,
	        'membrane_Et_model': TRUSS_UNIAXIAL * young * math.pi * r * r / h,
	        'mass_membrane': sum(O.bodies[i].state.mass for i in m['nodes']),
	        'density_node': rho_node,
	}
	res.update(_set_dt(dt_factor, kn_c, sid))
	res.update(counts())
	return res


# ----------------------------------------------------------------------------------------------
# b. bumpy: sphere rolling/sliding over a fixed PFacet heightfield
# ----------------------------------------------------------------------------------------------
def bumpy(
        n=16,
        size=1.0,
        amplitude=0.005,
        wavelength=0.5,
        thickness=0.004,
        young=1e9,
        poisson=0.3,
        sphere_radius=0.05,
        sphere_mass=1.0,
        sphere_young=1e9,
        speed=0.5,
        friction_deg=30.0,
        y0=None,
        dt_factor=0.5,
        neighbour_pairs=True
):
	"""Fixed heightfield z = amplitude sin(k x) sin(k y), k = 2 pi / wavelength, on [0,size]^2 with
	n x n cells (2 n^2 PFacets, every node blocked), gravity -z.  A FrictMat sphere touches the surface
	(zero overlap at its start point x = 2 sphere_radius, y = y0 (None: size/2 + wavelength/8)) and is given
	the horizontal velocity (speed, 0, 0).

	size, amplitude, wavelength, thickness (= 2 PFacet radius), sphere_radius [m]; young [Pa] bond and
	contact modulus of the surface; sphere_young [Pa]; sphere_mass [kg]; speed [m/s]; friction_deg [deg].

	Returns a dict like sheet() (scene='bumpy', sphere_id, kn_contact, dt...)."""
	O.reset()
	r = 0.5 * thickness
	k = 2.0 * math.pi / wavelength

	def height(x, y):
		return amplitude * math.sin(k * x) * math.sin(k * y)

	pts, tris, _ = grid_mesh(n, size, height)
	_MESH.clear()
	_MESH.update({'points': pts, 'triangles': tris, 'radius': r})
	_engines(gravity=(0, 0, -G_ACC), damping=0.0, neighbour_pairs=neighbour_pairs)
	node_mat, ext_mat = _mesh_materials(young, poisson, 1000.0, young, friction_deg)
	sph_mat = _sphere_material(sphere_young, poisson, sphere_mass / (4.0 / 3.0 * math.pi * sphere_radius**3), friction_deg)
	m = build_mesh(pts, tris, r, node_mat, ext_mat, fixed=range(len(pts)))
	x0 = 2.0 * sphere_radius
	if y0 is None:
		y0 = 0.5 * size + wavelength / 8.0
	# start with the sphere touching the (piecewise linear) surface: lift above the highest mesh point
	# under its footprint so that there is no initial overlap
	ztop = max(p[2] for p in pts if (p[0] - x0)**2 + (p[1] - y0)**2 <= (sphere_radius + size / n)**2)
	sid = O.bodies.append(utils.sphere(Vector3(x0, y0, ztop + r + sphere_radius), sphere_radius, material=sph_mat, mask=SPHERE_MASK))
	O.bodies[sid].state.vel = Vector3(speed, 0, 0)
	kn_c = contact_kn(sphere_young, sphere_radius, young, r)
	res = {'scene': 'bumpy', 'n': n, 'sphere_id': sid, 'kn_contact': kn_c, 'young': young}
	res.update(_set_dt(dt_factor, kn_c, sid))
	res.update(counts())
	return res


_MESH = {}  # the fixed mesh of the last bumpy() (points, triangles, radius) for mesh_gap()


def _closest_on_triangle(p, a, b, c):
	"""Closest point to p on the triangle abc (3-tuples) and its region ('vertex', 'edge' or 'face'):
	walk of the Voronoi regions of the vertices, edges and face (Ericson, Real-Time Collision Detection 5.1.5)."""
	def sub(u, v):
		return (u[0] - v[0], u[1] - v[1], u[2] - v[2])

	def dot(u, v):
		return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]

	def add(u, v, t):
		return (u[0] + t * v[0], u[1] + t * v[1], u[2] + t * v[2])

	ab, ac, ap = sub(b, a), sub(c, a), sub(p, a)
	d1, d2 = dot(ab, ap), dot(ac, ap)
	if d1 <= 0 and d2 <= 0:
		return a, 'vertex'
	bp = sub(p, b)
	d3, d4 = dot(ab, bp), dot(ac, bp)
	if d3 >= 0 and d4 <= d3:
		return b, 'vertex'
	vc = d1 * d4 - d3 * d2
	if vc <= 0 and d1 >= 0 and d3 <= 0:
		return add(a, ab, d1 / (d1 - d3)), 'edge'
	cp = sub(p, c)
	d5, d6 = dot(ab, cp), dot(ac, cp)
	if d6 >= 0 and d5 <= d6:
		return c, 'vertex'
	vb = d5 * d2 - d1 * d6
	if vb <= 0 and d2 >= 0 and d6 <= 0:
		return add(a, ac, d2 / (d2 - d6)), 'edge'
	va = d3 * d6 - d5 * d4
	if va <= 0 and (d4 - d3) >= 0 and (d5 - d6) >= 0:
		return add(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6))), 'edge'
	den = 1.0 / (va + vb + vc)
	v, w = vb * den, vc * den
	return add(add(a, ab, v), ac, w), 'face'


def mesh_gap(sid, with_region=False):
	"""Exact gap [m] between sphere sid and the fixed mesh of the last bumpy() (PFacet = triangle
	swept by a sphere of radius r): min over triangles of |centre - closest point| - R - r.
	Negative = geometric overlap, i.e. the sphere should feel a force.  with_region: returns
	(gap, region of the closest point: 'face', 'edge' or 'vertex')."""
	c = tuple(O.bodies[sid].state.pos)
	R = O.bodies[sid].shape.radius
	pts = _MESH['points']
	best, reg = float('inf'), '-'
	for t in _MESH['triangles']:
		a, b, d = pts[t[0]], pts[t[1]], pts[t[2]]
		if min(a[0], b[0], d[0]) > c[0] + R + 0.1 or max(a[0], b[0], d[0]) < c[0] - R - 0.1:
			continue
		if min(a[1], b[1], d[1]) > c[1] + R + 0.1 or max(a[1], b[1], d[1]) < c[1] - R - 0.1:
			continue
		q, rg = _closest_on_triangle(c, a, b, d)
		dist = math.dist(c, q)
		if dist < best - 1e-12:
			best, reg = dist, rg
	g = best - R - _MESH['radius']
	return (g, reg) if with_region else g


def contact_history(sid, n_steps, every=10, gap=False):
	"""Runs n_steps (O.step loop) and records every `every` steps: a list of dicts
	{'iter', 't' [s], 'x', 'z' [m], 'vx' [m/s], 'contacts' (real interactions of sid), 'active' (those the
	law does not skip as duplicates), 'fz' [N] (force on sid), and with gap=True 'gap' [m] (mesh_gap, the
	exact geometric gap to the mesh of the last bumpy(), negative = overlap), 'region' (closest feature:
	face/edge/vertex) and 'energy' [J] (kinetic + rotational + gravitational energy of the sphere).  The gap refers to
	the position at which the step computed its forces."""
	out = []
	for k in range(n_steps):
		g, reg = mesh_gap(sid, True) if gap and k % every == 0 else (None, None)
		O.step()
		if k % every == 0:
			st = O.bodies[sid].state
			rec = {}
			if gap:
				w = st.angVel
				erot = 0.5 * (st.inertia[0] * w[0]**2 + st.inertia[1] * w[1]**2 + st.inertia[2] * w[2]**2)
				rec = {'gap': g, 'region': reg, 'energy': 0.5 * st.mass * st.vel.squaredNorm() + erot + st.mass * G_ACC * st.pos[2]}
			out.append(dict(rec, **{
			        'iter': O.iter,
			        't': O.time,
			        'x': st.pos[0],
			        'z': st.pos[2],
			        'vx': st.vel[0],
			        'contacts': sphere_contacts(sid),
			        'active': active_contacts(sid),
			        'fz': O.forces.f(sid)[2],
			}))
	return out


# ----------------------------------------------------------------------------------------------
# c. timing
# ----------------------------------------------------------------------------------------------
def time_per_step(n_steps=500, reps=5, warmup=50, mode='step'):
	"""Median wall time per step [us] of the current scene over `reps` runs of n_steps (after `warmup`
	steps), O.timingEnabled off.  mode='step': a Python loop of O.step() (about 1-2 us of Python per
	call, negligible here); mode='poll': builtin_grid.run_steps (O.run + 0.2 ms poll).
	Returns {'us_per_step': median, 'us_per_step_all': [...], 'cpu_us_per_step': median of process CPU}."""
	O.timingEnabled = False

	def go(n):
		if mode == 'poll':
			bg.run_steps(n)
		else:
			for _ in range(n):
				O.step()

	go(warmup)
	wall, cpu = [], []
	for _ in range(reps):
		c0 = time.process_time()
		t0 = time.perf_counter()
		go(n_steps)
		wall.append((time.perf_counter() - t0) / n_steps * 1e6)
		cpu.append((time.process_time() - c0) / n_steps * 1e6)
	return {'us_per_step': statistics.median(wall), 'us_per_step_all': wall, 'cpu_us_per_step': statistics.median(cpu)}


def breakdown(n_steps=300):
	"""One run of n_steps with O.timingEnabled: per-engine time [us/step] and share [-] of the step, the
	timingDeltas of the InteractionLoop functors that have them, and census() at the end.
	Returns {'engines': {name: us_per_step}, 'share': {name: fraction}, 'functors': {...}, 'census': {...}}."""
	for e in O.engines:
		e.execTime = 0
		e.execCount = 0
	il = [e for e in O.engines if isinstance(e, InteractionLoop)][0]
	functors = list(il.geomDispatcher.functors) + list(il.physDispatcher.functors) + list(il.lawDispatcher.functors)
	for f in functors:
		if f.timingDeltas is not None:
			f.timingDeltas.reset()
	O.timingEnabled = True
	for _ in range(n_steps):
		O.step()
	O.timingEnabled = False
	eng = {(e.label or e.__class__.__name__): e.execTime * 1e-3 / n_steps for e in O.engines}
	tot = sum(eng.values())
	fun = {}
	for f in functors:
		td = f.timingDeltas
		if td is not None and td.data:
			fun[f.__class__.__name__] = {lab: (t * 1e-3 / n_steps, cnt) for lab, t, cnt in td.data}
	return {'engines': eng, 'share': {k: v / tot for k, v in eng.items()}, 'functors': fun, 'census': census()}


# ----------------------------------------------------------------------------------------------
# d. contact-correctness probes
# ----------------------------------------------------------------------------------------------
PROBE_R = 0.05  # sphere radius [m]
PROBE_r = 0.005  # PFacet radius [m]
PROBE_E = 1e8  # Pa, sphere and PFacet contact modulus
PROBE_OVERLAP = 1e-4  # m


def _probe_scene(points, triangles, friction_deg=0.0):
	"""Fixed PFacet mesh (every node blocked), no gravity."""
	O.reset()
	_engines(gravity=(0, 0, 0))
	node_mat, ext_mat = _mesh_materials(PROBE_E, 0.3, 1000.0, PROBE_E, friction_deg)
	sph_mat = _sphere_material(PROBE_E, 0.3, 1000.0, friction_deg)
	m = build_mesh(points, triangles, PROBE_r, node_mat, ext_mat, fixed=range(len(points)))
	return m, sph_mat


def _place_sphere(sph_mat, feature_point, direction, overlap):
	"""Sphere whose centre is at feature_point + (R + r - overlap) * unit(direction), all DOFs blocked."""
	d = Vector3(*direction)
	d.normalize()
	c = Vector3(*feature_point) + (PROBE_R + PROBE_r - overlap) * d
	sid = O.bodies.append(utils.sphere(c, PROBE_R, material=sph_mat, mask=SPHERE_MASK))
	O.bodies[sid].state.blockedDOFs = 'xyzXYZ'
	return sid, d


def _contact_kinds(sid):
	return '+'.join(sorted(_kind(O.bodies[i.id2 if i.id1 == sid else i.id1]) for i in O.interactions.withBody(sid) if i.isReal)) or '-'


def _rot_x(p, ang):
	c, s = math.cos(ang), math.sin(ang)
	return (p[0], c * p[1] - s * p[2], s * p[1] + c * p[2])


def probe_cases():
	"""The probe geometries: list of (name, description, points, triangles, feature point, outward direction
	[, extra]); extra: {'centre_dist': f(R, r, overlap) -> centre distance from the feature point,
	'factor': expected force / (kn overlap), 'overlap': overlap [m] instead of PROBE_OVERLAP}."""
	s3 = math.sqrt(3.0)
	tri = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.5, 0.5 * s3, 0.0)]
	cen = (0.5, 0.5 * s3 / 3.0, 0.0)
	cases = [('face', 'single facet, centroid, normal direction', tri, [(0, 1, 2)], cen, (0, 0, 1))]
	# (ii) free edges and (iii) free vertices of a single facet, each of the three (the built-in picks the
	# GridConnection from the barycentric region, so the result differs from edge to edge)
	for a, b in ((0, 1), (1, 2), (2, 0)):
		mid = tuple(0.5 * (tri[a][k] + tri[b][k]) for k in range(3))
		out = tuple(mid[k] - cen[k] for k in range(3))
		no = math.sqrt(out[0]**2 + out[1]**2)
		out = (out[0] / no, out[1] / no, 0.0)
		cases.append(('free_edge%d%d_45' % (a, b), 'single facet, midpoint of edge %d-%d, outward in-plane + up at 45 deg' % (a, b), tri,
		              [(0, 1, 2)], mid, (out[0], out[1], 1.0)))
		cases.append(('free_edge%d%d_inplane' % (a, b), 'single facet, midpoint of edge %d-%d, outward in the facet plane' % (a, b), tri,
		              [(0, 1, 2)], mid, out))
	# the miss does not depend on the overlap or on the position along the edge
	cases.append(('free_edge01_45_deep10mm', 'as free_edge01_45 with 10 mm overlap', tri, [(0, 1, 2)], (0.5, 0.0, 0.0), (0.0, -1.0, 1.0),
	              {'overlap': 0.01}))
	cases.append(('free_edge01_45_nearvertex', 'as free_edge01_45 at 0.1 % of the edge from vertex 1', tri, [(0, 1, 2)], (0.999, 0.0, 0.0),
	              (0.0, -1.0, 1.0)))
	for a in range(3):
		out = tuple(tri[a][k] - cen[k] for k in range(3))
		no = math.sqrt(out[0]**2 + out[1]**2)
		cases.append(('free_vertex%d_45' % a, 'single facet, vertex %d, outward along the bisector + up at 45 deg' % a, tri, [(0, 1, 2)], tri[a],
		              (out[0] / no, out[1] / no, 1.0)))
	# (iv) convex ridge: two facets sharing the edge along x, each tilted 15 deg down (fold of 30 deg)
	ang = math.radians(15.0)
	pr = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), _rot_x((0.5, 0.8, 0.0), -ang), _rot_x((0.5, -0.8, 0.0), ang)]
	cases.append(('ridge_30', 'two facets folded 30 deg (convex), ridge midpoint, along the bisector', pr, [(0, 1, 2), (1, 0, 3)], (0.5, 0.0, 0.0),
	              (0, 0, 1)))
	# concave fold (valley) of 30 deg: the sphere on the bisector touches both facets with `overlap` each;
	# expected total force along the bisector 2 kn overlap cos(15 deg)
	pv = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), _rot_x((0.5, 0.8, 0.0), ang), _rot_x((0.5, -0.8, 0.0), -ang)]
	cases.append(('valley_30', 'two facets folded 30 deg (concave), sphere on the bisector touching both', pv, [(0, 1, 2), (1, 0, 3)],
	              (0.5, 0.0, 0.0), (0, 0, 1), {'centre_dist': lambda R, r, d: (R + r - d) / math.cos(ang), 'factor': 2.0 * math.cos(ang)}))
	# (v) shared edge of two coplanar facets
	pc = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.5, 0.8, 0.0), (0.5, -0.8, 0.0)]
	cases.append(('shared_edge_flat', 'two coplanar facets, shared-edge midpoint, normal direction', pc, [(0, 1, 2), (1, 0, 3)], (0.5, 0.0, 0.0),
	              (0, 0, 1)))
	cases.append(('shared_edge_flat_eps', 'as shared_edge_flat, sphere 1e-6 m inside one facet', pc, [(0, 1, 2), (1, 0, 3)], (0.5, 1e-6, 0.0),
	              (0, 0, 1)))
	# (vi) shared vertex of 6 equilateral facets
	ph = [(0.0, 0.0, 0.0)] + [(math.cos(k * math.pi / 3), math.sin(k * math.pi / 3), 0.0) for k in range(6)]
	th = [(0, 1 + k, 1 + (k + 1) % 6) for k in range(6)]
	cases.append(('shared_vertex_6', 'six coplanar facets, common vertex, normal direction', ph, th, (0.0, 0.0, 0.0), (0, 0, 1)))
	cases.append(('shared_vertex_6_eps', 'as shared_vertex_6, sphere 1e-6 m inside one facet', ph, th, (0.3e-5, 1e-6, 0.0), (0, 0, 1)))
	return cases


def probe(name, points, triangles, feature, direction, overlap=PROBE_OVERLAP, steps=(1, 5), extra=None):
	"""Sphere (radius PROBE_R, blocked) placed with `overlap` [m] against `feature` of a fixed mesh; after
	each count of steps in `steps`, records contacts, contact kinds, normal force F.n [N] (n = unit
	direction) and |F| [N].  Analytic: kn_c * overlap with kn_c = contact_kn(E, R, E, r)."""
	m, sph_mat = _probe_scene(points, triangles)
	extra = extra or {}
	overlap = extra.get('overlap', overlap)
	place = overlap
	if 'centre_dist' in extra:  # centre distance from the feature given (e.g. valley: overlap with each facet)
		place = PROBE_R + PROBE_r - extra['centre_dist'](PROBE_R, PROBE_r, overlap)
	sid, n = _place_sphere(sph_mat, feature, direction, place)
	O.dt = 1e-5
	kn = contact_kn(PROBE_E, PROBE_R, PROBE_E, PROBE_r)
	fa = extra.get('factor', 1.0) * kn * overlap
	row = {'probe': name, 'overlap_m': overlap, 'kn_analytic_N_per_m': kn, 'F_analytic_N': fa}
	done = 0
	for s in steps:
		while done < s:
			O.step()
			done += 1
		f = O.forces.f(sid)
		row['contacts_step%d' % s] = sphere_contacts(sid)
		row['active_step%d' % s] = active_contacts(sid)
		row['kinds_step%d' % s] = _contact_kinds(sid)
		row['Fn_step%d_N' % s] = f.dot(n)
		row['Fabs_step%d_N' % s] = f.norm()
		row['ratio_step%d' % s] = f.dot(n) / fa
	return row


def slide_probe(y=0.0, x_from=0.35, x_to=0.65, n_samples=300, overlap=PROBE_OVERLAP, friction_deg=0.0):
	"""Sphere moved at imposed velocity along x with constant overlap over the two coplanar facets of
	'shared_edge_flat' rotated so that the shared edge is the line x = 0.5 (path crosses it at y).
	Returns a list of dicts {'x', 'contacts', 'kinds', 'fz' [N], 'fx' [N]} (one per step) and the
	summary {'F_analytic', 'fz_min', 'fz_max', 'max_jump' (largest |fz(k+1)-fz(k)|), 'x_jump' (x after that
	jump), 'min_contacts', 'max_contacts', 'x_lost' (x of the samples with no active contact)}."""
	pts = [(0.5, -1.0, 0.0), (0.5, 1.0, 0.0), (1.5, 0.0, 0.0), (-0.5, 0.0, 0.0)]
	m, sph_mat = _probe_scene(pts, [(0, 1, 2), (1, 0, 3)], friction_deg)
	sid, n = _place_sphere(sph_mat, (x_from, y, 0.0), (0, 0, 1), overlap)
	dx = (x_to - x_from) / n_samples
	O.dt = 1e-5
	O.bodies[sid].state.vel = Vector3(dx / O.dt, 0, 0)
	kn = contact_kn(PROBE_E, PROBE_R, PROBE_E, PROBE_r)
	rows = []
	for _ in range(n_samples):
		x = O.bodies[sid].state.pos[0]
		O.step()
		f = O.forces.f(sid)
		rows.append({'x': x, 'contacts': sphere_contacts(sid), 'active': active_contacts(sid), 'kinds': _contact_kinds(sid), 'fz': f[2], 'fx': f[0]})
	jumps = [(abs(b['fz'] - a['fz']), b['x']) for a, b in zip(rows[:-1], rows[1:])]
	mj = max(jumps)
	summ = {
	        'F_analytic': kn * overlap,
	        'fz_min': min(r['fz'] for r in rows),
	        'fz_max': max(r['fz'] for r in rows),
	        'max_jump': mj[0],
	        'x_jump': mj[1],
	        'max_contacts': max(r['contacts'] for r in rows),
	        'min_contacts': min(r['contacts'] for r in rows),
	        'x_lost': [r['x'] for r in rows if r['active'] == 0],
	}
	return rows, summ


# ----------------------------------------------------------------------------------------------
# demo
# ----------------------------------------------------------------------------------------------
def _results_dir():
	d = os.path.join(BENCH_DIR, 'results')
	os.makedirs(d, exist_ok=True)
	return d


def _write_csv(path, rows):
	keys = []
	for r in rows:
		for k in r:
			if k not in keys:
				keys.append(k)
	with open(path, 'w', newline='') as f:
		w = csv.DictWriter(f, fieldnames=keys)
		w.writeheader()
		for r in rows:
			w.writerow(r)


def run_probes(write=True):
	rows = []
	for case in probe_cases():
		name, desc, pts, tris, feat, d = case[:6]
		row = probe(name, pts, tris, feat, d, extra=case[6] if len(case) > 6 else None)
		row['description'] = desc
		rows.append(row)
	slides = (
	        ('slide_edge_hit', dict(n_samples=300), 'steps of 1 mm: one sample lands exactly on the edge'),
	        ('slide_edge_generic', dict(n_samples=307), 'steps of 0.977 mm: no sample on the edge'),
	        ('slide_edge_friction30', dict(n_samples=307, friction_deg=30.0), 'as slide_edge_generic, friction 30 deg'),
	)
	srows_all, summ = [], None
	for name, kw, what in slides:
		srows, sm = slide_probe(**kw)
		for r in srows:
			r['case'] = name
		srows_all += srows
		summ = summ or sm
		rows.append({
		        'probe': name,
		        'overlap_m': PROBE_OVERLAP,
		        'kn_analytic_N_per_m': sm['F_analytic'] / PROBE_OVERLAP,
		        'F_analytic_N': sm['F_analytic'],
		        'contacts_min': sm['min_contacts'],
		        'contacts_max': sm['max_contacts'],
		        'Fn_min_N': sm['fz_min'],
		        'Fn_max_N': sm['fz_max'],
		        'max_jump_N': sm['max_jump'],
		        'x_jump_m': sm['x_jump'],
		        'x_no_contact_m': ' '.join('%.6f' % x for x in sm['x_lost']),
		        'description': 'sphere moved along x (0.35 -> 0.65 m) across the shared edge x=0.5 of two coplanar facets at constant overlap; ' + what,
		})
	srows = srows_all
	if write:
		_write_csv(os.path.join(_results_dir(), 'builtin_pfacet_probes.csv'), rows)
		_write_csv(os.path.join(_results_dir(), 'builtin_pfacet_slide.csv'), srows)
	return rows, srows, summ


def _fmt_breakdown(b):
	return ' '.join('%s=%.1f(%.0f%%)' % (k, v, 100 * b['share'][k]) for k, v in b['engines'].items())


def _machine_line():
	"""'cpu model; cores; date; load average; YADE version, threads' for the results directory."""
	if BENCH_DIR not in sys.path:
		sys.path.insert(0, BENCH_DIR)
	from machine import machine_line
	return machine_line(yade.config.version, O.numThreads)


def main(n_steps=300, reps=5):
	with open(os.path.join(_results_dir(), 'builtin_pfacet_machine.txt'), 'w') as f:
		f.write(_machine_line())
	print('yade-flex bench: built-in PFacet reference, YADE %s, %d thread(s), %s' % (yade.config.version, O.numThreads, time.strftime('%Y-%m-%d %H:%M')))
	rows = []
	print('\n== timing: median of %d x %d steps (O.step loop), per-engine from one extra timed run ==' % (reps, n_steps))
	print('%-22s %5s %6s %6s %6s %6s %9s %9s  %s' % ('scene', 'facets', 'bodies', 'intrs', 'real', 'virt', 'dt', 'us/step', 'per-engine us/step (share)'))
	for label, builder in (
	        ('sheet n=12', lambda: sheet(n=12)),
	        ('sheet n=16', lambda: sheet(n=16)),
	        ('sheet n=12 no-nbr', lambda: sheet(n=12, neighbour_pairs=False)),
	        ('bumpy n=16', lambda: bumpy(n=16)),
	        ('bumpy n=16 no-nbr', lambda: bumpy(n=16, neighbour_pairs=False)),
	):
		info = builder()
		sid = info['sphere_id']
		# let the sphere reach the membrane/surface so that the timed steps include a real contact
		for _ in range(8000):
			O.step()
			if sphere_contacts(sid):
				break
		for _ in range(200):
			O.step()
		t = time_per_step(n_steps, reps)
		b = breakdown(n_steps)
		cz = b['census']
		print('%-22s %5d %6d %6d %6d %6d %9.3g %9.1f  %s' %
		      (label, info['facets'], info['bodies'], cz['total'], cz['real'], cz['virtual'], info['dt'], t['us_per_step'], _fmt_breakdown(b)))
		print('    census: ' + ', '.join('%s=%d' % (k, v) for k, v in sorted(cz.items()) if ' ' in k))
		row = {'scene': label, 'facets': info['facets'], 'nodes': info['nodes'], 'connections': info['connections'], 'bodies': info['bodies'],
		       'interactions': cz['total'], 'real': cz['real'], 'virtual': cz['virtual'], 'virtual_mesh': cz['virtual_mesh'], 'dt_s': info['dt'],
		       'us_per_step_median': t['us_per_step'], 'us_per_step_all': ' '.join('%.1f' % x for x in t['us_per_step_all']),
		       'sphere_contacts': sphere_contacts(sid), 'threads': O.numThreads}
		for k, v in b['engines'].items():
			row['us_' + k] = v
		rows.append(row)
		sys.stdout.flush()
	_write_csv(os.path.join(_results_dir(), 'builtin_pfacet_timing.csv'), rows)

	print('\n== sheet n=12: sphere settling (damping 0.2), 5 kg on Et=30 kN/m, 0.4 kg/m2 ==')
	info = sheet(n=12, damping=0.2)
	sid = info['sphere_id']
	print('  E_bond=%.4g Pa, Et_model=%.4g N/m, mass=%.4g kg, kn_contact=%.4g N/m, dt=%.3g s (pwave %.3g, stiff %.3g, contact %.3g)' %
	      (info['young_bond'], info['membrane_Et_model'], info['mass_membrane'], info['kn_contact'], info['dt'], info['dt_pwave'],
	       info['dt_stiff'], info['dt_contact']))
	hist = contact_history(sid, 12000, every=1000)
	for h in hist:
		print('  t=%.3f s  z=%.4f m  contacts=%d (active %d)  fz=%.2f N' % (h['t'], h['z'], h['contacts'], h['active'], h['fz']))

	print('\n== bumpy n=16: sphere 1 kg, R=0.05 m, v0=0.5 m/s over z = A sin(kx) sin(ky), A=5 mm, lambda=0.5 m ==')
	brows = []
	for dtf in (0.5, 0.1):
		info = bumpy(n=16, dt_factor=dtf)
		sid = info['sphere_id']
		hist = contact_history(sid, int(0.6 / info['dt']), every=1 if dtf == 0.5 else 5, gap=True)
		for h in hist:
			h['dt_factor'] = dtf
		brows += hist
		over = [h for h in hist if h['gap'] < -1e-6]
		miss = [h for h in over if h['active'] == 0]
		dist = {}
		for h in hist:
			dist[h['active']] = dist.get(h['active'], 0) + 1
		regions = {}
		for h in miss:
			regions[h['region']] = regions.get(h['region'], 0) + 1
		print('  dt=%.3g s (dt_factor %.1f): %d samples, x %.3f -> %.3f m; samples with overlap > 1 um: %d, of which with NO active'
		      ' contact: %d (closest feature %s), deepest missed overlap %.3g mm; active-contact distribution %s; sphere energy %.4g -> max %.4g J' %
		      (info['dt'], dtf, len(hist), hist[0]['x'], hist[-1]['x'], len(over), len(miss), regions, -1e3 * min([h['gap'] for h in miss] or [0]),
		       ', '.join('%d:%d' % kv for kv in sorted(dist.items())), hist[0]['energy'], max(h['energy'] for h in hist)))
	_write_csv(os.path.join(_results_dir(), 'builtin_pfacet_bumpy.csv'), brows)

	print('\n== contact probes: sphere R=%g m, PFacet r=%g m, E=%g Pa, overlap %g m, kn=%.4g N/m ==' %
	      (PROBE_R, PROBE_r, PROBE_E, PROBE_OVERLAP, contact_kn(PROBE_E, PROBE_R, PROBE_E, PROBE_r)))
	prows, srows, summ = run_probes()
	print('%-22s %9s %9s %9s %22s %10s %10s' % ('probe', 'contacts1', 'contacts5', 'active5', 'kinds(step5)', 'Fn/kn.d 1', 'Fn/kn.d 5'))
	for r in prows:
		if r['probe'].startswith('slide'):
			continue
		print('%-22s %9d %9d %9d %22s %10.4f %10.4f' %
		      (r['probe'], r['contacts_step1'], r['contacts_step5'], r['active_step5'], r['kinds_step5'], r['ratio_step1'], r['ratio_step5']))
	for r in prows:
		if r['probe'].startswith('slide'):
			print('%-22s contacts %d..%d, Fn %.4g..%.4g N (analytic %.4g), largest jump %.4g N; no contact at x = [%s]' %
			      (r['probe'], r['contacts_min'], r['contacts_max'], r['Fn_min_N'], r['Fn_max_N'], r['F_analytic_N'], r['max_jump_N'],
			       r['x_no_contact_m']))


if __name__ == '__main__':
	main()
