// Closest points between points and segments (GPL-2.0-or-later).
//
// Segment-segment, after the usual derivation: with d1 = a1-a0, d2 = b1-b0, r = a0-b0,
// minimise |r + s d1 - t d2|^2. Stationarity gives
//     a s - b t = -c,   b s - e t = -f,   a = d1.d1, b = d1.d2, e = d2.d2, c = d1.r, f = d2.r
// so s = (b f - c e) / (a e - b^2). Clamp s to [0,1], solve t for that s, and if t leaves
// [0,1] clamp it and solve s again: the objective is convex, so this reaches the minimum
// on the unit square. For a e - b^2 ~ 0 the axes are parallel and every s in the overlap of
// the projections is a minimiser; we take the middle of that overlap.
#include "ClosestPoints.hpp"

#include <algorithm>
#include <cmath>

namespace flex {

namespace {
	inline double clamp01(double x) { return x < 0 ? 0 : (x > 1 ? 1 : x); }
} // namespace

PointSegment closestPointOnSegment(const Vec3& p, const Vec3& a, const Vec3& b)
{
	const Vec3   d  = b - a;
	const double dd = d.squaredNorm();
	if (!(dd > 0)) return { 0.0, a };
	const double u = clamp01((p - a).dot(d) / dd);
	return { u, pointAt(a, b, u) };
}

SegmentSegment closestPointsSegments(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1)
{
	const Vec3   d1 = a1 - a0, d2 = b1 - b0, r = a0 - b0;
	const double a = d1.squaredNorm(), e = d2.squaredNorm(), b = d1.dot(d2), c = d1.dot(r), f = d2.dot(r);
	double       s = 0, t = 0;
	bool         parallel = false;
	if (!(a > 0) && !(e > 0)) { // both degenerate
		s = t = 0;
	} else if (!(a > 0)) { // segment 1 is a point
		t = clamp01(f / e);
	} else if (!(e > 0)) { // segment 2 is a point
		s = clamp01(-c / a);
	} else {
		const double denom = a * e - b * b; // = |d1 x d2|^2 >= 0
		// relative test: sin^2 of the angle between the axes below ~1e-12
		if (denom <= 1e-12 * a * e) {
			parallel = true;
			// parameters of b0 and b1 projected on axis 1
			const double sb0 = -c / a, sb1 = (b - c) / a;
			const double lo = std::max(0.0, std::min(sb0, sb1)), hi = std::min(1.0, std::max(sb0, sb1));
			if (lo <= hi)
				s = 0.5 * (lo + hi);
			else
				s = (std::max(sb0, sb1) < 0) ? 0.0 : 1.0;
			t = clamp01((b * s + f) / e);
		} else {
			s = clamp01((b * f - c * e) / denom);
			t = (b * s + f) / e;
			if (t < 0) {
				t = 0;
				s = clamp01(-c / a);
			} else if (t > 1) {
				t = 1;
				s = clamp01((b - c) / a);
			}
		}
	}
	return { s, t, pointAt(a0, a1, s), pointAt(b0, b1, t), parallel };
}

Vec3 anyPerpendicular(const Vec3& d)
{
	int i;
	d.cwiseAbs().minCoeff(&i);
	Vec3 ax = Vec3::Zero();
	ax[i]   = 1;
	return d.cross(ax).normalized();
}

Vec3 contactNormal(const Vec3& from, const Vec3& to, const Vec3& axis1, const Vec3& axis2, const Vec3& fallback)
{
	const Vec3   d     = to - from;
	const double len   = d.norm();
	const double scale = std::max(axis1.norm(), axis2.norm());
	if (len > 1e-14 * std::max(scale, 1e-300)) return d / len;
	// coincident points: try the previous normal, made perpendicular to the axes. Project off
	// an orthogonal basis of span(axis1, axis2) (Gram-Schmidt): projecting off two non-orthogonal
	// axes one after the other would leave a component along the first one.
	Vec3         n   = fallback;
	const double a12 = axis1.squaredNorm();
	Vec3         ax2 = axis2;
	if (a12 > 0) {
		n -= (n.dot(axis1) / a12) * axis1;
		ax2 -= (ax2.dot(axis1) / a12) * axis1;
	}
	const double a22 = ax2.squaredNorm();
	if (a22 > 1e-12 * axis2.squaredNorm() && a22 > 0) n -= (n.dot(ax2) / a22) * ax2; // else parallel axes (as in closestPointsSegments)
	if (n.squaredNorm() > 1e-6 * std::max(fallback.squaredNorm(), 1e-300) && fallback.squaredNorm() > 0) return n.normalized();
	const Vec3 c = axis1.cross(axis2);
	if (c.squaredNorm() > 1e-12 * axis1.squaredNorm() * axis2.squaredNorm() && c.squaredNorm() > 0) return c.normalized();
	if (axis1.squaredNorm() > 0) return anyPerpendicular(axis1);
	if (axis2.squaredNorm() > 0) return anyPerpendicular(axis2);
	return Vec3::UnitZ();
}

} // namespace flex

namespace flex {

double searchReach(const Vec3* p, int n, double reach)
{
	// reach plus a margin far above the round-off of the exact distance computations (whose
	// absolute error scales with the coordinates): a separation found here is never one the
	// exact test would have called a touch
	double scale = reach;
	for (int k = 0; k < n; ++k)
		scale = std::max(scale, p[k].cwiseAbs().maxCoeff());
	return reach + 1e-9 * scale;
}

bool boxesApart(const Vec3* p, int n1, int n2, double r)
{
	for (int ax = 0; ax < 3; ++ax) {
		double lo1 = p[0][ax], hi1 = lo1, lo2 = p[n1][ax], hi2 = lo2;
		for (int k = 1; k < n1; ++k) {
			lo1 = std::min(lo1, p[k][ax]);
			hi1 = std::max(hi1, p[k][ax]);
		}
		for (int k = n1 + 1; k < n1 + n2; ++k) {
			lo2 = std::min(lo2, p[k][ax]);
			hi2 = std::max(hi2, p[k][ax]);
		}
		if (lo2 > hi1 + r || lo1 > hi2 + r) return true;
	}
	return false;
}

bool segmentsApart(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1, double reach)
{
	const Vec3 p[4] = { a0, a1, b0, b1 };
	return boxesApart(p, 2, 2, searchReach(p, 4, reach));
}

} // namespace flex
