// The contacts between spheres (grains) on arrays of their own, one state beside each pair of a
// GrainNeighbours list (GPL-2.0-or-later).
//
// The law is yade-flex's frictional contact between two spheres, step for step what the plugin
// does for a sphere-sphere contact (Ig2_Sphere_Sphere_FlexContactGeom and
// Law2_FlexContactGeom_FrictPhys_CundallStrack, without crushing): a contact starts when the
// spheres overlap, with no shear; normal force kn d (d the overlap), shear force by
// increments ks du capped at tanPhi |Fn| (cappedSpringStep), rolling moment by increments
// kr dtheta capped at eta R |Fn| (kr = rollingStiffness ks R^2, R = r1 r2 / (r1 + r2)), the onset
// and release correction of Crossing.hpp (contacts kept two steps past separation for it), and
// the same energy terms (elastic, friction, rolling). Force F on sphere 2 at the contact point c
// and -F on sphere 1, each with the moment of its lever about the sphere's centre: sum of
// forces zero, sum of moments about any point zero.
//
// A contact's state is 152 bytes stored in pair order (the order of GrainNeighbours): the pass
// reads the pairs, the states and the spheres' arrays as streams, where the plugin reads three
// heap objects per interaction (the interaction, its geometry and its physics, 624 bytes).
#pragma once
#include "Crossing.hpp"
#include "GrainNeighbours.hpp"

#include <vector>

namespace flex {

/// One material for every grain (the plugin's Ip2_FrictMat_FrictMat_FrictPhys with equal
/// materials: kn = 2 E r1 r2 / (r1 + r2), ks = ksOverKn kn) and the law's settings.
struct GrainLaw {
	double young            = 0; ///< E [Pa]
	double ksOverKn         = 0; ///< [-] (FrictMat.poisson in YADE's Ip2)
	double tanPhi           = 0; ///< friction coefficient [-]
	double rollingStiffness = 0; ///< kr / (ks R^2) [-]; 0: no rolling resistance
	double rollingFriction  = 0; ///< eta [-]
	double onsetFactor      = 2; ///< a deep onset: overlap > onsetFactor x approach x dt
	bool   crossing         = true;
	bool   trackEnergy      = true;
	/// The stiffness a new contact of spheres of radii r1, r2 gets, with Ip2_FrictMat_FrictMat_FrictPhys's
	/// arithmetic (ks 0 where that gives 0 / 0: ksOverKn 0).
	void stiffness(double r1, double r2, double& kn, double& ks) const
	{
		const double E = young, V = ksOverKn;
		kn = 2 * E * r1 * E * r2 / (E * r1 + E * r2);
		ks = 2 * E * r1 * V * E * r2 * V / (E * r1 * V + E * r2 * V);
		if (!(ks == ks)) ks = 0;
	}
};

/// The spheres as the pass reads them (arrays by sphere index).
struct GrainMotion {
	const Vec3*   pos;
	const Vec3*   vel;
	const Vec3*   angVel;
	const double* radius;
	const double* invMass; ///< 1 / m, 0 for a sphere that cannot move
	long          n;
};

/// What the pass adds up: forces and torques (+=, by sphere index) and the energy terms.
struct GrainSums {
	Vec3*  force;
	Vec3*  torque;
	double elastic         = 0;                ///< stored in the springs at this step [J]
	double friction        = 0;                ///< dissipated by sliding this step [J]
	double rolling         = 0;                ///< dissipated by rolling this step [J]
	long   touching        = 0;                ///< contacts carrying force (touching) at this step
	long   deepOnsets      = 0;                ///< contacts starting deeper than onsetFactor x approach x dt
	double deepOnsetEnergy = 0;                ///< their springs' energy [J]
	double maxOverlapRatio = 0;                ///< largest d / (r1 + r2) of an active contact
	long   maxOverlapI = -1, maxOverlapJ = -1; ///< its spheres, when this pass raised it (else unchanged)
};

class GrainContacts {
public:
	explicit GrainContacts(const GrainLaw& law);

	/// Carry the contacts of the list they follow over to nb's list (after nb.build): a pair in
	/// both keeps its state. Returns the contacts that had no place in the new list (0 while the
	/// list is built before any sphere moves half the skin).
	long follow(const GrainNeighbours& nb);
	/// Take nb's list with no contacts (the spheres are not those of the list followed; their
	/// contacts are then put back with at()).
	void restart(const GrainNeighbours& nb);
	/// Other settings (the contacts keep their states; a contact's kn and ks stay those it started with).
	void setLaw(const GrainLaw& law);
	/// One step at iteration iter (consecutive steps: iter + 1) of length dt [s].
	void step(const GrainMotion& m, long iter, double dt, GrainSums& sums) { step(m, iter, dt, sums, 0, (long)first_.size() - 1); }
	/// The pairs of spheres [begin, end) only (their first sphere in that range): parts that
	/// cover the spheres, run at once on several threads each with sums of its own, together
	/// make one step (each pair's state is written by its part only).
	void step(const GrainMotion& m, long iter, double dt, GrainSums& sums, long begin, long end);
	/// The first sphere of part k of `parts` (k = parts: the number of spheres), the parts
	/// holding about equal numbers of pairs.
	long splitAt(int k, int parts) const;

	/// Contacts alive (touching, or kept past their separation for the correction).
	long contacts() const;
	/// Touching at the last step.
	long            active() const;
	const GrainLaw& law() const { return law_; }

	/// A contact's state (by pair index).
	struct State {
		Vec3          shear  = Vec3::Zero(); ///< shear force on sphere 2 [N]
		Vec3          roll   = Vec3::Zero(); ///< rolling moment on sphere 2 [N m]
		Vec3          normal = Vec3::UnitZ();
		double        kn = 0, ks = 0;
		CrossingState cross;                           ///< the onset and release correction's
		long          crossIter = -2, lastActive = -2; ///< the last steps it was updated / touching
		bool          exists = false;
	};
	const std::vector<State>& states() const { return state_; }
	/// The state of pair (i, j), i < j, of the list followed; null if the pair is not listed.
	State* at(long i, int j);
	/// The list followed (CSR, as GrainNeighbours::first and second).
	const std::vector<long>& first() const { return first_; }
	const std::vector<int>&  second() const { return second_; }

private:
	GrainLaw           law_;
	std::vector<long>  first_; // the pair list the states follow (a copy of GrainNeighbours')
	std::vector<int>   second_;
	std::vector<State> state_;
};

} // namespace flex
