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

TEST(Surface, SegmentOverAFacetEdgeIsMetBetweenItsNodes)
{
	// the triangle lies in z = 0 on the side x <= 0 of its edge (0, y, 0), y in [0, 2]
	const Vec3        a(0, 0, 0), b(0, 2, 0), c(-2, 1, 0);
	const Vec3        x0(-1, 1, 1.5), x1(1.5, 1, -1); // the line x + z = 0.5 in y = 1, nearest the edge at (0, 1, 0)
	const SegmentEdge e = segmentOnTriangleEdges(x0, x1, a, b, c);
	ASSERT_TRUE(e.valid);
	EXPECT_NEAR(e.u, 0.5, 1e-12);
	expectNear(e.point, Vec3(0, 1, 0));
	expectNear(e.onSegment, Vec3(0.25, 1, 0.25));
	expectNear(e.normal, Vec3(1, 0, 1).normalized());
	EXPECT_NEAR(e.distance, 0.5 / std::sqrt(2.0), 1e-14);
	EXPECT_EQ(e.support, 3u); // the edge a-b
	// past a vertex: the vertex alone carries it
	const SegmentEdge v = segmentOnTriangleEdges(Vec3(0.3, 2.6, 1), Vec3(0.3, 2.6, -1), a, b, c);
	ASSERT_TRUE(v.valid);
	expectNear(v.point, b);
	EXPECT_EQ(v.support, 2u);
	EXPECT_NEAR(v.distance, std::hypot(0.3, 0.6), 1e-14);
	// a wire lying over the face (its deepest points are its nodes), or one whose closest point is
	// a node, or one that crosses the face: no edge contact
	EXPECT_FALSE(segmentOnTriangleEdges(Vec3(-1.5, 1, 0.3), Vec3(-0.5, 1, 0.2), a, b, c).valid);
	EXPECT_FALSE(segmentOnTriangleEdges(Vec3(0.2, 1, 0.2), Vec3(2, 1, 2), a, b, c).valid);
	EXPECT_FALSE(segmentOnTriangleEdges(Vec3(-1, 1, 0.5), Vec3(-0.5, 1, -0.5), a, b, c).valid);
}

TEST(Surface, WireOverARidgeOfTwoFacetsCarriesOneContact)
{
	// a roof: two facets share the ridge (0, y, 0), their vertices stored apart (round-off apart)
	const double e = 1e-15, r = 0.4;
	const Vec3   a(0, 0, 0), b(0, 2, 0), c(-2, 1, -1), a2(e, 0, 0), b2(0, 2 + e, 0), d(2, 1, -1);
	for (double x : { -0.1, 0.0, 0.1 }) {
		const Vec3        x0(-1 + x, 1, 0.3), x1(1.2 + x, 1, 0.3);
		const SegmentEdge s0 = segmentOnTriangleEdges(x0, x1, a, b, c), s1 = segmentOnTriangleEdges(x0, x1, a2, b2, d);
		ASSERT_TRUE(s0.valid && s1.valid);
		EXPECT_NEAR(s0.distance, 0.3, 1e-14);
		EXPECT_NEAR(s1.distance, 0.3, 1e-14);
		FacetHit h[2];
		const SegmentEdge* s[2] = { &s0, &s1 };
		const Vec3         v[2][3] = { { a, b, c }, { a2, b2, d } };
		for (int k = 0; k < 2; ++k) {
			h[k].id      = 20 + k;
			h[k].overlap = r - s[k]->distance;
			h[k].support = s[k]->support;
			for (int j = 0; j < 3; ++j)
				h[k].v[j] = v[k][j];
		}
		int        beaten[8], nb0 = 0, nb1 = 0;
		const bool o0 = ownsFacetCluster(h, 2, 0, beaten, nb0), o1 = ownsFacetCluster(h, 2, 1, beaten, nb1);
		EXPECT_NE(o0, o1) << "one contact at the ridge, x = " << x;
		EXPECT_EQ(o0 ? nb0 : nb1, 1);
	}
}

