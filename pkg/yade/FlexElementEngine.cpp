// yade-flex adapter: FlexElementEngine, the internal forces of all bonds and membranes
// (GPL-2.0-or-later). Declaration: FlexElementEngine.hpp.
#include "FlexElements.hpp"
#include "FlexLaws.hpp"
#include "FlexProtocol.hpp"
#include "speed/FlexTuning.hpp"
#include "FlexSceneCheck.hpp"
#include "FlexWire.hpp"

#include <kernel/Hook.hpp>
#include <kernel/Onset.hpp>

#include <lib/factory/ClassFactory.hpp>

#include <algorithm>
#include <limits>
#ifdef YADE_OPENMP
#include <omp.h>
#endif

namespace yade {

YADE_PLUGIN((FlexElementEngine));

void FlexElementEngine::refresh()
{
	cylinders.clear();
	facets.clear();
	for (const auto& b : *scene->bodies) {
		if (!b || !b->shape) continue;
		if (dynamic_cast<const FlexCylinder*>(b->shape.get()))
			cylinders.push_back(b->id);
		else if (dynamic_cast<const FlexFacet*>(b->shape.get()))
			facets.push_back(b->id);
	}
	// the cylinders' nodes, for the serial loop's force sums (one addForce per node, not per element end)
	slotOf.assign(scene->bodies->size(), -1);
	slotNode.clear();
	for (Body::id_t id : cylinders) {
		const FlexCylinder& c = static_cast<const FlexCylinder&>(*(*scene->bodies)[id]->shape);
		for (int nid : { c.node1, c.node2, c.hookNodes[0], c.hookNodes[1] }) // (the far nodes of a hooked knot's legs get its stop's forces)
			if (nid >= 0 && nid < (int)slotOf.size() && slotOf[nid] < 0) {
				slotOf[nid] = (int)slotNode.size();
				slotNode.push_back(nid);
			}
	}
	links.clear();
	for (Body::id_t id : cylinders)
		links.push_back(linkOf(scene, (*scene->bodies)[id].get()));
	cachedBodyCount = scene->bodies->size();
}

FlexElementEngine::Link FlexElementEngine::linkOf(const Scene* scene, const Body* b)
{
	Link L;
	if (!b || !b->state) return L;
	FlexCylinder* c = dynamic_cast<FlexCylinder*>(b->shape.get());
	if (!c) return L;
	const auto& body = scene->bodies->body;
	const long  nb   = (long)body.size();
	if (c->node1 < 0 || c->node2 < 0 || c->node1 >= nb || c->node2 >= nb) return L;
	const Body *bi = body[c->node1].get(), *bj = body[c->node2].get();
	if (!bi || !bj || !bi->state || !bj->state) return L;
	L.b  = b;
	L.c  = c;
	L.m  = b->material.get();
	L.se = b->state.get();
	L.bi = bi;
	L.bj = bj;
	L.si = bi->state.get();
	L.sj = bj->state.get();
	return L;
}

namespace {
	// The forces of one cylinder on its nodes, and its strain. A bond without bending or twist
	// stiffness (bendingFactor 0: a bar, or a truss link of a wire mesh) is axial only: no
	// rotations to compute and no moments (tests/kernel/test_beam.cpp: the same forces bit for bit
	// as the beam with EI = GJ = 0). ew: the wire curve's elastic modulus (flexa::wireAxial).
	flex::BeamForces cylinderForces(FlexCylinder& c, const FlexMat& mat, const State& si, const State& sj, Real ew, flex::AxialState& st, Real& strain)
	{
		const bool wire = mat.isWire();
		if (mat.bendingFactor == 0) {
			const flex::Chord ch = flex::chord(si.pos, sj.pos);
			strain               = (ch.L - c.L0) / c.L0; // (the strain divided out once, not twice)
			return flex::barForces(ch,
			        wire ? flexa::wireAxial(mat, c, strain, ew)
			             : flex::axialForce(strain, flexa::section(mat, c.radius).EA, c.L0, flexa::axialLaw(mat, c.radius), st));
		}
		flex::BeamRest rest;
		rest.L0                        = c.L0;
		rest.Qi                        = c.Q1;
		rest.Qj                        = c.Q2;
		const flex::BeamKinematics kin = flex::beamKinematics(si.pos, sj.pos, si.ori, sj.ori, rest);
		strain                         = (kin.L - c.L0) / c.L0;
		return wire ? flex::beamForcesWithAxial(kin, rest, flexa::section(mat, c.radius), flexa::wireAxial(mat, c, strain, ew))
		            : flex::beamForces(kin, rest, flexa::section(mat, c.radius), flexa::axialLaw(mat, c.radius), st);
	}

