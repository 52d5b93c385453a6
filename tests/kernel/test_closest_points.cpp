// yade-flex kernel tests: closest points and contact normals (GPL-2.0-or-later)
#include "kernel/ClosestPoints.hpp"
#include "test_util.hpp"

#include <limits>

using namespace flex;
using flex::test::close;

namespace {

double dist(const SegmentSegment& r) { return (r.p1 - r.p2).norm(); }

// Optimality (KKT) of (s, t) for the convex problem min |x1(s) - x2(t)|^2 on [0,1]^2:
// g_s = d1.(p1 - p2) must vanish inside, be >= 0 at s = 0 and <= 0 at s = 1; g_t = -d2.(p1 - p2) likewise.
void expectOptimal(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1, const SegmentSegment& r, double tol)
{
	const Vec3   w  = r.p1 - r.p2;
	const double gs = (a1 - a0).dot(w), gt = -(b1 - b0).dot(w);
	ASSERT_GE(r.s, 0.0);
	ASSERT_LE(r.s, 1.0);
	ASSERT_GE(r.t, 0.0);
	ASSERT_LE(r.t, 1.0);
	if (r.s > 0 && r.s < 1) {
		EXPECT_NEAR(gs, 0.0, tol);
	}
	if (r.s == 0) {
		EXPECT_GE(gs, -tol);
	}
	if (r.s == 1) {
		EXPECT_LE(gs, tol);
	}
	if (r.t > 0 && r.t < 1) {
		EXPECT_NEAR(gt, 0.0, tol);
	}
	if (r.t == 0) {
		EXPECT_GE(gt, -tol);
	}
	if (r.t == 1) {
		EXPECT_LE(gt, tol);
	}
	EXPECT_TRUE(close(r.p1, pointAt(a0, a1, r.s), 1e-15, 1e-15));
	EXPECT_TRUE(close(r.p2, pointAt(b0, b1, r.t), 1e-15, 1e-15));
}

// Brute-force minimum distance: fine grid, then a finer grid around the best node.
double bruteForceDistance(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1)
{
	auto      d    = [&](double s, double t) { return ((a0 + s * (a1 - a0)) - (b0 + t * (b1 - b0))).norm(); };
	double    best = std::numeric_limits<double>::infinity(), bs = 0, bt = 0;
	const int n = 400;
	for (int i = 0; i <= n; ++i)
		for (int j = 0; j <= n; ++j) {
			const double v = d(double(i) / n, double(j) / n);
			if (v < best) best = v, bs = double(i) / n, bt = double(j) / n;
		}
	const double h = 2.0 / n;
	for (int i = 0; i <= n; ++i)
		for (int j = 0; j <= n; ++j) {
			const double s = std::clamp(bs - h + 2 * h * i / n, 0.0, 1.0), t = std::clamp(bt - h + 2 * h * j / n, 0.0, 1.0);
			best = std::min(best, d(s, t));
		}
	return best;
}

} // namespace

// ---------------------------------------------------------------- point - segment

TEST(PointSegment, Interior)
{
	const Vec3 a(0, 0, 0), b(2, 0, 0), p(0.5, 1, -2);
	const auto r = closestPointOnSegment(p, a, b);
	EXPECT_EQ(r.u, 0.25);
	EXPECT_EQ(r.point, Vec3(0.5, 0, 0));
}

TEST(PointSegment, InteriorGenericIsOrthogonalProjection)
{
	test::Rng rng(1);
	for (int k = 0; k < 200; ++k) {
		const Vec3 a = rng.vec(), b = rng.vec(), d = b - a;
		// point = foot + normal offset, foot at a known parameter
		const double u   = rng.uniform(0.05, 0.95);
		Vec3         off = rng.vec();
		off -= off.dot(d) / d.squaredNorm() * d;
		const Vec3 p = a + u * d + off;
		const auto r = closestPointOnSegment(p, a, b);
		EXPECT_NEAR(r.u, u, 1e-12 / d.norm());
		EXPECT_TRUE(close(r.point, Vec3(a + u * d), 1e-12, 1e-13));
		EXPECT_NEAR((p - r.point).dot(d), 0.0, 1e-13);
	}
}

