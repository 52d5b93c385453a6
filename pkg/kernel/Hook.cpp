// yade-flex kernel: the stop of a hooked knot (GPL-2.0-or-later). See Hook.hpp.
#include "Hook.hpp"

namespace flex {

HookForces hookForces(const Vec3& xi, const Vec3& xj, const Vec3& xa, const Vec3& xb, double c, double k)
{
	HookForces   h;
	const Vec3   m  = xi - 0.5 * (xa + xb);
	const Vec3   r  = xi - xj;
	const double lm = m.norm();
	const Vec3   n  = lm > 0 ? Vec3(m / lm) : Vec3::Zero();
	const double g  = r.dot(n);
	if (!(lm >= r.norm()) || lm == 0) { // a straightened bend no longer hooks
		h.released = true;
		if (lm > 0 && g < c) h.releasedEnergy = 0.5 * k * (c - g) * (c - g);
		return h;
	}
	if (!(g < c)) return h;
	const Vec3 t = (r - n * g) / lm;
	h.force      = k * (c - g);
	h.Fi         = h.force * (n + t);
	h.Fj         = -h.force * n;
	h.Fa         = -0.5 * h.force * t;
	h.energy     = 0.5 * h.force * (c - g);
	return h;
}

double hookMaxOmega2(double k, double m) { return 3.5 * k / m; }

} // namespace flex
