// Deformable cylinder as a co-rotational Euler-Bernoulli beam between two nodes.
//
// Frames. Each node carries a position x and an orientation o (unit quaternion, body to
// global). At bond creation the element frame R0 maps the local x axis onto the chord
// e0 = (xj - xi)/L0. We store the element frame seen from each node, Qi = conj(oi0) R0 and
// Qj = conj(oj0) R0, so that the current "element frame according to node k" is Rk = ok Qk.
// Under a rigid motion (x -> Q x + c, o -> Q o) the chord and both Rk turn by Q together:
// every deformation measure below is unchanged, so a rigid motion of any size gives no
// force (objectivity).
//
// Deformation measures (all invariant):
//   L     = |xj - xi|, e = (xj - xi)/L, axial strain eps = (L - L0)/L0
//   th_k  = rotation vector taking the chord e onto the x axis of Rk (bending at node k,
//           perpendicular to e)
//   phi   = twist: rotation about x of conj(Ri) Rj (swing-twist decomposition)
// Forces on the nodes (derivation in Beam.cpp):
//   axial  F_j = -N e,  F_i = +N e,          N = EA (eps - eps_p) (tension positive)
//   bending M_i = -(EI/L0)(4 th_i + 2 th_j),  M_j = -(EI/L0)(2 th_i + 4 th_j)
//           F_j += e x (M_i + M_j) / L,      F_i -= the same
//   twist  M_i += (GJ/L0) phi e,  M_j -= (GJ/L0) phi e
// Forces and moments of an element sum to zero exactly (any point as reference). For small
// displacements these are the 12x12 Euler-Bernoulli beam stiffness (EA/L, 12EI/L^3, 6EI/L^2,
// 4EI/L, 2EI/L, GJ/L), so nodal deflections of a cantilever under end loads are exact.
#pragma once
#include "Types.hpp"

#include <limits>

