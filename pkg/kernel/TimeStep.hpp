// Critical time step of the explicit central-difference (leap-frog) integrator.
//
// An undamped system M a = -K x integrated by central differences is stable iff
// dt <= 2 / omega_max, omega_max^2 the largest eigenvalue of M^-1 K. Two bounds make it
// computable without assembling K:
//  * element eigenvalue inequality (Irons): with lumped masses that are sums of element
//    shares, omega_max <= max over elements of the element's own omega_max computed with
//    its shares (bonds);
//  * Gershgorin on M^-1/2 K M^-1/2 (contacts): for every DOF, omega^2 <= sum of the
//    absolute entries of its row.
// Both parts add: lambda_max(A + B) <= lambda_max(A) + lambda_max(B).
#pragma once
#include "Beam.hpp"

namespace flex {

/// Largest omega^2 of one beam element with lumped node masses mi, mj [kg] and isotropic
/// rotational inertias Ii, Ij [kg m^2] (the element's own shares).
double beamMaxOmega2(const BeamSection& s, double L, double mi, double mj, double Ii, double Ij);

/// Stable step for omega^2 (2/omega); +inf for omega^2 <= 0.
double criticalTimeStep(double omega2);

} // namespace flex
