// yade-flex adapter: FlexNewtonIntegrator, NewtonIntegrator for scenes with yade-flex elements
// (GPL-2.0-or-later). Declaration: FlexNewtonIntegrator.hpp.
#include "FlexElements.hpp"
#include "FlexBoundDispatcher.hpp"
#include "FlexProtocol.hpp"
#include "speed/FlexTuning.hpp"

#include <kernel/LeapFrog.hpp>
#include "FlexSceneCheck.hpp"

#include <core/Clump.hpp>
#include <lib/factory/ClassFactory.hpp>

#include <algorithm>
#include <limits>
#ifdef YADE_OPENMP
#include <omp.h>
#endif

namespace yade {

YADE_PLUGIN((FlexNewtonIntegrator));

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
		if (b->shape && dynamic_cast<const FlexCylinder*>(b->shape.get()))
			elements.push_back(b->id);
		else if (b->shape && dynamic_cast<const FlexFacet*>(b->shape.get()))
			facets.push_back(b->id);
		else
			movers.push_back(b->id);
	}
	isMover.assign(scene->bodies->size(), 0);
	isSphere.assign(scene->bodies->size(), 0);
	for (Body::id_t id : movers) {
		isMover[id]         = 1;
		const Body* b       = flexa::bodyAt(scene, id);
		isSphere[id]        = b && b->shape && typeid(*b->shape) == typeid(Sphere);
	}
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
		const FlexCylinder* c  = static_cast<const FlexCylinder*>(b->shape.get());
		const State *       s1 = flexa::stateOf(scene, c->node1), *s2 = flexa::stateOf(scene, c->node2);
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
	nodeBase        = 0;
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
			} else if (nodeRef[nid] != refs[k])
				return false;
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
			const Real d = (b->state->se3.position - b->bound->refPos).cwiseAbs().maxCoeff();
			mx           = std::max(mx, (d == 0 || d < b->bound->sweepLength) ? Real(0.5) : Real(2));
		}
	};
} // namespace

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

Real FlexNewtonIntegrator::driveWork()
{
	const flex::LeapFrogSettings lf { scene->dt, gravity, damping, flex::DampFactors(damping), dampGravity };
	Real                         sum = 0;
	for (const auto& b : *scene->bodies) {
		if (!b || !b->isStandalone() || !b->state->blockedDOFs) continue;
		State&               st = *b->state;
		const flex::BodyDofs dofs { st.se3.position, st.vel, st.angVel, st.se3.orientation, st.inertia, st.mass, st.blockedDOFs, st.isDamped };
		sum += flex::driveWork(scene->forces.getForce(b->id), scene->forces.getTorque(b->id), dofs, lf);
	}
	return sum;
}

// One step: YADE's own integrator where the fast path does not apply (integrateWithYade), else
// the node table brought up to date with the collider (updateNodeTable) and every moving body
// integrated (integrate).
void FlexNewtonIntegrator::action()
{
	flexa::checkScene(scene, this);
	flexa::checkTimeStep(scene);
	if (scene->bodies->size() != cachedBodyCount) refresh();
	sweepFloorInPlace = FlexBoundDispatcher::install(scene, sweepFloor);
	usedFastPath = simple && !scene->isPeriodic && !(mask > 0) && !densityScaling; // body callbacks: not compiled in Debian's YADE
	if (!usedFastPath) {
		integrateWithYade();
		return;
	}
	scene->forces.sync();
	updateNodeTable();
	integrate();
}

// NewtonIntegrator::action, its energy booking corrected, the elements flagged and the motions
// checked as the fast path does.
void FlexNewtonIntegrator::integrateWithYade()
{
	// NewtonIntegrator books |v_i| |F_i + m g_i| c dt on every component of a damped body,
	// blocked ones too, where no damping acts (a driven DOF): what it will book there, from
	// the same velocities and forces, is taken back after it ran
	const Real blockedDamping = scene->trackEnergy && damping != 0 && !scene->isPeriodic ? dampingOnBlockedDofs() : 0;
	const Real drive          = scene->trackEnergy ? (scene->forces.sync(), driveWork()) : 0;
	NewtonIntegrator::action();
	if (blockedDamping != 0) scene->energy->add(-blockedDamping, "nonviscDamp", nonviscDampIx, false);
	if (drive != 0) flexa::addEnergy(scene, drive, "driveWork", driveWorkIx, false);
	flagElements();
	// the motions it made, refused as the fast path refuses them (a pass of its own here)
	for (const auto& b : *scene->bodies)
		if (b && !b->isClumpMember() && !flexa::motionValid(*b->state))
			flexa::refuseIntegrated(scene, b->id, scene->forces.getForce(b->id), scene->forces.getTorque(b->id));
	flexa::sceneState(scene).vouched.iter = scene->iter;
}

// The nodes' sweep table, rebuilt when the collider ran or an element was erased since.
void FlexNewtonIntegrator::updateNodeTable()
{
	const long               runs  = flexa::insertionSortColliderRuns(scene);
	const flexa::SceneState& state = flexa::sceneState(scene);
	if (runs < 0)
		nodeTableOk = false; // no InsertionSortCollider to tell when bounds change
	else if (runs != tableRuns || state.elementErasures != tableErasures || &state != tableState) {
		nodeTableOk   = buildNodeTable();
		tableRuns     = runs;
		tableErasures = state.elementErasures;
		tableState    = &state;
	}
}

