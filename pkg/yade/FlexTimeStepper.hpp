// yade-flex adapter (GPL-2.0-or-later): the critical time step from bonds and contacts.
#pragma once
#include "FlexPch.hpp"

#include <memory>

namespace yade {

namespace flexa {
	/// FlexTimeStepper.safety's default, and yadeflex.engines()' (which reads it from the class).
	constexpr Real kDefaultTimeStepSafety = 0.5;
} // namespace flexa

class FlexTimeStepper : public GlobalEngine {
	size_t lastInteractionCount = 0;
	long   lastColliderRuns     = -1;
	long   lastGrainBuilds      = 0; // FlexGrainEngine.builds, summed
	// where the last bounds came from (const estimates record them)
	mutable Body::id_t stiffestBondBody = -1, stiffestContactBody = -1, stiffestCache = -1;
	mutable long       skippedCache = 0;
	mutable std::vector<Body::id_t> stillCache; // the facets the last estimate took as standing still
	// the pass that made the marks before the loop of step earlyPassIter (flexa::stepper::ContactRowsPass)
	mutable std::shared_ptr<void> earlyPass;
	mutable long                  earlyPassIter = -1;

public:
	/// Largest omega^2 of bonds and of contacts (see pkg/kernel/TimeStep.hpp) [1/s^2].
	Real omega2Bonds() const;
	Real omega2Contacts() const;
	// skippedOut: collects the pairs left out; mark: also mark them for the geometry functors
	// (flexa::UnreachableMarks; only from action(), the engine's own serial run)
	Real omega2ContactsImpl(std::vector<std::pair<Body::id_t, Body::id_t>>* skippedOut, bool mark) const;
	Real criticalImpl(bool mark) const;
	// whether the marks were made before the loop of this step (markBeforeLoop) and nothing since
	// can have changed what this estimate would mark: only FlexElementEngine (or dead engines)
	// between that loop and this engine, and no element erased
	bool earlyMarksHold() const;
	/// The unreachable marks alone, made now as the next estimate would make them (with
	/// skipUnreachable, markUnreachable and marksBeforeLoop; else nothing): called by the
	/// FlexInteractionLoop at place loopIx in O.engines on a step the collider ran.
	void markBeforeLoop(size_t loopIx);
	/// the potential pairs the estimate leaves out now (see skipUnreachable), for tests
	boost::python::list unreachablePairs() const;
	Real                critical() const;
	/// Throws std::invalid_argument naming the first bad parameter (called when one is set).
	void validate() const;
	void postLoad(FlexTimeStepper&) { validate(); }
	void action() override;
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR_PY(FlexTimeStepper, GlobalEngine,
		"Sets O.dt to safety x the critical step of the central-difference integrator, bounded from the bonds (element eigenvalue inequality) and from all contacts with NormShearPhys (Gershgorin row sums with the node weights), translational and rotational, including potential contacts found by the collider (with the stiffness FrictMat contacts will have) that could start before the collider runs again (see skipUnreachable), so that a contact never starts with a step too long for it, and divided by sqrt(1 + NewtonIntegrator.damping) (Cundall's damping scales accelerations by up to 1 + damping). Runs every :yref:`FlexTimeStepper.interval` steps and whenever the collider ran (it alone adds interactions; without an InsertionSortCollider: whenever the number of interactions changes).",
		((Real, safety, flexa::kDefaultTimeStepSafety, Attr::triggerPostLoad, "Fraction of the critical step, in (0, 1]; yadeflex.engines() uses the same default [-]"))
		((int, interval, 50, Attr::triggerPostLoad, "Recompute every this many steps, >= 1 [-]"))
		((Real, dtCritical, NaN, Attr::readonly, "Last critical step [s]"))
		((Body::id_t, stiffestBody, -1, Attr::readonly, "Body that set the last critical step: the element with the largest bond omega^2, or the body (node, sphere) with the largest contact row, whichever bound is larger [-]"))
		((bool, skipUnreachable, true, , "Leave out potential contacts that cannot start before the collider runs again (their gap exceeds how far both sides can still travel inside the sweep of their bounds; needs an InsertionSortCollider before this engine; not in periodic scenes). The yade-flex geometry functors (and FlexInteractionLoop, for YADE's facet-sphere functor) then also skip those pairs until the collider runs again, instead of computing their distance at every step. False: count every potential contact (for comparisons)."))
		((bool, markUnreachable, true, , "With skipUnreachable: also let the yade-flex geometry functors skip the pairs left out, until the collider runs again (they cannot touch before then, so results are the same bit for bit; see bench/README.md); and leave out the pairs of YADE facets that stand still (not dynamic, no velocity: a container's sides), while they do (the estimate is made again when one moves). A body moved by assigning its position (not by the integrator) is seen by the collider one step late; a skipped pair may then miss that one step of contact, as YADE's collider misses a pair it never listed."))
		((bool, marksBeforeLoop, true, , "With markUnreachable: on a step the collider ran, make the marks at the start of FlexInteractionLoop (which calls this engine for them), from the positions this engine's estimate at the end of the step sees too, so that the loop and the functors leave those pairs out on that step as well (until then they were tested in full on every step the collider ran); the estimate then takes them as its own. The same results bit for bit; False: for comparisons."))
		((bool, prefetch, true, , "Ask for the interactions' data a few iterations ahead in the loop over interactions (same results; False: for comparisons)"))
		((long, skippedPairs, 0, Attr::readonly, "Potential contacts left out of the last estimate by :yref:`FlexTimeStepper.skipUnreachable` [-]"))
		((Real, minDtFraction, 0, Attr::triggerPostLoad, "Stop the run (yadeflex.Unstable, naming the stiffest body) when the critical step falls below this fraction of dtReference: a collapsed step (a crushed facet, a light node under a stiff contact) would run on for ever at a vanishing step; 0: never [-]"))
		((Real, dtReference, 0, , "The critical step minDtFraction compares with; 0: the next estimate sets it (set it to 0 to start again, e.g. at an impact) [s]")),
		,
		.def("critical", &FlexTimeStepper::critical, "Critical step of the current scene [s] (no change to O.dt)")
		.def("omega2Bonds", &FlexTimeStepper::omega2Bonds, "Bound of the largest omega^2 from bonds [1/s^2]")
		.def("omega2Contacts", &FlexTimeStepper::omega2Contacts, "Bound of the largest omega^2 from contacts [1/s^2]")
		.def("unreachablePairs", &FlexTimeStepper::unreachablePairs, "Potential contacts (id1, id2) that the estimate leaves out in the current state: they cannot start before the collider runs again (see skipUnreachable)")
	);
	// clang-format on
};
REGISTER_SERIALIZABLE(FlexTimeStepper);

} // namespace yade
