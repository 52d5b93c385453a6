// yade-flex adapter: the scene check that every yade-flex engine runs before it reads the scene
// (GPL-2.0-or-later).
//
// Python can change any attribute between two steps: an element's node ids, a radius, a mass, a
// position, a material's modulus. The engines index arrays by node id and cast a node's shape to
// FlexNode, so a wrong id would crash YADE, and a NaN or a zero mass would run on as NaN. The
// check runs once per step (the first yade-flex engine of the step does it; the others find it
// done) and throws std::invalid_argument naming the body and the field, before anything of the
// step is computed. What it refuses:
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
	/// problem found. Checks each scene once per iteration; `force`: check again.
	void checkScene(const Scene* scene, bool force = false);
	/// O.dt finite and positive (the integrator asks, after the time stepper had its turn).
	void checkTimeStep(const Scene* scene);
} // namespace flexa
} // namespace yade