namespace flex {

/// Cross-section stiffness of a cylinder (beam) element.
struct BeamSection {
	double EA = 0; ///< axial stiffness [N]
	double EI = 0; ///< bending stiffness (both axes) [N m^2]
	double GJ = 0; ///< torsional stiffness [N m^2]
	/// Solid circular section of radius r [m]: A = pi r^2, I = pi r^4/4, J = 2 I.
	/// bendingFactor [-] scales EI and GJ (a stranded rope bends far more easily than a bar).
	static BeamSection circular(double young, double shearModulus, double radius, double bendingFactor = 1.0);
};

/// Axial constitutive options of a bond.
struct AxialLaw {
	bool   tensionOnly   = false;                                   ///< ropes: no compression force
	double yieldForce    = std::numeric_limits<double>::infinity(); ///< [N] onset of plastic elongation
	double hardening     = 0;                                       ///< [-] post-yield stiffness / EA (linear isotropic)
	double ruptureForce  = std::numeric_limits<double>::infinity(); ///< [N] bond breaks when N reaches it
	double ruptureStrain = std::numeric_limits<double>::infinity(); ///< [-] bond breaks at this total strain
};

/// What an axial bond remembers (named state, never stored in the parameters).
struct AxialState {
	double plasticStrain = 0; ///< [-] permanent elongation / L0
	double hardeningVar  = 0; ///< [-] accumulated plastic strain (isotropic hardening)
};

struct AxialResult {
	double N             = 0;     ///< axial force, tension positive [N]
	double elasticEnergy = 0;     ///< stored axial energy [J]
	double plasticWork   = 0;     ///< plastic work of this step [J]
	bool   rupture       = false; ///< rupture criterion met this step
};

/// 1D elasto-plastic bar with linear isotropic hardening (return mapping on the force).
/// strain = (L - L0)/L0. Updates state.
AxialResult axialForce(double strain, double EA, double L0, const AxialLaw& law, AxialState& state);

/// Reference configuration of a bond.
struct BeamRest {
	double L0 = 0;                ///< rest length [m]
	Quat   Qi = Quat::Identity(); ///< element frame in node i's body frame
	Quat   Qj = Quat::Identity(); ///< element frame in node j's body frame
};
BeamRest makeBeamRest(const Vec3& xi, const Vec3& xj, const Quat& oi, const Quat& oj);

struct BeamKinematics {
	Vec3   e;      ///< unit chord i -> j
	double L;      ///< current length [m]
	Vec3   thetaI; ///< bending rotation at node i (perpendicular to e) [rad]
	Vec3   thetaJ; ///< bending rotation at node j [rad]
	double twist;  ///< twist of j relative to i about e [rad]
	// for the exact gradient (beamForcesWithAxial): the element axis at each node (a = x axis
	// of the node's element frame), theta = f (e x a) with f = alpha / sin alpha, and
	// h = f'(alpha) / sin alpha; the twist's gradient with respect to each node's rotation
	// (global frame)
	Vec3   aI, aJ;
	double fI = 1, hI = 1.0 / 3, fJ = 1, hJ = 1.0 / 3;
	Vec3   twistGradI, twistGradJ;
};
BeamKinematics beamKinematics(const Vec3& xi, const Vec3& xj, const Quat& oi, const Quat& oj, const BeamRest& rest);

struct BeamForces {
	Vec3   Fi = Vec3::Zero(), Fj = Vec3::Zero(); ///< forces on nodes i, j [N]
	Vec3   Mi = Vec3::Zero(), Mj = Vec3::Zero(); ///< moments on nodes i, j [N m]
	double N             = 0;                    ///< axial force, tension positive [N]
	double elasticEnergy = 0;                    ///< axial + bending + twist [J]
	double plasticWork   = 0;                    ///< [J] this step
	bool   rupture       = false;
};
BeamForces beamForces(const BeamKinematics& k, const BeamRest& rest, const BeamSection& s, const AxialLaw& law, AxialState& state);
/// The same with the axial response given (another axial law, e.g. the wire law in WireLaw.hpp):
/// bending and twist from the section, axial force, energy and rupture from `axial`.
BeamForces beamForcesWithAxial(const BeamKinematics& k, const BeamRest& rest, const BeamSection& s, const AxialResult& axial);

/// Chord of a bond: unit vector i -> j and length, computed exactly as in beamKinematics.
struct Chord {
	Vec3   e; ///< unit chord i -> j
	double L; ///< current length [m]
};
inline Chord chord(const Vec3& xi, const Vec3& xj)
{
	const Vec3   d = xj - xi;
	const double L = d.norm();
	return { d / L, L };
}

/// Axial-only bond (a bar or truss link: no bending or twist stiffness, the nodes' orientations
/// play no part): F_j = -N e, F_i = +N e, no moments, energy and rupture from `axial`. For a
/// section with EI = GJ = 0 this is beamForcesWithAxial without the rotations: the same forces
/// and energy, bit for bit (tests/kernel/test_beam.cpp), at a fraction of the cost.
inline BeamForces barForces(const Chord& c, const AxialResult& axial)
{
	BeamForces f; // moments stay zero
	f.N             = axial.N;
	f.plasticWork   = axial.plasticWork;
	f.rupture       = axial.rupture;
	f.Fj            = -f.N * c.e;
	f.Fi            = -f.Fj;
	f.elasticEnergy = axial.elasticEnergy;
	return f;
}

/// Local 12x12 Euler-Bernoulli stiffness, element axis = local x, DOF order
/// (u_i, theta_i, u_j, theta_j).
Eigen::Matrix<double, 12, 12> beamStiffnessLocal(const BeamSection& s, double L);

/// Lumped share of one cylinder (radius r, length L, density rho) for each end node:
/// mass rho pi r^2 L / 2 (the cylinder body only: the spherical caps overlap the
/// neighbouring segment in a continuous wire and are not counted) and the isotropic
/// rotational inertia of that half about the node, m_h (r^2/4 + L^2/12).
struct NodeShare {
	double mass, inertia;
};
NodeShare cylinderNodeShare(double rho, double radius, double length);

} // namespace flex