TEST(Surface, WireOverTheDiagonalOfAFlatSurfaceHasNoEdgeContact)
{
	// two coplanar facets sharing the diagonal (0,0,0)-(1,1,0); a tilted wire crossing the diagonal
	// over the flat square: its deepest point is its lower node, over the first facet's face
	const Vec3 tri[2][3] = { { Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0) }, { Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0) } };
	const int  ids[2]    = { 1, 2 };
	const Vec3 x0(0.7, 0.3, 0.02), x1(0.3, 0.7, 0.06); // x0 over the first facet, x1 over the second
	ASSERT_TRUE(segmentOnTriangleEdges(x0, x1, tri[1][0], tri[1][1], tri[1][2]).valid); // alone, the second facet's edge looks nearest
	SegmentEdge edge[2];
	FacetHit    hit[2];
	segmentOnFacets(x0, x1, 0.1, tri, ids, 2, edge, hit);
	EXPECT_FALSE(hit[0].overlap > 0);
	EXPECT_FALSE(hit[1].overlap > 0) << "the first facet's face is nearer to that point";
}

TEST(Surface, WireOverARidgeOfFourFacetsCarriesOneContact)
{
	// a roof of two slopes, each a rectangle of two triangles; the ridge (0.5, y, 0.2) is an edge of
	// one triangle of each slope
	const Vec3 r0(0.5, 0, 0.2), r1(0.5, 1, 0.2), a0(0, 0, -0.3), a1(0, 1, -0.3), b0(1, 0, -0.3), b1(1, 1, -0.3);
	const Vec3 tri[4][3] = { { r0, r1, a1 }, { r0, a1, a0 }, { r1, r0, b0 }, { r1, b0, b1 } };
	const int  ids[4]    = { 5, 6, 7, 8 };
	SegmentEdge edge[4];
	FacetHit    hit[4];
	for (double y : { 0.2, 0.5, 0.9 }) { // a wire across the ridge, 5 mm above it, its nodes high over both slopes
		segmentOnFacets(Vec3(0.45, y, 0.205), Vec3(0.56, y, 0.205), 0.01, tri, ids, 4, edge, hit);
		int owners = 0, beaten[8], nb = 0;
		for (int k = 0; k < 4; ++k)
			if (hit[k].overlap > 0 && ownsFacetCluster(hit, 4, k, beaten, nb)) {
				++owners;
				EXPECT_NEAR(edge[k].distance, 0.005, 1e-12);
				expectNear(edge[k].point, Vec3(0.5, y, 0.2));
			}
		EXPECT_EQ(owners, 1) << "y = " << y;
	}
}

TEST(Surface, WireFromANodeOnASharedDiagonalHasNoEdgeContact)
{
	// found on a net at rest on two facets: a wire from a node on their shared diagonal, over the
	// first facet, its far node 1e-7 m lower; alone, the second facet's diagonal looks nearest a
	// round-off away from the node (that node's own contact carries it)
	const Vec3 tri[2][3] = { { Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0) }, { Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0) } };
	const int  ids[2]    = { 1, 2 };
	const Vec3 x0(0.4, 0.4, 0.003), x1(0.5, 0.4, 0.003 - 1e-7);
	SegmentEdge edge[2];
	FacetHit    hit[2];
	segmentOnFacets(x0, x1, 0.003 + 1e-6, tri, ids, 2, edge, hit);
	EXPECT_FALSE(hit[0].overlap > 0);
	EXPECT_FALSE(hit[1].overlap > 0);
}

namespace {
// A large triangle in the plane n . x = h (n unit), around the point q of that plane.
void triangleAround(const Vec3& n, const Vec3& q, double size, Vec3 x[3])
{
	const Vec3 t = n.unitOrthogonal(), s = n.cross(t);
	for (int k = 0; k < 3; ++k) {
		const double a = 2 * M_PI * k / 3;
		x[k]           = q + size * (std::cos(a) * t + std::sin(a) * s);
	}
}
} // namespace

