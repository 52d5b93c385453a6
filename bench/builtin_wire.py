# Reference scene built from YADE's BUILT-IN WirePM classes (GPL-2.0-or-later): a wire-mesh panel of
# WireMat spheres (the nodes) bonded by WirePM links, pulled apart quasi-statically, in the style of
# YADE's scripts/checks-and-tests/checks/checkWirePM.py (written from scratch; no YADE code copied).
#
# Use from a yade-double script:
#     import sys; sys.path.insert(0, '/path/to/bench')
#     import builtin_wire as bw
#     info = bw.panel(); curve = bw.pull(); print(bw.time_per_link_step(500, 5))
# or run the demo (prints a table, writes bench/results/builtin_wire_*.csv):
#     yade-double -n -j1 -x bench/builtin_wire.py
#
# Every builder calls O.reset() and builds on the global O.
#
# ------------------------------------------------------------------------------------------------
# How YADE's WirePM works (read from pkg/dem/WirePM.{hpp,cpp} of 2023.02a; summary in our words)
# ------------------------------------------------------------------------------------------------
# Bodies are plain Spheres with a WireMat (a FrictMat) and a WireState (counts broken links).  A link
# is an ordinary sphere-sphere interaction (Ig2_Sphere_Sphere_ScGeom) whose physics WirePhys is made
# by Ip2_WireMat_WireMat_WirePhys and whose force comes from Law2_ScGeom_WirePhys_WirePM.
#
# Link creation.  Ip2 marks a link "isLinked" only if its physics is created while
# scene.iter < Ip2.linkThresholdIteration (default 1, i.e. during the first step); the usual way is a
# large Bo1_Sphere_Aabb.aabbEnlargeFactor / Ig2_Sphere_Sphere_ScGeom.interactionDetectionFactor for
# one step, then back to -1.  Interactions made later are not linked and are deleted by the law.
# Here we create exactly the links of the mesh topology with utils.createInteraction before the
# first step (force=True, so the Ig2 accepts separated spheres); no other pair is ever linked.
# (Law2.linkThresholdIteration exists but the law does not use it.)
#
# Force-displacement curve of a link (per link, computed once by Ip2):
#   l0 = initial centre distance (R1 + R2 - initD, initD = ScGeom.penetrationDepth at creation < 0);
#   D  = penetrationDepth - initD  (negative in tension: the law works with tension < 0);
#   from WireMat.strainStressValues [(eps_i > 0, sigma_i > 0), ...] (no (0,0) point, >= 2 points):
#       u_i = -eps_i * l0,  F_i = -sigma_i * A,  A = WireMat.as = pi d^2/4 (d = WireMat.diameter);
#   initial (and unloading) stiffness kn = F_1/u_1 = E_1 A / l0 (E_1 = sigma_1/eps_1);
#   segment stiffnesses k_i = (F_i - F_{i-1})/(u_i - u_{i-1}), curve stored with (0,0) prepended.
#   Loading: F = F_{i-1} + (D - u_{i-1}) k_{i-1} on the segment containing D; tension only (F <= 0
#   is kept, compression set to 0); unloading/reloading (D above the largest elongation reached)
#   elastic with kn from the plastic offset plastD (F = kn (D - plastD)).  The "largest point
#   reached" is stored by OVERWRITING the first point of the link's displForceValues (plastic
#   memory kept inside the curve).  Rupture: D beyond the last u_i -> isLinked = false, the
#   interaction is deleted, both WireStates count numBrokenLinks += 1.  No shear force, no moment
#   (the force is applied at ScGeom.contactPoint along the normal), no energy booked.
#
# WireMat parameters:
#   diameter [m]            wire diameter d; A = pi d^2/4 (WireMat.as, read-only).
#   strainStressValues      single-wire curve, list of (strain [-], stress [Pa]) points.
#   strainStressValuesDT    double-twist curve (types 1 and 2 only; 2A is then used as area).
#   isDoubleTwist [bool]    links between two bodies of THIS material whose ids differ by exactly 1
#                           are double-twisted (the mesh generator must number the two ends of a
#                           twist consecutively and must avoid consecutive ids on single wires).
#   type 0 (Bertrand et al. 2008): one curve; a double-twist link gets a stiffness
#           k_DT = 2 (lambdak k_h + (1 - lambdak) k),  k = E_1 A / l0,
#           k_h = k (l0 d / A) / (48 cos(alpha) (41/9 (1 + nu) + 17/4 tan^2 alpha)), alpha = atan(l0/(3 pi d))
#           (nu = WireMat.poisson), first point force F_1 = k_DT u_1; further points: displacements
#           times lambdaEps (strain at failure reduced), forces times F_1'/F_1 (curve scaled).
#           lambdak [-] (default 0.73), lambdaEps [-] (default 0.47).
#   type 1 (Thoeni et al. 2013): separate curves; double-twist links use strainStressValuesDT and 2A.
#   type 2 (Thoeni et al. 2013): as type 1 plus a stochastic initial slack of each link:
#           dl = lambdau * l0 * rnd,  rnd ~ triangular(0, mode 0.5, 1)  (seed >= 1: boost minstd_rand
#           seeded with `seed`; seed = 0: seeded from the clock; seed = -1: rnd = 1, no randomness);
#           the curve is shifted by dl: with l0' = l0 + dl, u_i = -eps_i l0' - dl; kn (unloading) =
#           F_1/(u_1 + dl) = E_1 A / l0'; the initial loading branch goes from (0,0) to (u_1, F_1), i.e.
#           it is softer (slope F_1/u_1) -- or, if lambdaF < 1, a point (-dl + lambdaF (u_1 + dl),
#           lambdaF F_1) is inserted first, so the soft branch meets the elastic line at lambdaF F_1.
#           lambdau [-] (default 0.2) maximum slack relative to l0; lambdaF [-] (default 1).
#           Caveat: the generator is a function-level static shared by every material, link and
#           thread and seeded ONCE per process (the first seed seen wins): the draws depend on the
#           order in which links are created, and a second scene in the same process continues the
#           sequence (not reproducible across O.reset()).
#   Two different WireMats in one link: the thinner wire's curve, never double-twisted.
#   young/poisson/frictionAngle/density are the FrictMat ones (young only used by time-step helpers
#   and by non-link contacts; checkWirePM sets young = sigma_1/eps_1).
#
# Defaults here (TECCO-like where we can): wire d = 3 mm.  Two curves are provided:
#   CURVE_YADE_EXAMPLE: the 7-point mild-steel curve of YADE's checkWirePM (E_1 = 130 GPa, fails at 35 %);
#   CURVE_HIGH_TENSILE: a high-tensile wire like TECCO's (>= 1770 MPa): E_1 = 200 GPa up to 1000 MPa,
#                       1500 MPa at 1 %, 1770 MPa at 3 %, 1800 MPa at 5 % (rupture after the last point).
# Topologies:
#   'hexagonal' double-twist mesh (as yade.pack.hexaNet / checkWirePM: mesh opening mos, twist length a,
#               single-wire rise b; twists along y);
#   'rhombic'   chain-link mesh like TECCO G65/3: rhomboid cells 83 x 143 mm (x = short diagonal,
#               y = long diagonal), nodes at the cell corners, one single-wire link per cell side.
# Pull: the nodes of the lowest row are clamped, those of the highest row move at constant +y velocity
# (both with blockedDOFs 'xyzXYZ'); force = sum of the y reactions on the moving row; elongation = the
# imposed displacement.  Node mass: lumped wire mass rho A (sum of half the lengths of its links;
# doubled for twists) unless node_mass is given; rotational inertia 2/5 m R^2.
# Time step: dt = dt_factor * min_i sqrt(m_i / sum_links(max stiffness of the link curve)), the
# Gershgorin bound of the links' largest tangent stiffness (dt_factor 0.5); checkWirePM uses
# 0.2 sqrt(m/(2 kn)) (= 0.14 sqrt(m/kn)).