TEST(PointSegment, ClampedEndsAreExactEndPoints)
{
	const Vec3 a(0.1, 0.2, 0.3), b(0.7, -0.4, 1.3), d = b - a;
	// make the bitwise test meaningful: the naive formula does not reproduce b
	ASSERT_NE(Vec3(a + 1.0 * d), b);
	const Vec3 perp = d.cross(Vec3(1, 2, 3)).normalized();
	{ // beyond b
		const auto r = closestPointOnSegment(b + 0.3 * d + 0.5 * perp, a, b);
		EXPECT_EQ(r.u, 1.0);
		EXPECT_EQ(r.point, b);
	}
	{ // before a
		const auto r = closestPointOnSegment(a - 2.0 * d + 0.1 * perp, a, b);
		EXPECT_EQ(r.u, 0.0);
		EXPECT_EQ(r.point, a);
	}
	{ // the end points themselves
		EXPECT_EQ(closestPointOnSegment(b, a, b).point, b);
		EXPECT_EQ(closestPointOnSegment(a, a, b).point, a);
	}
}

TEST(PointSegment, SharedNodeGivesBitIdenticalDistances)
{
	// two segments sharing node n; a point in the node's corner region is clamped on both
	const Vec3 p0(0.1, 0.2, 0.3), n(0.7, -0.4, 1.3), p2(1.9, -0.1, 0.8);
	const Vec3 q  = n + Vec3(0.05, -0.6, 0.4); // outward of both segments at n
	const auto r1 = closestPointOnSegment(q, p0, n), r2 = closestPointOnSegment(q, n, p2);
	ASSERT_EQ(r1.u, 1.0);
	ASSERT_EQ(r2.u, 0.0);
	EXPECT_EQ((q - r1.point).norm(), (q - r2.point).norm());
}

TEST(PointSegment, DegenerateSegment)
{
	const Vec3 a(1, 2, 3);
	const auto r = closestPointOnSegment(Vec3(4, 5, 6), a, a);
	EXPECT_EQ(r.u, 0.0);
	EXPECT_EQ(r.point, a);
	const auto r2 = closestPointOnSegment(a, a, a);
	EXPECT_EQ(r2.u, 0.0);
	EXPECT_EQ(r2.point, a);
}

// ---------------------------------------------------------------- segment - segment

TEST(SegmentSegment, SkewInteriorAnalytic)
{
	// x axis at z = 0 and y-parallel segment at z = 1, crossing above x = 0.5
	const Vec3 a0(-1, 0, 0), a1(2, 0, 0), b0(0.5, -1, 1), b1(0.5, 3, 1);
	const auto r = closestPointsSegments(a0, a1, b0, b1);
	EXPECT_FALSE(r.parallel);
	EXPECT_DOUBLE_EQ(r.s, 0.5);
	EXPECT_DOUBLE_EQ(r.t, 0.25);
	EXPECT_TRUE(close(r.p1, Vec3(0.5, 0, 0), 1e-15));
	EXPECT_TRUE(close(r.p2, Vec3(0.5, 0, 1), 1e-15));
	EXPECT_DOUBLE_EQ(dist(r), 1.0);
}

TEST(SegmentSegment, SkewInteriorGenericLines)
{
	// two lines with a known common perpendicular: feet c1, c2 = c1 + h n, n perpendicular to both
	test::Rng rng(2);
	for (int k = 0; k < 100; ++k) {
		const Vec3   d1 = rng.unit(), d2 = rng.unit();
		const Vec3   n  = d1.cross(d2).normalized();
		const Vec3   c1 = rng.vec();
		const double h  = rng.uniform(0.01, 2.0);
		const Vec3   c2 = c1 + h * n;
		if (d1.cross(d2).norm() < 0.05) continue;
		const double s = rng.uniform(0.1, 0.9), t = rng.uniform(0.1, 0.9), L1 = rng.uniform(0.5, 3), L2 = rng.uniform(0.5, 3);
		const Vec3   a0 = c1 - s * L1 * d1, a1 = a0 + L1 * d1, b0 = c2 - t * L2 * d2, b1 = b0 + L2 * d2;
		const auto   r = closestPointsSegments(a0, a1, b0, b1);
		EXPECT_FALSE(r.parallel);
		EXPECT_NEAR(r.s, s, 1e-12);
		EXPECT_NEAR(r.t, t, 1e-12);
		EXPECT_TRUE(close(r.p1, c1, 1e-12, 1e-12));
		EXPECT_TRUE(close(r.p2, c2, 1e-12, 1e-12));
		EXPECT_NEAR(dist(r), h, 1e-12);
	}
}

