// yade-flex kernel tests: closest points on triangles, facet kinematics (GPL-2.0-or-later)
#include "kernel/Triangle.hpp"
#include "test_util.hpp"

#include <limits>

using namespace flex;
using flex::test::close;

namespace {
// brute force: closest point of a densely sampled triangle
double sampledDistance(const Vec3& p, const Vec3& x1, const Vec3& x2, const Vec3& x3, int n = 400)
{
	double best = std::numeric_limits<double>::infinity();
	for (int i = 0; i <= n; ++i)
		for (int j = 0; i + j <= n; ++j) {
			const double u = double(i) / n, v = double(j) / n;
			best = std::min(best, (p - (x1 + u * (x2 - x1) + v * (x3 - x1))).norm());
		}
	return best;
}
} // namespace

// ---------------------------------------------------------------- point - triangle

TEST(ClosestPointOnTriangle, SevenVoronoiRegions)
{
	const Vec3 x1(0, 0, 0), x2(2, 0, 0), x3(0, 2, 0);
	struct Case {
		Vec3     p;
		unsigned support;
		Vec3     q;
	} cases[] = {
		{ Vec3(0.5, 0.5, 0.3), 7, Vec3(0.5, 0.5, 0) },  // face (above)
		{ Vec3(0.5, 0.5, -0.3), 7, Vec3(0.5, 0.5, 0) }, // face (below)
		{ Vec3(-1, -0.5, 0.2), 1, x1 },                 // vertex 1
		{ Vec3(3, -0.5, -0.1), 2, x2 },                 // vertex 2
		{ Vec3(-0.3, 3, 0.4), 4, x3 },                  // vertex 3
		{ Vec3(1, -0.7, 0.1), 3, Vec3(1, 0, 0) },       // edge 1-2
		{ Vec3(-0.6, 1.5, 0.3), 5, Vec3(0, 1.5, 0) },   // edge 1-3
		{ Vec3(1.5, 1.5, 0.2), 6, Vec3(1, 1, 0) },      // edge 2-3
	};
	for (const Case& c : cases) {
		const PointTriangle r = closestPointOnTriangle(c.p, x1, x2, x3);
		EXPECT_EQ(r.support, c.support) << c.p.transpose();
		EXPECT_TRUE(close(r.point, c.q, 1e-15, 1e-15));
		EXPECT_TRUE(close(Vec3(r.w[0] * x1 + r.w[1] * x2 + r.w[2] * x3), r.point, 1e-15, 1e-15));
		for (int a = 0; a < 3; ++a)
			EXPECT_EQ(r.w[a] != 0, bool(r.support & (1u << a)));
	}
}

TEST(ClosestPointOnTriangle, MatchesBruteForce)
{
	test::Rng rng(31);
	for (int k = 0; k < 300; ++k) {
		const Vec3          x1 = rng.vec(), x2 = rng.vec(), x3 = rng.vec(), p = rng.vec(2.0);
		const PointTriangle r = closestPointOnTriangle(p, x1, x2, x3);
		const double        d = (p - r.point).norm();
		// the exact distance is below every sample; samples come within the grid spacing
		EXPECT_LE(d, sampledDistance(p, x1, x2, x3, 100) + 1e-12);
		EXPECT_GE(d, sampledDistance(p, x1, x2, x3, 100) - 0.03);
		EXPECT_NEAR(r.w[0] + r.w[1] + r.w[2], 1.0, 1e-14);
		for (double w : r.w)
			EXPECT_GE(w, 0.0);
	}
}

TEST(ClosestPointOnTriangle, SharedEdgeAndVertexAreBitIdentical)
{
	// two facets sharing edge (b, c), listed in different orders: same point, same distance
	test::Rng rng(32);
	for (int k = 0; k < 200; ++k) {
		const Vec3          a = rng.vec(), b = rng.vec(), c = rng.vec();
		const Vec3          d        = b + c - a + 0.3 * rng.vec(); // across the edge from a
		const Vec3          m        = 0.5 * (b + c) + 2 * rng.vec();
		const PointTriangle r1       = closestPointOnTriangle(m, a, b, c);
		const PointTriangle r2       = closestPointOnTriangle(m, c, d, b);
		auto                onShared = [](unsigned s, unsigned shared) { return (s & ~shared) == 0; };
		if (onShared(r1.support, 6) && onShared(r2.support, 5)) {
			EXPECT_EQ((m - r1.point).norm(), (m - r2.point).norm());
			EXPECT_EQ(r1.point, r2.point);
		}
	}
}

