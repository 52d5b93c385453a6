// yade-flex kernel: the stop of a hooked knot (GPL-2.0-or-later). See Hook.hpp.
#include "Hook.hpp"

namespace flex {

HookForces hookForces(const Vec3& xi, const Vec3& xj, const Quat& qi, const Vec3& a, double c, double k)
{
	HookForces   h;
	const Vec3   n = qi * a;
	const Vec3   r = xi - xj;
	const double g = r.dot(n);
	if (!(g < c)) return h;
	h.force  = k * (c - g);
	h.Fi     = h.force * n;
	h.Mi     = h.force * n.cross(r);
	h.energy = 0.5 * h.force * (c - g);
	return h;
}

double hookMaxOmega2(double k, double lever, double m, double I) { return k * (2.0 / m + lever * lever / I); }

} // namespace flex
