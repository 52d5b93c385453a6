# Reference scenes built from YADE's BUILT-IN grid classes (GPL-2.0-or-later).
#
# GridNode / GridConnection bonded by CohFrictPhys (Law2_ScGeom6D_CohFrictPhys_CohesionMoment),
# sphere-GridConnection contacts through Ig2_Sphere_GridConnection_ScGridCoGeom.  These are the
# baselines that yade-flex is compared against (speed and cantilever accuracy).
#
# Use from a yade-double script:
#     import sys; sys.path.insert(0, '/path/to/bench')
#     import builtin_grid as bg
#     bg.helix(n_seg=200); print(bg.time_per_step(2000))
# or run the demo:  yade-double -n -j1 -x bench/builtin_grid.py
#
# Every builder calls O.reset() and builds on the global O.
#
# Time step.  Two estimates are computed for every scene and returned:
#   * 'dt_pwave'  : yade.utils.PWaveTimeStep(). GridNode derives from Sphere, so YADE uses the
#                   node radius and an "equivalent density" m/(4/3 pi r^3) from the node mass.
#   * 'dt_stiff'  : from the bond stiffnesses that yade.gridpfacet.gridConnection sets
#                   (kn = EA/L, ks = 12EI/L^3, kr = EI/L, ktw = 2GI/L) and the node masses and
#                   inertias: for node i,  K_t = sum over its bonds of max(kn, ks),
#                   K_r = sum of max(kr, ktw) + ks (L/2)^2  (shear force acting at the bond
#                   mid-point), dt_stiff = min_i min(sqrt(m_i/K_t), sqrt(J_i/K_r)).
#                   By Gershgorin, omega_max^2 <= 2 K/m, so the critical step of the central
#                   difference scheme (2/omega_max) is >= sqrt(2) * dt_stiff: dt_stiff already
#                   carries a safety factor of 1/sqrt(2).  (The bound assumes a symmetric
#                   stiffness; checked empirically: the 10-segment cantilever is stable at
#                   dt = 1.3 dt_stiff with either avoidGranularRatcheting setting.)
#   The step actually used is dt = dt_factor * min(dt_pwave, dt_stiff), dt_factor = 0.5 by
#   default.  For slender grids (r << L) dt_pwave is the smaller one, so dt = 0.5 * PWave.
#   Bodies that are not grid nodes (the net's sphere) enter through dt_pwave only.
#
# Masses.  yade.gridpfacet.gridNode gives a node zero mass; each gridConnection adds
# rho_node * (L/2) pi r^2 (and 2/5 of that times r^2 as inertia) to both of its nodes.  The summed
# GridNode mass is therefore exactly rho pi r^2 * (total wire length) (no spherical end caps).
# The GridConnection bodies get a mass too but are non-dynamic: it is never used.

import math
import os
import statistics
import sys
import time

import yade
from yade import O, utils
from yade.wrapper import (Bo1_GridConnection_Aabb, Bo1_Sphere_Aabb, CohFrictMat,
                          CohFrictPhys, ForceResetter, FrictMat, GridConnection, GridNode,
                          Ig2_GridConnection_GridConnection_GridCoGridCoGeom,
                          Ig2_GridNode_GridNode_GridNodeGeom6D,
                          Ig2_Sphere_GridConnection_ScGridCoGeom, InsertionSortCollider,
                          InteractionLoop, Ip2_CohFrictMat_CohFrictMat_CohFrictPhys,
                          Ip2_FrictMat_FrictMat_FrictPhys,
                          Law2_GridCoGridCoGeom_FrictPhys_CundallStrack,
                          Law2_ScGeom6D_CohFrictPhys_CohesionMoment,
                          Law2_ScGridCoGeom_FrictPhys_CundallStrack, NewtonIntegrator, Sphere)
from yade.gridpfacet import gridConnection, gridNode
from yade.minieigenHP import Vector3

from stepping import run_steps as _run_steps

G_ACC = 9.81
HUGE_COHESION = 1e30  # Pa; normalAdhesion = normalCohesion * r^2 -> bonds never break