// Every moving body one leap-frog step (kernel/LeapFrog.hpp), its energy terms summed and booked
// once, the collider's trigger from the nodes' table (or YADE's per-body sweep).
void FlexNewtonIntegrator::integrate()
{
	const Real      dt     = scene->dt;
	const bool      track  = scene->trackEnergy;
	const bool      byNode = nodeTableOk;
	const Real*     nSweep = nodeSweep.data();
	const Vector3r* nRef   = nodeRef.data();
	// the collider trigger's maximum (0.5: every body inside its sweep, 2: one left it), each
	// thread's own in the reduction (a shared table of per-thread entries would put two threads'
	// writes on one cache line)
	Real                         sweepMax = 0;
	const shared_ptr<Body>*      bodies   = scene->bodies->body.data();
	const long                   n        = (long)movers.size();
	const Body::id_t*            mv       = movers.data();
	const bool                   pf       = prefetch && n >= flexa::kPrefetchMin; // (small passes stay in cache)
	const flex::LeapFrogSettings lf { dt, gravity, damping, flex::DampFactors(damping), dampGravity };
	Real                         eDamp = 0, eKinT = 0, eKinR = 0, eGrav = 0, eDrive = 0;
	long                         nDamp    = 0;
	long                         firstBad = std::numeric_limits<long>::max(); // the smallest id moved to a non-finite state
#ifdef YADE_OPENMP
#pragma omp parallel for schedule(static) if (n >= parallelMin) reduction(+ : eDamp, eKinT, eKinR, eGrav, eDrive, nDamp) reduction(max : sweepMax) \
        reduction(min : firstBad)
#endif
	for (long k = 0; k < n; ++k) {
		if (pf) { // the body 8 ahead, the state and bound of the one 4 ahead (see speed/FlexLoop.hpp)
			using flexa::tuning::kAheadIntegratorBodies;
			using flexa::tuning::kAheadIntegratorParts;
			if (k + kAheadIntegratorBodies < n) flexa::prefetch(bodies[mv[k + kAheadIntegratorBodies]].get(), sizeof(Body));
			if (k + kAheadIntegratorParts < n)
				if (const Body* bb = bodies[mv[k + kAheadIntegratorParts]].get()) {
					// the State from se3 on (its first line holds the references pos and ori, not read)
					if (const State* s = bb->state.get()) {
						const char* from = reinterpret_cast<const char*>(&s->se3);
						flexa::prefetch(from, sizeof(State) - size_t(from - reinterpret_cast<const char*>(s)));
					}
					if (bb->bound) flexa::prefetch(bb->bound.get(), sizeof(Aabb));
				}
		}
		const Body::id_t        id = mv[k];
		const shared_ptr<Body>& b  = bodies[id];
		if (!b) continue; // erased; element bodies (no DOF) are not in `movers`
		State* st = b->state.get();
		Real&  mx = sweepMax;
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
		const Vector3r f       = scene->forces.getForce(id);
		const Vector3r m       = scene->forces.getTorque(id);
		const unsigned blocked = st->blockedDOFs;
		static_assert(unsigned(State::DOF_ALL) == flex::kAllDofs, "the kernel numbers DOFs as State::axisDOF");
		flex::BodyDofs dofs { st->se3.position, st->vel, st->angVel, st->se3.orientation, st->inertia, st->mass, blocked, st->isDamped };
		dofs.turns = sphereOrientation || !isSphere[id];
		if (track) {
			// the same terms as NewtonIntegrator (kernel/LeapFrog.hpp), summed here and booked
			// once per step; damping on free DOFs only
			if (damping != 0 && st->isDamped && blocked != State::DOF_ALL) {
				++nDamp;
				eDamp += flex::dampingWork(f, m, dofs, lf);
			}
			eKinT += 0.5 * st->mass * st->vel.squaredNorm();
			eKinR += 0.5 * st->angVel.dot(st->inertia.cwiseProduct(st->angVel));
			eGrav += -gravity.dot(st->vel) * st->mass * dt;
			if (blocked) eDrive += flex::driveWork(f, m, dofs, lf);
		}
		flex::leapFrog(f, m, dofs, lf);
		if (!flexa::motionValid(*st)) firstBad = std::min(firstBad, long(id));
		if (byNode && nSweep[id] >= 0) { // a node of bounded elements: their collider trigger
			const Real d = (st->se3.position - nRef[id]).cwiseAbs().maxCoeff();
			if (!(d == 0 || d < nSweep[id])) mx = 2;
		}
		MemberSweep sweep { mx };
		sweep.saveMaximaDisplacement(b); // collider trigger, as NewtonIntegrator
		if (b->isClump()) Clump::moveMembers(b, scene, &sweep);
	}
	if (firstBad != std::numeric_limits<long>::max())
		flexa::refuseIntegrated(scene, Body::id_t(firstBad), scene->forces.getForce(firstBad), scene->forces.getTorque(firstBad));
	flexa::sceneState(scene).vouched.iter = scene->iter; // (what a clump moved with its members too)
	if (track && n > 0) {
		if (nDamp) flexa::addEnergy(scene, eDamp, "nonviscDamp", nonviscDampIx, false);
		if (!kinSplit)
			flexa::addEnergy(scene, eKinT + eKinR, "kinetic", kinEnergyIx, true);
		else {
			flexa::addEnergy(scene, eKinT, "kinTrans", kinEnergyTransIx, true);
			flexa::addEnergy(scene, eKinR, "kinRot", kinEnergyRotIx, true);
		}
		flexa::addEnergy(scene, eGrav, "gravWork", fieldWorkIx, false);
		if (eDrive != 0) flexa::addEnergy(scene, eDrive, "driveWork", driveWorkIx, false);
	}
	maxVelocitySq = sweepMax;
	if (byNode)
		maxVelocitySq = std::max(maxVelocitySq, nodeBase);
	else
		flagElements();
}

} // namespace yade