import csv
import math
import os
import statistics
import sys
import time

import yade
from yade import O, utils
from yade.wrapper import (Bo1_Sphere_Aabb, ForceResetter, Ig2_Sphere_Sphere_ScGeom, InsertionSortCollider, InteractionLoop,
                          Ip2_WireMat_WireMat_WirePhys, Law2_ScGeom_WirePhys_WirePM, NewtonIntegrator, WireMat, WirePhys)
from yade.minieigenHP import Vector2, Vector3

from stepping import run_steps  # noqa: F401  (bench_wire steps by builtin_wire.run_steps)

CURVE_YADE_EXAMPLE = [(0.0019230769, 2.5e8), (0.0192, 3.2195e8), (0.05, 3.8292e8), (0.15, 5.1219e8), (0.25, 5.5854e8), (0.3, 5.6585e8),
                      (0.35, 5.6585e8)]
CURVE_HIGH_TENSILE = [(0.005, 1.0e9), (0.01, 1.5e9), (0.03, 1.77e9), (0.05, 1.8e9)]
STEEL_DENSITY = 7850.0


def _here():
	"""Directory of this file (when run by yade -x, __file__ is yade's own script)."""
	f = globals().get('__file__', '')
	if f.endswith('builtin_wire.py'):
		return os.path.dirname(os.path.abspath(f))
	for a in sys.argv:
		if a.endswith('builtin_wire.py'):
			return os.path.dirname(os.path.abspath(a))
	return os.path.join(os.getcwd(), 'bench')


