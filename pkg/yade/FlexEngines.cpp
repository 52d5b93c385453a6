// yade-flex adapter: element forces and the time stepper (GPL-2.0-or-later).
#include "FlexCommon.hpp"

#include <core/Clump.hpp>
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
	for (const auto& b : *scene->bodies)
		if (b && b->shape && dynamic_cast<const FlexCylinder*>(b->shape.get())) cylinders.push_back(b->id);
	cachedBodyCount = scene->bodies->size();
}

void FlexElementEngine::action()
{
	if (scene->bodies->size() != cachedBodyCount || cylinders.empty()) refresh();
	const long              n = (long)cylinders.size();
	std::vector<Body::id_t> broken;
	const bool              energy = scene->trackEnergy;
#ifdef YADE_OPENMP
#pragma omp parallel for schedule(static)
#endif
	for (long k = 0; k < n; ++k) {
		const Body::id_t id = cylinders[k];
		Body*            b  = (*scene->bodies)[id].get();
		if (!b) continue;
		FlexCylinder& c = static_cast<FlexCylinder&>(*b->shape);
		if (!c.attached) continue;
		State *si = (*scene->bodies)[c.node1] ? (*scene->bodies)[c.node1]->state.get() : nullptr;
		State *sj = (*scene->bodies)[c.node2] ? (*scene->bodies)[c.node2]->state.get() : nullptr;
		const FlexMat* mat = dynamic_cast<const FlexMat*>(b->material.get());
		if (!si || !sj || !mat) continue;
		flex::BeamRest rest;
		rest.L0 = c.L0;
		rest.Qi = c.Q1;
		rest.Qj = c.Q2;
		flex::AxialState st { c.plasticStrain, c.hardeningVar };
		const flex::BeamKinematics kin = flex::beamKinematics(si->pos, sj->pos, si->ori, sj->ori, rest);
		const flex::BeamForces     f   = flex::beamForces(kin, rest, flexa::section(*mat, c.radius), flexa::axialLaw(*mat, c.radius), st);
		c.plasticStrain                = st.plasticStrain;
		c.hardeningVar                 = st.hardeningVar;
		c.axialForce                   = f.N;
		c.strain                       = (kin.L - c.L0) / c.L0;
		c.elasticEnergy                = f.elasticEnergy;
		scene->forces.addForce(c.node1, f.Fi);
		scene->forces.addForce(c.node2, f.Fj);
		scene->forces.addTorque(c.node1, f.Mi);
		scene->forces.addTorque(c.node2, f.Mj);
		// the element body follows its nodes (output, display; it has no DOF)
		b->state->pos    = 0.5 * (si->pos + sj->pos);
		b->state->vel    = 0.5 * (si->vel + sj->vel);
		if (energy) {
			scene->energy->add(f.elasticEnergy, "flexBondElastic", elastIx, true);
			if (f.plasticWork != 0) scene->energy->add(f.plasticWork, "flexBondPlastic", plastIx, false);
		}
		if (f.rupture) {
#ifdef YADE_OPENMP
#pragma omp critical(flexRupture)
#endif
			broken.push_back(id);
		}
	}
	if (broken.empty()) return;
	std::sort(broken.begin(), broken.end()); // same order whatever the thread count
	for (Body::id_t id : broken) {
		const FlexCylinder& c = static_cast<const FlexCylinder&>(*(*scene->bodies)[id]->shape);
		// the bond's stored energy is released at rupture (elastic waves we do not resolve)
		if (energy) scene->energy->add(c.elasticEnergy, "flexRupture", ruptIx, false);
		for (int nid : { c.node1, c.node2 }) {
			if (!(*scene->bodies)[nid]) continue;
			auto& el = static_cast<FlexNode&>(*(*scene->bodies)[nid]->shape).elements;
			el.erase(std::remove(el.begin(), el.end(), id), el.end());
		}
		scene->bodies->erase(id, false); // erases its interactions too: no ghost element
		rupturedIds.push_back(id);
		++nRuptured;
	}
	refresh();
}