TEST(SegmentSegment, RandomAgainstBruteForceAndOptimality)
{
	test::Rng rng(3);
	for (int k = 0; k < 12; ++k) {
		const Vec3   a0 = rng.vec(), a1 = rng.vec(), b0 = rng.vec(), b1 = rng.vec();
		const auto   r  = closestPointsSegments(a0, a1, b0, b1);
		const double bf = bruteForceDistance(a0, a1, b0, b1);
		EXPECT_LE(dist(r), bf + 1e-14); // never worse than any sampled pair
		EXPECT_NEAR(dist(r), bf, 1e-5); // and the refined grid gets there
		expectOptimal(a0, a1, b0, b1, r, 1e-12);
	}
	// many more cases with the exact optimality conditions only (convex: KKT <=> minimum)
	for (int k = 0; k < 2000; ++k) {
		const Vec3 a0 = rng.vec(), a1 = rng.vec(), b0 = rng.vec(), b1 = rng.vec();
		expectOptimal(a0, a1, b0, b1, closestPointsSegments(a0, a1, b0, b1), 1e-12);
	}
}

TEST(SegmentSegment, CrossingAxes)
{
	{
		const auto r = closestPointsSegments(Vec3(-1, 0, 0), Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 1, 0));
		EXPECT_EQ(r.s, 0.5);
		EXPECT_EQ(r.t, 0.5);
		EXPECT_EQ(r.p1, Vec3::Zero());
		EXPECT_EQ(r.p2, Vec3::Zero());
		EXPECT_EQ(dist(r), 0.0);
	}
	test::Rng rng(4);
	for (int k = 0; k < 100; ++k) {
		const Vec3   c = rng.vec(), d1 = rng.unit(), d2 = rng.unit();
		const double s = rng.uniform(0.1, 0.9), t = rng.uniform(0.1, 0.9);
		if (d1.cross(d2).norm() < 0.05) continue;
		const auto r = closestPointsSegments(c - s * d1, c + (1 - s) * d1, c - 2 * t * d2, c + 2 * (1 - t) * d2);
		EXPECT_NEAR(dist(r), 0.0, 1e-14);
		EXPECT_TRUE(close(r.p1, c, 1e-13, 1e-14));
		EXPECT_NEAR(r.s, s, 1e-12);
		EXPECT_NEAR(r.t, t, 1e-12);
	}
}

TEST(SegmentSegment, OneClamped)
{
	const Vec3 a0(0.1, 0.2, 0.3), a1(0.7, -0.4, 1.3);
	ASSERT_NE(Vec3(a0 + 1.0 * (a1 - a0)), a1);
	// segment 2 perpendicular to segment 1, passing beyond a1: s clamps to 1, t interior
	const Vec3 d1 = (a1 - a0).normalized(), n = d1.cross(Vec3(0, 0, 1)).normalized(), m = d1.cross(n);
	const Vec3 c2 = a1 + 0.4 * d1 + 0.3 * m; // foot of a1 on line 2 is c2 - 0.4 d1 ... line 2 along n
	const Vec3 b0 = c2 - 0.6 * n, b1 = c2 + 1.4 * n;
	const auto r = closestPointsSegments(a0, a1, b0, b1);
	EXPECT_EQ(r.s, 1.0);
	EXPECT_EQ(r.p1, a1);
	EXPECT_NEAR(r.t, 0.3, 1e-12);
	EXPECT_TRUE(close(r.p2, c2, 1e-12));
	EXPECT_NEAR(dist(r), std::hypot(0.4, 0.3), 1e-12);
	// the same with the segments swapped: t clamps to 1
	const auto q = closestPointsSegments(b0, b1, a0, a1);
	EXPECT_EQ(q.t, 1.0);
	EXPECT_EQ(q.p2, a1);
	EXPECT_NEAR(q.s, 0.3, 1e-12);
}

TEST(SegmentSegment, BothClamped)
{
	const Vec3 a0(0, 0, 0), a1(1, 0, 0), b0(2, 0, 1), b1(3, 0, 2);
	const auto r = closestPointsSegments(a0, a1, b0, b1);
	EXPECT_EQ(r.s, 1.0);
	EXPECT_EQ(r.t, 0.0);
	EXPECT_EQ(r.p1, a1);
	EXPECT_EQ(r.p2, b0);
	EXPECT_DOUBLE_EQ(dist(r), std::sqrt(2.0));
	// awkward coordinates: the returned points are still the end points bit for bit
	const Vec3 c0(0.1, 0.2, 0.3), c1(0.7, -0.4, 1.3), e0(1.9, -1.1, 2.8), e1(3.3, -1.7, 4.1);
	const auto q = closestPointsSegments(e1, e0, c0, c1);
	EXPECT_EQ(q.s, 1.0);
	EXPECT_EQ(q.t, 1.0);
	EXPECT_EQ(q.p1, e0);
	EXPECT_EQ(q.p2, c1);
}

