// Closest points on a triangle, and the kinematics of a point attached to a deformable facet.
//
// A facet is a thick triangle: the points within distance r of the triangle (x1, x2, x3),
// its midplane. Contacts use the closest point q of the midplane to a probe point P (a
// sphere centre, a point of a cylinder axis). Where q lies tells the Voronoi region:
// the face (q inside, all three barycentric weights > 0), an edge (one weight exactly 0) or a
// vertex (q is exactly that node). The set of nodes with non-zero weight is the "support" of
// the contact (bit mask 1, 2, 4 for nodes 1, 2, 3): two facets sharing an edge or a vertex
// see the same contact when its support lies on what they share.
//
// Bit-identical shared features. On an edge both facets sharing it compute the closest point
// with the same arithmetic (the edge's end points are put in a fixed order first), and
// vertex regions return the node itself: two facets then compute equal distances for a probe
// in their common edge or vertex region, and ownership ties are decided by the tie rule, not
// by round-off.
//
// Kinematics of a point c attached to a facet (c = q + d, d the offset from the midplane
// point q = sum w_a x_a to the contact point). The facet has no DOF; its nodes carry no
// rotation that the membrane feels. Its spin is taken from the node velocities:
//     omega = n x dn/dt + n (n . (a x da/dt)) / |a|^2,  a = x2 - x1, b = x3 - x1,
//     n = (a x b)/|a x b|,  dn/dt = (I - n n^T)(da/dt x b + a x db/dt)/|a x b|,
// which equals the angular velocity W of any rigid motion (v_a = v0 + W x x_a). Then
//     v(c) = sum w_a v_a + omega x d
// is exact for rigid motions: a sphere moving rigidly with the facet does not slip.
// A force F at c goes to the nodes by the adjoint (transpose) of that velocity map, so the
// power is conserved exactly (F . v(c) = sum f_a . v_a for ANY node velocities) and, because
// the map is exact for rigid motions, sum f_a = F and sum x_a x f_a = c x F (force and
// moment balance) with forces only: no nodal moments.
#pragma once
#include "Types.hpp"

namespace flex {

struct PointTriangle {
	Vec3     point;   ///< closest point of the triangle to the probe
	double   w[3];    ///< barycentric weights of point (exactly 0 off the support)
	unsigned support; ///< bit mask of the nodes with non-zero weight (7: face region)
};

/// Closest point of triangle (x1, x2, x3) to p, with its Voronoi region. A degenerate
/// triangle is handled as its longest edge.
PointTriangle closestPointOnTriangle(const Vec3& p, const Vec3& x1, const Vec3& x2, const Vec3& x3);

struct SegmentTriangle {
	double        s;         ///< parameter of the closest point on the segment [0, 1]
	Vec3          p1;        ///< closest point on the segment
	PointTriangle t;         ///< closest point on the triangle
	bool          intersect; ///< the segment pierces the triangle (p1 == t.point)
};

/// Closest points between segment [a, b] and triangle (x1, x2, x3). When the segment is
/// parallel to the triangle's plane over its face, the middle of the parallel stretch is
/// returned (the contact point moves continuously as the segment slides).
SegmentTriangle closestPointsSegmentTriangle(const Vec3& a, const Vec3& b, const Vec3& x1, const Vec3& x2, const Vec3& x3);

/// Conservative separation test (see segmentsApart): true only if the segment a-b is farther
/// than `reach` from the triangle, because the boxes are disjoint or both ends lie beyond
/// reach on one side of the triangle's plane. False says nothing.
bool segmentTriangleApart(const Vec3& a, const Vec3& b, const Vec3& x1, const Vec3& x2, const Vec3& x3, double reach);

/// Velocity of the material point c attached to the facet (see above); w: barycentric
/// weights of the midplane point q; d = c - q.
Vec3 trianglePointVelocity(const Vec3 x[3], const Vec3 v[3], const double w[3], const Vec3& d);

/// Nodal forces f[3] of a force F acting at c = q + d (adjoint of trianglePointVelocity).
void distributeToTriangle(const Vec3 x[3], const double w[3], const Vec3& d, const Vec3& F, Vec3 f[3]);

/// Largest moment part of a node's share, in units of |F|: the offset of a facet contact is
/// capped so that distributeToTriangle puts at most |F| (w_a + kFacetMomentCap) on node a.
/// Without a cap the share grows like |d| / area as a triangle is crushed (a ring pinching
/// the lining), and with it the contact stiffness the nodes see and the stable step (measured:
/// 1.9e-6 s to 9e-9 s in the default module impact). The cap leaves a facet's own rotation in
/// the contact kinematics untouched until the triangle is ~25 times smaller in area than the
/// lining's (|d| = 1 mm, 8 cm triangles: the moment part is 0.04 |F|).
constexpr double kFacetMomentCap = 1.0;

/// The offset used for a contact at c = q + d on this facet: d, scaled down where the moment
/// part of the nodal shares would exceed kFacetMomentCap |F| (a continuous function of x and
/// d). The contact kinematics (trianglePointVelocity) and the force (distributeToTriangle)
/// both use it, so that power still balances exactly.
Vec3 cappedFacetOffset(const Vec3 x[3], const Vec3& d);

/// Bound on |f_a| / |F| of distributeToTriangle for any contact on this facet with a capped
/// offset of |d| <= r (for the time-step estimate): 1 + min(r G, kFacetMomentCap).
double triangleLoadFactor(const Vec3 x[3], double r);

} // namespace flex