BENCH_DIR = _here()

_PANEL = {}  # ids of the current panel (bottom, top rows, links) for pull()


def _hexagonal(width, height, mos, a, b):
	"""Double-twist hexagonal mesh.  Returns (points, links, twists): twist ends are consecutive points."""
	pts, links, twists = [], [], []
	rows = int((height - a) / (a + b)) + 1
	ncol = int(width / mos) + 1
	seg = {}  # (row, col) -> (bottom index, top index)
	for i in range(rows):
		y = i * (a + b)
		shift = 0.5 * mos if i % 2 else 0.0
		for j in range(ncol if i % 2 == 0 else ncol - 1):
			x = shift + j * mos
			seg[i, j] = (len(pts), len(pts) + 1)
			pts += [(x, y, 0.0), (x, y + a, 0.0)]
			twists.append(seg[i, j])
	for (i, j), (bot, top) in seg.items():
		# single wires from the top of this twist to the bottoms of the two twists above
		if i % 2 == 0:
			up = [(i + 1, j - 1), (i + 1, j)]
		else:
			up = [(i + 1, j), (i + 1, j + 1)]
		for key in up:
			if key in seg:
				links.append((top, seg[key][0]))
	return pts, links, twists


def _rhombic(width, height, w, h):
	"""Chain-link (rhomboid) mesh, cells w x h (diagonals).  Returns (points, links, [])."""
	pts, idx = [], {}
	nx, ny = int(round(width / w)), int(round(height / h))
	for j in range(2 * ny + 1):
		for i in range(nx + 1):
			x = i * w + (0.5 * w if j % 2 else 0.0)
			if j % 2 and i == nx:
				continue
			idx[i, j] = len(pts)
			pts.append((x, 0.5 * h * j, 0.0))
	links = []
	for (i, j), k in idx.items():
		for key in (((i, j + 1), (i - 1, j + 1)) if j % 2 == 0 else ((i, j + 1), (i + 1, j + 1))):
			if key in idx:
				links.append((k, idx[key]))
	return pts, links, []