TEST(SegmentSegment, ParallelOverlapMiddle)
{
	const Vec3 a0(0, 0, 0), a1(4, 0, 0);
	for (bool reversed : { false, true }) {
		const Vec3 b0 = reversed ? Vec3(6, 1, 0) : Vec3(1, 1, 0), b1 = reversed ? Vec3(1, 1, 0) : Vec3(6, 1, 0);
		const auto r = closestPointsSegments(a0, a1, b0, b1);
		EXPECT_TRUE(r.parallel);
		// overlap is x in [1, 4]: its middle x = 2.5
		EXPECT_DOUBLE_EQ(r.s, 2.5 / 4);
		EXPECT_TRUE(close(r.p1, Vec3(2.5, 0, 0), 1e-15));
		EXPECT_TRUE(close(r.p2, Vec3(2.5, 1, 0), 1e-15));
		EXPECT_DOUBLE_EQ(r.t, reversed ? 3.5 / 5 : 1.5 / 5);
	}
}

TEST(SegmentSegment, ParallelSlidingIsContinuous)
{
	// segment 2 (length 2, offset h) slides along segment 1 (length 3, along a generic direction)
	const Vec3   o(0.3, -0.2, 0.7), d = Vec3(1, 2, -0.5).normalized(), n = d.cross(Vec3(0, 0, 1)).normalized();
	const double L1 = 3, L2 = 2, h = 0.25;
	Vec3         prev;
	bool         first = true;
	for (int k = 0; k <= 1000; ++k) {
		const double x0 = -3.5 + 7.0 * k / 1000; // start of segment 2 along d
		const Vec3   b0 = o + x0 * d + h * n, b1 = o + (x0 + L2) * d + h * n;
		const auto   r = closestPointsSegments(o, o + L1 * d, b0, b1);
		EXPECT_TRUE(r.parallel);
		const double lo = std::max(0.0, x0), hi = std::min(L1, x0 + L2);
		if (lo <= hi) { // overlap: middle of it, at distance h
			EXPECT_NEAR(r.s * L1, 0.5 * (lo + hi), 1e-12);
			EXPECT_NEAR(dist(r), h, 1e-12);
		} else { // disjoint: nearest end points
			EXPECT_EQ(r.s, x0 > 0 ? 1.0 : 0.0);
			EXPECT_EQ(r.t, x0 > 0 ? 0.0 : 1.0);
			EXPECT_NEAR(dist(r), std::hypot(x0 > 0 ? x0 - L1 : -(x0 + L2), h), 1e-12);
		}
		if (!first) {
			EXPECT_LE((r.p1 - prev).norm(), 7.0 / 1000 + 1e-12);
		} // moves at most as far as segment 2
		prev  = r.p1;
		first = false;
	}
}

TEST(SegmentSegment, ParallelDisjointNearestEnds)
{
	const Vec3 a0(0, 0, 0), a1(1, 0, 0);
	{
		const Vec3 b0(2, 1, 0), b1(3, 1, 0);
		const auto r = closestPointsSegments(a0, a1, b0, b1);
		EXPECT_TRUE(r.parallel);
		EXPECT_EQ(r.s, 1.0);
		EXPECT_EQ(r.t, 0.0);
		EXPECT_EQ(r.p1, a1);
		EXPECT_EQ(r.p2, b0);
	}
	{
		const Vec3 b0(-2, 0, 1), b1(-3, 0, 1); // on the other side, reversed
		const auto r = closestPointsSegments(a0, a1, b0, b1);
		EXPECT_TRUE(r.parallel);
		EXPECT_EQ(r.s, 0.0);
		EXPECT_EQ(r.t, 0.0);
		EXPECT_EQ(r.p1, a0);
		EXPECT_EQ(r.p2, b0);
		EXPECT_DOUBLE_EQ(dist(r), std::sqrt(5.0));
	}
}

