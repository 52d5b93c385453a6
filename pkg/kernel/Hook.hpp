// yade-flex kernel: the stop of a hooked knot (GPL-2.0-or-later).
//
// Two hooked wire bends (nodes i and j of a knot link) can turn about each other but cannot
// pass through each other: bend i stays on its side of bend j along the hook's axis n, which
// turns with node i (n = qi a, a fixed in node i's frame). Gap g = (xi - xj) . n; the stop
// holds g >= c, c the gap at rest, with a penalty spring of stiffness k:
//   V = k (c - g)^2 / 2 while g < c, else 0
//   F_i = f n, F_j = -f n, M_i = f (n x (xi - xj)),   f = k (c - g) >= 0
// (M_i: the gradient of V with respect to node i's rotation, since n turns with it). Forces
// and moments sum to zero about any point, and they are the exact gradient of V: the stop is
// conservative.
#pragma once
#include "Types.hpp"

namespace flex {

struct HookForces {
	Vec3   Fi     = Vec3::Zero(); ///< force on node i [N] (node j: -Fi)
	Vec3   Mi     = Vec3::Zero(); ///< moment on node i [N m] (node j: none)
	double force  = 0;            ///< the stop's force f >= 0 [N]
	double energy = 0;            ///< stored energy V [J]
};

/// The stop's forces for nodes at xi, xj, node i's orientation qi, the axis a in node i's
/// frame (unit), the rest gap c [m] and the stiffness k [N/m].
HookForces hookForces(const Vec3& xi, const Vec3& xj, const Quat& qi, const Vec3& a, double c, double k);

/// Largest squared eigenfrequency of the stop alone on the link's own lumped shares (mass m
/// at each node, rotational inertia I at node i), for a lever |n x (xi - xj)| <= lever:
/// the stop's stiffness has rank one, so this is k (2/m + lever^2/I) exactly.
double hookMaxOmega2(double k, double lever, double m, double I);

} // namespace flex