TEST(ClosestPointOnTriangle, DegenerateIsItsLongestEdge)
{
	const Vec3          x1(0, 0, 0), x2(1, 0, 0), x3(2, 0, 0);
	const PointTriangle r = closestPointOnTriangle(Vec3(1.5, 1, 0), x1, x2, x3);
	EXPECT_TRUE(close(r.point, Vec3(1.5, 0, 0), 1e-15, 1e-15));
	EXPECT_TRUE(r.point.allFinite());
}

// ---------------------------------------------------------------- segment - triangle

TEST(SegmentTriangle, Piercing)
{
	const Vec3            x1(0, 0, 0), x2(2, 0, 0), x3(0, 2, 0);
	const SegmentTriangle r = closestPointsSegmentTriangle(Vec3(0.5, 0.5, -1), Vec3(0.5, 0.5, 3), x1, x2, x3);
	EXPECT_TRUE(r.intersect);
	EXPECT_NEAR(r.s, 0.25, 1e-15);
	EXPECT_TRUE(close(r.p1, Vec3(0.5, 0.5, 0), 1e-15, 1e-15));
	EXPECT_TRUE(close(r.t.point, r.p1, 0, 1e-15));
}

TEST(SegmentTriangle, ParallelOverFaceGivesMiddleOfOverlap)
{
	const Vec3 x1(0, 0, 0), x2(2, 0, 0), x3(0, 2, 0);
	// segment at height 0.1, from x = -1 to x = 1 at y = 0.5: over the face for x in [0, 1]
	const SegmentTriangle r = closestPointsSegmentTriangle(Vec3(-1, 0.5, 0.1), Vec3(1, 0.5, 0.1), x1, x2, x3);
	EXPECT_FALSE(r.intersect);
	EXPECT_NEAR((r.p1 - r.t.point).norm(), 0.1, 1e-15);
	EXPECT_TRUE(close(r.p1, Vec3(0.5, 0.5, 0.1), 1e-14, 1e-14));
	EXPECT_EQ(r.t.support, 7u);
}

TEST(SegmentTriangle, EdgeCrossing)
{
	const Vec3 x1(0, 0, 0), x2(2, 0, 0), x3(0, 2, 0);
	// a segment crossing over edge 2-3 above it, perpendicular to it
	const SegmentTriangle r = closestPointsSegmentTriangle(Vec3(1.2, 1.2, 0.5), Vec3(1.2, 1.2, 0.2) + Vec3(1, 1, 0), x1, x2, x3);
	EXPECT_EQ(r.t.support, 6u);
	EXPECT_NEAR((r.p1 - r.t.point).norm(), sampledDistance(r.p1, x1, x2, x3), 1e-3);
}

TEST(SegmentTriangle, MatchesBruteForce)
{
	test::Rng rng(33);
	for (int k = 0; k < 200; ++k) {
		const Vec3            x1 = rng.vec(), x2 = rng.vec(), x3 = rng.vec(), a = rng.vec(2.0), b = rng.vec(2.0);
		const SegmentTriangle r    = closestPointsSegmentTriangle(a, b, x1, x2, x3);
		const double          d    = (r.p1 - r.t.point).norm();
		double                best = std::numeric_limits<double>::infinity();
		for (int i = 0; i <= 100; ++i) {
			const Vec3          p = a + (i / 100.0) * (b - a);
			const PointTriangle q = closestPointOnTriangle(p, x1, x2, x3);
			best                  = std::min(best, (p - q.point).norm());
		}
		EXPECT_LE(d, best + 1e-12);
		EXPECT_GE(d, best - 0.03 * (b - a).norm());
		// the reported points are consistent
		EXPECT_TRUE(close(r.p1, Vec3(a + r.s * (b - a)), 1e-13, 1e-13));
		EXPECT_TRUE(close(Vec3(r.t.w[0] * x1 + r.t.w[1] * x2 + r.t.w[2] * x3), r.t.point, 1e-10, 1e-10));
	}
}

// ---------------------------------------------------------------- facet kinematics

TEST(TrianglePointVelocity, ExactForRigidMotion)
{
	test::Rng rng(34);
	for (double len : { 1e-3, 1.0, 1e2 }) {
		for (int k = 0; k < 100; ++k) {
			const Vec3   x[3] = { rng.vec(len), rng.vec(len), rng.vec(len) };
			const double u = rng.uniform(0, 1), v = rng.uniform(0, 1 - u);
			const double w[3] = { 1 - u - v, u, v };
			const Vec3   q    = w[0] * x[0] + w[1] * x[1] + w[2] * x[2];
			const Vec3   d    = rng.vec(len);
			const Vec3   v0 = rng.vec(), W = rng.vec();
			const Vec3   vel[3] = { v0 + W.cross(x[0]), v0 + W.cross(x[1]), v0 + W.cross(x[2]) };
			const Vec3   exact  = v0 + W.cross(q + d);
			EXPECT_TRUE(close(trianglePointVelocity(x, vel, w, d), exact, 1e-9, 1e-12 * (v0.norm() + W.norm() * len)));
		}
	}
}

