// yade-flex adapter: FlexTimeStepper, the critical time step from bonds and contacts
// (GPL-2.0-or-later). Declaration: FlexTimeStepper.hpp; the contact rows' derivation:
// pkg/kernel/ContactRows.hpp.
#include "speed/FlexStepperContacts.hpp"
#include "FlexRefuse.hpp"
#include "FlexElementEngine.hpp"
#include "FlexElements.hpp"
#include "FlexLaws.hpp"
#include "FlexProtocol.hpp"
#include "FlexSceneCheck.hpp"
#include "speed/FlexTuning.hpp"
#include "FlexUnstable.hpp"

#include <sstream>
#include <kernel/ClosestPoints.hpp>
#include <kernel/ContactRows.hpp>
#include <kernel/TimeStep.hpp>
#include <kernel/Triangle.hpp>

#include <core/InteractionLoop.hpp>
#include <pkg/common/InsertionSortCollider.hpp>
#include <lib/factory/ClassFactory.hpp>
#include <pkg/common/NormShearPhys.hpp>

#include <algorithm>
#ifdef YADE_OPENMP
#include <omp.h>
#endif

namespace yade {

YADE_PLUGIN((FlexTimeStepper));

using flexa::stepper::ContactRowsPass;

namespace {
	// Irons' bound with the element's own mass shares. If a node is lighter than the sum of the
	// shares attached to it (user-modified mass), scale that element's omega^2 up. The elements
	// are found in the estimate's table of the bodies (sb, in id order), not by a pass over the
	// bodies of its own.
	Real bondsOmega2(const Scene* scene, const std::vector<flexa::stepper::StepBody>& sb, Body::id_t& stiffest)
	{
		auto&             bodies = *scene->bodies;
		std::vector<Real> sumM(bodies.size(), 0), sumI(bodies.size(), 0);
		struct Share {
			const flexa::Element e;
			Real                 m, I, w2;
			Body::id_t           id;
		};
		std::vector<Share> shares;
		const long         nb = std::min((long)sb.size(), (long)bodies.size());
		for (long id = 0; id < nb; ++id) {
			const flexa::Element& e = sb[id].el;
			if (!e.nNodes) continue;
			// each element states its own bound (a membrane's at the strains FlexElementEngine
			// computed this step)
			if (e.cyl && e.cyl->attached)
				shares.push_back({ e, e.cyl->massShare, e.cyl->inertiaShare, e.cyl->stepOmega2(), (Body::id_t)id });
			else if (e.fac && e.fac->attached) {
				const shared_ptr<Body>& b = bodies[id];
				shares.push_back(
				        { e, e.fac->massShare, e.fac->inertiaShare, e.fac->stepOmega2(b ? b->material.get() : nullptr), (Body::id_t)id });
			}
		}
		for (const Share& sh : shares)
			for (int k = 0; k < sh.e.nNodes; ++k) {
				sumM[sh.e.nodes[k]] += sh.m;
				sumI[sh.e.nodes[k]] += sh.I;
			}
		Real w2  = 0;
		stiffest = -1;
		for (const Share& sh : shares) {
			bool moves = false; // an element whose nodes are all clamped has no mode of its own
			for (int k = 0; k < sh.e.nNodes && !moves; ++k) {
				const shared_ptr<Body>& nb = bodies[sh.e.nodes[k]];
				moves                      = nb && nb->isDynamic() && nb->state->blockedDOFs != State::DOF_ALL;
			}
			if (!moves) continue;
			// the element's omega^2 with the nodes' actual masses, each node's mass split among its
			// elements in proportion to their shares: at most omega2 x the largest share-to-mass ratio
			// (Irons), below omega2 where every node is heavier than its shares (mass scaling)
			Real scale = 0;
			for (int k = 0; k < sh.e.nNodes; ++k) {
				const int               nid = sh.e.nodes[k];
				const shared_ptr<Body>& nb  = bodies[nid];
				if (!nb || !nb->isDynamic()) continue;
				const State& s = *nb->state;
				if (s.mass > 0) scale = std::max(scale, sumM[nid] / s.mass);
				const Real I = s.inertia.minCoeff();
				if (I > 0) scale = std::max(scale, sumI[nid] / I);
			}
			// nodes as heavy as their shares (up to the round-off of summing them): the element's own
			// omega2, as computed
			if (scale == 0 || scale > 1 - 1e-9) scale = std::max(scale, Real(1));
			if (sh.w2 * scale > w2) {
				w2       = sh.w2 * scale;
				stiffest = sh.id;
			}
		}
		return w2;
	}
} // namespace

Real FlexTimeStepper::omega2Bonds() const { return bondsOmega2(scene, flexa::stepper::stepBodies(scene), stiffestBondBody); }

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
	ContactRowsPass pass(scene, prefetch, skipUnreachable, mark, skippedOut);
	return pass.run(stiffestContactBody, skippedCache);
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
	// (one table of the bodies for both bounds; the pass that made the marks before the loop of
	// this step, if they hold)
	std::shared_ptr<ContactRowsPass> pp;
	if (mark && marksBeforeLoop && earlyPass && earlyPassIter == scene->iter && earlyMarksHold()) {
		pp = std::static_pointer_cast<ContactRowsPass>(earlyPass);
		pp->adoptMarks();
	} else
		pp = std::make_shared<ContactRowsPass>(scene, prefetch, skipUnreachable, mark, nullptr);
	earlyPass.reset();
	ContactRowsPass& pass = *pp;
	const Real       wc   = pass.run(stiffestContactBody, skippedCache);
	const Real      wb = bondsOmega2(scene, pass.bodies(), stiffestBondBody);
	stillCache         = pass.still();
	stiffestCache      = wc >= wb ? stiffestContactBody : stiffestBondBody;
	return flex::criticalTimeStep((1 + c) * (wb + wc));
}