def panel(
        topology='hexagonal',
        width=1.0,
        height=0.5,
        mos=0.08,
        twist_length=0.04,
        rise=0.04,
        cell=(0.083, 0.143),
        wire_d=0.003,
        node_radius=None,
        strain_stress=None,
        strain_stress_dt=None,
        wire_type=0,
        double_twist=None,
        lambda_eps=0.47,
        lambda_k=0.73,
        lambda_u=0.2,
        lambda_F=1.0,
        seed=12345,
        poisson=0.3,
        node_mass=None,
        damping=0.5,
        dt_factor=0.5,
        gravity=(0, 0, 0)
):
	"""Wire-mesh panel in the x-y plane, lower-left corner at the origin, bonded by WirePM links.

	topology 'hexagonal': double-twist mesh, mesh opening mos [m], twist length twist_length [m] (a),
	single-wire rise [m] (b), twists along y; 'rhombic': chain-link cells cell = (w, h) [m] (diagonals,
	h along y).  width, height [m]: target size.  wire_d [m]: WireMat.diameter.  node_radius [m]
	(None: 4 wire_d as in checkWirePM; contact size only).  strain_stress: list of (strain [-], stress [Pa])
	(None: CURVE_YADE_EXAMPLE for 'hexagonal', CURVE_HIGH_TENSILE for 'rhombic'); strain_stress_dt: the
	double-twist curve for wire_type 1/2 (None: same as strain_stress).  wire_type: WireMat.type (0, 1, 2).
	double_twist: WireMat.isDoubleTwist (None: True for 'hexagonal').  lambda_eps, lambda_k, lambda_u,
	lambda_F [-], seed: WireMat parameters (see the file header).  node_mass [kg] (None: lumped wire mass).
	damping [-]: NewtonIntegrator local damping.  dt_factor [-].  gravity [m/s2].

	Returns a dict: scene, topology, nodes, links (linked interactions after the first step),
	twists, bottom_ids, top_ids, size_x, size_y [m], kn_single, kn_twist [N/m] (elastic stiffness of
	the first link of each kind), dt [s], mass_total [kg], A [m2]."""
	O.reset()
	if topology == 'hexagonal':
		pts, links, twists = _hexagonal(width, height, mos, twist_length, rise)
		curve = strain_stress or CURVE_YADE_EXAMPLE
		dtw = True if double_twist is None else double_twist
	elif topology == 'rhombic':
		pts, links, twists = _rhombic(width, height, cell[0], cell[1])
		curve = strain_stress or CURVE_HIGH_TENSILE
		dtw = False if double_twist is None else double_twist
	else:
		raise ValueError("panel: topology must be 'hexagonal' or 'rhombic', not %r" % (topology, ))
	R = 4.0 * wire_d if node_radius is None else node_radius
	E1 = curve[0][1] / curve[0][0]
	kw = dict(young=E1, poisson=poisson, frictionAngle=math.radians(30), density=STEEL_DENSITY, diameter=wire_d, isDoubleTwist=dtw,
	          type=wire_type, lambdaEps=lambda_eps, lambdak=lambda_k, lambdau=lambda_u, lambdaF=lambda_F, seed=seed, label='wireMat')
	mat = WireMat(**kw)
	if wire_type in (1, 2) and dtw:  # before strainStressValues: its postLoad checks the DT curve
		mat.strainStressValuesDT = [Vector2(e, s) for e, s in (strain_stress_dt or curve)]
	mat.strainStressValues = [Vector2(e, s) for e, s in curve]
	mid = O.materials.append(mat)
	O.engines = [
	        ForceResetter(),
	        InsertionSortCollider([Bo1_Sphere_Aabb()], label='collider'),
	        InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_WireMat_WireMat_WirePhys(linkThresholdIteration=1)],
	                        [Law2_ScGeom_WirePhys_WirePM(linkThresholdIteration=1)],
	                        label='iloop'),
	        NewtonIntegrator(damping=damping, gravity=gravity, label='newton'),
	]
	ids = [O.bodies.append(utils.sphere(Vector3(*p), R, material=mid)) for p in pts]
	twist_set = set(twists)
	for a, b in list(twists) + list(links):
		if abs(ids[a] - ids[b]) == 1 and (a, b) not in twist_set and dtw:
			raise RuntimeError('panel: single wire between consecutive ids would be taken as a double twist')
		utils.createInteraction(ids[a], ids[b])
	# lumped masses
	area = math.pi * wire_d**2 / 4.0
	lump = [0.0] * len(pts)
	for a, b in list(twists) + list(links):
		L = math.dist(pts[a], pts[b]) * (2.0 if (a, b) in twist_set else 1.0)
		lump[a] += 0.5 * L
		lump[b] += 0.5 * L
	for k, bid in enumerate(ids):
		m = node_mass if node_mass is not None else STEEL_DENSITY * area * lump[k]
		st = O.bodies[bid].state
		st.mass = m
		j = 0.4 * m * R * R
		st.inertia = Vector3(j, j, j)
	ymin = min(p[1] for p in pts)
	ymax = max(p[1] for p in pts)
	bottom = [ids[k] for k, p in enumerate(pts) if p[1] < ymin + 1e-9]
	top = [ids[k] for k, p in enumerate(pts) if p[1] > ymax - 1e-9]
	O.dt = 1e-9
	O.step()  # links are made (Ip2) during the first step
	kmax = {}
	kn_single = kn_twist = None
	nlinks = 0
	for i in O.interactions:
		p = i.phys
		if not isinstance(p, WirePhys) or not p.isLinked:
			continue
		nlinks += 1
		k = max([p.kn] + [abs(x) for x in p.stiffnessValues])
		for bid in (i.id1, i.id2):
			kmax[bid] = kmax.get(bid, 0.0) + k
		if p.isDoubleTwist and kn_twist is None:
			kn_twist = p.kn
		if not p.isDoubleTwist and kn_single is None:
			kn_single = p.kn
	dt_links = min(math.sqrt(O.bodies[b].state.mass / k) for b, k in kmax.items())
	O.dt = dt_factor * dt_links
	_PANEL.clear()
	_PANEL.update({'bottom': bottom, 'top': top})
	for bid in bottom + top:
		O.bodies[bid].state.blockedDOFs = 'xyzXYZ'
		O.bodies[bid].state.vel = Vector3(0, 0, 0)
	return {
	        'scene': 'wire_panel',
	        'topology': topology,
	        'nodes': len(ids),
	        'links': nlinks,
	        'links_planned': len(links) + len(twists),
	        'twists': len(twists),
	        'bottom_ids': bottom,
	        'top_ids': top,
	        'size_x': max(p[0] for p in pts) - min(p[0] for p in pts),
	        'size_y': ymax - ymin,
	        'kn_single': kn_single,
	        'kn_twist': kn_twist,
	        'dt': O.dt,
	        'dt_links': dt_links,
	        'mass_total': sum(O.bodies[b].state.mass for b in ids),
	        'A': area,
	        'curve': curve,
	}


