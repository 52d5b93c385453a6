// yade-flex adapter: element forces and the time stepper (GPL-2.0-or-later).
#include "FlexCommon.hpp"
#include "FlexSceneCheck.hpp"
#include "FlexWire.hpp"

#include <core/Clump.hpp>
#include <core/InteractionLoop.hpp>
#include <pkg/common/InsertionSortCollider.hpp>
#include <lib/factory/ClassFactory.hpp>
#include <pkg/common/NormShearPhys.hpp>

#include <algorithm>
#ifdef YADE_OPENMP
#include <omp.h>
#endif

namespace yade {

YADE_PLUGIN((FlexElementEngine)(FlexTimeStepper)(FlexNewtonIntegrator));

void FlexElementEngine::refresh()
{
	cylinders.clear();
	facets.clear();
	for (const auto& b : *scene->bodies) {
		if (!b || !b->shape) continue;
		if (dynamic_cast<const FlexCylinder*>(b->shape.get())) cylinders.push_back(b->id);
		else if (dynamic_cast<const FlexFacet*>(b->shape.get()))
			facets.push_back(b->id);
	}
	// the cylinders' nodes, for the serial loop's force sums (one addForce per node, not per element end)
	slotOf.assign(scene->bodies->size(), -1);
	slotNode.clear();
	for (Body::id_t id : cylinders) {
		const FlexCylinder& c = static_cast<const FlexCylinder&>(*(*scene->bodies)[id]->shape);
		for (int nid : { c.node1, c.node2 })
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
	L.b   = b;
	L.c   = c;
	L.m   = b->material.get();
	L.se  = b->state.get();
	L.bi  = bi;
	L.bj  = bj;
	L.si  = bi->state.get();
	L.sj  = bj->state.get();
	return L;
}

void FlexElementEngine::action()
{
	flexa::checkScene(scene);
	if (scene->bodies->size() != cachedBodyCount) refresh(); // erased bodies are skipped below
	flexa::checkWireMaterials(scene);
	const long              n = (long)cylinders.size();
	std::vector<Body::id_t> broken;
	const bool              energy = scene->trackEnergy;
	const Material* lastMat  = nullptr; // elements mostly share a material: cast it once
	const FlexMat*  lastFlex = nullptr;
	Real            lastEw   = 0; // its wire curve's elastic modulus (0: not a wire; see flexa::wireAxial)
	const shared_ptr<Body>* bodies   = scene->bodies->body.data(); // (indexed directly: BodyContainer::operator[] is an out-of-line call)
	const long              nBodies  = (long)scene->bodies->body.size();
	// energies summed here and booked once per step (not twice per element)
	Real eElastic = 0, ePlastic = 0;
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
	// element loops on several threads: their forces into each thread's own sums, added once per
	// body after both loops (flexa::ThreadForceSums; addForce from two threads at once contends)
	sinks.clear();
#ifdef YADE_OPENMP
	if ((parallel || (long)facets.size() >= parallelMin) && omp_get_max_threads() > 1) {
		const int threads = omp_get_max_threads();
		sums.prepare(threads, nBodies);
		for (int t = 0; t < threads; ++t)
			sinks.push_back(sums.sink(t));
	}
#endif
	if (serial) accF.assign(slotNode.size(), Vector3r::Zero()); // (accM: at the first element with moments)
	bool anyMoment = false;
#ifdef YADE_OPENMP
#pragma omp parallel for schedule(static) if (parallel) firstprivate(lastMat, lastFlex, lastEw) reduction(+ : eElastic, ePlastic, nPlastic)
#endif
	for (long k = 0; k < n; ++k) {
		if (ahead && k + 4 < n) { // the shape and node states of the element 4 ahead (from the table: no chain;
			                           // serial only: in the parallel loop another thread may be rewriting it)
			const Link& A = links[k + 4];
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
		const bool current = b == lk.b && b->shape.get() == lk.c && b->material.get() == lk.m && b->state.get() == lk.se
		        && lk.c->node1 >= 0 && lk.c->node1 < nBodies && lk.c->node2 >= 0 && lk.c->node2 < nBodies
		        && bodies[lk.c->node1].get() == lk.bi && bodies[lk.c->node2].get() == lk.bj && lk.bi->state.get() == lk.si
		        && lk.bj->state.get() == lk.sj;
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
		State *si = lk.si, *sj = lk.sj;
		const bool       wire = mat->isWire();
		flex::AxialState st { c.plasticStrain, c.hardeningVar };
		flex::BeamForces f;
		Real             L, strain; // (the strain divided out once, not twice)
		// a bond without bending or twist stiffness (bendingFactor 0: a bar, or a truss link of a
		// wire mesh) is axial only: no rotations to compute and no moments (tests/kernel/test_beam.cpp:
		// the same forces bit for bit as the beam with EI = GJ = 0)
		const bool bar = mat->bendingFactor == 0;
		if (bar) {
			const flex::Chord ch = flex::chord(si->pos, sj->pos);
			L                    = ch.L;
			strain               = (L - c.L0) / c.L0;
			f = flex::barForces(ch, wire ? flexa::wireAxial(*mat, c, strain, lastEw) : flex::axialForce(strain, flexa::section(*mat, c.radius).EA, c.L0, flexa::axialLaw(*mat, c.radius), st));
		} else {
			flex::BeamRest rest;
			rest.L0                        = c.L0;
			rest.Qi                        = c.Q1;
			rest.Qj                        = c.Q2;
			const flex::BeamKinematics kin = flex::beamKinematics(si->pos, sj->pos, si->ori, sj->ori, rest);
			L                              = kin.L;
			strain                         = (L - c.L0) / c.L0;
			f                              = wire ? flex::beamForcesWithAxial(kin, rest, flexa::section(*mat, c.radius), flexa::wireAxial(*mat, c, strain, lastEw))
			                                      : flex::beamForces(kin, rest, flexa::section(*mat, c.radius), flexa::axialLaw(*mat, c.radius), st);
		}
		if (!wire) {
			c.plasticStrain = st.plasticStrain;
			c.hardeningVar  = st.hardeningVar;
		}
		c.axialForce    = f.N;
		c.strain        = strain;
		c.elasticEnergy = f.elasticEnergy;
		const int s1 = serial ? slotOf[c.node1] : -1, s2 = serial ? slotOf[c.node2] : -1;
		if (s1 >= 0 && s2 >= 0) {
			accF[s1] += f.Fi;
			accF[s2] += f.Fj;
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
			flexa::addForce(scene, sk, c.node1, f.Fi);
			flexa::addForce(scene, sk, c.node2, f.Fj);
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
	if (serial && !slotNode.empty()) {
		if (facets.empty()) {
			// The contact forces summed first (ForceContainer::sync), the element forces then added
			// to those sums directly: addForce costs a thread lookup and a size check per call, and
			// the integrator's sync then has nothing left to do. With one thread each node's sum is
			// the same bit for bit (its contact forces, then its element force); with several, the
			// threads' contact sums are added before the element force instead of after. A later
			// engine's addForce marks the container unsynced again and the integrator's sync adds
			// it on top, as before. (With facets, facetForces below adds with addForce: kept.)
			scene->forces.addMaxId((Body::id_t)nBodies - 1); // so that sync() sizes the sums to every body
			scene->forces.sync();
			for (size_t i = 0; i < slotNode.size(); ++i) {
				if (!bodies[slotNode[i]]) continue;
				scene->forces.addForceUnsynced(slotNode[i], accF[i]);
				if (anyMoment) scene->forces.addTorqueUnsynced(slotNode[i], accM[i]);
			}
		} else
			for (size_t i = 0; i < slotNode.size(); ++i) {
				if (!bodies[slotNode[i]]) continue;
				scene->forces.addForce(slotNode[i], accF[i]);
				if (anyMoment) scene->forces.addTorque(slotNode[i], accM[i]);
			}
	}
	if (energy && n > 0) {
		flexa::addEnergy(scene, eElastic, "flexBondElastic", elastIx, true);
		if (nPlastic) flexa::addEnergy(scene, ePlastic, "flexBondPlastic", plastIx, false);
	}
	if (!facets.empty()) facetForces(broken);
	if (!sinks.empty()) flexa::mergeThreadSums(scene, sums, (int)sinks.size());
	{ // erase the collider pairs of bonded neighbours reported by the Ig2 (see FlexCommon.hpp)
		flexa::NeighbourPairs&      np = flexa::neighbourPairs();
		std::lock_guard<std::mutex> lock(np.m);
		if (np.scene == scene && !np.pairs.empty()) {
			for (const auto& pr : np.pairs) {
				const shared_ptr<Interaction> I = scene->interactions->find(pr.first, pr.second);
				if (I && !I->isReal()) scene->interactions->erase(pr.first, pr.second, I->linIx);
			}
			np.pairs.clear();
		}
	}
	if (broken.empty()) return;
	std::sort(broken.begin(), broken.end()); // same order whatever the thread count
	for (Body::id_t id : broken) {
		const flexa::Element e = flexa::elementOf(scene, id);
		// the element's stored energy is released at rupture (elastic waves we do not resolve)
		if (energy) flexa::addEnergy(scene, e.cyl ? e.cyl->elasticEnergy : e.fac->elasticEnergy, "flexRupture", ruptIx, false);
		for (int k = 0; k < e.nNodes; ++k) {
			const int nid = e.nodes[k];
			if (!(*scene->bodies)[nid]) continue;
			auto& el = static_cast<FlexNode&>(*(*scene->bodies)[nid]->shape).elements;
			el.erase(std::remove(el.begin(), el.end(), id), el.end());
		}
		rupturedBodies.push_back((*scene->bodies)[id]); // released with the engine (see Flex.hpp)
		scene->bodies->erase(id, false); // erases its interactions too: no ghost element
		++flexa::elementErasures();
		rupturedIds.push_back(id);
		++nRuptured;
	}
	refresh();
}

void FlexElementEngine::facetForces(std::vector<Body::id_t>& broken)
{
	const bool      energy   = scene->trackEnergy;
	const Material* lastMat  = nullptr;
	const FlexMembraneMat* mat = nullptr;
	flex::MembraneLaw      law;
	const shared_ptr<Body>* bodies = scene->bodies->body.data();
	const Real             dt     = scene->dt;
	const long             n      = (long)facets.size();
	Real eMemb = 0, ePress = 0;
	long nPress = 0;
#ifdef YADE_OPENMP
#pragma omp parallel for schedule(static) if (n >= parallelMin) firstprivate(lastMat, mat, law) reduction(+ : eMemb, ePress, nPress)
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
		for (int a = 0; a < 3; ++a)
			flexa::addForce(scene, sk, ids[a], r.f[a] + fp);
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
}

Real FlexTimeStepper::omega2Bonds() const
{
	// Irons' bound with the element's own mass shares. If a node is lighter than the sum of
	// the shares attached to it (user-modified mass), scale that element's omega^2 up.
	auto&             bodies = *scene->bodies;
	std::vector<Real> sumM(bodies.size(), 0), sumI(bodies.size(), 0);
	struct Share {
		const flexa::Element e;
		Real                 m, I, w2;
		Body::id_t           id;
	};
	std::vector<Share> shares;
	const shared_ptr<Body>* body = bodies.body.data();
	const long              nb   = (long)bodies.body.size();
	for (long id = 0; id < nb; ++id) {
		// the bodies and their shapes ahead (without, each waited on its shape's type)
		flexa::prefetchBodiesAhead(body, nb, id, [](const Body& c) { flexa::prefetch(c.shape.get(), sizeof(Sphere)); });
		const shared_ptr<Body>& b = body[id];
		if (!b || !b->shape) continue;
		const flexa::Element e = flexa::elementOf(b->shape.get());
		if (e.cyl && e.cyl->attached) shares.push_back({ e, e.cyl->massShare, e.cyl->inertiaShare, e.cyl->omega2, b->id });
		else if (e.fac && e.fac->attached) {
			// a stretched membrane is stiffer than at rest (FlexFacet.omega2): scale by the bound
			// of its tangent stiffness at the strains FlexElementEngine computed this step
			const FlexMembraneMat* mat = flexa::fastCast<FlexMembraneMat>(b->material.get());
			const Real             f   = mat ? flex::membraneStretchFactor(e.fac->e1, e.fac->e2, flexa::membraneLaw(*mat)) : 1;
			shares.push_back({ e, e.fac->massShare, e.fac->inertiaShare, e.fac->omega2 * f, b->id });
		}
	}
	for (const Share& sh : shares)
		for (int k = 0; k < sh.e.nNodes; ++k) {
			sumM[sh.e.nodes[k]] += sh.m;
			sumI[sh.e.nodes[k]] += sh.I;
		}
	Real w2          = 0;
	stiffestBondBody = -1;
	for (const Share& sh : shares) {
		bool moves = false; // an element whose nodes are all clamped has no mode of its own
		for (int k = 0; k < sh.e.nNodes && !moves; ++k) {
			const shared_ptr<Body>& nb = bodies[sh.e.nodes[k]];
			moves = nb && nb->isDynamic() && nb->state->blockedDOFs != State::DOF_ALL;
		}
		if (!moves) continue;
		Real scale = 1;
		for (int k = 0; k < sh.e.nNodes; ++k) {
			const int               nid = sh.e.nodes[k];
			const shared_ptr<Body>& nb  = bodies[nid];
			if (!nb || !nb->isDynamic()) continue;
			const State& s = *nb->state;
			if (s.mass > 0) scale = std::max(scale, sumM[nid] / s.mass);
			const Real I = s.inertia.minCoeff();
			if (I > 0) scale = std::max(scale, sumI[nid] / I);
		}
		if (sh.w2 * scale > w2) {
			w2                = sh.w2 * scale;
			stiffestBondBody = sh.id;
		}
	}
	return w2;
}

namespace {
	// Interactions from which FlexTimeStepper's pass over them runs on every OpenMP thread
	// (below, starting the threads costs more than they save)
	constexpr long kParallelStepperMin = 4096;

	// What the time step needs of one body, gathered once per estimate (dynamic_casts and
	// shared_ptr hops once per body instead of once per interaction side).
	struct StepBody {
		Real            invSqrtMass = 0; // 1/sqrt(m); 0: no row of its own, infinite mass to others
		Real            Imin        = 0; // smallest principal inertia of a dynamic body, else 0
		Real            radius      = -1; // contact radius (sphere, cylinder, facet), -1: Ip2 takes the other side's
		Real            kappa       = 0; // facet: triangle load factor - 1 (see triangleLoadFactor)
		const FrictMat* mat         = nullptr;
		bool            sphere      = false; // a Sphere shape (clump members too)
		bool            shaped      = false; // the body exists and has a shape
		flexa::Element  el;
	};

	std::vector<StepBody> stepBodies(const Scene* scene)
	{
		const auto&           bodies = *scene->bodies;
		const shared_ptr<Body>* body = bodies.body.data(); // (BodyContainer::operator[] is an out-of-line call)
		const long              n    = (long)bodies.body.size();
		std::vector<StepBody>   out(n);
		const Material*         lastMat   = nullptr;
		const FrictMat*         lastFrict = nullptr;
		for (long id = 0; id < n; ++id) {
			// the bodies and their states and shapes ahead (without, it waited on each body's
			// state, 12% of the estimate)
			flexa::prefetchBodiesAhead(body, n, id, [](const Body& c) {
				flexa::prefetch(c.state.get(), sizeof(State));
				flexa::prefetch(c.shape.get(), sizeof(Sphere));
			});
			const shared_ptr<Body>& b = body[id];
			if (!b) continue;
			StepBody& s = out[id];
			if (b->isDynamic()) {
				const State& st = *b->state;
				if (st.mass > 0 && st.blockedDOFs != State::DOF_ALL) s.invSqrtMass = 1 / std::sqrt(st.mass);
				s.Imin = st.inertia.minCoeff();
			}
			const Material* m = b->material.get();
			if (m != lastMat) { // bodies share materials: one cast per run of equal materials
				lastMat   = m;
				lastFrict = flexa::fastCast<FrictMat>(m);
			}
			s.mat = lastFrict;
			if (!b->shape) continue;
			s.shaped = true;
			// a node (no contact radius, no element): told by its exact type first, which a
			// failed cast to Sphere took a dynamic_cast to find (one per node and estimate)
			if (typeid(*b->shape) == typeid(FlexNode)) continue;
			if (const Sphere* sp = flexa::fastCast<Sphere>(b->shape.get())) {
				s.radius = sp->radius;
				s.sphere = true;
			} else {
				s.el = flexa::elementOf(b->shape.get());
				if (s.el.nNodes) s.radius = s.el.radius;
				if (s.el.fac) {
					Vector3r x[3];
					bool     ok = true;
					for (int a = 0; a < 3 && ok; ++a) {
						const State* st = flexa::stateOf(scene, s.el.nodes[a]);
						if ((ok = st != nullptr)) x[a] = st->pos;
					}
					s.kappa = ok ? flex::triangleLoadFactor(x, s.el.radius) - 1 : 0;
				}
			}
		}
		return out;
	}
}

Real FlexTimeStepper::omega2Contacts() const { return omega2ContactsImpl(nullptr, false); }

boost::python::list FlexTimeStepper::unreachablePairs() const
{
	std::vector<std::pair<Body::id_t, Body::id_t>> out;
	omega2ContactsImpl(&out, false);
	boost::python::list l;
	for (const auto& pr : out)
		l.append(boost::python::make_tuple(pr.first, pr.second));
	return l;
}

Real FlexTimeStepper::omega2ContactsImpl(std::vector<std::pair<Body::id_t, Body::id_t>>* skippedOut, bool mark) const
{
	// Gershgorin rows of M^-1/2 K M^-1/2 for all contact springs. A contact couples the
	// entries g = (-w on side 1, +w on side 2) with stiffness k = max(kn, ks) in any
	// direction; row a collects k |g_a|/sqrt(m_a) * sum_b |g_b|/sqrt(m_b). Rotations: the
	// shear spring at lever l on inertia I gives k_s l^2 / I per side, doubled for coupling.
	// Potential contacts (bounds overlap, no contact yet) count too, with the stiffness
	// Ip2_FrictMat_FrictMat_FrictPhys will give them and, for each row, the worst weight over
	// the contact's position on an element (u = 0 or 1): a contact appearing between two
	// updates must not find a step that is already too long for it (it would run unstable from
	// its first step: measured in the wire-and-ring demo).
	const std::vector<StepBody> sb = stepBodies(scene);
	const Body::id_t            nb = (Body::id_t)sb.size();
	std::vector<Real>           row(sb.size(), 0), rowRot(sb.size(), 0);
	auto invSqrtMass = [&](Body::id_t id) -> Real { return (id < 0 || id >= nb) ? 0 : sb[id].invSqrtMass; };
	// (rows: the thread's own row sums, see the parallel loop below)
	auto addRot = [&](Real* rot, Body::id_t id, Real ks, Real w, Real lever) {
		const Real Imin = sb[id].Imin;
		if (Imin > 0 && std::isfinite(lever)) rot[id] += 2 * ks * std::abs(w) * lever * lever / Imin;
	};
	// the contact law, for rolling resistance between spheres (a rotational spring kr)
	const Law2_FlexContactGeom_FrictPhys_CundallStrack* law = nullptr;
	for (const auto& e : scene->engines)
		if (const InteractionLoop* il = dynamic_cast<const InteractionLoop*>(e.get()))
			for (const auto& f : il->lawDispatcher->functors)
				if (!law) law = dynamic_cast<const Law2_FlexContactGeom_FrictPhys_CundallStrack*>(f.get());
	// Potential pairs that cannot touch before the collider runs again are left out: the collider
	// re-runs once a point leaves the sweep box of its bound, and this estimate is then made again
	// before the integrator uses the step (see flex::cannotTouch). Only with an
	// InsertionSortCollider (the guarantee is its trigger) and for shapes whose points are known:
	// spheres (clump members too) and elements; everything else counts as before.
	bool canSkip = skipUnreachable && !scene->isPeriodic; // (the gaps below ignore periodic images)
	if (canSkip) {
		canSkip = false;
		for (const auto& e : scene->engines)
			if (dynamic_cast<const InsertionSortCollider*>(e.get())) canSkip = true;
	}
	long skipped = 0;
	// the skipped pairs are also marked for the geometry functors (flexa::UnreachableMarks)
	flexa::UnreachableMarks& marks = flexa::unreachableMarks();
	if (mark) {
		marks.scene = nullptr;
		++marks.generation;
		marks.pair.assign(scene->interactions->size(), std::make_pair(Body::id_t(-1), Body::id_t(-1)));
	}
	// the defining points of a body (sphere centre, element nodes) and how far they may still
	// travel before the collider runs; false: unknown (no bound yet, another shape)
	// per body, once per estimate (on first use): its points, how far they may still travel, and
	// the size of their coordinates (for the round-off margin)
	struct Side {
		signed char state = 0; // 0: not computed yet, 1: known, -1: unknown
		int         n     = 0;
		Real        reach = 0, size = 0;
		Vector3r    x[3];
	};
	std::vector<Side> sides(canSkip ? sb.size() : 0);
	auto              sideOf = [&](Body::id_t id) -> const Side& {
                Side& sd = sides[id];
                if (sd.state) return sd;
                sd.state      = -1;
                const Body* b = scene->bodies->body[id].get();
                if (!b || !b->bound) return sd;
                const Real            sweep = b->bound->sweepLength;
                const flexa::Element& el    = sb[id].el;
                if (el.nNodes) {
                        const Vector3r* ref[3] { nullptr, nullptr, nullptr };
                        if (el.cyl) {
                                ref[0] = &el.cyl->boundRef1;
                                ref[1] = &el.cyl->boundRef2;
                        } else {
                                ref[0] = &el.fac->boundRef1;
                                ref[1] = &el.fac->boundRef2;
                                ref[2] = &el.fac->boundRef3;
                        }
                        for (int a = 0; a < el.nNodes; ++a) {
                                const State* st = flexa::stateOf(scene, el.nodes[a]);
                                if (!st) return sd;
                                sd.x[a]  = st->pos;
                                sd.reach = std::max(sd.reach, flex::reachableDistance(sd.x[a], *ref[a], sweep));
                                sd.size  = std::max(sd.size, sd.x[a].cwiseAbs().maxCoeff());
                        }
                        sd.n = el.nNodes;
                } else if (sb[id].sphere) {
                        sd.x[0]  = b->state->pos;
                        sd.reach = flex::reachableDistance(sd.x[0], b->bound->refPos, sweep);
                        sd.size  = sd.x[0].cwiseAbs().maxCoeff();
                        sd.n     = 1;
                } else
                        return sd;
                sd.state = 1;
                return sd;
	};
	auto cannotTouchBeforeCollider = [&](Body::id_t i1, Body::id_t i2) -> bool {
		const Side &s1 = sideOf(i1), &s2 = sideOf(i2);
		if (s1.state < 0 || s2.state < 0) return false;
		const int      n1 = s1.n, n2 = s2.n;
		const Vector3r *x1 = s1.x, *x2 = s2.x;
		const Real     reach1 = s1.reach, reach2 = s2.reach, size = std::max(s1.size, s2.size);
		// cheap first: the points' boxes farther apart than both radii and both reaches
		Vector3r p[6];
		for (int a = 0; a < n1; ++a)
			p[a] = x1[a];
		for (int a = 0; a < n2; ++a)
			p[n1 + a] = x2[a];
		const Real reachAll = sb[i1].radius + sb[i2].radius + reach1 + reach2;
		if (flex::boxesApart(p, n1, n2, flex::searchReach(p, n1 + n2, reachAll))) return true;
		// a point or segment and a triangle: the plane test next (a wire or grain beside a
		// lining), before the exact distance
		if (n2 == 3 && n1 < 3 && flex::segmentTriangleApart(x1[0], x1[n1 - 1], x2[0], x2[1], x2[2], reachAll)) return true;
		if (n1 == 3 && n2 < 3 && flex::segmentTriangleApart(x2[0], x2[n2 - 1], x1[0], x1[1], x1[2], reachAll)) return true;
		const Real gap = flex::primitiveGap(x1, n1, sb[i1].radius, x2, n2, sb[i2].radius);
		return flex::cannotTouch(gap, reach1, reach2, size);
	};
	// The rows of a pair that may carry a contact before the next estimate (a potential pair, or
	// a contact not carrying force now), with stiffness k = max(kn, ks): each side's DOF bodies
	// (an element's nodes, else the body itself), each row at its worst position (all weight on
	// that node), and the excess kappa of a facet node's share over its weight (load factor - 1).
	auto potentialRows = [&](Real* rowOut, Real* rotOut, Body::id_t i1, Body::id_t i2, Real kn, Real ks) {
		const StepBody*  bs[2] = { &sb[i1], &sb[i2] };
		const Real       k     = std::max(kn, ks);
		Real             r[2]  = { bs[0]->radius, bs[1]->radius };
		if (r[0] <= 0) r[0] = r[1];
		if (r[1] <= 0) r[1] = r[0];
		Body::id_t       ids[2][3];
		int              nid[2];
		Real             smax[2], kappa[2];
		const Body::id_t self[2] = { i1, i2 };
		for (int s = 0; s < 2; ++s) {
			const flexa::Element& el = bs[s]->el;
			kappa[s]                 = el.fac ? bs[s]->kappa : 0;
			if (el.nNodes) {
				nid[s] = el.nNodes;
				for (int a = 0; a < el.nNodes; ++a)
					ids[s][a] = el.nodes[a];
			} else {
				ids[s][0] = self[s];
				nid[s]    = 1;
			}
			smax[s] = 0;
			for (int a = 0; a < nid[s]; ++a)
				smax[s] = std::max(smax[s], invSqrtMass(ids[s][a]));
		}
		for (int s = 0; s < 2; ++s)
			for (int a = 0; a < nid[s]; ++a) {
				const Real ia = invSqrtMass(ids[s][a]);
				if (ia == 0) continue;
				// worst position: all weight on this node; its side's other nodes carry kappa each
				const Real own   = (1 + kappa[s]) * ia + (nid[s] - 1) * kappa[s] * smax[s];
				const Real other = smax[1 - s] * (1 + nid[1 - s] * kappa[1 - s]);
				rowOut[ids[s][a]] += k * (1 + kappa[s]) * ia * (own + other);
				if (!bs[s]->el.fac) addRot(rotOut, ids[s][a], ks, 1, r[s]);
			}
	};
	InteractionContainer&          ic    = *scene->interactions;
	const long                     nI    = (long)ic.size();
	const shared_ptr<Interaction>* intrs = nI ? &ic[0] : nullptr;
	// In parallel on large scenes (it is a serial engine's pass over every interaction, run at
	// each collider run): each thread sums its interactions into its own rows, added up in
	// thread order afterwards (one thread: the serial sums, bit for bit); the bodies' Sides are
	// all computed first, so that the threads only read them. A list of the skipped pairs
	// (unreachablePairs) is made serially, in order.
	int nThreads = 1;
#ifdef YADE_OPENMP
	if (!skippedOut && nI >= kParallelStepperMin) nThreads = omp_get_max_threads();
#endif
	std::vector<std::vector<Real>> moreRows(2 * (nThreads - 1), std::vector<Real>(sb.size(), 0));
	if (canSkip) {
		// all at once, in id order with the bodies' bounds and states asked for ahead (computed on
		// first use, in the order of the interactions, each waited on its body: 12% of the estimate)
		const shared_ptr<Body>* body = scene->bodies->body.data();
#ifdef YADE_OPENMP
#pragma omp parallel for schedule(static) num_threads(nThreads)
#endif
		for (long id = 0; id < (long)nb; ++id) {
			flexa::prefetchBodiesAhead(body, (long)nb, id, [](const Body& c) {
				flexa::prefetch(c.bound.get(), sizeof(Aabb));
				if (const State* st = c.state.get()) flexa::prefetch(&st->pos, sizeof(Vector3r));
			});
			sideOf((Body::id_t)id);
		}
	}
#ifdef YADE_OPENMP
#pragma omp parallel num_threads(nThreads) reduction(+ : skipped)
#endif
	{
#ifdef YADE_OPENMP
	const int thread = omp_get_thread_num();
#else
	const int thread = 0;
#endif
	Real* const myRow = thread == 0 ? row.data() : moreRows[2 * (thread - 1)].data();
	Real* const myRot = thread == 0 ? rowRot.data() : moreRows[2 * (thread - 1) + 1].data();
#ifdef YADE_OPENMP
#pragma omp for schedule(static)
#endif
	for (long li = 0; li < nI; ++li) {
		if (prefetch) { // the interaction 12 ahead, what the one 6 ahead points to (FlexLoop.hpp)
			if (li + 12 < nI) flexa::prefetch(intrs[li + 12].get(), sizeof(Interaction));
			if (li + 6 < nI) {
				const Interaction* J = intrs[li + 6].get();
				if (J->geom) flexa::prefetch(J->geom.get(), sizeof(FlexContactGeom));
				if (J->phys) flexa::prefetch(J->phys.get(), sizeof(FrictPhys));
				else { // a potential pair: what is read of its two bodies (tables in id order)
					for (Body::id_t id : { J->getId1(), J->getId2() })
						if (id >= 0 && id < nb) {
							flexa::prefetch(&sb[id], sizeof(StepBody));
							if (canSkip) flexa::prefetch(&sides[id], sizeof(Side));
						}
				}
			}
		}
		const shared_ptr<Interaction>& I = intrs[li];
		if (I->isReal()) {
			const IPhys*         ip = I->phys.get();
			const FrictPhys*     fp = flexa::fastCast<FrictPhys>(ip);
			const NormShearPhys* ph = fp ? fp : dynamic_cast<const NormShearPhys*>(ip);
			if (!ph) continue;
			const FlexContactGeom* fg = flexa::fastCast<FlexContactGeom>(I->geom.get());
			if (law && law->rollingStiffness > 0)
				if (const FlexContactGeom* g = fg)
					if (fp) {
						const Real kr = law->rollingK(*g, *fp);
						if (kr > 0) { // 2 kr / I on each side (Gershgorin row of the coupled pair)
							addRot(myRot, I->getId1(), kr, 1, 1);
							addRot(myRot, I->getId2(), kr, 1, 1);
						}
					}
			const Real k = std::max(ph->kn, ph->ks);
			struct Entry {
				Body::id_t id;
				Real       w, lever;
			} e[6];
			int ne = 0;
			if (const FlexContactGeom* g = fg) {
				// a contact that is not carrying force (it separated this step, or another contact
				// of its cluster owns the force) can carry it again at the next step, before the
				// next estimate: it counts with the worst weights of a potential pair
				if (!g->active) {
					const Body::id_t i1 = I->getId1(), i2 = I->getId2();
					if (i1 >= 0 && i2 >= 0 && i1 < nb && i2 < nb) potentialRows(myRow, myRot, i1, i2, ph->kn, ph->ks);
					continue;
				}
				const Vector2i*  nodes[2] = { &g->nodes1, &g->nodes2 };
				const Vector3i*  tris[2]  = { &g->tri1, &g->tri2 };
				const Vector3r*  bary[2]  = { &g->bary1, &g->bary2 };
				const Real       us[2] = { g->u1, g->u2 }, rs[2] = { g->refR1, g->refR2 };
				const Body::id_t ids[2] = { I->getId1(), I->getId2() };
				for (int s = 0; s < 2; ++s) {
					if ((*tris[s])[0] >= 0) {
						// facet: forces only, each node's share bounded by w_a + (load factor - 1)
						Vector3r x[3];
						bool     ok = true;
						for (int a = 0; a < 3 && ok; ++a) {
							const State* st = flexa::stateOf(scene, (*tris[s])[a]);
							if ((ok = st != nullptr)) x[a] = st->pos;
						}
						const Real extra = ok ? flex::triangleLoadFactor(x, rs[s]) - 1 : 0;
						for (int a = 0; a < 3; ++a)
							e[ne++] = { (*tris[s])[a], (*bary[s])[a] + extra, 0 };
					} else if ((*nodes[s])[0] < 0)
						e[ne++] = { ids[s], 1, rs[s] };
					else {
						e[ne++] = { (*nodes[s])[0], 1 - us[s], rs[s] };
						e[ne++] = { (*nodes[s])[1], us[s], rs[s] };
					}
				}
			} else if (const GenericSpheresContact* g = dynamic_cast<const GenericSpheresContact*>(I->geom.get())) {
				e[ne++] = { I->getId1(), 1, g->refR1 };
				e[ne++] = { I->getId2(), 1, g->refR2 };
			} else
				continue;
			Real S = 0;
			for (int a = 0; a < ne; ++a)
				S += std::abs(e[a].w) * invSqrtMass(e[a].id);
			for (int a = 0; a < ne; ++a) {
				const Real ia = invSqrtMass(e[a].id);
				if (ia == 0) continue;
				myRow[e[a].id] += k * std::abs(e[a].w) * ia * S;
				addRot(myRot, e[a].id, ph->ks, e[a].w, e[a].lever);
			}
			continue;
		}
		// potential contact
		if (!I->functorCache.geomExists) continue; // bonded neighbours: never a contact
		const Body::id_t i1 = I->getId1(), i2 = I->getId2();
		if (i1 < 0 || i2 < 0 || i1 >= nb || i2 >= nb) continue;
		const StepBody* bs[2] = { &sb[i1], &sb[i2] };
		if (!bs[0]->mat || !bs[1]->mat || !bs[0]->shaped || !bs[1]->shaped) continue; // (no body: no material, no shape)
		Real r1 = bs[0]->radius, r2 = bs[1]->radius;
		if (r1 <= 0) r1 = r2;
		if (r2 <= 0) r2 = r1;
		if (!(r1 > 0)) continue;
		if (canSkip && cannotTouchBeforeCollider(i1, i2)) {
			++skipped;
			if (skippedOut) skippedOut->emplace_back(i1, i2);
			if (mark && I->linIx >= 0 && (size_t)I->linIx < marks.pair.size()) marks.pair[I->linIx] = std::make_pair(i1, i2);
			continue;
		}
		const FrictMat *m1 = bs[0]->mat, *m2 = bs[1]->mat;
		const Real      k1 = m1->young * r1, k2 = m2->young * r2, kn = 2 * k1 * k2 / (k1 + k2);
		const Real      s1 = k1 * m1->poisson, s2 = k2 * m2->poisson, ks = (s1 + s2 > 0) ? 2 * s1 * s2 / (s1 + s2) : 0;
		potentialRows(myRow, myRot, i1, i2, kn, ks);
	}
	} // omp parallel
	for (int t = 1; t < nThreads; ++t)
		for (size_t i = 0; i < sb.size(); ++i) {
			row[i] += moreRows[2 * (t - 1)][i];
			rowRot[i] += moreRows[2 * (t - 1) + 1][i];
		}
	skippedCache = skipped;
	if (mark) {
		if (canSkip) {
			marks.scene                              = scene;
			scene->interactions->iterColliderLastRun = flexa::kMarksValid; // until a collider runs
		} else if (scene->interactions->iterColliderLastRun == flexa::kMarksValid)
			scene->interactions->iterColliderLastRun = -1;
	}
	Real w2             = 0;
	stiffestContactBody = -1;
	for (size_t i = 0; i < row.size(); ++i)
		if (std::max(row[i], rowRot[i]) > w2) {
			w2                   = std::max(row[i], rowRot[i]);
			stiffestContactBody = (Body::id_t)i;
		}
	return w2;
}

// Cundall's non-viscous damping (NewtonIntegrator.damping = c) multiplies each acceleration
// component by 1 - c sign(a v), up to 1 + c when a body decelerates: the effective stiffness,
// hence omega^2, grows by that factor and the stable step shrinks by sqrt(1 + c). (Measured: a
// 20-element cantilever with c = 0.8 runs wild at 0.8 of the undamped limit, 0.8 sqrt(1.8) > 1,
// and is stable at 0.4.)
Real FlexTimeStepper::critical() const { return criticalImpl(false); }

Real FlexTimeStepper::criticalImpl(bool mark) const
{
	Real c = 0;
	for (const auto& e : scene->engines)
		if (const NewtonIntegrator* nw = dynamic_cast<const NewtonIntegrator*>(e.get())) c = std::max(c, std::abs(nw->damping));
	const Real wb = omega2Bonds(), wc = omega2ContactsImpl(nullptr, mark);
	stiffestCache = wc >= wb ? stiffestContactBody : stiffestBondBody;
	return flex::criticalTimeStep((1 + c) * (wb + wc));
}

namespace {
	// How many times the scene's InsertionSortCollider has run (-1: the scene has none). Bounds
	// and potential interactions change only when it runs. Asked twice per step (time stepper,
	// integrator): the engine list is checked against the one seen last (each engine's address
	// and dynamic type, a pointer comparison each) and searched with dynamic_cast only when it
	// changed (a dynamic_cast over the engines cost about 2,200 instructions per call: 1.4% of
	// the wire net's instructions per step for the two calls).
	struct ColliderMemo {
		const Scene*                                                 scene = nullptr;
		std::vector<std::pair<const Engine*, const std::type_info*>> seen;
		const InsertionSortCollider*                                 collider = nullptr;
	};
	long insertionSortColliderRuns(const Scene* scene)
	{
		thread_local ColliderMemo m;
		const auto&               engines = scene->engines;
		bool                      same    = m.scene == scene && m.seen.size() == engines.size();
		for (size_t i = 0; same && i < engines.size(); ++i) {
			const Engine* e = engines[i].get();
			same            = e == m.seen[i].first && (!e || &typeid(*e) == m.seen[i].second);
		}
		if (!same) {
			m.scene    = scene;
			m.collider = nullptr;
			m.seen.clear();
			for (const auto& e : engines) {
				m.seen.emplace_back(e.get(), e ? &typeid(*e) : nullptr);
				if (const InsertionSortCollider* c = dynamic_cast<const InsertionSortCollider*>(e.get())) m.collider = c; // the last one, as before
			}
		}
		return m.collider ? m.collider->numAction : -1;
	}
}

void FlexTimeStepper::action()
{
	flexa::checkScene(scene);
	if (interval < 1) throw std::invalid_argument("FlexTimeStepper.interval must be >= 1");
	if (!(safety > 0) || safety > 1) throw std::invalid_argument("FlexTimeStepper.safety must be in (0, 1]");
	// Also whenever the collider ran: only the collider adds (potential) interactions, and a new
	// pair may be stiffer than any counted so far. Contacts ending between collider runs can only
	// lengthen the critical step: they wait for the next update. (Recomputing at every change of
	// the interaction count cost 11% of a granular impact's step: contacts end at almost every
	// step.) Without an InsertionSortCollider: at every change of the count, as before.
	const long   colliderRuns = insertionSortColliderRuns(scene);
	const size_t nIntr   = scene->interactions->size();
	const bool   changed = colliderRuns >= 0 ? colliderRuns != lastColliderRuns : nIntr != lastInteractionCount;
	lastInteractionCount = nIntr;
	lastColliderRuns     = colliderRuns;
	if (!markUnreachable && scene->interactions->iterColliderLastRun == flexa::kMarksValid) scene->interactions->iterColliderLastRun = -1; // switched off: retire the marks
	if (scene->iter % interval != 0 && dtCritical > 0 && !changed) return;
	dtCritical           = criticalImpl(markUnreachable);
	stiffestBody         = stiffestCache;
	skippedPairs         = skippedCache;
	if (std::isfinite(dtCritical)) scene->dt = safety * dtCritical;
}

void FlexNewtonIntegrator::refresh()
{
	simple = true;
	movers.clear();
	elements.clear();
	facets.clear();
	for (const auto& b : *scene->bodies) {
		if (!b) continue;
		if (b->isClumpMember()) continue; // moved by its clump
		// aspherical bodies take NewtonIntegrator's aspherical integrator (and its kinetic energy);
		// a clump with isotropic inertia, not flagged aspherical, integrates like a sphere
		if (b->isAspherical()) simple = false;
		if (b->shape && dynamic_cast<const FlexCylinder*>(b->shape.get())) elements.push_back(b->id);
		else if (b->shape && dynamic_cast<const FlexFacet*>(b->shape.get()))
			facets.push_back(b->id);
		else
			movers.push_back(b->id);
	}
	isMover.assign(scene->bodies->size(), 0);
	for (Body::id_t id : movers)
		isMover[id] = 1;
	cachedBodyCount = scene->bodies->size();
	tableRuns       = -2; // rebuild the node table
}

// The collider re-runs when some bounded body left the sweep of its bound; NewtonIntegrator
// reports that through maxVelocitySq (2: left, 0.5: inside). An element's bound comes from its
// nodes (Bo1_FlexCylinder_Aabb), so judge it by the nodes' motion since that bound was built.
void FlexNewtonIntegrator::flagElements()
{
	Real flag = 0;
	for (Body::id_t id : elements) {
		const Body* b = flexa::bodyAt(scene, id);
		if (!b || !b->bound) continue;
		const FlexCylinder* c = static_cast<const FlexCylinder*>(b->shape.get());
		const State *s1 = flexa::stateOf(scene, c->node1), *s2 = flexa::stateOf(scene, c->node2);
		if (!s1 || !s2) continue;
		const Real d = std::max((s1->pos - c->boundRef1).cwiseAbs().maxCoeff(), (s2->pos - c->boundRef2).cwiseAbs().maxCoeff());
		flag         = std::max(flag, (d == 0 || d < b->bound->sweepLength) ? Real(0.5) : Real(2));
		if (flag == 2) break;
	}
	for (Body::id_t id : facets) {
		if (flag == 2) break;
		const Body* b = flexa::bodyAt(scene, id);
		if (!b || !b->bound) continue;
		const FlexFacet* f  = static_cast<const FlexFacet*>(b->shape.get());
		const State *    s1 = flexa::stateOf(scene, f->node1), *s2 = flexa::stateOf(scene, f->node2), *s3 = flexa::stateOf(scene, f->node3);
		if (!s1 || !s2 || !s3) continue;
		const Real d = std::max({ (s1->pos - f->boundRef1).cwiseAbs().maxCoeff(), (s2->pos - f->boundRef2).cwiseAbs().maxCoeff(),
		                          (s3->pos - f->boundRef3).cwiseAbs().maxCoeff() });
		flag         = std::max(flag, (d == 0 || d < b->bound->sweepLength) ? Real(0.5) : Real(2));
	}
	maxVelocitySq = std::max(maxVelocitySq, flag);
}

// The same trigger per node, for the fast path: every bound is rebuilt from the nodes' current
// positions whenever the collider runs (BoundDispatcher processes all bodies), so all elements at
// a node share its reference position. An element's test "some node moved by d != 0, d >= its
// sweep" is then "some node moved by d != 0, d >= the smallest sweep of its elements": one test per
// node in the integrator's own loop instead of one pass over all elements per step. The table is
// rebuilt when the collider ran, bodies were added or an element was erased; if two elements
// disagree on a node's reference (a bound built some other way), flagElements is used instead.
bool FlexNewtonIntegrator::buildNodeTable()
{
	const auto&  bodies = *scene->bodies;
	const size_t n      = bodies.size();
	nodeSweep.assign(n, -1);
	nodeRef.resize(n);
	nodeBase = 0;
	auto addElement = [&](const Body& b, const int* nodes, const Vector3r* refs, int nNodes) -> bool {
		for (int k = 0; k < nNodes; ++k)
			if (!flexa::stateOf(scene, nodes[k])) return true; // skipped, as in flagElements
		nodeBase         = 0.5;
		const Real sweep = b.bound->sweepLength;
		for (int k = 0; k < nNodes; ++k) {
			const Body::id_t nid = nodes[k];
			if (!isMover[nid]) return false; // not integrated in the fast loop (a clump member)
			Real& sw = nodeSweep[nid];
			if (sw < 0) {
				sw           = sweep;
				nodeRef[nid] = refs[k];
			} else if (nodeRef[nid] != refs[k]) return false;
			else
				sw = std::min(sw, sweep);
		}
		return true;
	};
	for (Body::id_t id : elements) {
		const shared_ptr<Body>& b = bodies[id];
		if (!b || !b->bound) continue;
		const FlexCylinder* c        = static_cast<const FlexCylinder*>(b->shape.get());
		const int           nodes[2] = { c->node1, c->node2 };
		const Vector3r      refs[2]  = { c->boundRef1, c->boundRef2 };
		if (!addElement(*b, nodes, refs, 2)) return false;
	}
	for (Body::id_t id : facets) {
		const shared_ptr<Body>& b = bodies[id];
		if (!b || !b->bound) continue;
		const FlexFacet* f        = static_cast<const FlexFacet*>(b->shape.get());
		const int        nodes[3] = { f->node1, f->node2, f->node3 };
		const Vector3r   refs[3]  = { f->boundRef1, f->boundRef2, f->boundRef3 };
		if (!addElement(*b, nodes, refs, 3)) return false;
	}
	return true;
}

namespace {
	// The collider trigger of NewtonIntegrator::saveMaximaDisplacement (2: a body left the sweep
	// of its bound, 0.5: inside), into a per-thread maximum; Clump::moveMembers calls it for members.
	struct MemberSweep {
		Real& mx;
		void  saveMaximaDisplacement(const shared_ptr<Body>& b)
		{
			if (!b->bound) return;
			const Real d = (b->state->pos - b->bound->refPos).cwiseAbs().maxCoeff();
			mx           = std::max(mx, (d == 0 || d < b->bound->sweepLength) ? Real(0.5) : Real(2));
		}
	};
	// Cundall's non-viscous damping factor 1 - c sign(x_i) of each component (x_i = a_i v_i, v at
	// mid-step), picked among 1 - c, 1 + c and 1 (the same values, bit for bit): about 5
	// instructions a component instead of 22 (sign as an int, converted, multiplied, in a loop
	// writing the vectors' components one by one; callgrind on the wire-net bench)
	struct DampFactors {
		Real     minus, plus; // 1 - c, 1 + c
		Real     of(Real x) const { return x > 0 ? minus : (x < 0 ? plus : Real(1)); }
		Vector3r factors(const Vector3r& x) const { return Vector3r(of(x[0]), of(x[1]), of(x[2])); }
	};
}

Real FlexNewtonIntegrator::dampingOnBlockedDofs()
{
	scene->forces.sync();
	Real sum = 0;
	for (const auto& b : *scene->bodies) {
		if (!b || !b->isStandalone()) continue; // (a clump's summed force is NewtonIntegrator's own)
		const State& st = *b->state;
		if (!st.blockedDOFs || !st.isDamped) continue;
		const Vector3r f = scene->forces.getForce(b->id) + st.mass * gravity;
		const Vector3r m = scene->forces.getTorque(b->id);
		for (int i = 0; i < 3; ++i) {
			if (st.blockedDOFs & State::axisDOF(i, false)) sum += std::abs(st.vel[i]) * std::abs(f[i]);
			if (st.blockedDOFs & State::axisDOF(i, true)) sum += std::abs(st.angVel[i]) * std::abs(m[i]);
		}
	}
	return sum * damping * scene->dt;
}

void FlexNewtonIntegrator::action()
{
	flexa::checkScene(scene);
	flexa::checkTimeStep(scene);
	if (scene->bodies->size() != cachedBodyCount) refresh();
	usedFastPath = simple && !scene->isPeriodic && !(mask > 0) && !densityScaling; // body callbacks: not compiled in Debian's YADE
	if (!usedFastPath) {
		// NewtonIntegrator books |v_i| |F_i + m g_i| c dt on every component of a damped body,
		// blocked ones too, where no damping acts (a driven DOF): what it will book there, from
		// the same velocities and forces, is taken back after it ran
		const Real blockedDamping = scene->trackEnergy && damping != 0 && !scene->isPeriodic ? dampingOnBlockedDofs() : 0;
		NewtonIntegrator::action();
		if (blockedDamping != 0) scene->energy->add(-blockedDamping, "nonviscDamp", nonviscDampIx, false);
		flagElements();
		return;
	}
	scene->forces.sync();
	const Real dt    = scene->dt;
	const bool track = scene->trackEnergy;
	const long runs  = insertionSortColliderRuns(scene);
	if (runs < 0) nodeTableOk = false; // no InsertionSortCollider to tell when bounds change
	else if (runs != tableRuns || flexa::elementErasures() != tableErasures) {
		nodeTableOk    = buildNodeTable();
		tableRuns      = runs;
		tableErasures  = flexa::elementErasures();
	}
	const bool  byNode = nodeTableOk;
	const Real* nSweep = nodeSweep.data();
	const Vector3r* nRef = nodeRef.data();
	// the collider trigger's maximum (0.5: every body inside its sweep, 2: one left it), each
	// thread's own in the reduction. It was a table of per-thread entries, 8 bytes apart and
	// written at every body, so two threads wrote one cache line by turns: the integrator took
	// 1.18x less time on two threads than on one; 1.92x less with the reduction (the damping
	// module 5 ms into the impact, medians of 5 runs; bench/README.md, "Two threads")
	Real sweepMax = 0;
	const shared_ptr<Body>* bodies = scene->bodies->body.data();
	const long n      = (long)movers.size();
	const Body::id_t* mv = movers.data();
	const bool        pf = prefetch && n >= flexa::kPrefetchMin; // (small passes stay in cache)
	const DampFactors damp { 1 - damping, 1 + damping };
	Real eDamp = 0, eKinT = 0, eKinR = 0, eGrav = 0;
	long nDamp = 0;
#ifdef YADE_OPENMP
#pragma omp parallel for schedule(static) if (n >= parallelMin) reduction(+ : eDamp, eKinT, eKinR, eGrav, nDamp) reduction(max : sweepMax)
#endif
	for (long k = 0; k < n; ++k) {
		if (pf) { // the body 8 ahead, the state and bound of the one 4 ahead (see FlexLoop.hpp)
			if (k + 8 < n) flexa::prefetch(bodies[mv[k + 8]].get(), sizeof(Body));
			if (k + 4 < n)
				if (const Body* bb = bodies[mv[k + 4]].get()) {
					flexa::prefetch(bb->state.get(), sizeof(State));
					if (bb->bound) flexa::prefetch(bb->bound.get(), sizeof(Aabb));
				}
		}
		const Body::id_t        id = mv[k];
		const shared_ptr<Body>& b  = bodies[id];
		if (!b) continue; // erased; element bodies (no DOF) are not in `movers`
		State* st = b->state.get();
		Real& mx = sweepMax;
		if (b->isClump()) { // the members' forces and moments about the clump's centre, added as NewtonIntegrator does
			Vector3r F = Vector3r::Zero(), T = Vector3r::Zero();
			static_cast<Clump*>(b->shape.get())->addForceTorqueFromMembers(st, scene, F, T);
#ifdef YADE_OPENMP
			scene->forces.addTorqueUnsynced(id, T);
			scene->forces.addForceUnsynced(id, F);
#else
			scene->forces.addTorque(id, T);
			scene->forces.addForce(id, F);
#endif
		}
		const Vector3r f = scene->forces.getForce(id);
		const Vector3r m = scene->forces.getTorque(id);
		const unsigned blocked = st->blockedDOFs;
		if (track) {
			// the same terms as NewtonIntegrator: non-viscous damping |v_i||F_i| c dt (gravity
			// included), kinetic energy before the update, work of gravity -m g.v dt. Unlike
			// NewtonIntegrator, damping is booked on free DOFs only: a blocked (driven) DOF is not
			// damped, and booking |v||F| c dt there would claim energy nothing dissipated. Summed
			// here and booked once per step (with addEnergy below, O.trackEnergy went from 9.7% to
			// 3.8% of a granular step, both changes together, paired).
			if (damping != 0 && st->isDamped && blocked != State::DOF_ALL) {
				++nDamp;
				if (blocked == 0) // the common case
					eDamp += (st->vel.cwiseAbs().dot((f + st->mass * gravity).cwiseAbs()) + st->angVel.cwiseAbs().dot(m.cwiseAbs())) * damping * dt;
				else {
					Real e = 0;
					for (int i = 0; i < 3; ++i) {
						if (!(blocked & State::axisDOF(i, false))) e += std::abs(st->vel[i]) * std::abs(f[i] + st->mass * gravity[i]);
						if (!(blocked & State::axisDOF(i, true))) e += std::abs(st->angVel[i]) * std::abs(m[i]);
					}
					eDamp += e * damping * dt;
				}
			}
			eKinT += 0.5 * st->mass * st->vel.squaredNorm();
			eKinR += 0.5 * st->angVel.dot(st->inertia.cwiseProduct(st->angVel));
			eGrav += -gravity.dot(st->vel) * st->mass * dt;
		}
		if (blocked != State::DOF_ALL) {
			// accelerations on free DOFs; Cundall's non-viscous damping scales each component by
			// 1 - c sign(a_i v_i), v taken at mid-step (v + a dt/2)
			Vector3r a, al;
			if (blocked == 0) { // the common case, as vectors (the same IEEE operations per component)
				a = dampGravity ? Vector3r(f / st->mass + gravity) : Vector3r(f / st->mass);
				// no moment (the nodes of bar and truss links, grains without contact): +-0 / I is
				// +-0 for I > 0, so the quotient is the moment itself, bit for bit, without its
				// three divisions
				if (m[0] == 0 && m[1] == 0 && m[2] == 0 && st->inertia[0] > 0 && st->inertia[1] > 0 && st->inertia[2] > 0) al = m;
				else
					al = m.cwiseQuotient(st->inertia);
			} else {
				a = al = Vector3r::Zero();
				for (int i = 0; i < 3; ++i) {
					if (!(blocked & State::axisDOF(i, false))) a[i] = f[i] / st->mass + (dampGravity ? gravity[i] : 0);
					if (!(blocked & State::axisDOF(i, true))) al[i] = m[i] / st->inertia[i];
				}
			}
			if (st->isDamped && damping != 0) {
				a  = a.cwiseProduct(damp.factors(a.cwiseProduct(st->vel + (0.5 * dt) * a)));
				al = al.cwiseProduct(damp.factors(al.cwiseProduct(st->angVel + (0.5 * dt) * al)));
			}
			if (!dampGravity)
				for (int i = 0; i < 3; ++i)
					if (!(blocked & State::axisDOF(i, false))) a[i] += gravity[i];
			st->vel += dt * a;
			st->angVel += dt * al;
		}
		st->pos += st->vel * dt;
		const Real w2 = st->angVel.squaredNorm();
		if (w2 != 0) {
			const Real w = sqrt(w2);
			st->ori      = Quaternionr(AngleAxisr(w * dt, st->angVel / w)) * st->ori;
		}
		// Eigen's normalize() (divide by sqrt(|q|^2) if |q|^2 > 0), written out so that |q|^2 is
		// computed once, and skipped when |q|^2 is exactly 1, where it is the identity (sqrt(1) = 1,
		// x / 1 = x): a node that never turned saves a square root and four divisions
		const Real q2 = st->ori.squaredNorm();
		if (q2 != 1 && q2 > 0) st->ori.coeffs() /= sqrt(q2);
		if (byNode && nSweep[id] >= 0) { // a node of bounded elements: their collider trigger
			const Real d = (st->pos - nRef[id]).cwiseAbs().maxCoeff();
			if (!(d == 0 || d < nSweep[id])) mx = 2;
		}
		MemberSweep sweep { mx };
		sweep.saveMaximaDisplacement(b); // collider trigger, as NewtonIntegrator
		if (b->isClump()) Clump::moveMembers(b, scene, &sweep);
	}
	if (track && n > 0) {
		if (nDamp) flexa::addEnergy(scene, eDamp, "nonviscDamp", nonviscDampIx, false);
		if (!kinSplit) flexa::addEnergy(scene, eKinT + eKinR, "kinetic", kinEnergyIx, true);
		else {
			flexa::addEnergy(scene, eKinT, "kinTrans", kinEnergyTransIx, true);
			flexa::addEnergy(scene, eKinR, "kinRot", kinEnergyRotIx, true);
		}
		flexa::addEnergy(scene, eGrav, "gravWork", fieldWorkIx, false);
	}
	maxVelocitySq = sweepMax;
	if (byNode) maxVelocitySq = std::max(maxVelocitySq, nodeBase);
	else
		flagElements();
}

} // namespace yade