// A box corner pressed into the middle of a sheet: met at the corner, between the sheet's nodes.
TEST(Surface, BoxCornerUnderAMembraneIsMetBetweenItsNodes)
{
	const Vec3 ext(1, 1, 1), n = Vec3(1, 1, 1).normalized();
	Vec3       x[3];
	triangleAround(n, Vec3(1, 1, 1) + 0.3 * n, 4, x); // 0.3 from the corner
	const TriangleEdge e = boxEdgesOnTriangle(x[0], x[1], x[2], ext);
	ASSERT_TRUE(e.valid);
	EXPECT_FALSE(e.pierced);
	expectNear(e.point, Vec3(1, 1, 1));
	EXPECT_NEAR(e.distance, 0.3, 1e-14);
	EXPECT_LT((e.normal - n).norm(), 1e-14);
	EXPECT_EQ(e.triSupport, 7u);
	EXPECT_NEAR(e.w[0] + e.w[1] + e.w[2], 1, 1e-14);
	EXPECT_LT((e.w[0] * x[0] + e.w[1] * x[1] + e.w[2] * x[2] - e.onTriangle).norm(), 1e-13);
	// pushed past the midplane: pierced (the piercing point on the sheet)
	triangleAround(n, Vec3(1, 1, 1) - 0.1 * n, 4, x);
	const TriangleEdge p = boxEdgesOnTriangle(x[0], x[1], x[2], ext);
	ASSERT_TRUE(p.valid);
	EXPECT_TRUE(p.pierced);
	EXPECT_EQ(p.distance, 0);
}

// A box edge under a sheet draped over it, the sheet's nodes beyond: met on the edge.
TEST(Surface, BoxEdgeUnderAMembraneIsMetOnTheEdge)
{
	const Vec3 ext(1, 1, 1), n = Vec3(1, 0, 1).normalized();
	Vec3       x[3];
	triangleAround(n, Vec3(1, 0, 1) + 0.2 * n, 5, x);
	const TriangleEdge e = boxEdgesOnTriangle(x[0], x[1], x[2], ext);
	ASSERT_TRUE(e.valid);
	EXPECT_NEAR(e.point[0], 1, 1e-14);
	EXPECT_NEAR(e.point[2], 1, 1e-14);
	EXPECT_LE(std::abs(e.point[1]), 1);
	EXPECT_NEAR(e.distance, 0.2, 1e-14);
}

// A sheet lying over a box's top face, or whose nearest point is a node: no edge contact (the
// nodes carry it).
TEST(Surface, MembraneOverABoxFaceOrNearestAtANodeHasNoEdgeContact)
{
	const Vec3 ext(1, 1, 1);
	// flat over the top face, its nodes over the face (one of them the deepest, tilted slightly)
	EXPECT_FALSE(boxEdgesOnTriangle(Vec3(-0.8, -0.8, 1.1), Vec3(0.8, -0.8, 1.12), Vec3(0, 0.8, 1.15), ext).valid);
	// a node nearest the corner
	EXPECT_FALSE(boxEdgesOnTriangle(Vec3(1.1, 1.1, 1.1), Vec3(3, 1.1, 2), Vec3(1.1, 3, 2), ext).valid);
}