	// The serial loop's sums per node (accF, accM by slot) into the ForceContainer. Without
	// facets: the contact forces summed first (sync), the element forces then added to those sums
	// directly (addForce costs a thread lookup and a size check per call, and the integrator's
	// sync then has nothing left to do); with one thread each node's sum is the same bit for bit
	// (its contact forces, then its element force). A later engine's addForce marks the container
	// unsynced again and the integrator's sync adds it on top. With facets (facetForces adds with
	// addForce afterwards): addForce.
	void addNodeSums(Scene* scene, const std::vector<Body::id_t>& slotNode, const std::vector<Vector3r>& accF, const std::vector<Vector3r>& accM,
	        bool anyMoment, bool direct)
	{
		const shared_ptr<Body>* bodies  = scene->bodies->body.data();
		const long              nBodies = (long)scene->bodies->body.size();
		if (direct) {
			scene->forces.addMaxId((Body::id_t)nBodies - 1); // so that sync() sizes the sums to every body
			scene->forces.sync();
		}
		for (size_t i = 0; i < slotNode.size(); ++i) {
			if (!bodies[slotNode[i]]) continue;
			if (direct) {
				scene->forces.addForceUnsynced(slotNode[i], accF[i]);
				if (anyMoment) scene->forces.addTorqueUnsynced(slotNode[i], accM[i]);
			} else {
				scene->forces.addForce(slotNode[i], accF[i]);
				if (anyMoment) scene->forces.addTorque(slotNode[i], accM[i]);
			}
		}
	}

	// Energy held by a body's yade-flex contacts that carried a force this step: their normal and
	// shear springs (as the law books them in flexContactElastic)
	Real contactEnergyOf(const Body& b)
	{
		Real held = 0;
		for (const auto& kv : b.intrs) {
			const Interaction& I = *kv.second;
			if (!I.isReal()) continue;
			const auto* g = dynamic_cast<const FlexContactGeom*>(I.geom.get());
			const auto* p = dynamic_cast<const FrictPhys*>(I.phys.get());
			if (!g || !p || !g->active) continue;
			held += flex::normalSpring(p->kn, g->penetrationDepth, g->plasticOverlap, g->pierced).energy;
			if (p->ks > 0) held += 0.5 * p->shearForce.squaredNorm() / p->ks;
		}
		return held;
	}

