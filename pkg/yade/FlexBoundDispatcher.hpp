// yade-flex adapter (GPL-2.0-or-later): the collider's BoundDispatcher, without the zero sweep
// that makes the collider run on most steps of a bed at rest.
//
// Why: with InsertionSortCollider.targetInterv > 0 (YADE's default, 100), BoundDispatcher gives
// each bound a sweep from how far its body moved since the bound's last update, and a sweep of
// zero to a body that did not move at all. A grain of a settled bed often has not (the collider
// ran a step or a few before); its bound is then not enlarged, and the next round-off motion of
// its centre (1e-18 m) is a displacement past its sweep, which makes the integrator ask for
// the collider again. Each run leaves more grains with zero sweep: the collider ran on one step
// in four on the module's bed at rest (bench/README.md, "The collider after a reload").
//
// What: BoundDispatcher's pass unchanged, then every bound it made this step with a zero sweep for
// a body that moves (dynamic, or given a velocity) gets the smallest sweep BoundDispatcher ever
// gives a moving body (minSweepDistFactor x sweepDist), its box enlarged by it. Static bodies
// (walls, fixed facets) keep their zero sweep. The pairs this adds are potential pairs only.
// FlexNewtonIntegrator puts it in place of the collider's own dispatcher (sweepFloor).
#pragma once
#include "FlexPch.hpp"

namespace yade {
class Scene;

class FlexBoundDispatcher : public BoundDispatcher {
public:
	void action() override;
	/// Make the scene's InsertionSortCollider (if any) use a FlexBoundDispatcher (on) or YADE's
	/// BoundDispatcher (off) with the functors of the one it has (a dispatcher of another class
	/// is left alone); returns whether a FlexBoundDispatcher is in place.
	static bool install(const Scene* scene, bool on);
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS(FlexBoundDispatcher, BoundDispatcher,
		"BoundDispatcher that never leaves a moving body's bound with a zero sweep (yade-flex): YADE's gives a zero sweep to a body that did not move since its bound's last update (InsertionSortCollider.targetInterv > 0), and the collider then runs again as soon as its centre moves by round-off. Put in place of the collider's own by FlexNewtonIntegrator (sweepFloor); see pkg/yade/FlexBoundDispatcher.hpp.",
		((long, floored, 0, Attr::readonly, "Bounds given the smallest sweep instead of zero on the collider's last run [-]"))
	);
	// clang-format on
};
REGISTER_SERIALIZABLE(FlexBoundDispatcher);

} // namespace yade
