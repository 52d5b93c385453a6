// Contact kinematics and the Cundall-Strack law (GPL-2.0-or-later). See Contact.hpp.
#include "Contact.hpp"

#include <cmath>

namespace flex {

Vec3 segmentPointVelocity(double u, const Vec3& p, const Vec3& c, const Vec3& vA, const Vec3& wA, const Vec3& vB, const Vec3& wB)
{
	return (1 - u) * vA + u * vB + ((1 - u) * wA + u * wB).cross(c - p);
}

void distributeToSegment(double u, const Vec3& p, const Vec3& c, const Vec3& F, NodeLoad& A, NodeLoad& B)
{
	const Vec3 m = (c - p).cross(F);
	A.F          = (1 - u) * F;
	B.F          = u * F;
	A.M          = (1 - u) * m;
	B.M          = u * m;
}

// rotateShear, cappedSpringStep and frictionalStepWithNormal: inline in Contact.hpp (every contact
// calls them, up to four times a step).

FrictionalResult frictionalStep(const FrictionalContact& p, double overlap, const Vec3& n, const Vec3& shearOld, const Vec3& dus)
{
	return frictionalStepWithNormal(p, p.kn * overlap, n, shearOld, dus);
}

} // namespace flex