bool FlexTimeStepper::earlyMarksHold() const
{
	const flexa::UnreachableMarks& m = flexa::sceneState(scene).unreachable;
	if (!m.valid(scene) || m.earlyIter != scene->iter || m.earlyErasures != flexa::sceneState(scene).elementErasures) return false;
	const auto&  E  = scene->engines;
	const size_t me = std::find_if(E.begin(), E.end(), [this](const shared_ptr<Engine>& e) { return e.get() == this; }) - E.begin();
	if (me >= E.size() || m.earlyLoopIx >= me) return false;
	for (size_t k = m.earlyLoopIx + 1; k < me; ++k)
		if (E[k] && !E[k]->dead && typeid(*E[k]) != typeid(FlexElementEngine)) return false;
	return true;
}

void FlexTimeStepper::markBeforeLoop(size_t loopIx)
{
	if (!skipUnreachable || !markUnreachable || !marksBeforeLoop || scene->isPeriodic || flexa::insertionSortColliderRuns(scene) < 0) return;
	auto pass = std::make_shared<ContactRowsPass>(scene, prefetch, skipUnreachable, true, nullptr);
	pass->markOnly(loopIx);
	earlyPass     = pass; // (for the estimate at the end of this step)
	earlyPassIter = scene->iter;
}

void FlexTimeStepper::validate() const
{
	auto bad = [this](const char* name, Real v, const char* need) { flexa::refuseAttribute(*this, name, v, need); };
	if (interval < 1) bad("interval", interval, ">= 1");
	if (!(safety > 0) || safety > 1) bad("safety", safety, "in (0, 1]");
	if (!(minDtFraction >= 0) || !std::isfinite(minDtFraction)) bad("minDtFraction", minDtFraction, "finite and >= 0");
}

void FlexTimeStepper::action()
{
	flexa::checkScene(scene, this);
	validate(); // (a value refused when set stays stored: it must not run)
	if (earlyPass && earlyPassIter != scene->iter) earlyPass.reset(); // (made on a step without an estimate)
	// Also whenever the collider ran: only the collider adds (potential) interactions, and a new
	// pair may be stiffer than any counted so far. Contacts ending between collider runs can only
	// lengthen the critical step: they wait for the next update. (Not at every change of the
	// interaction count: in a granular impact contacts end at almost every step, and the estimate
	// would run at each.) Without an InsertionSortCollider: at every change of the count, as before.
	const long   colliderRuns = flexa::insertionSortColliderRuns(scene);
	const size_t nIntr        = scene->interactions->size();
	// and whenever a FlexGrainEngine built its neighbour list again (it alone adds grain pairs)
	long grainBuilds = 0;
	flexa::forEachGrainEngine(scene, [&](const FlexGrainEngine& ge) { grainBuilds += ge.builds; });
	// and whenever a facet the last estimate took as standing still moved (its pairs were left out)
	const bool stillMoved = !flexa::allStandStill(scene, stillCache);
	const bool changed
	        = (colliderRuns >= 0 ? colliderRuns != lastColliderRuns : nIntr != lastInteractionCount) || grainBuilds != lastGrainBuilds || stillMoved;
	lastGrainBuilds      = grainBuilds;
	lastInteractionCount = nIntr;
	lastColliderRuns     = colliderRuns;
	if (!markUnreachable) flexa::sceneState(scene).unreachable.set = false; // switched off: retire the marks
	if (scene->iter % interval != 0 && dtCritical > 0 && !changed) return;
	dtCritical   = criticalImpl(markUnreachable);
	stiffestBody = stiffestCache;
	skippedPairs = skippedCache;
	if (std::isfinite(dtCritical) && minDtFraction > 0) {
		if (!(dtReference > 0)) dtReference = dtCritical;
		if (dtCritical < minDtFraction * dtReference) {
			std::ostringstream os;
			os.precision(4);
			os << "the critical time step collapsed from " << dtReference << " s to " << dtCritical
			   << " s (below FlexTimeStepper.minDtFraction = " << minDtFraction << " of it) at iter " << scene->iter << ", t = " << scene->time
			   << " s; it is set by body #" << stiffestBody;
			if (const Body* b = flexa::bodyAt(scene, stiffestBody))
				if (b->shape) os << " (" << b->shape->getClassName() << ")";
			throw flexa::Unstable(os.str());
		}
	}
	if (std::isfinite(dtCritical)) scene->dt = safety * dtCritical;
}

} // namespace yade
