// Closest points between a point and a segment and between two segments.
//
// Segment k is x(u) = a + u (b - a), u in [0, 1]. Clamped parameters are returned as the
// exact values 0 or 1 and the points as the exact end points (not a + 1*(b-a)), so that
// two segments sharing a node compute bit-identical distances to a point in the node's
// corner region: ownership ties are then decided by the tie rule, not by round-off.
#pragma once
#include "Types.hpp"

namespace flex {

struct PointSegment {
	double u;     ///< parameter of the closest point on the segment, in [0, 1]
	Vec3   point; ///< closest point on the segment
};

/// Closest point on segment [a, b] to p. A degenerate segment (a == b) gives u = 0.
PointSegment closestPointOnSegment(const Vec3& p, const Vec3& a, const Vec3& b);

struct SegmentSegment {
	double s, t;     ///< parameters on segment 1 and segment 2, in [0, 1]
	Vec3   p1, p2;   ///< the closest points
	bool   parallel; ///< axes parallel within round-off; (s, t) is then the middle of the overlap
};

/// Closest points between segments [a0, a1] and [b0, b1].
/// Parallel axes: the closest pairs form a whole interval; the middle of the interval of
/// overlap is returned, so the contact point moves continuously when one segment slides
/// along the other. Without overlap the nearest end points are returned.
SegmentSegment closestPointsSegments(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1);

/// A cheap, conservative separation test for contact search: true only if every point of
/// segment a0-a1 is farther than `reach` from every point of segment b0-b1 (the segments'
/// boxes, grown by reach plus a relative margin of 1e-9 that dwarfs round-off, are disjoint
/// along an axis). False says nothing: compute the closest points.
bool segmentsApart(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1, double reach);
/// reach grown by the margin the separation tests use, for the points p[0..n)
double searchReach(const Vec3* p, int n, double reach);
/// whether the boxes of p[0..n1) and p[n1..n1+n2) are more than r apart along some axis
bool boxesApart(const Vec3* p, int n1, int n2, double r);

/// Point of segment [a, b] at u, exact at the end points.
inline Vec3 pointAt(const Vec3& a, const Vec3& b, double u)
{
	if (u <= 0) return a;
	if (u >= 1) return b;
	return a + u * (b - a);
}

/// A unit vector perpendicular to d (d need not be unit; d != 0), chosen continuously
/// from the smallest component of d.
Vec3 anyPerpendicular(const Vec3& d);

/// Unit contact normal pointing from `from` to `to`. When the two points coincide (a
/// sphere centre on the axis, intersecting axes) the normal is taken from `fallback`
/// projected off the axis direction(s) when that is usable, else from the cross product
/// of the two axes (segment-segment), else any perpendicular of axis1.
Vec3 contactNormal(const Vec3& from, const Vec3& to, const Vec3& axis1, const Vec3& axis2, const Vec3& fallback);

} // namespace flex
