// A contact that yields at the load that splits a grain (GPL-2.0-or-later). See Crushing.hpp.
#include "Crushing.hpp"

#include <algorithm>
#include <cmath>

namespace flex {

double pointLoadFailure(double d, double is50)
{
	constexpr double d50 = 0.05, sizeExponent = 0.45;
	return is50 * d * d * std::pow(d50 / d, sizeExponent);
}

NormalYield yieldingNormalStep(double kn, double limit, double overlap, double plasticOld, double forceOld)
{
	NormalYield  r;
	const double trial = kn * (overlap - plasticOld);
	r.plastic          = plasticOld;
	if (trial > limit) {
		r.force    = limit;
		r.plastic  = overlap - limit / kn;
		r.yielding = true;
	} else {
		r.force = std::max(trial, 0.0);
	}
	r.dissipated = 0.5 * (forceOld + r.force) * (r.plastic - plasticOld);
	return r;
}

} // namespace flex
