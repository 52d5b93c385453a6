// Energy-consistent onset and release of a linear penalty contact (GPL-2.0-or-later).
#include "Crossing.hpp"

#include <algorithm>

namespace flex {

CrossingState crossingStart(double k, double depth, double rate, double dt)
{
	CrossingState st;
	st.prevDepth = depth - rate * dt;
	st.prevForce = st.prevDepth > 0 ? k * st.prevDepth : 0.0;
	return st;
}

double crossingForce(double S, double k, double d0, double a)
{
	if (!(d0 != 0) || !std::isfinite(S)) return 0;
	const double disc = d0 * d0 - 8 * a * S;
	double       c    = disc >= 0 ? 4 * S / (d0 + std::copysign(std::sqrt(disc), d0)) : 2 * S / d0;
	const double cap  = k * std::abs(d0);
	return std::clamp(c, -cap, cap);
}

} // namespace flex
