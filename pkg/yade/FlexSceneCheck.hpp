// yade-flex adapter: the scene check that every yade-flex engine runs before it reads the scene
// (GPL-2.0-or-later).
//
// Python can change any attribute between two steps: an element's node ids, a radius, a mass, a
// position, a material's modulus. The engines index arrays by node id and cast a node's shape to
// FlexNode, so a wrong id would crash YADE, and a NaN or a zero mass would run on as NaN. The
// check runs at the start of each step (the first yade-flex engine of the step does it; the
// others find it done) and throws std::invalid_argument naming the body and the field, before
// anything of the step is computed. Its full pass over every body runs whenever a script can have
// changed something since the last step: at the first step of each O.run() and each O.step(),
// after a step in which a PyRunner (or another periodic engine) ran, when the engine list, the
// interaction container or the number of bodies changed, after a step whose states the yade-flex
// integrator did not vouch for (its fast path refuses the positions and velocities it makes
// non-finite), and at least every tuning::kFullCheckPeriod steps. What it refuses:
//  - an element (FlexCylinder, FlexFacet) whose node ids are not distinct FlexNode bodies, or
//    whose radius is not finite and positive; a sphere whose radius is not;
//  - a body with a non-finite (or above 1e100 in magnitude) position, orientation, velocity, angular velocity, mass or
//    inertia, a negative mass or inertia, or a free (dynamic, not fully blocked) body other than
//    an element or a clump member with zero mass;
//  - a contact material (FrictMat) with a non-finite or non-positive young, a negative or
//    non-finite poisson or friction angle; a FlexMat with a non-positive element modulus or a
//    beamPoisson outside (-1, 0.5); a FlexMembraneMat with a non-positive stiffness or a
//    membranePoisson outside [0, 0.5) (the membrane's stiffness bound holds for nu >= 0);
//  - an integrator's damping outside [0, 1) or a non-finite gravity; a yade-flex contact law's
//    rolling stiffness, rolling friction or onset factor that is negative or not finite.
#pragma once
#include "FlexPch.hpp"

namespace yade {
namespace flexa {
	/// Throws std::invalid_argument naming the body (or material) and the field at the first
	/// problem found. Runs once per step, in full when a script can have changed the scene since
	/// the last step (see checkScene's fullCheckDue). `caller`: the engine
	/// asking; the first to ask in a step asks for the step, so its asking again at the same
	/// iteration is a step run again (after one that threw: a refused step leaves the bodies it
	/// moved moved, O.iter and O.time where they were) and is checked again.
	void checkScene(const Scene* scene, const void* caller);
	/// The scene's next step is checked in full (for callers that run steps themselves).
	void checkNextStepInFull(const Scene* scene);
	/// While one lives, the steps this thread runs have no script between them although Python's
	/// lock is held (FlexRun.until: as O.step() it keeps the lock, handing it to other threads would
	/// cost a switch interval each time it is taken back); the check then does not take the lock
	/// as a sign that a script ran.
	struct ScriptFreeSteps {
		ScriptFreeSteps();
		~ScriptFreeSteps();
		ScriptFreeSteps(const ScriptFreeSteps&)            = delete;
		ScriptFreeSteps& operator=(const ScriptFreeSteps&) = delete;
	};
	/// Largest magnitude taken for a coordinate, velocity, radius, mass or inertia: the contact
	/// and energy arithmetic multiplies up to three such values (k d^2, m v^2), which then stay
	/// finite in double precision (1e100^3 = 1e300 < 1.8e308).
	constexpr Real kHugeValue = 1e100;
	/// Position, orientation, velocity and angular velocity all finite and below kHugeValue (one
	/// test for the lot: the integrator asks it of every body it moves).
	inline bool motionValid(const State& s)
	{
		constexpr Real     h  = kHugeValue;
		const Vector3r&    p  = s.se3.position;
		const Quaternionr& q  = s.se3.orientation;
		bool               ok = (std::abs(p[0]) < h) & (std::abs(p[1]) < h) & (std::abs(p[2]) < h);
		ok &= (std::abs(q.w()) < h) & (std::abs(q.x()) < h) & (std::abs(q.y()) < h) & (std::abs(q.z()) < h);
		ok &= (std::abs(s.vel[0]) < h) & (std::abs(s.vel[1]) < h) & (std::abs(s.vel[2]) < h);
		ok &= (std::abs(s.angVel[0]) < h) & (std::abs(s.angVel[1]) < h) & (std::abs(s.angVel[2]) < h);
		return ok;
	}
	/// Throws std::invalid_argument: body `id`'s motion (motionValid false) became non-finite in
	/// the step the integrator just took; names the field, the force and the torque on the body.
	[[noreturn]] void refuseIntegrated(const Scene* scene, Body::id_t id, const Vector3r& force, const Vector3r& torque);
	/// O.dt finite and positive (the integrator asks, after the time stepper had its turn).
	void checkTimeStep(const Scene* scene);
} // namespace flexa
} // namespace yade
