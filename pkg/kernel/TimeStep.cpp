// Critical time step (GPL-2.0-or-later). See TimeStep.hpp.
#include "TimeStep.hpp"

#include "ClosestPoints.hpp"
#include "Triangle.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

namespace flex {

double beamMaxOmega2(const BeamSection& s, double L, double mi, double mj, double Ii, double Ij)
{
	const Eigen::Matrix<double, 12, 12> K = beamStiffnessLocal(s, L);
	Eigen::Matrix<double, 12, 1>        d;
	d << mi, mi, mi, Ii, Ii, Ii, mj, mj, mj, Ij, Ij, Ij;
	const Eigen::Matrix<double, 12, 1>                           w = d.cwiseSqrt().cwiseInverse();
	const Eigen::Matrix<double, 12, 12>                          A = w.asDiagonal() * K * w.asDiagonal();
	Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 12, 12>> es(A, Eigen::EigenvaluesOnly);
	return es.eigenvalues().maxCoeff();
}

double criticalTimeStep(double omega2) { return omega2 > 0 ? 2.0 / std::sqrt(omega2) : std::numeric_limits<double>::infinity(); }

} // namespace flex

namespace flex {

double reachableDistance(const Vec3& x, const Vec3& ref, double sweep) { return ((x - ref).cwiseAbs() + Vec3::Constant(std::max(sweep, 0.0))).norm(); }

double primitiveGap(const Vec3* a, int na, double ra, const Vec3* b, int nb, double rb)
{
	if (na > nb) return primitiveGap(b, nb, rb, a, na, ra);
	double d;
	if (na == 1 && nb == 1)
		d = (a[0] - b[0]).norm();
	else if (na == 1 && nb == 2)
		d = (a[0] - closestPointOnSegment(a[0], b[0], b[1]).point).norm();
	else if (na == 1 && nb == 3)
		d = (a[0] - closestPointOnTriangle(a[0], b[0], b[1], b[2]).point).norm();
	else if (na == 2 && nb == 2) {
		const SegmentSegment ss = closestPointsSegments(a[0], a[1], b[0], b[1]);
		d                       = (ss.p2 - ss.p1).norm();
	} else if (na == 2 && nb == 3) {
		const SegmentTriangle st = closestPointsSegmentTriangle(a[0], a[1], b[0], b[1], b[2]);
		d                        = (st.t.point - st.p1).norm();
	} else
		return -std::numeric_limits<double>::infinity();
	return d - ra - rb;
}

bool cannotTouch(double gap, double reachA, double reachB, double size)
{
	const double reach = reachA + reachB;
	return gap > reach + 1e-9 * (std::abs(size) + reach + std::abs(gap));
}

double flooredSweep(double sweep, bool moving, double minSweep)
{
	return moving && sweep < minSweep && minSweep > 0 ? minSweep : sweep;
}

} // namespace flex