# ----------------------------------------------------------------------------------------------
# common helpers
# ----------------------------------------------------------------------------------------------
GC_MASK = 2  # mask of every GridConnection
SPHERE_MASK = 3  # mask of external spheres (shares bit 2 with the GridConnections)


def _engines(gravity=(0, 0, -G_ACC), damping=0.0, with_spheres=False, avoid_ratcheting=True, self_contact=False):
	"""Engines for bonded grids (+ optional sphere-GridConnection contacts).

	Must be installed before gridConnection() is called: yade.gridpfacet.gridConnection uses
	createInteraction, which runs the functors of the current InteractionLoop.

	GridConnection-GridConnection pairs: GridConnection derives from Sphere in YADE, so with
	Ig2_Sphere_GridConnection_ScGridCoGeom in the dispatcher a GC-GC pair found by the collider is
	handled as "sphere"-GC and produces garbage (NaN forces at the first step for the net, where
	crossing connections share nodes).  Unless self_contact=True, GC-GC pairs are therefore
	removed at the collider (all GridConnections get mask GC_MASK and
	collider.avoidSelfInteractionMask = GC_MASK); this also saves the useless potential
	interactions between neighbouring connections in the chain-like scenes.  With
	self_contact=True the proper Ig2_GridConnection_GridConnection_GridCoGridCoGeom +
	Law2_GridCoGridCoGeom_FrictPhys_CundallStrack pair is added instead."""
	bo1 = [Bo1_GridConnection_Aabb()]
	ig2 = [Ig2_GridNode_GridNode_GridNodeGeom6D(avoidGranularRatcheting=avoid_ratcheting)]
	ip2 = [Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(setCohesionNow=True, setCohesionOnNewContacts=False)]
	law = [Law2_ScGeom6D_CohFrictPhys_CohesionMoment()]
	if with_spheres or self_contact:
		ip2.append(Ip2_FrictMat_FrictMat_FrictPhys())
	if with_spheres:
		bo1.insert(0, Bo1_Sphere_Aabb())
		ig2.append(Ig2_Sphere_GridConnection_ScGridCoGeom())
		law.append(Law2_ScGridCoGeom_FrictPhys_CundallStrack())
	if self_contact:
		ig2.append(Ig2_GridConnection_GridConnection_GridCoGridCoGeom())
		law.append(Law2_GridCoGridCoGeom_FrictPhys_CundallStrack())
	collider = InsertionSortCollider(bo1)
	if not self_contact:
		collider.avoidSelfInteractionMask = GC_MASK
	O.engines = [
	        ForceResetter(),
	        collider,
	        InteractionLoop(ig2, ip2, law),
	        NewtonIntegrator(gravity=gravity, damping=damping, label='newton'),
	]


def _materials(young, poisson, density, friction_deg=30.0):
	"""Returns (node material id, connection material id).

	The node material (CohFrictMat) defines the internal bonds; the GridConnection material
	(FrictMat) is used only for contacts with external bodies (spheres)."""
	node_mat = O.materials.append(
	        CohFrictMat(
	                young=young,
	                poisson=poisson,
	                density=density,
	                frictionAngle=math.radians(friction_deg),
	                isCohesive=True,
	                momentRotationLaw=True,
	                normalCohesion=HUGE_COHESION,
	                shearCohesion=HUGE_COHESION,
	                label='gridNodeMat'
	        )
	)
	conn_mat = O.materials.append(
	        FrictMat(young=young, poisson=poisson, density=density, frictionAngle=math.radians(friction_deg), label='gridConnMat')
	)
	return node_mat, conn_mat


def _is_node(b):
	return b is not None and isinstance(b.shape, GridNode)


def _is_conn(b):
	return b is not None and isinstance(b.shape, GridConnection)


