// yade-flex kernel tests: the conservative separation tests of the contact search
// (segmentsApart, segmentTriangleApart) never call apart what the exact closest points call a
// touch, and do reject the pairs they are for (GPL-2.0-or-later)
#include "kernel/ClosestPoints.hpp"
#include "kernel/Triangle.hpp"
#include "test_util.hpp"

#include <random>

using namespace flex;

namespace {

Vec3 randomUnit(std::mt19937_64& g)
{
	std::normal_distribution<double> n(0, 1);
	Vec3                             v(n(g), n(g), n(g));
	return v.normalized();
}

double segTriDist(const Vec3& a, const Vec3& b, const Vec3& x1, const Vec3& x2, const Vec3& x3)
{
	const SegmentTriangle st = closestPointsSegmentTriangle(a, b, x1, x2, x3);
	return (st.p1 - st.t.point).norm();
}

} // namespace

TEST(Separation, SegmentsNeverApartWhenTheExactDistanceIsWithinReach)
{
	// random pairs, many placed so that their exact distance is reach x (1 +- 1e-12 .. 1e-1):
	// the test may say "apart" only when the exact distance exceeds reach
	std::mt19937_64                        g(11);
	std::uniform_real_distribution<double> u(-1, 1), lg(-12, -1);
	int                                    apart = 0, n = 200000;
	for (int k = 0; k < n; ++k) {
		const double scale = std::pow(10.0, 3 * u(g));     // 1e-3 .. 1e3 m
		const Vec3   off   = Vec3(u(g), u(g), u(g)) * 1e3; // far from the origin too
		Vec3         a0 = off + scale * Vec3(u(g), u(g), u(g)), a1 = off + scale * Vec3(u(g), u(g), u(g));
		Vec3         b0 = off + scale * Vec3(u(g), u(g), u(g)), b1 = off + scale * Vec3(u(g), u(g), u(g));
		if (k % 3 == 0) { // both in planes x = const, a box gap equal to the distance: the boundary case
			a1[0] = a0[0];
			b0[0] = b1[0] = a0[0] + scale * 0.1 * (1 + u(g));
		}
		const double d     = (closestPointsSegments(a0, a1, b0, b1).p2 - closestPointsSegments(a0, a1, b0, b1).p1).norm();
		const double reach = (k % 2) ? d * (1 + (u(g) > 0 ? 1 : -1) * std::pow(10.0, lg(g))) : scale * 0.1 * (1 + u(g));
		if (segmentsApart(a0, a1, b0, b1, reach)) {
			++apart;
			ASSERT_GT(d, reach) << "pair " << k;
		}
	}
	EXPECT_GT(apart, n / 20); // and it does reject pairs
}

TEST(Separation, SegmentTriangleNeverApartWhenTheExactDistanceIsWithinReach)
{
	std::mt19937_64                        g(12);
	std::uniform_real_distribution<double> u(-1, 1), lg(-12, -1);
	int                                    apart = 0, n = 100000;
	for (int k = 0; k < n; ++k) {
		const double scale = std::pow(10.0, 3 * u(g));
		const Vec3   off   = Vec3(u(g), u(g), u(g)) * 1e3;
		Vec3         x1 = off + scale * Vec3(u(g), u(g), u(g)), x2 = off + scale * Vec3(u(g), u(g), u(g)), x3;
		if (k % 5 == 0) // nearly degenerate triangles (slivers)
			x3 = x1 + (x2 - x1) * u(g) + scale * std::pow(10.0, lg(g)) * randomUnit(g);
		else
			x3 = off + scale * Vec3(u(g), u(g), u(g));
		Vec3 a = off + scale * Vec3(u(g), u(g), u(g)), b = off + scale * Vec3(u(g), u(g), u(g));
		if (k % 3 == 0) { // a segment nearly parallel to the plane, just above or below it
			const Vec3   nrm = (x2 - x1).cross(x3 - x1).normalized();
			const Vec3   c   = (x1 + x2 + x3) / 3;
			const Vec3   t   = nrm.cross(randomUnit(g)).normalized();
			const double h   = scale * 0.01 * u(g);
			a                = c + h * nrm + scale * t;
			b                = c + h * nrm * (1 + 1e-6 * u(g)) - scale * t;
		}
		const double d     = segTriDist(a, b, x1, x2, x3);
		const double reach = (k % 2) ? d * (1 + (u(g) > 0 ? 1 : -1) * std::pow(10.0, lg(g))) : scale * 0.05 * (1 + u(g));
		if (segmentTriangleApart(a, b, x1, x2, x3, reach)) {
			++apart;
			ASSERT_GT(d, reach) << "case " << k;
		}
	}
	EXPECT_GT(apart, n / 20);
}

TEST(Separation, RejectsAWireLyingAlongALiningOutsideItsReach)
{
	// the damping module's case: a wire leg 10 mm outside a lining triangle, parallel to it,
	// with boxes that overlap (the plane test decides); and the same wire within reach
	const Vec3   x1(0, 0, 0), x2(0.1, 0, 0), x3(0, 0.1, 0.002);
	const Vec3   n = (x2 - x1).cross(x3 - x1).normalized();
	const Vec3   a = Vec3(0.02, 0.02, 0) + 0.010 * n, b = Vec3(0.06, 0.03, 0.0006) + 0.010 * n;
	const double reach = 0.0015 + 0.001;
	EXPECT_TRUE(segmentTriangleApart(a, b, x1, x2, x3, reach));
	EXPECT_FALSE(segmentTriangleApart(a - 0.008 * n, b - 0.008 * n, x1, x2, x3, reach));
	EXPECT_LT(segTriDist(a - 0.008 * n, b - 0.008 * n, x1, x2, x3), reach);
	// two crossing wires 5 mm apart: apart; 2 mm apart: not (reach 3 mm)
	EXPECT_TRUE(segmentsApart(Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0.05, -0.05, 0.005), Vec3(0.05, 0.05, 0.005), 0.003));
	EXPECT_FALSE(segmentsApart(Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0.05, -0.05, 0.002), Vec3(0.05, 0.05, 0.002), 0.003));
}