	// The collider pairs of bonded neighbours the Ig2s reported this step, erased (FlexProtocol.hpp)
	void eraseNeighbourPairs(Scene* scene)
	{
		flexa::NeighbourPairs&      np = flexa::sceneState(scene).neighbourPairs;
		std::lock_guard<std::mutex> lock(np.m);
		if (np.pairs.empty()) return;
		for (const auto& pr : np.pairs) {
			const shared_ptr<Interaction> I = scene->interactions->find(pr.first, pr.second);
			if (I && !I->isReal()) scene->interactions->erase(pr.first, pr.second, I->linIx);
		}
		np.pairs.clear();
	}
} // namespace

// One step: the cylinders' forces, the membranes' forces, the threads' sums merged, the bonded
// neighbours' pairs erased, then the elements that ruptured this step erased.
void FlexElementEngine::action()
{
	flexa::checkScene(scene, this);
	if (scene->bodies->size() != cachedBodyCount) refresh(); // erased bodies are skipped below
	flexa::checkWireMaterials(scene);
	std::vector<Body::id_t> broken;
	// the smallest and largest node id added to the threads' sinks: their merge visits only these
	long sinkLo = std::numeric_limits<long>::max(), sinkHi = -1;
	prepareSinks();
	bondForces(broken, sinkLo, sinkHi);
	if (!facets.empty()) facetForces(broken, sinkLo, sinkHi);
	if (!sinks.empty()) flexa::mergeThreadSums(scene, sums, (int)sinks.size(), sinkHi < 0 ? 0 : sinkLo, sinkHi + 1);
	eraseNeighbourPairs(scene);
	if (!broken.empty()) rupture(broken);
}

// Element loops on several threads: their forces into each thread's own sums, added once per
// body after both loops (flexa::ThreadForceSums; addForce from two threads at once contends).
void FlexElementEngine::prepareSinks()
{
	sinks.clear();
#ifdef YADE_OPENMP
	if (((long)cylinders.size() >= parallelMin || (long)facets.size() >= parallelMin) && omp_get_max_threads() > 1) {
		const int threads = omp_get_max_threads();
		sums.prepare(threads, (long)scene->bodies->body.size());
		for (int t = 0; t < threads; ++t)
			sinks.push_back(sums.sink(t));
	}
#endif
}

// Every cylinder's bond forces (co-rotational beam or wire law, and a hooked knot's stop) to its
// nodes, its state written back, its energy booked; the ruptured ones into broken.
void FlexElementEngine::bondForces(std::vector<Body::id_t>& broken, long& lo, long& hi)
{
	long                    sinkLo = lo, sinkHi = hi; // (reduced over the threads)
	const long              n        = (long)cylinders.size();
	const bool              energy   = scene->trackEnergy;
	const Material*         lastMat  = nullptr; // elements mostly share a material: cast it once
	const FlexMat*          lastFlex = nullptr;
	Real                    lastEw   = 0;                          // its wire curve's elastic modulus (0: not a wire; see flexa::wireAxial)
	const shared_ptr<Body>* bodies   = scene->bodies->body.data(); // (indexed directly: BodyContainer::operator[] is an out-of-line call)
	const long              nBodies  = (long)scene->bodies->body.size();
	// energies summed here and booked once per step (not twice per element)
	Real eElastic = 0, ePlastic = 0, eReleased = 0;
	long nPlastic = 0;
	// Serial loop (below parallelMin, and always on one thread): forces and moments summed per
	// node here and added to the ForceContainer once per node (each addForce costs a thread
	// lookup and a size check)
	bool parallel = false;
#ifdef YADE_OPENMP
	parallel = n >= parallelMin && omp_get_max_threads() > 1;
#endif
	const bool serial = !parallel;
	const bool ahead  = serial && n >= flexa::kPrefetchMin;
	if (serial) accF.assign(slotNode.size(), Vector3r::Zero()); // (accM: at the first element with moments)
	bool anyMoment = false;
#ifdef YADE_OPENMP
#pragma omp parallel for schedule(static) if (parallel) firstprivate(lastMat, lastFlex, lastEw) reduction(+ : eElastic, ePlastic, nPlastic, eReleased) \
        reduction(min : sinkLo) reduction(max : sinkHi)
#endif
	for (long k = 0; k < n; ++k) {
		if (ahead && k + flexa::tuning::kAheadElements < n) { // the shape and node states of the element 4 ahead (from the table: no chain;
			                                              // serial only: in the parallel loop another thread may be rewriting it)
			const Link& A = links[k + flexa::tuning::kAheadElements];
			flexa::prefetch(A.c, sizeof(FlexCylinder));
			if (A.si) flexa::prefetch(&A.si->pos, sizeof(Vector3r));
			if (A.sj) flexa::prefetch(&A.sj->pos, sizeof(Vector3r));
		}
		const Body::id_t id = cylinders[k];
		Body*            b  = bodies[id].get();
		if (!b) continue;
		Link& lk = links[k];
		// the table checked against the bodies (each pointer compared only once the one it was read
		// from is known to be current); looked up again if anything was replaced
		const bool current = b == lk.b && b->shape.get() == lk.c && b->material.get() == lk.m && b->state.get() == lk.se && lk.c->node1 >= 0
		        && lk.c->node1 < nBodies && lk.c->node2 >= 0 && lk.c->node2 < nBodies && bodies[lk.c->node1].get() == lk.bi
		        && bodies[lk.c->node2].get() == lk.bj && lk.bi->state.get() == lk.si && lk.bj->state.get() == lk.sj;
		if (!current) lk = linkOf(scene, b);
		if (!lk.c) continue;
		FlexCylinder& c = *lk.c;
		if (!c.attached) continue;
		if (lk.m != lastMat) {
			lastMat  = lk.m;
			lastFlex = dynamic_cast<const FlexMat*>(lastMat);
			lastEw   = lastFlex && lastFlex->isWire() ? flexa::wireModulus(*lastFlex) : 0;
		}
		const FlexMat* mat = lastFlex;
		if (!mat) continue;
		State *          si = lk.si, *sj = lk.sj;
		const bool       wire = mat->isWire();
		const bool       bar  = mat->bendingFactor == 0;
		flex::AxialState st { c.plasticStrain, c.hardeningVar };
		Real             strain;
		flex::BeamForces f = cylinderForces(c, *mat, *si, *sj, lastEw, st, strain);
		// a hooked knot's stop (FlexCylinder.hookNodes; kernel/Hook.hpp): forces on the link's nodes
		// and on the far nodes of node1's legs (hookFa each; only on the few links with a stop)
		bool     hooked = false;
		Vector3r hookFa;
		if (c.hookStiffness > 0) {
			const State *          sa = flexa::stateOf(scene, c.hookNodes[0]), *sb = flexa::stateOf(scene, c.hookNodes[1]);
			const flex::HookForces hook
			        = sa && sb ? flex::hookForces(si->pos, sj->pos, sa->pos, sb->pos, c.hookGap, c.hookStiffness) : flex::HookForces();
			if (hook.released) { // its bend was pulled straight: let go for good, the energy it held to flexRupture
				c.hookStiffness = 0;
				eReleased += hook.releasedEnergy;
			}
			c.hookForce = hook.force;
			hooked      = hook.force > 0;
			hookFa      = hook.Fa;
			f.Fi += hook.Fi;
			f.Fj += hook.Fj;
			f.elasticEnergy += hook.energy;
		}
		if (!wire) {
			c.plasticStrain = st.plasticStrain;
			c.hardeningVar  = st.hardeningVar;
		}
		c.axialForce    = f.N;
		c.strain        = strain;
		c.elasticEnergy = f.elasticEnergy;
		const int s1 = serial ? slotOf[c.node1] : -1, s2 = serial ? slotOf[c.node2] : -1;
		const int sa1 = serial && hooked ? slotOf[c.hookNodes[0]] : -1, sa2 = serial && hooked ? slotOf[c.hookNodes[1]] : -1;
		if (s1 >= 0 && s2 >= 0 && (!hooked || (sa1 >= 0 && sa2 >= 0))) {
			accF[s1] += f.Fi;
			accF[s2] += f.Fj;
			if (hooked) {
				accF[sa1] += hookFa;
				accF[sa2] += hookFa;
			}
			if (!bar) {
				if (!anyMoment) { // (zeroed only on steps with moments: bar meshes have none)
					accM.assign(slotNode.size(), Vector3r::Zero());
					anyMoment = true;
				}
				accM[s1] += f.Mi;
				accM[s2] += f.Mj;
			}
		} else {
			const flexa::ForceSink* sk = nullptr;
#ifdef YADE_OPENMP
			if (!sinks.empty()) sk = &sinks[omp_get_thread_num()];
#endif
			if (sk) {
				sinkLo = std::min(sinkLo, (long)std::min(c.node1, c.node2));
				sinkHi = std::max(sinkHi, (long)std::max(c.node1, c.node2));
			}
			flexa::addForce(scene, sk, c.node1, f.Fi);
			flexa::addForce(scene, sk, c.node2, f.Fj);
			if (hooked) {
				if (sk) {
					sinkLo = std::min(sinkLo, (long)std::min(c.hookNodes[0], c.hookNodes[1]));
					sinkHi = std::max(sinkHi, (long)std::max(c.hookNodes[0], c.hookNodes[1]));
				}
				flexa::addForce(scene, sk, c.hookNodes[0], hookFa);
				flexa::addForce(scene, sk, c.hookNodes[1], hookFa);
			}
			if (!bar) {
				flexa::addTorque(scene, sk, c.node1, f.Mi);
				flexa::addTorque(scene, sk, c.node2, f.Mj);
			}
		}
		// the element body follows its nodes (output, display; it has no DOF)
		lk.se->pos = 0.5 * (si->pos + sj->pos);
		lk.se->vel = 0.5 * (si->vel + sj->vel);
		if (energy) {
			// a breaking element's stored energy goes to flexRupture (below), not here too: counted
			// in both, the balance showed it twice for the one step of the rupture
			if (!f.rupture) eElastic += f.elasticEnergy;
			if (f.plasticWork != 0) {
				ePlastic += f.plasticWork;
				++nPlastic;
			}
		}
		if (f.rupture) {
#ifdef YADE_OPENMP
#pragma omp critical(flexRupture)
#endif
			broken.push_back(id);
		}
	}
	if (serial && !slotNode.empty()) addNodeSums(scene, slotNode, accF, accM, anyMoment, facets.empty());
	if (energy && n > 0) {
		flexa::addEnergy(scene, eElastic, "flexBondElastic", elastIx, true);
		if (nPlastic) flexa::addEnergy(scene, ePlastic, "flexBondPlastic", plastIx, false);
		if (eReleased != 0) flexa::addEnergy(scene, eReleased, "flexRupture", ruptIx, false);
	}
	lo = sinkLo;
	hi = sinkHi;
}

// The elements that ruptured this step erased with their bodies (their nodes keep their mass):
// the energy they and their contacts held booked to flexRupture, hooked knots on them let go.
void FlexElementEngine::rupture(std::vector<Body::id_t>& broken)
{
	const bool energy = scene->trackEnergy;
	std::sort(broken.begin(), broken.end()); // same order whatever the thread count
	for (Body::id_t id : broken) {
		const flexa::Element e = flexa::elementOf(scene, id);
		// the element's stored energy is released at rupture (elastic waves we do not resolve)
		if (energy) {
			flexa::addEnergy(scene, e.cyl ? e.cyl->elasticEnergy : e.fac->elasticEnergy, "flexRupture", ruptIx, false);
			// so does the energy held by the contacts that go with it (their springs were booked in
			// flexContactElastic this step: moved, so that the step's balance counts them once)
			const Real held = contactEnergyOf(*(*scene->bodies)[id]);
			if (held != 0) {
				flexa::addEnergy(scene, held, "flexRupture", ruptIx, false);
				flexa::addEnergy(scene, -held, "flexContactElastic", contactIx, true);
			}
		}
		if (e.cyl) releaseHooks(*e.cyl, energy);
		for (int k = 0; k < e.nNodes; ++k) {
			const int nid = e.nodes[k];
			if (!(*scene->bodies)[nid]) continue;
			auto& el = static_cast<FlexNode&>(*(*scene->bodies)[nid]->shape).elements;
			el.erase(std::remove(el.begin(), el.end(), id), el.end());
		}
		rupturedBodies.push_back((*scene->bodies)[id]); // released with the engine (see FlexElementEngine.hpp)
		scene->bodies->erase(id, false);                // erases its interactions too: no ghost element
		++flexa::sceneState(scene).elementErasures;
		rupturedIds.push_back(id);
		++nRuptured;
	}
	refresh();
}

void FlexElementEngine::releaseHooks(const FlexCylinder& leg, bool energy)
{
	// a hooked knot whose bend (node1) loses this leg lets go for good: its bend no longer opens
	// between two legs; the energy its stop held goes to flexRupture with the leg's
	for (int end = 0; end < 2; ++end) {
		const int       apex = end ? leg.node2 : leg.node1, far = end ? leg.node1 : leg.node2;
		const Body*     nb   = flexa::bodyAt(scene, apex);
		const FlexNode* node = nb ? flexa::fastCast<FlexNode>(nb->shape.get()) : nullptr;
		if (!node) continue;
		for (int eid : node->elements) {
			const Body*   b = flexa::bodyAt(scene, eid);
			FlexCylinder* c = b ? const_cast<FlexCylinder*>(flexa::fastCast<FlexCylinder>(b->shape.get())) : nullptr;
			if (!c || !(c->hookStiffness > 0) || c->node1 != apex || (c->hookNodes[0] != far && c->hookNodes[1] != far)) continue;
			if (energy) { // (its energy is in this step's flexBondElastic: moved, as a breaking bond's is)
				const Real v = 0.5 * c->hookForce * c->hookForce / c->hookStiffness;
				flexa::addEnergy(scene, -v, "flexBondElastic", elastIx, true);
				flexa::addEnergy(scene, v, "flexRupture", ruptIx, false);
			}
			c->hookStiffness = 0;
			c->hookForce     = 0;
		}
	}
}

void FlexElementEngine::facetForces(std::vector<Body::id_t>& broken, long& lo, long& hi)
{
	long                    sinkLo = lo, sinkHi = hi;
	const bool              energy  = scene->trackEnergy;
	const Material*         lastMat = nullptr;
	const FlexMembraneMat*  mat     = nullptr;
	flex::MembraneLaw       law;
	const shared_ptr<Body>* bodies = scene->bodies->body.data();
	const Real              dt     = scene->dt;
	const long              n      = (long)facets.size();
	Real                    eMemb = 0, ePress = 0;
	long                    nPress = 0;
#ifdef YADE_OPENMP
#pragma omp parallel for schedule(static) if (n >= parallelMin) firstprivate(lastMat, mat, law) reduction(+ : eMemb, ePress, nPress) \
        reduction(min : sinkLo) reduction(max : sinkHi)
#endif
	for (long k = 0; k < n; ++k) {
		const Body::id_t id = facets[k];
		Body*            b  = bodies[id].get();
		if (!b) continue;
		FlexFacet& f = static_cast<FlexFacet&>(*b->shape);
		if (!f.attached) continue;
		if (b->material.get() != lastMat) {
			lastMat = b->material.get();
			mat     = dynamic_cast<const FlexMembraneMat*>(lastMat);
			if (mat) law = flexa::membraneLaw(*mat);
		}
		const int ids[3] = { f.node1, f.node2, f.node3 };
		State*    s[3];
		bool      ok = mat != nullptr;
		for (int a = 0; a < 3 && ok; ++a)
			ok = bodies[ids[a]] && (s[a] = bodies[ids[a]]->state.get());
		if (!ok) continue;
		const Vector3r             x[3] = { s[0]->pos, s[1]->pos, s[2]->pos };
		const flex::MembraneResult r    = flex::membraneForces(x, flexa::membraneRest(f), law);
		f.n1                            = r.n1;
		f.n2                            = r.n2;
		f.e1                            = r.e1;
		f.e2                            = r.e2;
		f.elasticEnergy                 = r.energy;
		Vector3r fp                     = Vector3r::Zero();
		if (f.pressure != 0) // follower pressure: p A n / 3 on each node, A n = (x2-x1)x(x3-x1)/2
			fp = f.pressure * (x[1] - x[0]).cross(x[2] - x[0]) / 6;
		const flexa::ForceSink* sk = nullptr;
#ifdef YADE_OPENMP
		if (!sinks.empty() && n >= parallelMin) sk = &sinks[omp_get_thread_num()];
#endif
		for (int a = 0; a < 3; ++a) {
			if (sk) {
				sinkLo = std::min(sinkLo, (long)ids[a]);
				sinkHi = std::max(sinkHi, (long)ids[a]);
			}
			flexa::addForce(scene, sk, ids[a], r.f[a] + fp);
		}
		b->state->pos = (x[0] + x[1] + x[2]) / 3;
		b->state->vel = (s[0]->vel + s[1]->vel + s[2]->vel) / 3;
		if (energy) {
			if (!r.rupture) eMemb += r.energy; // a breaking facet's energy goes to flexRupture (as the cylinders')
			// work done BY the pressure, booked with the opposite sign like YADE's gravWork
			if (f.pressure != 0) {
				ePress += -fp.dot(s[0]->vel + s[1]->vel + s[2]->vel) * dt;
				++nPress;
			}
		}
		if (r.rupture) {
#ifdef YADE_OPENMP
#pragma omp critical(flexRupture)
#endif
			broken.push_back(id);
		}
	}
	if (energy && n > 0) {
		flexa::addEnergy(scene, eMemb, "flexMembraneElastic", membIx, true);
		if (nPress) flexa::addEnergy(scene, ePress, "flexPressureWork", pressIx, false);
	}
	lo = sinkLo;
	hi = sinkHi;
}

} // namespace yade
