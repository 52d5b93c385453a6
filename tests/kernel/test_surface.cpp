// yade-flex kernel tests: a node against a plane, a box and a triangle, and the ownership of a
// node's contacts on a surface of several triangles (GPL-2.0-or-later). Exact geometry.
#include "kernel/Surface.hpp"

#include <gtest/gtest.h>

using namespace flex;

namespace {
constexpr double kTol = 1e-14;
void expectNear(const Vec3& a, const Vec3& b) { EXPECT_LT((a - b).norm(), kTol) << a.transpose() << " vs " << b.transpose(); }
FacetHit hitOn(int id, const Vec3& x, double r, const Vec3& a, const Vec3& b, const Vec3& c)
{
	const SurfacePoint s = nodeOnTriangle(x, a, b, c, 0);
	FacetHit           h;
	h.id      = id;
	h.overlap = r - s.distance;
	h.v[0]    = a;
	h.v[1]    = b;
	h.v[2]    = c;
	h.support = s.support;
	return h;
}
} // namespace

TEST(Surface, PlaneOneSidedPushesTowardsItsSideEvenFromBehind)
{
	const SurfacePoint s = nodeOnPlane(Vec3(1, 2, -0.25), 2, 0.0, +1, 0);
	expectNear(s.point, Vec3(1, 2, 0));
	expectNear(s.normal, Vec3(0, 0, 1));
	EXPECT_DOUBLE_EQ(s.distance, -0.25);
	const SurfacePoint t = nodeOnPlane(Vec3(1, 0.5, 2), 1, 1.0, -1, 0);
	expectNear(t.normal, Vec3(0, -1, 0));
	EXPECT_DOUBLE_EQ(t.distance, 0.5);
}

TEST(Surface, TwoSidedPlaneKeepsTheSideTheContactStartedFrom)
{
	const SurfacePoint now = nodeOnPlane(Vec3(0, 0, -0.1), 2, 0.0, 0, 0);
	expectNear(now.normal, Vec3(0, 0, -1));
	EXPECT_DOUBLE_EQ(now.distance, 0.1);
	const SurfacePoint kept = nodeOnPlane(Vec3(0, 0, -0.1), 2, 0.0, 0, +1); // pushed through from above
	expectNear(kept.normal, Vec3(0, 0, 1));
	EXPECT_DOUBLE_EQ(kept.distance, -0.1);
}

TEST(Surface, BoxOutsideFaceEdgeAndCorner)
{
	const Vec3 ext(1, 2, 3);
	SurfacePoint s = nodeOnBox(Vec3(1.5, 0.5, 0.5), ext); // face
	expectNear(s.point, Vec3(1, 0.5, 0.5));
	expectNear(s.normal, Vec3(1, 0, 0));
	EXPECT_DOUBLE_EQ(s.distance, 0.5);
	s = nodeOnBox(Vec3(2, 3, 0), ext); // edge
	expectNear(s.point, Vec3(1, 2, 0));
	expectNear(s.normal, Vec3(1, 1, 0).normalized());
	EXPECT_NEAR(s.distance, std::sqrt(2.0), kTol);
	s = nodeOnBox(Vec3(-2, -3, -4), ext); // corner
	expectNear(s.point, Vec3(-1, -2, -3));
	EXPECT_NEAR(s.distance, std::sqrt(3.0), kTol);
}

TEST(Surface, BoxInsideIsPushedOutThroughTheNearestFace)
{
	const SurfacePoint s = nodeOnBox(Vec3(0.2, -1.9, 0.0), Vec3(1, 2, 3));
	expectNear(s.point, Vec3(0.2, -2, 0.0));
	expectNear(s.normal, Vec3(0, -1, 0));
	EXPECT_NEAR(s.distance, -0.1, kTol);
}

TEST(Surface, TriangleFaceEdgeAndVertexRegions)
{
	const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
	SurfacePoint s = nodeOnTriangle(Vec3(0.2, 0.2, -0.3), a, b, c, 0);
	EXPECT_EQ(s.support, 7u);
	expectNear(s.normal, Vec3(0, 0, -1));
	EXPECT_DOUBLE_EQ(s.distance, 0.3);
	s = nodeOnTriangle(Vec3(0.2, 0.2, -0.3), a, b, c, +1); // started above: pushed back up
	expectNear(s.normal, Vec3(0, 0, 1));
	EXPECT_DOUBLE_EQ(s.distance, -0.3);
	s = nodeOnTriangle(Vec3(0.5, -0.3, 0.4), a, b, c, 0); // edge ab
	EXPECT_EQ(s.support, 3u);
	expectNear(s.point, Vec3(0.5, 0, 0));
	EXPECT_NEAR(s.distance, 0.5, kTol);
	expectNear(s.normal, Vec3(0, -0.6, 0.8));
	s = nodeOnTriangle(Vec3(-0.3, -0.4, 0), a, b, c, 0); // vertex a
	EXPECT_EQ(s.support, 1u);
	EXPECT_NEAR(s.distance, 0.5, kTol);
}

