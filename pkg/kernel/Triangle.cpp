// Closest points on a triangle; facet point kinematics (GPL-2.0-or-later). See Triangle.hpp.
#include "Triangle.hpp"
#include "ClosestPoints.hpp"

#include <cmath>
#include <limits>

namespace flex {

namespace {
	// Fixed order of an edge's end points (lexicographic on the coordinates), so that both
	// facets sharing the edge run the same arithmetic on it.
	inline bool before(const Vec3& p, const Vec3& q)
	{
		if (p[0] != q[0]) return p[0] < q[0];
		if (p[1] != q[1]) return p[1] < q[1];
		return p[2] < q[2];
	}

	// the point at parameter u of edge (xi, xj) (node indices i, j), exact at the ends
	PointTriangle edgePoint(int i, int j, double u, const Vec3& point)
	{
		PointTriangle r;
		r.w[0] = r.w[1] = r.w[2] = 0;
		r.point                  = point;
		if (u <= 0) {
			r.w[i]    = 1;
			r.support = 1u << i;
		} else if (u >= 1) {
			r.w[j]    = 1;
			r.support = 1u << j;
		} else {
			r.w[i]    = 1 - u;
			r.w[j]    = u;
			r.support = (1u << i) | (1u << j);
		}
		return r;
	}

	// closest point on edge (xi, xj) of the triangle (node indices i, j)
	PointTriangle onEdge(const Vec3& p, const Vec3* x, int i, int j)
	{
		if (before(x[j], x[i])) std::swap(i, j);
		const PointSegment ps = closestPointOnSegment(p, x[i], x[j]);
		return edgePoint(i, j, ps.u, ps.point);
	}

	PointTriangle atVertex(const Vec3* x, int i)
	{
		PointTriangle r;
		r.w[0] = r.w[1] = r.w[2] = 0;
		r.w[i]                   = 1;
		r.point                  = x[i];
		r.support                = 1u << i;
		return r;
	}

	bool degenerate(const Vec3& ab, const Vec3& ac) { return ab.cross(ac).squaredNorm() <= 1e-24 * ab.squaredNorm() * ac.squaredNorm(); }

	PointTriangle nearestEdge(const Vec3& p, const Vec3* x)
	{
		PointTriangle best;
		double        d2 = std::numeric_limits<double>::infinity();
		for (int k = 0; k < 3; ++k) {
			const PointTriangle e  = onEdge(p, x, k, (k + 1) % 3);
			const double        dd = (p - e.point).squaredNorm();
			if (dd < d2) {
				d2   = dd;
				best = e;
			}
		}
		return best;
	}

