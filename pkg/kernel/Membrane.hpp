// Membrane law of a facet: constant-strain triangle (CST), St. Venant-Kirchhoff, plane stress.
//
// Rest configuration: the facet's rest edges in its own 2D frame, Dm = [X2 - X1, X3 - X1]
// (2x2), and its rest area A0. Current: Ds = [x2 - x1, x3 - x1] (3x2). Deformation gradient
// F = Ds Dm^-1 (3x2), Green-Lagrange strain E = (F^T F - I)/2 (2x2). E is unchanged by any
// rigid rotation of the facet, however large (objective), and exact for a uniform stretch.
// Membrane forces per unit rest width (second Piola-Kirchhoff, N/m), with Et = E t [N/m]:
//     S = Et/(1 - nu^2) [(1 - nu) E + nu tr(E) I]                     (taut)
// Tension-only fabrics wrinkle instead of taking compression (tension-field model): with the
// principal strains e1 >= e2 and direction v1 of e1,
//     e1 <= 0:             S = 0,              W = 0                  (slack)
//     e2 < -nu e1:         S = Et e1 v1 v1^T,  W = Et e1^2 / 2        (wrinkled, uniaxial)
//     otherwise:           taut,               W = S : E / 2
// W (energy per rest area) is continuous across the cases and S = dW/dE in each: the law is
// hyperelastic, so the elastic energy A0 W closes with the work of the nodal forces.
// Nodal forces: f_2, f_3 = columns of -A0 F S Dm^-T, f_1 = -(f_2 + f_3). They sum to zero, and
// their moment vanishes because W is invariant under rotation.
#pragma once
#include "Types.hpp"

#include <limits>

namespace flex {

struct MembraneLaw {
	double Et          = 0;                                       ///< tensile stiffness E t [N/m]
	double nu          = 0;                                       ///< Poisson ratio [-]
	bool   tensionOnly = false;                                   ///< wrinkling fabric: no compression
	double strength    = std::numeric_limits<double>::infinity(); ///< rupture at this principal membrane force per rest width [N/m]
};

struct MembraneRest {
	double          A0    = 0;                       ///< rest area [m^2] (0: degenerate)
	Eigen::Matrix2d DmInv = Eigen::Matrix2d::Zero(); ///< inverse of the rest edge matrix [1/m]
};
/// Rest state from the node positions; A0 = 0 if the triangle is degenerate.
MembraneRest makeMembraneRest(const Vec3& x1, const Vec3& x2, const Vec3& x3);

struct MembraneResult {
	Vec3   f[3];            ///< forces on the nodes [N]
	double energy = 0;      ///< elastic energy A0 W [J]
	double n1 = 0, n2 = 0;  ///< principal membrane forces per unit rest width (nominal) [N/m]
	double e1 = 0, e2 = 0;  ///< principal Green strains [-]
	bool   rupture = false; ///< n1 reached the strength (a fold or wrinkle never raises n1)
};
MembraneResult membraneForces(const Vec3 x[3], const MembraneRest& rest, const MembraneLaw& law);

/// Largest omega^2 of the facet's in-plane stiffness at rest with mass m on each node [1/s^2].
double membraneMaxOmega2(const MembraneRest& rest, const MembraneLaw& law, double nodeMass);

/// Factor >= 1 by which the largest eigenvalue of the facet's tangent stiffness (all 9 DOFs) at
/// principal Green strains e1 >= e2 can exceed membraneMaxOmega2's rest value: a stretched
/// St. Venant-Kirchhoff membrane stiffens, k(3 lambda^2 - 1)/2 = k lambda^2 + S along a uniaxial
/// stretch lambda (twice the rest stiffness at 30% strain). Returns
///     max(1, lambda1^2 + s1 / (k (1 - nu))),  lambda1^2 = 1 + 2 e1, k = Et / (1 - nu^2),
/// s1 the larger principal second Piola-Kirchhoff force of the law's branch (taut, wrinkled,
/// slack). Reached in some states; an upper bound for 0 <= nu < 0.5, checked against the
/// finite-difference tangent of membraneForces over random triangles, stretches, rotations and
/// both laws (kernel test Membrane.StretchFactorBoundsTheTangentStiffness). NOT a bound for
/// nu < 0 (1.19x at nu = -0.99): auxetic membranes are rejected by the builders.
double membraneStretchFactor(double e1, double e2, const MembraneLaw& law);

} // namespace flex