def stiffness_dt():
	"""dt_stiff as described in the file header (bonded GridNode pairs only)."""
	kt = {}
	kr = {}
	for i in O.interactions:
		if not i.isReal or not isinstance(i.phys, CohFrictPhys):
			continue
		b1, b2 = O.bodies[i.id1], O.bodies[i.id2]
		if not (_is_node(b1) and _is_node(b2)):
			continue
		p = i.phys
		half = 0.5 * (b2.state.pos - b1.state.pos).norm()
		for bid in (i.id1, i.id2):
			kt[bid] = kt.get(bid, 0.0) + max(p.kn, p.ks)
			kr[bid] = kr.get(bid, 0.0) + max(p.kr, p.ktw) + p.ks * half * half
	dt = float('inf')
	for bid, k in kt.items():
		st = O.bodies[bid].state
		if st.mass > 0 and k > 0:
			dt = min(dt, math.sqrt(st.mass / k))
		j = min(st.inertia[0], st.inertia[1], st.inertia[2])
		if j > 0 and kr[bid] > 0:
			dt = min(dt, math.sqrt(j / kr[bid]))
	return dt


def _set_dt(dt_factor):
	dtp = utils.PWaveTimeStep()
	dts = stiffness_dt()
	O.dt = dt_factor * min(dtp, dts)
	return {'dt': O.dt, 'dt_pwave': dtp, 'dt_stiff': dts}


def counts():
	"""Body / interaction counts of the current scene."""
	nodes = sum(1 for b in O.bodies if _is_node(b))
	conns = sum(1 for b in O.bodies if _is_conn(b))
	spheres = sum(1 for b in O.bodies if b is not None and type(b.shape) is Sphere)
	return {
	        'bodies': len(O.bodies),
	        'nodes': nodes,
	        'connections': conns,
	        'spheres': spheres,
	        'interactions': len(O.interactions),
	        'interactions_real': O.interactions.countReal(),
	}


def run_steps(n):
	"""stepping.run_steps with a 0.2 ms poll."""
	_run_steps(n, poll=2e-4)


def node_mass_total():
	return sum(b.state.mass for b in O.bodies if _is_node(b))


def _build_chain(points, radius, node_mat, conn_mat):
	"""GridNodes at points, consecutive ones joined by GridConnections. Returns (nodes, conns)."""
	nodes = [O.bodies.append(gridNode(p, radius, material=node_mat)) for p in points]
	conns = [O.bodies.append(gridConnection(a, b, radius, material=conn_mat, mask=GC_MASK)) for a, b in zip(nodes[:-1], nodes[1:])]
	return nodes, conns


# ----------------------------------------------------------------------------------------------
# 1. helix
# ----------------------------------------------------------------------------------------------
def helix(
        n_seg=200,
        radius_wire=0.002,
        coil_radius=0.05,
        pitch=0.01,
        turns=None,
        young=200e9,
        poisson=0.3,
        density=7850,
        damping=0.0,
        dt_factor=0.5,
        segs_per_turn=20
):
	"""Helix of n_seg GridConnections (n_seg+1 GridNodes) about the z axis, cohesive CohFrict
	bonds with moments, node 0 clamped (xyzXYZ), gravity -z.  turns=None -> n_seg/segs_per_turn
	turns (segment length ~ 2 pi coil_radius / segs_per_turn)."""
	O.reset()
	if turns is None:
		turns = n_seg / float(segs_per_turn)
	_engines(gravity=(0, 0, -G_ACC), damping=damping)
	node_mat, conn_mat = _materials(young, poisson, density)
	pts = []
	for k in range(n_seg + 1):
		phi = 2.0 * math.pi * turns * k / n_seg
		pts.append(Vector3(coil_radius * math.cos(phi), coil_radius * math.sin(phi), pitch * phi / (2.0 * math.pi)))
	seg_len = (pts[1] - pts[0]).norm()
	if seg_len <= 2.0 * radius_wire:
		raise ValueError('helix: segment length %g <= wire diameter %g' % (seg_len, 2 * radius_wire))
	nodes, conns = _build_chain(pts, radius_wire, node_mat, conn_mat)
	O.bodies[nodes[0]].state.blockedDOFs = 'xyzXYZ'
	res = {'scene': 'helix', 'n_seg': n_seg, 'turns': turns, 'seg_len': seg_len}
	res.update(_set_dt(dt_factor))
	res.update(counts())
	res['mass_nodes'] = node_mass_total()
	return res


