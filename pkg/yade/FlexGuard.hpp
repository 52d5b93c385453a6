// yade-flex adapter: FlexGuard, an engine that stops a run at the first sign of numerical
// instability and names the bodies involved (GPL-2.0-or-later).
//
// Checks, on one pass over the bodies every `interval` steps:
//  1. non-finite position, velocity, angular velocity, force or torque;
//  2. step length |v| dt above maxStepFraction x the body's contact radius (a sphere's radius;
//     for a FlexNode the smallest radius of its attached FlexCylinder/FlexFacet elements):
//     a contact cannot resolve an overlap that changes by a sizeable fraction of the radius in
//     one step, and a node moving by more than its wire's radius can tunnel through a wire;
//     in a blow-up |v| grows geometrically, so this fires long before the values overflow;
//  3. speed above maxSpeed (off by default);
//  4. with O.trackEnergy, energy created without external work: the balance residual
//         R = (O.energy.total() - total at the first check) - W_ext
//     where W_ext is the work done on the scene by permanent forces (O.forces.setPermF:
//     F . v dt; the work of kinematically driven DOFs, blocked DOFs that move, is in
//     O.energy as the integrator's 'driveWork'), relative to the energy scale
//         S = max over the checks so far of (sum_k |E_k| + |W_ext|)
//     (every term the run has booked, so S >= the impact or initial energy). A blow-up
//     creates energy that soon dominates every other term, so R / S -> 1; the integration
//     error of a stable run is a few percent of S at most (the wire-and-ring demo at
//     timestep safety 0.8: yadeflex.engines). The check fires when R > energyTolerance x S.
//
//  5. with O.trackEnergy, the same balance as booked (O.energy.total(), no leap-frog correction)
//     above rawEnergyTolerance x the energy put in (start, external work, gravity, drives, pressure): past the critical step the velocities alternate in sign and
//     grow, the corrected kinetic term 1/2 m v-.v+ turns negative and keeps the corrected
//     balance constant, while the booked one runs away.
//
// Forces added from Python each step (O.forces.addF in a PyRunner) are external work the guard
// cannot see: such scenes need energyTolerance = inf (or the work booked in O.energy).
//
// On detection: `message` and `bodies` are set and flexa::Unstable is thrown, which O.step()
// raises as yadeflex.Unstable (a RuntimeError) and O.run() reports through O.wait() (and O.run(n, True)). The guard
// should be the FIRST engine: it then inspects the state left by the previous step before any
// other engine of this step has run, and the scene is left exactly in that state (the step in
// which it threw does not count: O.iter is unchanged).
#pragma once
#include "FlexPch.hpp"

#include <sstream>
#include <vector>