TEST(SegmentSegment, Collinear)
{
	const Vec3 a0(0, 0, 0), a1(2, 0, 0);
	{ // overlapping: [1, 2]
		const auto r = closestPointsSegments(a0, a1, Vec3(1, 0, 0), Vec3(3, 0, 0));
		EXPECT_TRUE(r.parallel);
		EXPECT_EQ(r.s, 0.75);
		EXPECT_EQ(r.t, 0.25);
		EXPECT_EQ(r.p1, Vec3(1.5, 0, 0));
		EXPECT_EQ(dist(r), 0.0);
	}
	{ // one inside the other
		const auto r = closestPointsSegments(a0, a1, Vec3(0.5, 0, 0), Vec3(1.0, 0, 0));
		EXPECT_EQ(r.p1, Vec3(0.75, 0, 0));
		EXPECT_EQ(r.t, 0.5);
	}
	{ // disjoint
		const auto r = closestPointsSegments(a0, a1, Vec3(5, 0, 0), Vec3(3, 0, 0));
		EXPECT_EQ(r.s, 1.0);
		EXPECT_EQ(r.t, 1.0);
		EXPECT_EQ(r.p1, a1);
		EXPECT_EQ(r.p2, Vec3(3, 0, 0));
		EXPECT_EQ(dist(r), 1.0);
	}
}

TEST(SegmentSegment, DegenerateSegments)
{
	const Vec3 b0(0.1, 0.2, 0.3), b1(0.7, -0.4, 1.3);
	{ // segment 1 is a point projecting inside segment 2
		const Vec3 p = b0 + 0.3 * (b1 - b0) + (b1 - b0).cross(Vec3(1, 0, 0));
		const auto r = closestPointsSegments(p, p, b0, b1);
		EXPECT_EQ(r.s, 0.0);
		EXPECT_EQ(r.p1, p);
		EXPECT_NEAR(r.t, 0.3, 1e-14);
		EXPECT_EQ(closestPointOnSegment(p, b0, b1).point, r.p2);
	}
	{ // segment 1 is a point beyond b1: clamped, exact end point
		const Vec3 p = b1 + 0.5 * (b1 - b0);
		const auto r = closestPointsSegments(p, p, b0, b1);
		EXPECT_EQ(r.t, 1.0);
		EXPECT_EQ(r.p2, b1);
	}
	{ // segment 2 is a point
		const Vec3 p(0.2, 5, -1);
		const auto r = closestPointsSegments(b0, b1, p, p);
		EXPECT_EQ(r.t, 0.0);
		EXPECT_EQ(r.p2, p);
		EXPECT_EQ(r.s, closestPointOnSegment(p, b0, b1).u);
		EXPECT_EQ(r.p1, closestPointOnSegment(p, b0, b1).point);
	}
	{ // both points
		const Vec3 p(1, 2, 3), q(4, 6, 3);
		const auto r = closestPointsSegments(p, p, q, q);
		EXPECT_EQ(r.s, 0.0);
		EXPECT_EQ(r.t, 0.0);
		EXPECT_EQ(r.p1, p);
		EXPECT_EQ(r.p2, q);
		EXPECT_EQ(dist(r), 5.0);
	}
}

// ---------------------------------------------------------------- contact normal

namespace {
void expectUnitPerp(const Vec3& n, const Vec3& ax1, const Vec3& ax2)
{
	ASSERT_TRUE(n.allFinite());
	EXPECT_NEAR(n.norm(), 1.0, 1e-14);
	if (ax1.norm() > 0) {
		EXPECT_NEAR(n.dot(ax1.normalized()), 0.0, 1e-12);
	}
	if (ax2.norm() > 0) {
		EXPECT_NEAR(n.dot(ax2.normalized()), 0.0, 1e-12);
	}
}
} // namespace

TEST(ContactNormal, DistinctPoints)
{
	EXPECT_EQ(contactNormal(Vec3(1, 1, 1), Vec3(1, 1, 3), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, -1)), Vec3(0, 0, 1));
	test::Rng rng(5);
	for (int k = 0; k < 50; ++k) {
		const Vec3 a = rng.vec(), b = rng.vec();
		EXPECT_TRUE(close(contactNormal(a, b, rng.vec(), rng.vec(), rng.vec()), Vec3((b - a).normalized()), 1e-15));
	}
}