# ----------------------------------------------------------------------------------------------
# 2. net + falling sphere
# ----------------------------------------------------------------------------------------------
def net(
        n=20,
        spacing=0.05,
        radius_wire=0.002,
        sphere_radius=0.1,
        sphere_speed=5.0,
        young=200e9,
        poisson=0.3,
        density=7850,
        sphere_young=None,
        sphere_density=7850,
        friction_deg=30.0,
        gap=0.001,
        damping=0.0,
        dt_factor=0.5,
        self_contact=False
):
	"""Square net of n x n GridNodes in the plane z=0 (spacing apart), GridConnections along x and
	y, boundary nodes clamped, cohesive CohFrict bonds (self_contact: see _engines).  A FrictMat sphere starts `gap` above the
	net centre (surface to wire surface) moving at -sphere_speed along z; gravity -z."""
	O.reset()
	_engines(gravity=(0, 0, -G_ACC), damping=damping, with_spheres=True, self_contact=self_contact)
	node_mat, conn_mat = _materials(young, poisson, density, friction_deg)
	sph_mat = O.materials.append(
	        FrictMat(
	                young=young if sphere_young is None else sphere_young,
	                poisson=poisson,
	                density=sphere_density,
	                frictionAngle=math.radians(friction_deg),
	                label='sphereMat'
	        )
	)
	ids = {}
	for i in range(n):
		for j in range(n):
			ids[i, j] = O.bodies.append(gridNode(Vector3(i * spacing, j * spacing, 0.0), radius_wire, material=node_mat))
	for i in range(n):
		for j in range(n):
			if i + 1 < n:
				O.bodies.append(gridConnection(ids[i, j], ids[i + 1, j], radius_wire, material=conn_mat, mask=GC_MASK))
			if j + 1 < n:
				O.bodies.append(gridConnection(ids[i, j], ids[i, j + 1], radius_wire, material=conn_mat, mask=GC_MASK))
	for (i, j), bid in ids.items():
		if i in (0, n - 1) or j in (0, n - 1):
			O.bodies[bid].state.blockedDOFs = 'xyzXYZ'
	c = 0.5 * (n - 1) * spacing
	sid = O.bodies.append(utils.sphere(Vector3(c, c, radius_wire + sphere_radius + gap), sphere_radius, material=sph_mat, mask=SPHERE_MASK))
	O.bodies[sid].state.vel = Vector3(0, 0, -sphere_speed)
	res = {'scene': 'net', 'n': n, 'sphere_id': sid}
	res.update(_set_dt(dt_factor))
	res.update(counts())
	res['mass_nodes'] = node_mass_total()
	return res


def sphere_contacts(sid):
	"""Number of real interactions of body sid (for the net: sphere-GridConnection contacts)."""
	return sum(1 for i in O.interactions.withBody(sid) if i.isReal)