def linked_count():
	"""Number of WirePM links still linked."""
	return sum(1 for i in O.interactions if isinstance(i.phys, WirePhys) and i.phys.isLinked)


def pull_force():
	"""Sum of the +y reactions [N] on the moving (top) row: minus the sum of the link forces on it."""
	return -sum(O.forces.f(b)[1] for b in _PANEL['top'])


def pull(velocity=0.05, max_elongation=None, record_every=100, stop_drop=0.2, max_steps=400000):
	"""Pulls the current panel: the top row moves at +velocity [m/s] along y, the bottom row stays.
	Runs O.step() until max_elongation [m] (None: 40 % of the panel height), or the force has dropped
	below stop_drop x peak after the peak, or max_steps.  Records every record_every steps.

	Returns {'curve': [(elongation [m], force [N], broken links)], 'peak_force' [N],
	'elongation_at_peak' [m], 'broken_links', 'steps', 'wall_s'}."""
	top = _PANEL['top']
	ys = [O.bodies[b].state.pos[1] for b in top]
	ybot = O.bodies[_PANEL['bottom'][0]].state.pos[1]
	if max_elongation is None:
		max_elongation = 0.4 * (ys[0] - ybot)
	for b in top:
		O.bodies[b].state.vel = Vector3(0, velocity, 0)
	y0 = O.bodies[top[0]].state.pos[1]
	n0 = linked_count()
	curve, peak, upeak = [], 0.0, 0.0
	t0 = time.perf_counter()
	steps = 0
	while steps < max_steps:
		for _ in range(record_every):
			O.step()
		steps += record_every
		u = O.bodies[top[0]].state.pos[1] - y0
		f = pull_force()
		broken = n0 - linked_count()
		curve.append((u, f, broken))
		if f > peak:
			peak, upeak = f, u
		if u >= max_elongation or (peak > 0 and f < stop_drop * peak and broken > 0):
			break
	for b in top:
		O.bodies[b].state.vel = Vector3(0, 0, 0)
	return {
	        'curve': curve,
	        'peak_force': peak,
	        'elongation_at_peak': upeak,
	        'broken_links': n0 - linked_count(),
	        'steps': steps,
	        'wall_s': time.perf_counter() - t0
	}


def time_per_link_step(n_steps=500, reps=5, warmup=50, velocity=0.05):
	"""Times the current panel while the top row moves at `velocity` [m/s] (links loaded), steps by
	run_steps, O.timingEnabled off.  Returns {'us_per_step': median, 'us_per_link_step': median / links,
	'us_per_step_all': [...], 'links': linked links, 'engines': {name: us/step} from one extra timed run}."""
	for b in _PANEL['top']:
		O.bodies[b].state.vel = Vector3(0, velocity, 0)
	O.timingEnabled = False
	for _ in range(warmup):
		O.step()
	wall = []
	for _ in range(reps):
		t0 = time.perf_counter()
		run_steps(n_steps)
		wall.append((time.perf_counter() - t0) / n_steps * 1e6)
	for e in O.engines:
		e.execTime = 0
	O.timingEnabled = True
	run_steps(n_steps)
	O.timingEnabled = False
	eng = {(e.label or e.__class__.__name__): e.execTime * 1e-3 / n_steps for e in O.engines}
	for b in _PANEL['top']:
		O.bodies[b].state.vel = Vector3(0, 0, 0)
	nl = linked_count()
	med = statistics.median(wall)
	return {'us_per_step': med, 'us_per_link_step': med / nl, 'us_per_step_all': wall, 'links': nl, 'interactions': len(O.interactions),
	        'engines': eng}


