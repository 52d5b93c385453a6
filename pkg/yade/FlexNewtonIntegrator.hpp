// yade-flex adapter (GPL-2.0-or-later): the NewtonIntegrator that skips element bodies (no DOF) and tells the
// collider when an element moved, from both of its nodes.
#pragma once
#include "FlexPch.hpp"
#include "speed/FlexTuning.hpp"

namespace yade {

class FlexNewtonIntegrator : public NewtonIntegrator {
	std::vector<Body::id_t> movers, elements, facets; // bodies with DOFs / cylinder and facet bodies (cached)
	size_t                  cachedBodyCount = 0;
	bool                    simple          = false; // no clump, no aspherical body: the fast path applies
	void                    refresh();
	void                    flagElements(); // collider trigger from element nodes (both paths)
	// the same trigger per node on the fast path (see buildNodeTable in FlexNewtonIntegrator.cpp)
	std::vector<char>     isMover;
	std::vector<char>     isSphere; // by id: a plain Sphere (sphereOrientation)
	std::vector<Real>     nodeSweep;       // smallest sweep of the bounds of the node's elements, -1: none
	std::vector<Vector3r> nodeRef;         // node position when those bounds were built
	Real                  nodeBase    = 0; // 0.5 if some element has a bound (flagElements' "inside")
	bool                  nodeTableOk = false;
	long                  tableRuns = -2, tableErasures = -1;
	const void*           tableState = nullptr; // the flexa::SceneState the table was built for
	bool                  buildNodeTable();
	Real                  dampingOnBlockedDofs(); // what NewtonIntegrator books on blocked DOFs this step [J]
	Real                  driveWork();            // booked for the driven DOFs this step (flex::driveWork) [J]
	int                   driveWorkIx = -1;
	// the passes of a step (action)
	void integrateWithYade(); // where the fast path does not apply
	void updateNodeTable();
	void integrate(); // the fast path

public:
	void action() override;
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS(FlexNewtonIntegrator, NewtonIntegrator,
		"NewtonIntegrator for scenes with yade-flex elements. Element bodies (:yref:`FlexCylinder`) carry no DOF: they are skipped (FlexElementEngine keeps their position), and the collider is told to run when either NODE of an element left its bound's sweep (NewtonIntegrator only sees the element's midpoint, which moves half as far as the free end of a swinging element). Same leap-frog, damping and energy terms as NewtonIntegrator (except that local damping is booked in nonviscDamp on free DOFs only: NewtonIntegrator also books |v||F| c dt on blocked, driven DOFs, where no damping acts; on its fallback to NewtonIntegrator's loop this class takes that share back), clumps included (members' forces summed about the clump's centre, members moved with it). The work done by prescribed motion (a blocked DOF moving at the velocity the user or an engine gave it: an indenter, a plate, a pulled edge) is booked as 'driveWork' in O.energy, in gravWork's sign (minus the work put in), so that the energy balance of a driven test closes as that of a free impact (kernel/LeapFrog.hpp); scenes with periodic cells, aspherical bodies (a clump whose inertia is not isotropic is flagged aspherical by YADE), masks or density scaling use NewtonIntegrator's own loop.",
		((bool, usedFastPath, false, Attr::readonly, "Whether the last step used the fast path"))
		((bool, prefetch, true, , "On the fast path, ask for the bodies' data a few bodies ahead, when at least 512 bodies move (fewer stay in cache between steps); same results; False: for comparisons"))
		((bool, sphereOrientation, false, , "On the fast path, integrate the orientation of plain spheres (Sphere shapes) too. No force of YADE or yade-flex depends on a sphere's orientation (its angular velocity is integrated, and drives rolling and shear), so by default it is left as it is, which saves a sine, a cosine and a quaternion product per sphere and step; True: as NewtonIntegrator (to follow a sphere's turning, or to compare)"))
		((bool, sweepFloor, true, , "Give the collider (InsertionSortCollider) a FlexBoundDispatcher, which never leaves a moving body's bound with a zero sweep: with YADE's own, a grain that did not move between two bound updates gets one, and the collider then runs again as soon as its centre moves by round-off (on most steps of a bed at rest). Same contacts; the collider runs less often. False: YADE's BoundDispatcher (for comparisons)"))
		((bool, sweepFloorInPlace, false, Attr::readonly, "Whether the collider had a FlexBoundDispatcher on the last step (sweepFloor)"))
		((int, parallelMin, flexa::tuning::kIntegratorParallelMin, , "Integrate on several threads only from this many bodies on (see FlexElementEngine.parallelMin) [-]"))
	);
	// clang-format on
};
REGISTER_SERIALIZABLE(FlexNewtonIntegrator);

} // namespace yade