namespace yade {

class FlexGuard : public GlobalEngine {
	std::vector<Real>       contactRadius; // per body id; +inf: no step check
	std::vector<Body::id_t> loaded;        // bodies with a permanent force or torque
	size_t                  cachedBodyCount = 0;
	long                    lastWorkIter    = -1;
	size_t                  lastEnergyCount = 0; // number of O.energy terms at the last check
	// Leap-frog energy identity (see FlexGuard.cpp): velocities at the previous step and the
	// external work of the step just taken, which the booked energies do not include yet
	std::vector<Vector3r> prevVel, prevAngVel;
	long                  prevVelIter       = -2;
	Real                  lastWorkIncrement = 0, startIncrement = 0;
	Real                  kineticCorrection() const;
	void                  storeVelocities();
	Real                  driveWork() const; // O.energy's driveWork (0 before any drive) [J]
	Real                  prevDrive = 0;     // driveWork when the velocities were stored [J]
	void                  refresh();
	void                  addExternalWork();
	// the checks of a step: 1-3 over the bodies, 4 on the energy balance (they throw on failure)
	void checkBodies();
	void checkEnergy(bool storeNow);
	// appends the bodies of largest kinetic energy to a message; returns their ids
	std::vector<Body::id_t> largestKinetic(std::ostringstream& os) const;
	[[noreturn]] void       fail(const std::string& what, const std::vector<Body::id_t>& ids);

public:
	/// Throws std::invalid_argument naming the first bad parameter.
	void validate() const;
	void postLoad(FlexGuard&) { validate(); }
	void action() override;
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR_PY(FlexGuard, GlobalEngine,
		"Stops a run at the first sign of numerical instability and names the bodies involved (yade-flex): non-finite state, a step longer than :yref:`FlexGuard.maxStepFraction` of a body's contact radius, a speed above :yref:`FlexGuard.maxSpeed`, or (with O.trackEnergy) energy created without external work beyond :yref:`FlexGuard.energyTolerance`. Sets :yref:`FlexGuard.message` and :yref:`FlexGuard.bodies` and throws: O.step() raises yadeflex.Unstable (a RuntimeError and a ValueError) with the message, O.run() stops and O.wait() raises it. Put it first in O.engines so that the state it reports is kept unchanged. See pkg/yade/FlexGuard.hpp for the definitions.",
		((int, interval, 1, Attr::triggerPostLoad, "Check every this many steps (>= 1); the external work is summed every step [-]"))
		((Real, maxStepFraction, 0.5, Attr::triggerPostLoad, "Largest step |v| dt as a fraction of the body's contact radius, in (0, inf]; inf: off [-]"))
		((Real, maxSpeed, std::numeric_limits<Real>::infinity(), Attr::triggerPostLoad, "Largest speed of any body, > 0; inf (default): off [m/s]"))
		((Real, energyTolerance, 0.25, Attr::triggerPostLoad, "Largest energy created without external work, as a fraction of the energy scale (see :yref:`FlexGuard.energyScale`), > 0; inf: off. Only with O.trackEnergy [-]"))
		((Real, maxKineticRatio, 10, Attr::triggerPostLoad, "Largest kinetic energy (YADE's form, 1/2 m v^2 at the half step) as a multiple of the energy put in (see :yref:`FlexGuard.energyInput`), > 0; inf: off. Only with O.trackEnergy. Catches the linear blow-up of a step above the critical one, which the leap-frog form of the balance cannot see (it stays constant while every term grows). A stable run stays below 1/(1 - (omega dt)^2/4) of it: 1.33 at half the critical step, 10 only within 5% of it [-]"))
		((Real, rawEnergyTolerance, 2.0, Attr::triggerPostLoad, "Largest energy created without external work in the balance as booked (O.energy.total(), kinetic energy at the half step, no leap-frog correction), as a multiple of the energy put in (see :yref:`FlexGuard.energyInput`), > 0; inf: off. Only with O.trackEnergy. Above the critical step the corrected balance stays constant while this one runs away; in a stable run at a fraction s of the critical step the two differ by at most (1/(1 - s^2) - 1) x the energy put in (0.33 at s = 0.5, 1.78 at 0.8) [-]"))
		((Real, rawEnergyStart, NaN, Attr::readonly, "O.energy.total() when energyStart was taken [J]"))
		((Real, rawEnergyResidual, 0, Attr::readonly, "(O.energy.total() - rawEnergyStart) - externalWork at the last check [J]"))
		((std::string, message, "", Attr::readonly, "What was detected (empty: nothing)"))
		((vector<int>, bodies, , Attr::readonly, "Ids of the bodies involved, worst first"))
		((long, detectedIter, -1, Attr::readonly, "O.iter at detection (-1: none)"))
		((Real, energyStart, NaN, Attr::readonly, "O.energy.total() at the first check after a step has booked energy (taken again after O.energy.clear()) [J]"))
		((Real, energyScale, 0, Attr::readonly, "Largest sum of |O.energy terms| + |externalWork| seen so far [J]"))
		((Real, energyResidual, 0, Attr::readonly, "Energy created without external work at the last check, (total - energyStart) - externalWork, taken at the last step's positions: kinetic energy in the form of the leap-frog identity, 1/2 m v_{n-1/2}.v_{n+1/2}, and the work of the step just taken left to the next check (see FlexGuard.cpp) [J]"))
		((Real, externalWork, 0, Attr::readonly, "Work done on the scene by moving blocked DOFs and permanent forces since energyStart was taken [J]"))
		((Real, maxStepSeen, 0, Attr::readonly, "Largest |v| dt / contact radius at the last check [-]"))
		((Real, energyInput, 0, Attr::readonly, "Energy put in, for maxKineticRatio: the largest |energyStart| + |externalWork| + |work of gravity| (O.energy['gravWork']) + |work of pressure| (O.energy['flexPressureWork']) seen since energyStart was taken [J]"))
		((Real, kineticSeen, 0, Attr::readonly, "Kinetic energy at the last check, as the integrator booked it in the step just taken (O.energy['kinetic'], or kinTrans + kinRot) [J]")),
		,
		.def("reset", &FlexGuard::resetPy, "Forget a detection and the energy reference (the next check starts a new balance).")
	);
	// clang-format on
	void resetPy();
};
REGISTER_SERIALIZABLE(FlexGuard);

} // namespace yade