# ----------------------------------------------------------------------------------------------
# 3. cantilever
# ----------------------------------------------------------------------------------------------
def cantilever(
        n_seg=10,
        length=1.0,
        radius_wire=0.01,
        young=200e9,
        poisson=0.3,
        density=7850,
        load='tip',
        tip_force=None,
        rel_deflection=1e-3,
        damping=0.5,
        dt_factor=0.5,
        avoid_ratcheting=True,
        check_every=2000,
        max_iter=3000000,
        max_wall_s=None,
        tol_unbalanced=1e-6,
        tol_rel_change=1e-8
):
	"""Horizontal cantilever along +x, node 0 clamped (xyzXYZ), run quasi-statically (local
	damping) to equilibrium.

	load='tip' : permanent force -tip_force e_z on the last node; tip_force=None -> chosen so that
	             the Euler-Bernoulli deflection is rel_deflection*length (P = 3 E I d / L^3).
	load='self': gravity -z on the node masses.

	Convergence (checked every check_every steps): utils.unbalancedForce() < tol_unbalanced AND
	|tip deflection change over the last check_every steps| < tol_rel_change * |deflection|.
	Capped at max_iter steps and, if given, max_wall_s seconds ('converged' tells which happened).

	Analytic references (I = pi r^4 / 4):
	  tip : P L^3 / (3 E I)
	  self: q L^4 / (8 E I) with q_nominal = rho pi r^2 g and q_model = (sum of GridNode masses) g / L;
	        'analytic_lumped' = exact Euler-Bernoulli tip deflection for the gravity forces the
	        model actually applies (node masses m_k g at x_k; the clamped node's load is lost):
	        sum_k F_k x_k^2 (3 L - x_k) / (6 E I).
	avoid_ratcheting is passed to Ig2_GridNode_GridNode_GridNodeGeom6D.avoidGranularRatcheting
	(YADE default True).  With True, ScGeom::getIncidentVel scales the relative translational
	velocity by alpha = (r1+r2)/(r1+r2-penetrationDepth) = 2r/L_seg and uses the wire radius r
	(not L_seg/2) as lever for the rotations, so the bond's shear displacement is 2r/L_seg times the
	beam's true transverse "shear" (dv - L_seg*theta_avg): the shear spring ks = 12EI/L^3 set by
	gridConnection acts as if it were ks*2r/L_seg.  The moment kr = EI/L_seg is unaffected.  For a
	tip load this gives (derivation, Euler-Bernoulli, n equal segments)
	    measured/analytic = 1 + (L_seg/(2r) - 1) / (4 n^2)         ('predicted_ratio')
	and exactly 1 with avoid_ratcheting=False (a chain of these bonds with the true shear
	measure reproduces Euler-Bernoulli nodal deflections exactly for point loads)."""
	O.reset()
	if load not in ('tip', 'self'):
		raise ValueError("load must be 'tip' or 'self'")
	grav = (0, 0, -G_ACC) if load == 'self' else (0, 0, 0)
	_engines(gravity=grav, damping=damping, avoid_ratcheting=avoid_ratcheting)
	node_mat, conn_mat = _materials(young, poisson, density)
	pts = [Vector3(length * k / n_seg, 0, 0) for k in range(n_seg + 1)]
	nodes, conns = _build_chain(pts, radius_wire, node_mat, conn_mat)
	O.bodies[nodes[0]].state.blockedDOFs = 'xyzXYZ'
	tip = nodes[-1]

	I = math.pi * radius_wire**4 / 4.0
	EI = young * I
	area = math.pi * radius_wire**2
	m_model = node_mass_total()
	m_nominal = density * area * length
	res = {
	        'scene': 'cantilever',
	        'load': load,
	        'n_seg': n_seg,
	        'avoid_ratcheting': avoid_ratcheting,
	        'mass_nominal': m_nominal,
	        'mass_model': m_model,
	        'mass_connections_unused': sum(b.state.mass for b in O.bodies if _is_conn(b)),
	}
	if load == 'tip':
		if tip_force is None:
			tip_force = 3.0 * EI * rel_deflection * length / length**3
		if hasattr(O.forces, 'setPermF'):
			O.forces.setPermF(tip, Vector3(0, 0, -tip_force))
		else:  # older YADE
			O.forces.addF(tip, Vector3(0, 0, -tip_force), permanent=True)
		res['tip_force'] = tip_force
		res['analytic'] = tip_force * length**3 / (3.0 * EI)
		seg = length / n_seg
		res['predicted_ratio'] = 1.0 + ((seg / (2.0 * radius_wire) - 1.0) if avoid_ratcheting else 0.0) / (4.0 * n_seg**2)
	else:
		q_nom = density * area * G_ACC
		q_mod = m_model * G_ACC / length
		res['analytic'] = q_nom * length**4 / (8.0 * EI)
		res['analytic_model_mass'] = q_mod * length**4 / (8.0 * EI)
		lumped = 0.0
		for nid in nodes[1:]:
			x = O.bodies[nid].state.pos[0]
			lumped += O.bodies[nid].state.mass * G_ACC * x * x * (3 * length - x) / (6.0 * EI)
		res['analytic_lumped'] = lumped
	res.update(_set_dt(dt_factor))

	z0 = O.bodies[tip].state.pos[2]
	prev = 0.0
	converged = False
	t0 = time.perf_counter()
	while O.iter < max_iter and (max_wall_s is None or time.perf_counter() - t0 < max_wall_s):
		run_steps(check_every)
		d = z0 - O.bodies[tip].state.pos[2]
		unb = utils.unbalancedForce()
		if unb < tol_unbalanced and abs(d - prev) < tol_rel_change * abs(d):
			converged = True
			break
		prev = d
	res['wall_s'] = time.perf_counter() - t0
	res['iterations'] = O.iter
	res['converged'] = converged
	res['unbalanced'] = utils.unbalancedForce()
	res['measured'] = z0 - O.bodies[tip].state.pos[2]
	res['ratio'] = res['measured'] / res['analytic']
	if load == 'self':
		res['ratio_model_mass'] = res['measured'] / res['analytic_model_mass']
		res['ratio_lumped'] = res['measured'] / res['analytic_lumped']
	return res