	// barycentric weights of a point q of the triangle's plane, clamped into the triangle
	void barycentric(const Vec3& q, const Vec3* x, double w[3])
	{
		const Vec3   ab = x[1] - x[0], ac = x[2] - x[0], aq = q - x[0];
		const double d00 = ab.dot(ab), d01 = ab.dot(ac), d11 = ac.dot(ac), d20 = aq.dot(ab), d21 = aq.dot(ac);
		const double den = d00 * d11 - d01 * d01;
		double       v = (d11 * d20 - d01 * d21) / den, u = (d00 * d21 - d01 * d20) / den;
		v    = std::max(0.0, v);
		u    = std::max(0.0, u);
		w[1] = v;
		w[2] = u;
		w[0] = 1 - v - u;
	}
} // namespace

PointTriangle closestPointOnTriangle(const Vec3& p, const Vec3& x1, const Vec3& x2, const Vec3& x3)
{
	const Vec3 x[3] = { x1, x2, x3 };
	const Vec3 ab = x2 - x1, ac = x3 - x1;
	if (degenerate(ab, ac)) return nearestEdge(p, x);
	// Voronoi regions by the signs of dot products (vertex, then edge, else face)
	const Vec3   ap = p - x1;
	const double d1 = ab.dot(ap), d2 = ac.dot(ap);
	if (d1 <= 0 && d2 <= 0) return atVertex(x, 0);
	const Vec3   bp = p - x2;
	const double d3 = ab.dot(bp), d4 = ac.dot(bp);
	if (d3 >= 0 && d4 <= d3) return atVertex(x, 1);
	const double vc = d1 * d4 - d3 * d2;
	if (vc <= 0 && d1 >= 0 && d3 <= 0) return onEdge(p, x, 0, 1);
	const Vec3   cp = p - x3;
	const double d5 = ab.dot(cp), d6 = ac.dot(cp);
	if (d6 >= 0 && d5 <= d6) return atVertex(x, 2);
	const double vb = d5 * d2 - d1 * d6;
	if (vb <= 0 && d2 >= 0 && d6 <= 0) return onEdge(p, x, 0, 2);
	const double va = d3 * d6 - d5 * d4;
	if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return onEdge(p, x, 1, 2);
	// face: barycentric weights (va, vb, vc) / (va + vb + vc), all > 0 here
	const double  den = 1 / (va + vb + vc);
	PointTriangle r;
	r.w[1]    = vb * den;
	r.w[2]    = vc * den;
	r.w[0]    = 1 - r.w[1] - r.w[2];
	r.point   = x1 + ab * r.w[1] + ac * r.w[2];
	r.support = 7;
	return r;
}

SegmentTriangle closestPointsSegmentTriangle(const Vec3& a, const Vec3& b, const Vec3& x1, const Vec3& x2, const Vec3& x3)
{
	const Vec3      x[3] = { x1, x2, x3 };
	SegmentTriangle best;
	best.intersect = false;
	double d2      = std::numeric_limits<double>::infinity();
	// 1. the three edges (segment - segment)
	for (int k = 0; k < 3; ++k) {
		int i = k, j = (k + 1) % 3;
		if (before(x[j], x[i])) std::swap(i, j);
		const SegmentSegment ss = closestPointsSegments(a, b, x[i], x[j]);
		const double         dd = (ss.p2 - ss.p1).squaredNorm();
		if (dd < d2) {
			d2      = dd;
			best.s  = ss.s;
			best.p1 = ss.p1;
			best.t  = edgePoint(i, j, ss.t, ss.p2);
		}
	}
	const Vec3 ab = x2 - x1, ac = x3 - x1;
	if (degenerate(ab, ac)) return best;
	// 2. the part of the segment over the face (inside the triangle's prism): there the
	//    distance is the height |h(s)|, linear in s
	const Vec3 n = ab.cross(ac).normalized(), d = b - a;
	double     lo = 0, hi = 1;
	for (int k = 0; k < 3 && lo <= hi; ++k) {
		const Vec3   e  = x[(k + 1) % 3] - x[k];
		const Vec3   m  = n.cross(e); // inward in-plane normal of edge k
		const double g0 = m.dot(a - x[k]), g1 = m.dot(b - x[k]);
		if (g0 < 0 && g1 < 0)
			hi = -1;
		else if (g0 < 0)
			lo = std::max(lo, g0 / (g0 - g1));
		else if (g1 < 0)
			hi = std::min(hi, g0 / (g0 - g1));
	}
	if (lo > hi) return best;
	const double h0 = n.dot(a - x1), h1 = n.dot(b - x1);
	auto         h = [&](double s) { return h0 + s * (h1 - h0); };
	double       s;
	bool         pierce = false;
	if (h(lo) * h(hi) <= 0 && h0 != h1) {
		s      = std::min(hi, std::max(lo, h0 / (h0 - h1)));
		pierce = true;
	} else {
		const double dl = std::abs(h(lo)), dh = std::abs(h(hi));
		const double tol = 1e-12 * (d.norm() + dl + dh);
		s                = std::abs(dl - dh) <= tol ? 0.5 * (lo + hi) : (dl < dh ? lo : hi);
	}
	const Vec3   p1 = a + s * d;
	const double hs = pierce ? 0.0 : h(s);
	// ties (a parallel stretch reaching an edge) go to the face: its point is the middle
	if (!pierce && hs * hs > d2 * (1 + 1e-12)) return best;
	best.s         = s;
	best.p1        = p1;
	best.intersect = pierce;
	PointTriangle t;
	t.point = p1 - hs * n;
	barycentric(t.point, x, t.w);
	t.support = 7;
	best.t    = t;
	return best;
}

namespace {
	struct Frame {
		Vec3   a, b, n;
		double An, a2;
	};
	inline Frame frameOf(const Vec3 x[3])
	{
		Frame f;
		f.a          = x[1] - x[0];
		f.b          = x[2] - x[0];
		const Vec3 N = f.a.cross(f.b);
		f.An         = N.norm();
		f.n          = N / f.An;
		f.a2         = f.a.squaredNorm();
		return f;
	}
} // namespace

Vec3 trianglePointVelocity(const Vec3 x[3], const Vec3 v[3], const double w[3], const Vec3& d)
{
	const Frame f  = frameOf(x);
	const Vec3  ad = v[1] - v[0], bd = v[2] - v[0];
	Vec3        nd   = ad.cross(f.b) + f.a.cross(bd);
	nd               = (nd - f.n * f.n.dot(nd)) / f.An;
	const Vec3 omega = f.n.cross(nd) + f.n * (f.n.dot(f.a.cross(ad)) / f.a2);
	return w[0] * v[0] + w[1] * v[1] + w[2] * v[2] + omega.cross(d);
}

void distributeToTriangle(const Vec3 x[3], const double w[3], const Vec3& d, const Vec3& F, Vec3 out[3])
{
	const Frame f  = frameOf(x);
	const Vec3  T  = d.cross(F);
	const Vec3  U  = T.cross(f.n);
	const Vec3  Ga = f.b.cross(U) / f.An + f.n.cross(f.a) * (f.n.dot(T) / f.a2);
	const Vec3  Gb = U.cross(f.a) / f.An;
	out[0]         = w[0] * F - Ga - Gb;
	out[1]         = w[1] * F + Ga;
	out[2]         = w[2] * F + Gb;
}

namespace {
	// moment part of the nodal shares per unit offset: |f_a| <= |F| (w_a + |d| G)
	inline double momentGain(const Frame& f) { return (std::sqrt(f.a2) + f.b.norm()) / f.An + 1 / std::sqrt(f.a2); }
} // namespace

double triangleLoadFactor(const Vec3 x[3], double r)
{
	const Frame f = frameOf(x);
	if (!(f.An > 0)) return 1 + kFacetMomentCap;
	return 1 + std::min(r * momentGain(f), kFacetMomentCap);
}

Vec3 cappedFacetOffset(const Vec3 x[3], const Vec3& d)
{
	const Frame f = frameOf(x);
	if (!(f.An > 0)) return Vec3::Zero(); // no rotation of a degenerate facet to speak of
	const double m = d.norm() * momentGain(f);
	return m > kFacetMomentCap ? Vec3(d * (kFacetMomentCap / m)) : d;
}

} // namespace flex

namespace flex {

bool segmentTriangleApart(const Vec3& a, const Vec3& b, const Vec3& x1, const Vec3& x2, const Vec3& x3, double reach)
{
	const Vec3   p[5] = { a, b, x1, x2, x3 };
	const double r    = searchReach(p, 5, reach);
	if (boxesApart(p, 2, 3, r)) return true;
	// both ends beyond r on one side of the plane: every point of the segment is farther than
	// r from the plane, hence from the triangle. n unnormalised: compare h with r |n|. Only for
	// a triangle far from degenerate (angle > 1e-6 rad), where n's direction is accurate to
	// ~1e-10, and with a margin that covers that error over the lever arms involved.
	const Vec3   e1 = x2 - x1, e2 = x3 - x1, n = e1.cross(e2);
	const double nn = n.norm(), l1 = e1.norm(), l2 = e2.norm();
	if (!(nn > 1e-6 * l1 * l2)) return false;
	const double rn = (r + 1e-9 * (l1 + l2 + (a - x1).norm() + (b - x1).norm())) * nn;
	const double ha = n.dot(a - x1), hb = n.dot(b - x1);
	return (ha > rn && hb > rn) || (ha < -rn && hb < -rn);
}

} // namespace flex
