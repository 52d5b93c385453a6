// A node of deformable elements against a rigid surface (GPL-2.0-or-later); see Surface.hpp.
#include "Surface.hpp"
#include "ClosestPoints.hpp"

#include <algorithm>
#include <cmath>

namespace flex {

namespace {
	int sideOf(double signedDistance, int side) { return side != 0 ? (side > 0 ? 1 : -1) : (signedDistance < 0 ? -1 : 1); }

	// best becomes the segment point ss.p1 against the surface point sp, if it is the nearest yet
	void keepNearest(SegmentEdge& best, const SegmentSegment& ss, const SurfacePoint& sp)
	{
		if (best.valid && best.distance <= sp.distance) return;
		best.valid     = true;
		best.u         = ss.s;
		best.onSegment = ss.p1;
		best.point     = sp.point;
		best.normal    = sp.normal;
		best.distance  = sp.distance;
		best.support   = sp.support;
	}
} // namespace

SurfacePoint nodeOnPlane(const Vec3& x, int axis, double pos, int sense, int side)
{
	SurfacePoint s;
	const double d = x[axis] - pos;
	const int    w = sense != 0 ? (sense > 0 ? 1 : -1) : sideOf(d, side);
	s.point        = x;
	s.point[axis]  = pos;
	s.normal[axis] = w;
	s.distance     = w * d;
	return s;
}

SurfacePoint nodeOnBox(const Vec3& x, const Vec3& ext)
{
	SurfacePoint s;
	const Vec3   c = x.cwiseMax(-ext).cwiseMin(ext);
	const Vec3   d = x - c;
	const double n = d.norm();
	if (n > 0) {
		s.point    = c;
		s.normal   = d / n;
		s.distance = n;
		return s;
	}
	// inside (or on the surface): the nearest face
	int    k     = 0;
	double depth = ext[0] - std::abs(x[0]);
	for (int a = 1; a < 3; ++a)
		if (ext[a] - std::abs(x[a]) < depth) {
			depth = ext[a] - std::abs(x[a]);
			k     = a;
		}
	const double w = x[k] < 0 ? -1 : 1;
	s.point        = x;
	s.point[k]     = w * ext[k];
	s.normal[k]    = w;
	s.distance     = -depth;
	return s;
}

SegmentEdge segmentOnBoxEdges(const Vec3& x0, const Vec3& x1, const Vec3& ext)
{
	SegmentEdge  best;
	const double d0 = nodeOnBox(x0, ext).distance, d1 = nodeOnBox(x1, ext).distance;
	const double tol = 1e-12 * (ext.norm() + x0.norm() + x1.norm());
	for (int axis = 0; axis < 3; ++axis) // the 4 edges along each axis
		for (int k = 0; k < 4; ++k) {
			Vec3 a = ext, b = ext;
			const int i = (axis + 1) % 3, j = (axis + 2) % 3;
			a[i] = b[i] = (k & 1) ? ext[i] : -ext[i];
			a[j] = b[j] = (k & 2) ? ext[j] : -ext[j];
			a[axis]                 = -ext[axis];
			const SegmentSegment ss = closestPointsSegments(x0, x1, a, b);
			if (!(ss.s > 0 && ss.s < 1)) continue;
			const SurfacePoint sp = nodeOnBox(ss.p1, ext);
			if (!(sp.distance > 0) || (sp.point - ss.p2).norm() > tol) continue; // inside, or a face is nearer
			if (!(sp.distance < d0 && sp.distance < d1)) continue;
			keepNearest(best, ss, sp);
		}
	return best;
}

SurfacePoint nodeOnTriangle(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c, int side)
{
	SurfacePoint        s;
	const PointTriangle pt = closestPointOnTriangle(x, a, b, c);
	const Vec3          nf = (b - a).cross(c - a).normalized();
	const Vec3          d  = x - pt.point;
	s.point                = pt.point;
	s.support              = pt.support;
	const int w            = sideOf(d.dot(nf), side);
	if (pt.support == 7) {
		s.normal   = w * nf;
		s.distance = d.dot(s.normal);
		return s;
	}
	s.distance = d.norm();
	s.normal   = s.distance > 0 ? Vec3(d / s.distance) : Vec3(w * nf);
	return s;
}

SegmentEdge segmentOnTriangleEdges(const Vec3& x0, const Vec3& x1, const Vec3& a, const Vec3& b, const Vec3& c)
{
	SegmentEdge  best;
	const double d0 = std::abs(nodeOnTriangle(x0, a, b, c, 0).distance), d1 = std::abs(nodeOnTriangle(x1, a, b, c, 0).distance);
	const double len = std::max({ (b - a).norm(), (c - b).norm(), (a - c).norm() });
	const double tol = 1e-12 * (len + a.norm() + x0.norm() + x1.norm());
	const double near = kNodeTie * (len + (x1 - x0).norm());
	const Vec3*  v[3] = { &a, &b, &c };
	for (int k = 0; k < 3; ++k) {
		const SegmentSegment ss = closestPointsSegments(x0, x1, *v[k], *v[(k + 1) % 3]);
		if (!(ss.s > 0 && ss.s < 1)) continue;
		const SurfacePoint sp = nodeOnTriangle(ss.p1, a, b, c, 0);
		// the face nearer (the segment over the face: a node ties or is nearer), or the point found
		// on this edge not the triangle's closest (another edge's)
		if (sp.support == 7 || !(sp.distance > 0) || (sp.point - ss.p2).norm() > tol) continue;
		if (!(sp.distance < d0 - near && sp.distance < d1 - near)) continue;
		keepNearest(best, ss, sp);
	}
	return best;
}

namespace {
	// A contact found on facet k at elementPoint(k) -> surface point edgePoint(k), distance(k): where
	// another facet is as near to that point at another point of the surface (its face, or an edge
	// the two do not share), the surface's closest point is not this edge: hit[k] drops out. At an
	// edge or vertex two facets share both reach the same point: the cluster carries it once.
	template <class ElementPoint, class EdgePoint, class Distance>
	void dropHiddenEdges(const Vec3 (*tri)[3], int n, FacetHit* hit, ElementPoint elementPoint, EdgePoint edgePoint, Distance distance)
	{
		for (int k = 0; k < n; ++k) {
			if (!(hit[k].overlap > 0)) continue;
			const double tol = kNodeTie * std::max({ (tri[k][1] - tri[k][0]).norm(), (tri[k][2] - tri[k][1]).norm(), (tri[k][0] - tri[k][2]).norm() });
			for (int j = 0; j < n; ++j) {
				if (j == k) continue;
				const SurfacePoint o = nodeOnTriangle(elementPoint(k), tri[j][0], tri[j][1], tri[j][2], 0);
				if (std::abs(o.distance) <= distance(k) + tol && (o.point - edgePoint(k)).norm() > tol) {
					hit[k].overlap = -1;
					break;
				}
			}
		}
	}
	void setHit(FacetHit& h, int id, bool valid, double overlap, unsigned support, const Vec3* v)
	{
		h.id      = id;
		h.support = support;
		h.overlap = valid ? overlap : -1;
		for (int j = 0; j < 3; ++j)
			h.v[j] = v[j];
	}
} // namespace

void segmentOnFacets(const Vec3& x0, const Vec3& x1, double r, const Vec3 (*tri)[3], const int* ids, int n, SegmentEdge* edge, FacetHit* hit)
{
	for (int k = 0; k < n; ++k) {
		edge[k] = segmentOnTriangleEdges(x0, x1, tri[k][0], tri[k][1], tri[k][2]);
		setHit(hit[k], ids[k], edge[k].valid, r - edge[k].distance, edge[k].support, tri[k]);
	}
	dropHiddenEdges(
	        tri, n, hit, [&](int k) { return edge[k].onSegment; }, [&](int k) { return edge[k].point; }, [&](int k) { return edge[k].distance; });
}

namespace {
	// The surface's edges (nEdges segments) against the membrane (x0, x1, x2); at(p): the surface's
	// closest point to p; onRim(sp): whether that point lies on an edge or vertex (not a face);
	// nodeDist: the nodes' distances from the surface. The contact is the surface's closest point
	// to the membrane's point nearest an edge: an edge nearly parallel to the membrane fixes that
	// point along the edge only to round-off over the curvature (1e-9 m over a 0.1 m facet, for a
	// sheet 1 mm over a ridge), so the surface point is recomputed from the membrane's.
	template <class At, class OnRim>
	TriangleEdge edgesOnTriangle(const Vec3 (*edges)[2], int nEdges, const Vec3& x0, const Vec3& x1, const Vec3& x2, At at, OnRim onRim, const double nodeDist[3],
	        double size)
	{
		TriangleEdge best;
		const double len  = std::max({ (x1 - x0).norm(), (x2 - x1).norm(), (x0 - x2).norm() });
		const double near = kNodeTie * (size + len);
		for (int k = 0; k < nEdges; ++k) {
			SegmentTriangle st = closestPointsSegmentTriangle(edges[k][0], edges[k][1], x0, x1, x2);
			// the membrane's support from the weights: a point on an edge of the membrane found
			// through its face region has a round-off weight for the third node (the ownership
			// among the membrane's facets links two facets by what their points share)
			st.t.support = 0;
			for (int j = 0; j < 3; ++j)
				if (st.t.w[j] > 1e-12) st.t.support |= 1u << j;
			if (st.intersect) { // through the midplane: nothing is nearer
				best            = TriangleEdge();
				best.valid      = true;
				best.pierced    = true;
				best.onTriangle = best.point = st.t.point;
				best.triSupport              = st.t.support;
				for (int j = 0; j < 3; ++j)
					best.w[j] = st.t.w[j];
				best.support = at(st.p1).support;
				return best;
			}
			const unsigned ms = st.t.support;
			if (((ms & 1) + ((ms >> 1) & 1) + ((ms >> 2) & 1)) < 2) continue; // a node: its own contact
			const SurfacePoint sp = at(st.t.point);
			if (!(sp.distance > 0) || !onRim(sp)) continue; // inside, or a face is nearer
			if (!(sp.distance < nodeDist[0] - near && sp.distance < nodeDist[1] - near && sp.distance < nodeDist[2] - near)) continue;
			if (best.valid && best.distance <= sp.distance) continue;
			best.valid      = true;
			best.onTriangle = st.t.point;
			best.triSupport = ms;
			for (int j = 0; j < 3; ++j)
				best.w[j] = st.t.w[j];
			best.point    = sp.point;
			best.normal   = sp.normal;
			best.distance = sp.distance;
			best.support  = sp.support;
		}
		return best;
	}
} // namespace

bool membraneApartFromBox(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& ext, double reach)
{
	for (int a = 0; a < 3; ++a) {
		const double lim = ext[a] + reach;
		if ((x0[a] > lim && x1[a] > lim && x2[a] > lim) || (x0[a] < -lim && x1[a] < -lim && x2[a] < -lim)) return true;
	}
	return false;
}

bool membraneApartFromTriangle(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& a, const Vec3& b, const Vec3& c, double reach)
{
	const Vec3 n = (b - a).cross(c - a);
	const double len = n.norm();
	if (!(len > 0)) return false;
	const double d0 = n.dot(x0 - a) / len, d1 = n.dot(x1 - a) / len, d2 = n.dot(x2 - a) / len;
	return (d0 > reach && d1 > reach && d2 > reach) || (d0 < -reach && d1 < -reach && d2 < -reach);
}

TriangleEdge boxEdgesOnTriangle(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& ext)
{
	Vec3 edges[12][2];
	int  m = 0;
	for (int axis = 0; axis < 3; ++axis) // the 4 edges along each axis
		for (int k = 0; k < 4; ++k) {
			Vec3      a = ext;
			const int i = (axis + 1) % 3, j = (axis + 2) % 3;
			a[i]        = (k & 1) ? ext[i] : -ext[i];
			a[j]        = (k & 2) ? ext[j] : -ext[j];
			a[axis]     = -ext[axis];
			Vec3 b      = a;
			b[axis]     = ext[axis];
			edges[m][0] = a;
			edges[m++][1] = b;
		}
	const double d[3] = { nodeOnBox(x0, ext).distance, nodeOnBox(x1, ext).distance, nodeOnBox(x2, ext).distance };
	const auto onRim = [&](const SurfacePoint& sp) { // two or three coordinates on the box's extent
		int n = 0;
		for (int a = 0; a < 3; ++a)
			n += std::abs(sp.point[a]) == ext[a] ? 1 : 0;
		return n >= 2;
	};
	return edgesOnTriangle(edges, 12, x0, x1, x2, [&](const Vec3& p) { return nodeOnBox(p, ext); }, onRim, d, ext.norm());
}

TriangleEdge triangleEdgesOnTriangle(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& a, const Vec3& b, const Vec3& c)
{
	const Vec3   edges[3][2] = { { a, b }, { b, c }, { c, a } };
	const double d[3]        = { std::abs(nodeOnTriangle(x0, a, b, c, 0).distance), std::abs(nodeOnTriangle(x1, a, b, c, 0).distance),
                std::abs(nodeOnTriangle(x2, a, b, c, 0).distance) };
	const double size        = std::max({ (b - a).norm(), (c - b).norm(), (a - c).norm() }) + a.norm();
	return edgesOnTriangle(
	        edges, 3, x0, x1, x2, [&](const Vec3& p) { return nodeOnTriangle(p, a, b, c, 0); }, [](const SurfacePoint& sp) { return sp.support != 7; }, d, size);
}

void membraneOnFacets(const Vec3& x0, const Vec3& x1, const Vec3& x2, double r, const Vec3 (*tri)[3], const int* ids, int n, TriangleEdge* edge, FacetHit* hit)
{
	for (int k = 0; k < n; ++k) {
		edge[k] = triangleEdgesOnTriangle(x0, x1, x2, tri[k][0], tri[k][1], tri[k][2]);
		setHit(hit[k], ids[k], edge[k].valid, r - edge[k].distance, edge[k].support, tri[k]);
	}
	dropHiddenEdges(
	        tri, n, hit, [&](int k) { return edge[k].onTriangle; }, [&](int k) { return edge[k].point; }, [&](int k) { return edge[k].distance; });
}

bool onSharedFeature(const FacetHit& a, const FacetHit& b)
{
	double len = 0;
	for (int k = 0; k < 3; ++k) {
		len = std::max(len, (a.v[(k + 1) % 3] - a.v[k]).norm());
		len = std::max(len, (b.v[(k + 1) % 3] - b.v[k]).norm());
	}
	const double tol = 1e-9 * len;
	if (a.support == 7 || a.support == 0) return false; // a face point is a's own
	for (int k = 0; k < 3; ++k) {
		if (!(a.support & (1u << k))) continue;
		bool found = false;
		for (int j = 0; j < 3 && !found; ++j)
			found = (a.v[k] - b.v[j]).norm() <= tol;
		if (!found) return false;
	}
	return true;
}

bool ownsFacetCluster(const FacetHit* hit, int n, int self, int* beaten, int& nBeaten)
{
	nBeaten = 0;
	if (!(hit[self].overlap > 0)) return false;
	// the cluster of self: breadth-first over links among the touching contacts
	constexpr int kMax = 64;
	if (self >= kMax) return false; // (the adapter passes at most kMax, self among them)
	int           queue[kMax];
	bool          in[kMax] = {};
	const int     m        = std::min(n, kMax);
	int           head = 0, tail = 0;
	queue[tail++] = self;
	in[self]      = true;
	while (head < tail) {
		const int i = queue[head++];
		for (int j = 0; j < m; ++j) {
			if (in[j] || !(hit[j].overlap > 0)) continue;
			if (onSharedFeature(hit[i], hit[j]) || onSharedFeature(hit[j], hit[i])) {
				in[j]         = true;
				queue[tail++] = j;
			}
		}
	}
	// the owner: the lowest id among the members within round-off of the deepest (the overlaps of
	// two facets at their shared edge agree only to round-off, computed from vertices stored
	// apart: without the tolerance the owner would flip from step to step as a node moves along it)
	double deepest = hit[self].overlap, len = 0;
	for (int q = 0; q < tail; ++q) {
		const FacetHit& h = hit[queue[q]];
		deepest           = std::max(deepest, h.overlap);
		for (int k = 0; k < 3; ++k)
			len = std::max(len, (h.v[(k + 1) % 3] - h.v[k]).norm());
	}
	const double tol   = 1e-9 * len;
	int          owner = -1;
	for (int q = 0; q < tail; ++q) {
		const int j = queue[q];
		if (hit[j].overlap >= deepest - tol && (owner < 0 || hit[j].id < hit[owner].id)) owner = j;
	}
	if (owner != self) return false;
	for (int q = 0; q < tail; ++q)
		if (queue[q] != self && nBeaten < 8) beaten[nBeaten++] = hit[queue[q]].id;
	return true;
}

bool ownsOnUnion(const MemberPoint& self, const MemberPoint* others, int n, double tol, int* beaten, int& nBeaten)
{
	nBeaten = 0;
	for (int k = 0; k < n; ++k) {
		const MemberPoint& o    = others[k];
		const bool         same = (o.point - self.point).norm() <= tol;
		if (same && std::abs(o.distance - self.distance) <= tol) {
			if (o.id < self.id) return false;
			if (nBeaten < 8) beaten[nBeaten++] = o.id;
		} else if (!same && self.onRim && o.distance <= self.distance + tol)
			return false;
	}
	return true;
}

bool onBoxRim(const Vec3& p, const Vec3& ext, double tol)
{
	int n = 0;
	for (int a = 0; a < 3; ++a)
		n += std::abs(std::abs(p[a]) - ext[a]) <= tol ? 1 : 0;
	return n >= 2;
}

} // namespace flex