# ----------------------------------------------------------------------------------------------
# 4. timing
# ----------------------------------------------------------------------------------------------
def time_per_step(n_steps=2000, repeats=5, warmup=200, per_engine=True, fine_wait=True):
	"""Times the current scene: warmup steps, then `repeats` runs of n_steps, each timed with
	time.perf_counter (wall) and time.process_time (CPU of all threads), O.timingEnabled off.

	fine_wait=True  : run with run_steps() (O.run(n) + 0.2 ms poll of O.running);
	fine_wait=False : O.run(n, True) literally; its 40 ms wait poll inflates short runs (see
	                  run_steps), so prefer True unless n_steps * (s/step) >> 40 ms.
	If per_engine, one extra run of n_steps with O.timingEnabled=True gives, for each engine, its
	total time / n_steps (not part of the median)."""
	def go(n):
		if fine_wait:
			run_steps(n)
		else:
			O.run(n, True)

	O.timingEnabled = False
	go(warmup)
	wall, cpu = [], []
	for _ in range(repeats):
		c0 = time.process_time()
		t0 = time.perf_counter()
		go(n_steps)
		wall.append((time.perf_counter() - t0) / n_steps)
		cpu.append((time.process_time() - c0) / n_steps)
	res = {
	        'median_s_per_step': statistics.median(wall),
	        's_per_step': wall,
	        'median_cpu_s_per_step': statistics.median(cpu),
	        'threads': O.numThreads,
	}
	if per_engine:
		for e in O.engines:
			e.execTime = 0
			e.execCount = 0
		O.timingEnabled = True
		go(n_steps)
		O.timingEnabled = False
		# per step of the run (the collider executes only when a bound is left, see execCount)
		res['per_engine_s_per_step'] = {(e.label or e.__class__.__name__): e.execTime * 1e-9 / n_steps for e in O.engines}
		res['per_engine_exec_count'] = {(e.label or e.__class__.__name__): e.execCount for e in O.engines}
	return res


# ----------------------------------------------------------------------------------------------
# demo
# ----------------------------------------------------------------------------------------------
def _fmt(x):
	if isinstance(x, float):
		return '%.4g' % x
	return str(x)


def _wait_for_sphere_contact(sid, chunk=500, cap=20000):
	"""Run until body sid has a real contact at a chunk boundary (contacts of the light net are
	intermittent at first).  Returns (iteration, contacts) or (iteration, 0) at the cap."""
	start = O.iter
	while O.iter - start < cap:
		run_steps(chunk)
		nc = sphere_contacts(sid)
		if nc:
			return O.iter, nc
	return O.iter, 0