Real FlexTimeStepper::omega2Bonds() const
{
	// Irons' bound with the element's own mass shares. If a node is lighter than the sum of
	// the shares attached to it (user-modified mass), scale that element's omega^2 up.
	auto&             bodies = *scene->bodies;
	std::vector<Real> sumM(bodies.size(), 0), sumI(bodies.size(), 0);
	for (const auto& b : bodies) {
		if (!b || !b->shape) continue;
		const FlexCylinder* c = dynamic_cast<const FlexCylinder*>(b->shape.get());
		if (!c || !c->attached) continue;
		for (int nid : { c->node1, c->node2 }) {
			sumM[nid] += c->massShare;
			sumI[nid] += c->inertiaShare;
		}
	}
	Real w2 = 0;
	for (const auto& b : bodies) {
		if (!b || !b->shape) continue;
		const FlexCylinder* c = dynamic_cast<const FlexCylinder*>(b->shape.get());
		if (!c || !c->attached) continue;
		Real scale = 1;
		for (int nid : { c->node1, c->node2 }) {
			const shared_ptr<Body>& nb = bodies[nid];
			if (!nb || !nb->isDynamic()) continue;
			const State& s = *nb->state;
			if (s.mass > 0) scale = std::max(scale, sumM[nid] / s.mass);
			const Real I = s.inertia.minCoeff();
			if (I > 0) scale = std::max(scale, sumI[nid] / I);
		}
		w2 = std::max(w2, c->omega2 * scale);
	}
	return w2;
}