# ----------------------------------------------------------------------------------------------
# demo
# ----------------------------------------------------------------------------------------------
def _write_csv(path, header, rows):
	with open(path, 'w', newline='') as f:
		w = csv.writer(f)
		w.writerow(header)
		w.writerows(rows)


def _machine_line():
	"""'cpu model; cores; date; load average; YADE version, threads' for the results directory."""
	if BENCH_DIR not in sys.path:
		sys.path.insert(0, BENCH_DIR)
	from machine import machine_line
	return machine_line(yade.config.version, O.numThreads)


def main(n_steps=500, reps=5):
	res_dir = os.path.join(BENCH_DIR, 'results')
	os.makedirs(res_dir, exist_ok=True)
	with open(os.path.join(res_dir, 'builtin_wire_machine.txt'), 'w') as f:
		f.write(_machine_line())
	print('yade-flex bench: built-in WirePM reference, YADE %s, %d thread(s), %s' % (yade.config.version, O.numThreads, time.strftime('%Y-%m-%d %H:%M')))
	print('\n%-26s %6s %6s %9s %9s %9s %9s %10s %10s %8s %7s' %
	      ('case', 'nodes', 'links', 'kn_single', 'kn_twist', 'dt', 'us/step', 'us/link', 'peak F', 'u_peak', 'broken'))
	trows, crows = [], []
	for label, kw, do_pull in (
	        ('hexagonal type0 d3', dict(topology='hexagonal'), True),
	        ('hexagonal type2 d3', dict(topology='hexagonal', wire_type=2, lambda_F=0.7), True),
	        ('rhombic TECCO-like d3', dict(topology='rhombic', height=0.572), True),
	        ('hexagonal type0 3x1.5 m', dict(topology='hexagonal', width=3.0, height=1.5), False),
	):
		info = panel(**kw)
		t = time_per_link_step(n_steps, reps)
		if do_pull:
			info = panel(**kw)  # fresh panel for the pull
			p = pull(velocity=0.1, max_steps=600000)
		else:
			p = {'peak_force': float('nan'), 'elongation_at_peak': float('nan'), 'broken_links': 0, 'curve': [], 'steps': 0, 'wall_s': 0.0}
		print('%-26s %6d %6d %9.4g %9s %9.3g %9.1f %10.4f %10.1f %8.4f %7d' %
		      (label, info['nodes'], info['links'], info['kn_single'] or 0, ('%.4g' % info['kn_twist']) if info['kn_twist'] else '-', info['dt'],
		       t['us_per_step'], t['us_per_link_step'], p['peak_force'], p['elongation_at_peak'], p['broken_links']))
		print('    per-engine us/step: ' + ' '.join('%s=%.1f' % kv for kv in t['engines'].items()) +
		      '; pull: %d steps in %.1f s' % (p['steps'], p['wall_s']))
		trows.append([label, info['nodes'], info['links'], info['size_x'], info['size_y'], info['dt'], t['us_per_step'], t['us_per_link_step'],
		              ' '.join('%.1f' % x for x in t['us_per_step_all']), p['peak_force'], p['elongation_at_peak'], p['broken_links'],
		              O.numThreads])
		crows += [[label, u, f, br] for u, f, br in p['curve']]
		sys.stdout.flush()
	_write_csv(os.path.join(res_dir, 'builtin_wire_timing.csv'),
	           ['case', 'nodes', 'links', 'size_x_m', 'size_y_m', 'dt_s', 'us_per_step_median', 'us_per_link_step', 'us_per_step_all', 'peak_force_N',
	            'elongation_at_peak_m', 'broken_links', 'threads'], trows)
	_write_csv(os.path.join(res_dir, 'builtin_wire_pull.csv'), ['case', 'elongation_m', 'force_N', 'broken_links'], crows)


if __name__ == '__main__':
	main()