def main(n_steps=2000, repeats=5, warmup=200, cantilever_segs=(2, 5, 10, 20), cantilever_ratch=None, cantilever_max_wall_s=None):
	"""Demo.  By default the cantilever sweep runs with avoidGranularRatcheting True and False on
	one thread, and only True (YADE's default) with a 10 s cap per case on several threads: the
	accuracy does not depend on the thread count, and tiny scenes are slow with OpenMP."""
	nthr = O.numThreads
	print('yade-flex bench: built-in grid reference, YADE %s, %d thread(s)' % (yade.config.version, nthr))
	if nthr > 1 and not os.environ.get('OMP_WAIT_POLICY'):
		print('note: OMP_WAIT_POLICY not set; on a loaded machine spinning OpenMP barriers can make -j%d runs\n'
		      '      10-40x slower than -j1 (OMP_WAIT_POLICY=passive avoids most of that)' % nthr)
	if cantilever_ratch is None:
		cantilever_ratch = (True, False) if nthr == 1 else (True, )
	if cantilever_max_wall_s is None:
		cantilever_max_wall_s = 60.0 if nthr == 1 else 10.0

	print('\n== timing (median of %d x %d steps after %d warm-up; wall and process CPU) ==' % (repeats, n_steps, warmup))
	print('%-16s %6s %6s %6s %9s %9s %9s %11s %11s  %s' %
	      ('scene', 'bodies', 'intrs', 'real', 'dt', 'dt_pwave', 'dt_stiff', 'wall s/step', 'cpu s/step', 'per-engine s/step'))
	for name, builder in (('helix n_seg=200', lambda: helix(200)), ('net n=20', lambda: net(20))):
		r = builder()
		t = time_per_step(n_steps, repeats, warmup)
		c = counts()
		pe = ' '.join('%s=%.2g' % (k, v) for k, v in t['per_engine_s_per_step'].items())
		print(
		        '%-16s %6d %6d %6d %9.3g %9.3g %9.3g %11.4g %11.4g  %s' % (
		                name, c['bodies'], c['interactions'], c['interactions_real'], r['dt'], r['dt_pwave'], r['dt_stiff'],
		                t['median_s_per_step'], t['median_cpu_s_per_step'], pe
		        )
		)
		if r['scene'] == 'net':
			sid = r['sphere_id']
			it, nc = _wait_for_sphere_contact(sid)
			print(
			        '  net: sphere-GridConnection contacts=%d at iter %d (sphere vz=%.3f m/s, lowest node z=%.4f m)' %
			        (nc, it, O.bodies[sid].state.vel[2], min(b.state.pos[2] for b in O.bodies if _is_node(b)))
			)
		else:
			bad = sum(1 for b in O.bodies if _is_node(b) and not (b.state.pos.norm() < 1e10))
			print('  helix: tip z=%.5f m after %d steps, non-finite nodes=%d' % (O.bodies[r['n_seg']].state.pos[2], O.iter, bad))

	print('\n== cantilever: length 1, r=0.01, E=200e9, rho=7850; ratio = measured / Euler-Bernoulli ==')
	print('ratch = Ig2_GridNode_GridNode_GridNodeGeom6D.avoidGranularRatcheting (YADE default True)')
	print('tip : predicted = 1 + (L_seg/2r - 1)/(4 n^2) if ratch else 1')
	print('self: r_mmass uses q from the summed GridNode masses, r_lump the exact EB deflection for the nodal loads')
	print('%-5s %5s %5s %11s %11s %9s %9s %9s %9s %9s %8s %5s %6s' %
	      ('load', 'n_seg', 'ratch', 'measured', 'analytic', 'ratio', 'predicted', 'r_mmass', 'r_lump', 'm_mod/nom', 'iters', 'conv', 'wall_s'))
	for ratch in cantilever_ratch:
		for load in ('tip', 'self'):
			for ns in cantilever_segs:
				r = cantilever(n_seg=ns, load=load, avoid_ratcheting=ratch, max_wall_s=cantilever_max_wall_s)
				print(
				        '%-5s %5d %5s %11.5g %11.5g %9.6f %9s %9s %9s %9.6f %8d %5s %6.1f' % (
				                load, ns, ratch, r['measured'], r['analytic'], r['ratio'],
				                ('%.6f' % r['predicted_ratio']) if load == 'tip' else '-',
				                ('%.6f' % r['ratio_model_mass']) if load == 'self' else '-',
				                ('%.6f' % r['ratio_lumped']) if load == 'self' else '-', r['mass_model'] / r['mass_nominal'],
				                r['iterations'], r['converged'], r['wall_s']
				        )
				)
				sys.stdout.flush()


if __name__ == '__main__':
	main()