Real FlexTimeStepper::omega2Contacts() const
{
	// Gershgorin rows of M^-1/2 K M^-1/2 for all contact springs. A contact couples the
	// entries g = (-w on side 1, +w on side 2) with stiffness k = max(kn, ks) in any
	// direction; row a collects k |g_a|/sqrt(m_a) * sum_b |g_b|/sqrt(m_b). Rotations: the
	// shear spring at lever l on inertia I gives k_s l^2 / I per side, doubled for coupling.
	auto&             bodies = *scene->bodies;
	std::vector<Real> row(bodies.size(), 0), rowRot(bodies.size(), 0);
	struct Entry {
		Body::id_t id;
		Real       w, lever;
	};
	auto invSqrtMass = [&](Body::id_t id) -> Real {
		const shared_ptr<Body>& b = bodies[id];
		if (!b || !b->isDynamic() || !(b->state->mass > 0)) return 0;
		return 1 / std::sqrt(b->state->mass);
	};
	for (const auto& I : *scene->interactions) {
		if (!I->isReal()) continue;
		const NormShearPhys* ph = dynamic_cast<const NormShearPhys*>(I->phys.get());
		if (!ph) continue;
		const Real k = std::max(ph->kn, ph->ks);
		Entry      e[4];
		int        ne = 0;
		if (const FlexContactGeom* g = dynamic_cast<const FlexContactGeom*>(I->geom.get())) {
			if (!g->active) continue;
			const Vector2i* nodes[2] = { &g->nodes1, &g->nodes2 };
			const Real      us[2] = { g->u1, g->u2 }, rs[2] = { g->refR1, g->refR2 };
			const Body::id_t ids[2] = { I->getId1(), I->getId2() };
			for (int s = 0; s < 2; ++s) {
				if ((*nodes[s])[0] < 0) e[ne++] = { ids[s], 1, rs[s] };
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
			row[e[a].id] += k * std::abs(e[a].w) * ia * S;
			const Real Imin = bodies[e[a].id]->state->inertia.minCoeff();
			if (Imin > 0 && std::isfinite(e[a].lever)) rowRot[e[a].id] += 2 * ph->ks * std::abs(e[a].w) * e[a].lever * e[a].lever / Imin;
		}
	}
	Real w2 = 0;
	for (size_t i = 0; i < row.size(); ++i)
		w2 = std::max(w2, std::max(row[i], rowRot[i]));
	return w2;
}

Real FlexTimeStepper::critical() const { return flex::criticalTimeStep(omega2Bonds() + omega2Contacts()); }

void FlexTimeStepper::action()
{
	if (interval < 1) throw std::invalid_argument("FlexTimeStepper.interval must be >= 1");
	if (!(safety > 0) || safety > 1) throw std::invalid_argument("FlexTimeStepper.safety must be in (0, 1]");
	if (scene->iter % interval != 0 && dtCritical > 0) return;
	dtCritical = critical();
	if (std::isfinite(dtCritical)) scene->dt = safety * dtCritical;
}

void FlexNewtonIntegrator::refresh()
{
	simple = true;
	movers.clear();
	elements.clear();
	for (const auto& b : *scene->bodies) {
		if (!b) continue;
		if (b->isClump() || b->isClumpMember() || (exactAsphericalRot && b->isAspherical())) simple = false;
		if (b->shape && dynamic_cast<const FlexCylinder*>(b->shape.get())) elements.push_back(b->id);
		else movers.push_back(b->id);
	}
	cachedBodyCount = scene->bodies->size();
}

// The collider re-runs when some bounded body left the sweep of its bound; NewtonIntegrator
// reports that through maxVelocitySq (2: left, 0.5: inside). An element's bound comes from its
// nodes (Bo1_FlexCylinder_Aabb), so judge it by the nodes' motion since that bound was built.
void FlexNewtonIntegrator::flagElements()
{
	Real flag = 0;
	for (Body::id_t id : elements) {
		const shared_ptr<Body>& b = (*scene->bodies)[id];
		if (!b || !b->bound) continue;
		const FlexCylinder* c = static_cast<const FlexCylinder*>(b->shape.get());
		const State *s1 = flexa::stateOf(scene, c->node1), *s2 = flexa::stateOf(scene, c->node2);
		if (!s1 || !s2) continue;
		const Real d = std::max((s1->pos - c->boundRef1).cwiseAbs().maxCoeff(), (s2->pos - c->boundRef2).cwiseAbs().maxCoeff());
		flag         = std::max(flag, (d == 0 || d < b->bound->sweepLength) ? Real(0.5) : Real(2));
		if (flag == 2) break;
	}
	maxVelocitySq = std::max(maxVelocitySq, flag);
}

void FlexNewtonIntegrator::action()
{
	if (scene->bodies->size() != cachedBodyCount) refresh();
	usedFastPath = simple && !scene->isPeriodic && !(mask > 0) && !densityScaling; // body callbacks: not compiled in Debian's YADE
	if (!usedFastPath) {
		NewtonIntegrator::action();
		flagElements();
		return;
	}
	scene->forces.sync();
	const Real dt    = scene->dt;
	const bool track = scene->trackEnergy;
#ifdef YADE_OPENMP
	const int nThr = omp_get_max_threads();
#else
	const int nThr = 1;
#endif
	thrMax.assign(nThr, 0);
	auto&      bodies = *scene->bodies;
	const long n      = (long)movers.size();
#ifdef YADE_OPENMP
#pragma omp parallel for schedule(static)
#endif
	for (long k = 0; k < n; ++k) {
		const Body::id_t        id = movers[k];
		const shared_ptr<Body>& b  = bodies[id];
		if (!b) continue; // erased; element bodies (no DOF) are not in `movers`
		State*         st = b->state.get();
		const Vector3r f  = scene->forces.getForce(id);
		const Vector3r m  = scene->forces.getTorque(id);
		if (track) {
			// the same terms as NewtonIntegrator: non-viscous damping |v_i||F_i| c dt (gravity
			// included), kinetic energy before the update, work of gravity -m g.v dt
			if (damping != 0 && st->isDamped) {
				scene->energy->add(st->vel.cwiseAbs().dot((f + st->mass * gravity).cwiseAbs()) * damping * dt, "nonviscDamp", nonviscDampIx, false);
				scene->energy->add(st->angVel.cwiseAbs().dot(m.cwiseAbs()) * damping * dt, "nonviscDamp", nonviscDampIx, false);
			}
			const Real Et = 0.5 * st->mass * st->vel.squaredNorm(), Er = 0.5 * st->angVel.dot(st->inertia.cwiseProduct(st->angVel));
			if (!kinSplit) scene->energy->add(Et + Er, "kinetic", kinEnergyIx, true);
			else {
				scene->energy->add(Et, "kinTrans", kinEnergyTransIx, true);
				scene->energy->add(Er, "kinRot", kinEnergyRotIx, true);
			}
			scene->energy->add(-gravity.dot(st->vel) * st->mass * dt, "gravWork", fieldWorkIx, false);
		}
		const unsigned blocked = st->blockedDOFs;
		if (blocked != State::DOF_ALL) {
			// accelerations on free DOFs; Cundall's non-viscous damping scales each component by
			// 1 - c sign(a_i v_i), v taken at mid-step (v + a dt/2)
			Vector3r a = Vector3r::Zero(), al = Vector3r::Zero();
			for (int i = 0; i < 3; ++i) {
				if (!(blocked & State::axisDOF(i, false))) a[i] = f[i] / st->mass + (dampGravity ? gravity[i] : 0);
				if (!(blocked & State::axisDOF(i, true))) al[i] = m[i] / st->inertia[i];
			}
			if (st->isDamped && damping != 0)
				for (int i = 0; i < 3; ++i) {
					a[i] *= 1 - damping * math::sign(a[i] * (st->vel[i] + 0.5 * dt * a[i]));
					al[i] *= 1 - damping * math::sign(al[i] * (st->angVel[i] + 0.5 * dt * al[i]));
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
		st->ori.normalize();
		if (b->bound) { // collider trigger, as NewtonIntegrator
			const Real d = (st->pos - b->bound->refPos).cwiseAbs().maxCoeff();
#ifdef YADE_OPENMP
			Real& mx = thrMax[omp_get_thread_num()];
#else
			Real& mx = thrMax[0];
#endif
			mx = std::max(mx, (d == 0 || d < b->bound->sweepLength) ? Real(0.5) : Real(2));
		}
	}
	maxVelocitySq = 0;
	for (Real v : thrMax)
		maxVelocitySq = std::max(maxVelocitySq, v);
	flagElements();
}

} // namespace yade
