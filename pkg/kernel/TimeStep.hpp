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

// Which potential contacts can start before the collider runs again.
// With a sweep s (YADE's Bound::sweepLength) the collider re-runs as soon as a body's point x
// is found farther than s, in any coordinate, from the position ref it had when its bound was
// built; until then x stays in the box |x - ref|_inf < s. The gap between two shapes (each
// the points within a radius of a point, segment or triangle spanned by such points) can
// shrink at most by the distances their defining points can still travel, so a pair whose
// gap exceeds the sum cannot touch before the next collider run, when the time step is
// estimated again.

/// Farthest distance from x to a point of the box |y - ref|_inf <= sweep [m].
double reachableDistance(const Vec3& x, const Vec3& ref, double sweep);

/// Gap between two thick primitives: the distance between the point (n = 1), segment (2) or
/// triangle (3) spanned by a[0..na) and the one spanned by b[0..nb), minus ra + rb [m];
/// negative: overlap. Triangle-triangle: -infinity (not computed, never called apart).
double primitiveGap(const Vec3* a, int na, double ra, const Vec3* b, int nb, double rb);

/// Whether a pair with this gap cannot touch while its two sides travel at most reachA and
/// reachB: gap > reachA + reachB with a relative margin of 1e-9 that covers round-off.
bool cannotTouch(double gap, double reachA, double reachB, double size);

/// The sweep a bound keeps: YADE's (BoundDispatcher: zero for a body that did not move since its
/// bound's last update), except that a body that moves (`moving`) gets at least minSweep, the
/// smallest sweep YADE gives a body that moved [m].
double flooredSweep(double sweep, bool moving, double minSweep);

} // namespace flex