// A sheet across the ridge of a roof of two facets (vertices stored apart): one contact, at the ridge.
TEST(Surface, MembraneOverARidgeOfTwoFacetsCarriesOneContact)
{
	const double e = 1e-15, r = 0.4;
	const Vec3   tri[2][3] = { { Vec3(0, 0, 0), Vec3(0, 2, 0), Vec3(-2, 1, -1) }, { Vec3(e, 0, 0), Vec3(0, 2 + e, 0), Vec3(2, 1, -1) } };
	const int    ids[2]    = { 20, 21 };
	for (double dx : { -0.1, 0.0, 0.1 }) {
		// a horizontal sheet 0.3 above the ridge, its nodes far over both slopes
		const Vec3   x0(-1.5 + dx, -2, 0.3), x1(1.5 + dx, 1, 0.3), x2(-1 + dx, 4, 0.3);
		TriangleEdge edge[2];
		FacetHit     hit[2];
		membraneOnFacets(x0, x1, x2, r, tri, ids, 2, edge, hit);
		ASSERT_TRUE(edge[0].valid && edge[1].valid);
		EXPECT_NEAR(edge[0].distance, 0.3, 1e-14);
		EXPECT_NEAR(edge[0].point[0], 0, 1e-14);
		int        beaten[8], nb0 = 0, nb1 = 0;
		const bool o0 = ownsFacetCluster(hit, 2, 0, beaten, nb0), o1 = ownsFacetCluster(hit, 2, 1, beaten, nb1);
		EXPECT_NE(o0, o1) << "one contact at the ridge, dx = " << dx;
	}
	// over one facet's face only (a node the deepest): none
	EXPECT_FALSE(triangleEdgesOnTriangle(Vec3(-1.5, 0.5, -0.2), Vec3(-0.5, 0.5, 0.1), Vec3(-1, 1.5, 0.0), tri[0][0], tri[0][1], tri[0][2]).valid);
}

// A box corner under the diagonal two facets of a sheet share: the point lies on that edge of
// both (its support the edge's two nodes), so the sheet's ownership carries it once.
TEST(Surface, BoxCornerUnderASheetsDiagonalLiesOnThatEdge)
{
	const Vec3 ext(1, 1, 1);
	// the box turned so that its corner (1, 1, 1) points along n; the sheet in the plane n.x = sqrt3 + 0.2
	const Vec3 n = Vec3(1, 1, 1).normalized(), t = Vec3(1, -1, 0).normalized(), s = n.cross(t);
	const Vec3 c = Vec3(1, 1, 1) + 0.2 * n;
	// two facets sharing the diagonal (c - 0.5 t, c + 0.5 t)
	const Vec3         a = c - 0.5 * t, b = c + 0.5 * t, p = c + 0.5 * s, q = c - 0.5 * s;
	const TriangleEdge e1 = boxEdgesOnTriangle(a, b, p, ext), e2 = boxEdgesOnTriangle(b, a, q, ext);
	ASSERT_TRUE(e1.valid && e2.valid);
	EXPECT_EQ(e1.triSupport, 3u);
	EXPECT_EQ(e2.triSupport, 3u);
	EXPECT_NEAR(e1.distance, 0.2, 1e-14);
}

// Found on a sheet landing on a ridge: a ridge nearly parallel to a facet of the sheet, 1 mm below
// it; the closest points of the ridge's line and the facet agree along the ridge to 1e-9 m only.
TEST(Surface, SheetJustOverARidgeIsMetOnTheRidge)
{
	const Vec3 a(0.5, 0, 0), b(0.5, 1, 0), c(0, 1, -0.28867513459481287);
	const Vec3 x0(0.450000000000016, 0.45000000000003654, 0.00097834033827502828), x1(0.54999999999999993, 0.45000000000002233, 0.00097825545717458761),
	        x2(0.55000000000000127, 0.55000000000000004, 0.00097834033827502828);
	const TriangleEdge e = triangleEdgesOnTriangle(x0, x1, x2, a, b, c);
	ASSERT_TRUE(e.valid);
	EXPECT_EQ(e.support, 3u);
	EXPECT_NEAR(e.point[0], 0.5, 1e-15);
	EXPECT_NEAR(e.point[2], 0, 1e-15);
	EXPECT_NEAR(e.distance, 0.000978297898, 1e-12);
}