TEST(DistributeToTriangle, PowerForceAndMomentBalance)
{
	test::Rng rng(35);
	for (int k = 0; k < 200; ++k) {
		const Vec3   x[3] = { rng.vec(), rng.vec(), rng.vec() };
		const double u = rng.uniform(0, 1), v = rng.uniform(0, 1 - u);
		const double w[3] = { 1 - u - v, u, v };
		const Vec3   q    = w[0] * x[0] + w[1] * x[1] + w[2] * x[2];
		const Vec3   d = cappedFacetOffset(x, 0.1 * rng.vec()), F = rng.vec(100.0); // as the contact code uses it
		Vec3         f[3];
		distributeToTriangle(x, w, d, F, f);
		const Vec3 c = q + d;
		EXPECT_TRUE(close(Vec3(f[0] + f[1] + f[2]), F, 1e-12, 1e-12));
		EXPECT_TRUE(close(Vec3(x[0].cross(f[0]) + x[1].cross(f[1]) + x[2].cross(f[2])), c.cross(F), 1e-9, 1e-9));
		// adjoint: the power of F at c equals the nodal power, for ANY node velocities
		const Vec3 vel[3] = { rng.vec(), rng.vec(), rng.vec() };
		EXPECT_NEAR(F.dot(trianglePointVelocity(x, vel, w, d)), f[0].dot(vel[0]) + f[1].dot(vel[1]) + f[2].dot(vel[2]), 1e-9 * F.norm());
		// the load factor bounds every nodal share
		const double fac = triangleLoadFactor(x, d.norm());
		for (int a = 0; a < 3; ++a)
			EXPECT_LE(f[a].norm(), fac * F.norm() * (1 + 1e-12));
	}
}

TEST(DistributeToTriangle, NormalForceOnFaceIsBarycentric)
{
	const Vec3   x[3] = { Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0) };
	const double w[3] = { 0.5, 0.3, 0.2 };
	const Vec3   F(0, 0, -7), d(0, 0, 0.01); // pushed along the normal at an offset along it
	Vec3         f[3];
	distributeToTriangle(x, w, d, F, f);
	for (int a = 0; a < 3; ++a)
		EXPECT_TRUE(close(f[a], Vec3(w[a] * F), 1e-15, 1e-15));
}

TEST(DistributeToTriangle, CrushedTriangleSharesStayBoundedByTheCap)
{
	// a triangle squashed towards a line: the uncapped moment part grows like |d| / area; the
	// capped offset keeps every nodal share below (w_a + kFacetMomentCap) |F|, with force and
	// power still balanced; a regular lining triangle keeps its offset unchanged
	const Vec3   d(0.0004, -0.0003, 0.001), F(3.0, -2.0, 5.0);
	const double w[3] = { 0.2, 0.5, 0.3 };
	for (double h : { 0.08, 1e-2, 1e-3, 1e-5, 1e-8 }) {
		const Vec3 x[3] = { Vec3(0, 0, 0), Vec3(0.08, 0, 0), Vec3(0.04, h, 0) };
		const Vec3 dc   = cappedFacetOffset(x, d);
		Vec3       f[3], fu[3];
		distributeToTriangle(x, w, dc, F, f);
		distributeToTriangle(x, w, d, F, fu);
		EXPECT_TRUE(close(Vec3(f[0] + f[1] + f[2]), F, 1e-12, 1e-12));
		const Vec3 vel[3] = { Vec3(0.1, 0.2, -0.3), Vec3(-0.2, 0.4, 0.1), Vec3(0.3, 0.0, 0.2) };
		EXPECT_NEAR(F.dot(trianglePointVelocity(x, vel, w, dc)), f[0].dot(vel[0]) + f[1].dot(vel[1]) + f[2].dot(vel[2]), 1e-9 * F.norm());
		double worstUncapped = 0;
		for (int a = 0; a < 3; ++a) {
			EXPECT_LE(f[a].norm(), (w[a] + kFacetMomentCap) * F.norm() * (1 + 1e-12)) << "h = " << h;
			EXPECT_LE(f[a].norm(), triangleLoadFactor(x, d.norm()) * F.norm() * (1 + 1e-12));
			worstUncapped = std::max(worstUncapped, fu[a].norm() / F.norm());
		}
		if (h == 0.08) EXPECT_EQ(dc, d);                              // a regular triangle: untouched
		if (h <= 1e-5) EXPECT_GT(worstUncapped, 1 + kFacetMomentCap); // what the cap prevents (8.4 at h = 1e-5)
	}
}