// Two coplanar triangles sharing the edge (1,0,0)-(0,1,0), a square's halves, with their
// vertices stored apart (the second offset by round-off).
TEST(Surface, CoplanarNeighboursCarryOneContactAcrossTheirSharedEdge)
{
	const double r = 0.05, e = 1e-15;
	const Vec3   a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
	const Vec3   b2(1 + e, 0, 0), c2(0, 1 - e, 0), d(1, 1, 0);
	for (const Vec3& x : { Vec3(0.3, 0.3, 0.03), Vec3(0.5, 0.5, 0.03), Vec3(0.6, 0.6, 0.03) }) {
		FacetHit h[2] = { hitOn(10, x, r, a, b, c), hitOn(11, x, r, b2, d, c2) };
		int      beaten[8], nb0 = 0, nb1 = 0;
		const bool o0 = ownsFacetCluster(h, 2, 0, beaten, nb0), o1 = ownsFacetCluster(h, 2, 1, beaten, nb1);
		EXPECT_NE(o0, o1) << "exactly one carries the contact at x = " << x.transpose();
		const FacetHit& owner = o0 ? h[0] : h[1];
		EXPECT_NEAR(owner.overlap, r - 0.03, 1e-14); // the face's overlap, the node's true one
		if (x[0] + x[1] == 1) EXPECT_TRUE(o0) << "on the shared edge the lower id carries it, whatever the round-off";
	}
}

TEST(Surface, NodeInAValleyTouchesBothFaces)
{
	// a V: two faces meeting along the x axis at +-45 degrees, the node on the bisector
	const double r = 0.1;
	const Vec3   o(0, 0, 0), o2(2, 0, 0), p2(2, 1, 1), q2(2, -1, 1);
	const Vec3   x(1, 0, 0.12);
	FacetHit     h[2] = { hitOn(1, x, r, o, o2, p2), hitOn(2, x, r, o, q2, o2) };
	ASSERT_EQ(h[0].support, 7u);
	ASSERT_EQ(h[1].support, 7u);
	int beaten[8], nb = 0;
	EXPECT_TRUE(ownsFacetCluster(h, 2, 0, beaten, nb));
	EXPECT_TRUE(ownsFacetCluster(h, 2, 1, beaten, nb));
}

TEST(Surface, ClusterIsClosedTransitively)
{
	// three coplanar strips in a row: A-B share an edge, B-C share an edge, A and C nothing
	const double r = 0.2;
	const auto   strip = [&](int id, double x0, const Vec3& x) { return hitOn(id, x, r, Vec3(x0, 0, 0), Vec3(x0 + 1, 0, 0), Vec3(x0, 1, 0)); };
	// the node over B's corner near A; C touches at its edge shared with B
	const Vec3 x(1.05, 0.02, 0.1);
	FacetHit   h[3] = { strip(1, 0, x), hitOn(2, x, r, Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)), strip(3, 1, x) };
	int        beaten[8], nb = 0, owners = 0;
	for (int i = 0; i < 3; ++i)
		owners += ownsFacetCluster(h, 3, i, beaten, nb) ? 1 : 0;
	EXPECT_EQ(owners, 1);
}

// A wire across the top edge of a box, its nodes beyond: met at the edge, between its nodes.
TEST(Surface, SegmentOverABoxEdgeIsMetBetweenItsNodes)
{
	const Vec3        ext(1, 1, 1);
	const Vec3        x0(0, 0, 2.5), x1(2.5, 0, 0); // the line x + z = 2.5, nearest the edge (1, y, 1)
	const SegmentEdge e = segmentOnBoxEdges(x0, x1, ext);
	ASSERT_TRUE(e.valid);
	EXPECT_NEAR(e.u, 0.5, 1e-12);
	expectNear(e.point, Vec3(1, 0, 1));
	expectNear(e.normal, Vec3(1, 0, 1).normalized());
	EXPECT_NEAR(e.distance, 0.5 / std::sqrt(2.0), 1e-14);
	// a wire lying over the top face: its deepest points are its nodes, no edge contact
	EXPECT_FALSE(segmentOnBoxEdges(Vec3(-0.5, 0, 1.2), Vec3(0.5, 0, 1.3), ext).valid);
	// a wire whose closest point to the edge is a node: the node's contact
	EXPECT_FALSE(segmentOnBoxEdges(Vec3(1.2, 0, 1.2), Vec3(3, 0, 3), ext).valid);
}