// Two boxes side by side (a clump), their seam the plane y = 0: a probe under the seam touches
// both bottom edges at one point (one contact, the lower id's); a probe under one box near the
// seam touches its face and the other's seam edge (that edge is inside the union's face: dropped);
// a probe in the valley of an L touches two faces (both kept).
TEST(Surface, AClumpOfBoxesMeetsAProbeOncePerPointOfItsSurface)
{
	const Vec3   ext(1, 0.5, 1);
	const Vec3   c1(0, -0.5, 0), c2(0, 0.5, 0); // centres: box 1 in y in [-1, 0], box 2 in [0, 1]
	const double tol = 1e-9;
	const auto   hit = [&](int id, const Vec3& c, const Vec3& x) {
                const SurfacePoint sp = nodeOnBox(x - c, ext);
                MemberPoint        m;
                m.id       = id;
                m.distance = sp.distance;
                m.point    = sp.point + c;
                m.onRim    = onBoxRim(sp.point, ext, tol);
                return m;
	};
	int beaten[8], nb = 0;
	// under the seam
	MemberPoint a = hit(1, c1, Vec3(0.2, 0, -1.3)), b = hit(2, c2, Vec3(0.2, 0, -1.3));
	EXPECT_TRUE(a.onRim && b.onRim);
	EXPECT_TRUE(ownsOnUnion(a, &b, 1, tol, beaten, nb));
	EXPECT_EQ(nb, 1);
	EXPECT_FALSE(ownsOnUnion(b, &a, 1, tol, beaten, nb));
	// under box 1, 0.1 from the seam: box 1's face carries it, box 2's seam edge is dropped
	a = hit(1, c1, Vec3(0.2, -0.1, -1.3));
	b = hit(2, c2, Vec3(0.2, -0.1, -1.3));
	EXPECT_FALSE(a.onRim);
	EXPECT_TRUE(b.onRim);
	EXPECT_TRUE(ownsOnUnion(a, &b, 1, tol, beaten, nb));
	EXPECT_FALSE(ownsOnUnion(b, &a, 1, tol, beaten, nb));
	// an L: box 2 raised by 2 (its side face y = 0 rises above box 1's top face z = 1); a probe in the
	// valley touches box 1's top and box 2's side: both faces
	const Vec3 c3(0, 0.5, 2), x(0.2, -0.2, 1.3);
	a                   = hit(1, c1, x);
	const MemberPoint d = hit(2, c3, x);
	EXPECT_FALSE(a.onRim);
	EXPECT_FALSE(d.onRim);
	EXPECT_TRUE(ownsOnUnion(a, &d, 1, tol, beaten, nb));
	EXPECT_TRUE(ownsOnUnion(d, &a, 1, tol, beaten, nb));
}

// The separation tests only say "apart" where no point of the membrane comes within reach.
TEST(Surface, MembraneApartTestsAreConservative)
{
	const Vec3 ext(1, 1, 1);
	EXPECT_TRUE(membraneApartFromBox(Vec3(-3, -3, 1.2), Vec3(3, -3, 1.3), Vec3(0, 3, 1.25), ext, 0.1));
	EXPECT_FALSE(membraneApartFromBox(Vec3(-3, -3, 1.05), Vec3(3, -3, 1.3), Vec3(0, 3, 1.25), ext, 0.1)); // a node within reach
	// a sheet over the box corner, its nodes far out: not apart (the corner is near its middle)
	const Vec3 n = Vec3(1, 1, 1).normalized(), t = n.unitOrthogonal(), s = n.cross(t), c = Vec3(1, 1, 1) + 0.05 * n;
	EXPECT_FALSE(membraneApartFromBox(c + 4 * t, c - 2 * t + 3 * s, c - 2 * t - 3 * s, ext, 0.1));
	const Vec3 a(0, 0, 0), b(1, 0, 0), cc(0, 1, 0);
	EXPECT_TRUE(membraneApartFromTriangle(Vec3(5, 5, 0.2), Vec3(-5, 5, 0.3), Vec3(0, -5, 0.25), a, b, cc, 0.1));
	EXPECT_FALSE(membraneApartFromTriangle(Vec3(5, 5, 0.2), Vec3(-5, 5, -0.3), Vec3(0, -5, 0.25), a, b, cc, 0.1)); // crosses the plane
	EXPECT_FALSE(membraneApartFromTriangle(Vec3(5, 5, 0.05), Vec3(-5, 5, 0.3), Vec3(0, -5, 0.25), a, b, cc, 0.1));
}
