// yade-flex kernel: the stop of a hooked knot (GPL-2.0-or-later).
//
// Two hooked wire bends (nodes i and j of a knot link) can turn about each other but cannot
// pass through each other: bend i stays on its side of bend j along the hook's axis n, the
// direction in which bend i opens: from the midpoint of its two legs' far nodes a, b to its
// apex, n = m / |m|, m = xi - (xa + xb) / 2. Gap g = (xi - xj) . n; the stop holds g >= c, c
// the gap at rest, with a penalty spring of stiffness k:
//   V = k (c - g)^2 / 2 while g < c, else 0
//   f = k (c - g) >= 0,  t = (r - n (n . r)) / |m|,  r = xi - xj
//   F_i = f (n + t),  F_j = -f n,  F_a = F_b = -f t / 2
// (t: how g changes as n turns with the apex and its legs). The forces are the exact gradient
// of V; they sum to zero and, V depending only on differences of positions and their dot
// products, so do their moments: the stop is conservative and needs no node orientation. A bend
// pulled nearly straight (|m| < |r|: its apex within one link length of its legs' midline) no
// longer hooks: the stop lets go (released, with the energy it held).
#pragma once
#include "Types.hpp"

namespace flex {

struct HookForces {
	Vec3   Fi             = Vec3::Zero(); ///< force on node i (the hooked bend) [N]
	Vec3   Fj             = Vec3::Zero(); ///< force on node j (the other bend) [N]
	Vec3   Fa             = Vec3::Zero(); ///< force on each of the far nodes a, b of bend i's legs [N]
	double force          = 0;            ///< the stop's force f >= 0 [N]
	double energy         = 0;            ///< stored energy V [J]
	bool   released       = false;        ///< bend i is straight (|m| < |r|): the stop lets go (for good, in the adapter)
	double releasedEnergy = 0;            ///< V it held as it let go [J]
};

/// The stop's forces for bends at xi, xj, bend i's legs' far nodes at xa, xb, the rest gap c
/// [m] and the stiffness k [N/m].
HookForces hookForces(const Vec3& xi, const Vec3& xj, const Vec3& xa, const Vec3& xb, double c, double k);

/// Largest squared eigenfrequency of the stop alone with mass m at each of its four nodes: its
/// stiffness k (grad g)(grad g)^T has rank one, eigenvalue k |grad g|^2 / m = k (2 + 3 |t|^2 / 2)
/// / m, and |t| <= 1 while the stop holds (|m| >= |r|): at most 3.5 k / m.
double hookMaxOmega2(double k, double m);

} // namespace flex
