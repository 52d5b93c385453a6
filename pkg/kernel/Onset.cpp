// The normal spring of a contact with a deformable element (GPL-2.0-or-later). See Onset.hpp.
#include "Onset.hpp"

#include <algorithm>

namespace flex {

double onsetOffset(double k, double depth, double taken) { return k > 0 ? std::max(0.0, depth - std::max(0.0, taken) / k) : 0.0; }

double shrinkOffset(double offset, double depth) { return std::max(0.0, std::min(offset, depth)); }

NormalSpring normalSpring(double k, double depth, double offset, bool pierced)
{
	const double d = std::max(0.0, depth - offset);
	NormalSpring s;
	s.force  = pierced ? 0.0 : k * d;
	s.energy = 0.5 * k * d * d;
	return s;
}

double releasedEnergy(double force, double d) { return 0.5 * force * std::max(0.0, d); }

double takenOverEnergy(double force, double d, double approach, double dt) { return 0.5 * force * std::max(0.0, d - approach * dt); }

} // namespace flex