TEST(ContactNormal, CoincidentUsesPreviousNormalProjectedOffBothAxes)
{
	const Vec3 c(0.3, 0.4, 0.5);
	// orthogonal axes: the previous normal is carried, sign kept
	{
		const Vec3 n = contactNormal(c, c, Vec3(1, 0, 0), Vec3(0, 2, 0), Vec3(0.3, 0.2, -1));
		EXPECT_TRUE(close(n, Vec3(0, 0, -1), 1e-15));
	}
	// non-orthogonal crossing axes: the only unit vectors perpendicular to both are +-z
	{
		const Vec3 n = contactNormal(c, c, Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 1));
		expectUnitPerp(n, Vec3(1, 0, 0), Vec3(1, 1, 0));
		EXPECT_TRUE(close(n, Vec3(0, 0, 1), 1e-15));
	}
	test::Rng rng(6);
	for (int k = 0; k < 200; ++k) {
		const Vec3 ax1 = rng.vec(), ax2 = rng.vec(), prev = rng.unit();
		const Vec3 perp = ax1.cross(ax2).normalized();
		if (std::abs(prev.dot(perp)) < 0.1 || ax1.cross(ax2).norm() < 0.05 * ax1.norm() * ax2.norm()) continue;
		const Vec3 n = contactNormal(c, c, ax1, ax2, prev);
		expectUnitPerp(n, ax1, ax2);
		EXPECT_GT(n.dot(prev), 0.0); // same side as the previous normal
	}
	// sphere on a cylinder axis (one axis): previous normal minus its axial part
	{
		const Vec3 ax(0, 0, 3), prev(1, 1, 1);
		const Vec3 n = contactNormal(c, c, ax, Vec3::Zero(), prev);
		EXPECT_TRUE(close(n, Vec3(Vec3(1, 1, 0).normalized()), 1e-15));
	}
	// parallel axes: previous normal minus the common axial part
	{
		const Vec3 n = contactNormal(c, c, Vec3(0, 0, 1), Vec3(0, 0, -2), Vec3(0, 3, 4));
		EXPECT_TRUE(close(n, Vec3(0, 1, 0), 1e-15));
	}
	// axes parallel to within round-off (1e-9 rad): still the previous normal minus the axial part,
	// not a direction amplified from the tiny difference of the axes
	{
		const Vec3 ax1(0, 0, 1), ax2(1e-9, 0, 1), prev(0.6, 0.8, 0.3);
		const Vec3 n = contactNormal(c, c, ax1, ax2, prev);
		EXPECT_TRUE(close(n, Vec3(0.6, 0.8, 0), 1e-15));
		EXPECT_NEAR(n.dot(ax2.normalized()), 0.0, 1e-9);
	}
}

TEST(ContactNormal, CoincidentFallbacksNeverNaN)
{
	const Vec3 c(1, 2, 3);
	// no previous normal: cross product of the axes
	{
		const Vec3 n = contactNormal(c, c, Vec3(2, 0, 0), Vec3(1, 1, 0), Vec3::Zero());
		EXPECT_TRUE(close(n.cwiseAbs(), Vec3(0, 0, 1), 1e-15));
	}
	// previous normal along an axis (unusable): cross product of the axes
	{
		const Vec3 n = contactNormal(c, c, Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(0, 5, 0));
		expectUnitPerp(n, Vec3(0, 1, 0), Vec3(0, 0, 1));
	}
	// previous normal in the plane of the two axes (unusable)
	{
		const Vec3 n = contactNormal(c, c, Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0.3, -0.7, 0));
		expectUnitPerp(n, Vec3(1, 0, 0), Vec3(1, 1, 0));
	}
	// parallel axes, no previous normal: any perpendicular of the axis
	{
		const Vec3 n = contactNormal(c, c, Vec3(1, 2, 3), Vec3(-2, -4, -6), Vec3::Zero());
		expectUnitPerp(n, Vec3(1, 2, 3), Vec3(-2, -4, -6));
	}
	// sphere centre on the axis, no previous normal
	{
		const Vec3 n = contactNormal(c, c, Vec3(0.3, -0.1, 2), Vec3::Zero(), Vec3::Zero());
		expectUnitPerp(n, Vec3(0.3, -0.1, 2), Vec3::Zero());
	}
	// everything degenerate: still a finite unit vector
	{
		const Vec3 n = contactNormal(c, c, Vec3::Zero(), Vec3::Zero(), Vec3::Zero());
		ASSERT_TRUE(n.allFinite());
		EXPECT_NEAR(n.norm(), 1.0, 1e-15);
	}
	// anyPerpendicular itself
	test::Rng rng(7);
	for (int k = 0; k < 100; ++k) {
		const Vec3 d = rng.vec() * std::pow(10.0, rng.uniform(-6, 6));
		const Vec3 p = anyPerpendicular(d);
		ASSERT_TRUE(p.allFinite());
		EXPECT_NEAR(p.norm(), 1.0, 1e-14);
		EXPECT_NEAR(p.dot(d.normalized()), 0.0, 1e-14);
	}
}
