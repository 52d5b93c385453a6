// Which element carries a contact when a body touches several elements that share nodes.
//
// A sphere resting where two wires of a chain meet touches both wires, and a bar lying on a
// fold of a membrane touches both facets: counted per element, such a contact would push
// twice. The elements a probe touches fall into clusters of LINKED contacts (the same
// contact), and each cluster gives ONE contact, carried by its member with the largest
// overlap (ties: the lower id). Every member computes the same cluster from bit-identical
// overlaps (the same kernel call, the same node order, whoever asks), so exactly one owns it.
// The contact's potential is that of the largest overlap, a continuous function of the
// positions: hand-overs inside a cluster neither create nor destroy energy.
//
// Contacts of a probe sphere (a grain, the boulder's sphere) with elements: ownsCluster,
// owns. Contacts between two elements: one decision per cluster of element PAIRS, ownsPair.
//
// The kernel reads the mesh through a view, `Mesh`, with
//   const Vec3*             pos(int node) const;        // the node's position; null: no such node
//   IdRange                 elementsAt(int node) const; // ids of the elements on the node; empty: none
//   ElementNodes            element(int id) const;      // nNodes 0: not an element
#pragma once
#include "ClosestPoints.hpp"
#include "SlotArray.hpp"
#include "Triangle.hpp"
#include "Types.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace flex {

/// Ids in an array, as a range (a mesh's elements on a node).
struct IdRange {
	const int* first = nullptr;
	const int* last  = nullptr;
	const int* begin() const { return first; }
	const int* end() const { return last; }
	bool       empty() const { return first == last; }
};
/// The ids of v (null: none).
inline IdRange idRange(const std::vector<int>* v) { return v ? IdRange { v->data(), v->data() + v->size() } : IdRange(); }

/// A deformable element seen by its nodes: 2 nodes a segment (a cylinder of `radius` around
/// it), 3 a triangle (a facet of thickness 2 `radius`); 0 not an element.
struct ElementNodes {
	int    nodes[3] { -1, -1, -1 };
	int    nNodes = 0;
	double radius = 0;
	bool   isSegment() const { return nNodes == 2; }
	bool   isTriangle() const { return nNodes == 3; }
};

inline bool shareNode(const ElementNodes& a, const ElementNodes& b)
{
	for (int i = 0; i < a.nNodes; ++i)
		for (int j = 0; j < b.nNodes; ++j)
			if (a.nodes[i] == b.nodes[j]) return true;
	return false;
}

/// Closest point of an element to a probe: the overlap and the nodes that carry the closest
/// point (its support: one node in a cap or vertex region, two on a cylinder's side or a
/// facet's edge, three on a facet's face).
struct Hit {
	double overlap = -std::numeric_limits<double>::infinity();
	Vec3   point   = Vec3::Zero();
	int    support[3] { -1, -1, -1 };
	int    nSupport = 0;
};
inline Hit segmentHit(const ElementNodes& e, const PointSegment& ps, double overlap)
{
	Hit h;
	h.point = ps.point;
	if (ps.u > 0 && ps.u < 1) {
		h.support[h.nSupport++] = e.nodes[0];
		h.support[h.nSupport++] = e.nodes[1];
	} else
		h.support[h.nSupport++] = e.nodes[ps.u <= 0 ? 0 : 1];
	h.overlap = overlap;
	return h;
}
/// (A point of the face region with a zero weight lies on that edge: its support is the edge's
/// nodes, so that the two facets sharing the edge link whichever region each found it in.)
inline Hit triangleHit(const ElementNodes& e, const PointTriangle& pt, double overlap)
{
	Hit h;
	h.point = pt.point;
	for (int k = 0; k < 3; ++k)
		if ((pt.support & (1u << k)) && (pt.support != 7 || pt.w[k] > 1e-12)) h.support[h.nSupport++] = e.nodes[k];
	h.overlap = overlap;
	return h;
}
/// The contact of element e with a probe sphere (centre P, radius R), with the SAME arithmetic
/// as the element's own contact functor (same kernel call, same node order), so that overlaps
/// compare bit-identically.
template <class Mesh> inline Hit probe(const Mesh& mesh, const ElementNodes& e, const Vec3& P, double R)
{
	const Vec3* x[3] = { nullptr, nullptr, nullptr };
	for (int k = 0; k < e.nNodes; ++k)
		if (!(x[k] = mesh.pos(e.nodes[k]))) return Hit();
	if (e.isSegment()) {
		const PointSegment ps = closestPointOnSegment(P, *x[0], *x[1]);
		return segmentHit(e, ps, R + e.radius - (P - ps.point).norm());
	}
	if (e.isTriangle()) {
		const PointTriangle pt = closestPointOnTriangle(P, *x[0], *x[1], *x[2]);
		return triangleHit(e, pt, R + e.radius - (P - pt.point).norm());
	}
	return Hit();
}

/// Two contacts of one probe on elements sharing a node are LINKED (the same contact) when the
/// closest point on either lies on what the two share: the cap region at a chain's shared node,
/// a facet's shared edge or vertex. There the two elements touch the probe at the same point
/// with the same overlap (bit for bit: the same node), so a hand-over between them passes on
/// the same overlap. Contacts at distinct points always count, however close their normals: a
/// sphere resting on a net cell touches its four wires, a boulder on a mesh the many legs it
/// presses, a wire wrapped around a boulder each of its links (a line contact, carried link by
/// link). A normal-angle criterion would merge those into one and hand the force from leg to
/// leg at finite overlaps, creating and destroying spring energy at every hand-over. The links
/// are closed transitively (a pairwise rule, "lose to a linked neighbour with a larger overlap",
/// is not transitive: with A > B > C, A-B and B-C linked but not A-C, C is suppressed by B, which
/// itself is inactive, and C's contact later appears with a finite overlap).
constexpr double kMergeCos   = 0.96592582628906831; // cos(15 deg): element pairs (ownsPair)
constexpr int    kMaxCluster = 48;
/// Whether the closest point h lies on what elements a and b share (every node of its support
/// belongs to both: a shared node, edge or vertex).
inline bool onShared(const Hit& h, const ElementNodes& a, const ElementNodes& b)
{
	for (int k = 0; k < h.nSupport; ++k) {
		bool inA = false, inB = false;
		for (int i = 0; i < a.nNodes; ++i)
			inA |= a.nodes[i] == h.support[k];
		for (int j = 0; j < b.nNodes; ++j)
			inB |= b.nodes[j] == h.support[k];
		if (!(inA && inB)) return false;
	}
	return true;
}

/// Ownership of a contact by element `self` (id selfId) among the elements sharing its nodes.
/// `hit` is self's contact and `n` its direction (from the element's closest point towards the
/// probe); hitOf(element, normal out) gives a neighbour's contact the same way, with the same
/// arithmetic as that neighbour's own functor. A contact without a normal (the probe's centre
/// exactly on the element's axis or plane: a zero normal) is also linked to a neighbour's whose
/// closest point lies closer than the thinner element's radius: one contact patch (only there:
/// applied to every pair, that distance rule also merges distinct contacts of grains on wires).
/// Returns true if self carries its cluster's contact; the other members are then in `beaten`
/// (at most 8 kept) for the shear hand-over. On false, `beaten` means nothing: the search stops
/// at the first member that beats self (most pairs that overlap are losers, found after a probe
/// or two instead of the whole cluster).
template <class Mesh, class HitOf>
inline bool ownsCluster(const Mesh& mesh, const ElementNodes& self, int selfId, const Hit& hit, const Vec3& n, HitOf hitOf, int* beaten, int& nBeaten)
{
	nBeaten = 0;
	struct Member {
		int          id;
		ElementNodes e;
		Hit          h;
		Vec3         n;
	};
	SlotArray<Member, kMaxCluster> cl;
	int                            seen[4 * kMaxCluster];
	int                            nCl = 0, nSeen = 0;
	cl.put(nCl++, { selfId, self, hit, n });
	seen[nSeen++] = selfId;
	for (int m = 0; m < nCl; ++m) {    // breadth-first over linked neighbours
		const Member& cur = cl[m]; // (slots stay where they are while members are added)
		for (int k = 0; k < cur.e.nNodes; ++k) {
			for (int other : mesh.elementsAt(cur.e.nodes[k])) {
				bool dup = false;
				for (int i = 0; i < nSeen && !dup; ++i)
					dup = seen[i] == other;
				if (dup) continue;
				const ElementNodes oe = mesh.element(other);
				if (!oe.nNodes) continue;
				Vec3      on;
				const Hit oh = hitOf(oe, on);
				if (!(oh.overlap > 0)) { // not touching: never part of a cluster
					if (nSeen < 4 * kMaxCluster) seen[nSeen++] = other;
					continue;
				}
				const double near   = std::min(cur.e.radius, oe.radius);
				const bool   linked = onShared(cur.h, cur.e, oe) || onShared(oh, cur.e, oe)
				        || ((cur.n.squaredNorm() == 0 || on.squaredNorm() == 0) && (cur.h.point - oh.point).squaredNorm() < near * near);
				if (!linked) continue; // may still join through another member
				if (nSeen < 4 * kMaxCluster) seen[nSeen++] = other;
				if (nCl < kMaxCluster) {
					cl.put(nCl++, { other, oe, oh, on });
					if (oh.overlap > hit.overlap || (oh.overlap == hit.overlap && other < selfId)) return false;
				}
			}
		}
	}
	for (int m = 1; m < nCl; ++m) {
		if (cl[m].h.overlap > hit.overlap || (cl[m].h.overlap == hit.overlap && cl[m].id < selfId)) return false;
		if (nBeaten < 8) beaten[nBeaten++] = cl[m].id;
	}
	return true;
}
/// Ownership test of element `self` for a probe sphere (P, R), e.g. a grain, with closest point
/// `hit` on self: every neighbour is probed with the same sphere.
template <class Mesh>
inline bool owns(const Mesh& mesh, const ElementNodes& self, int selfId, const Vec3& P, double R, const Hit& hit, int* beaten, int& nBeaten)
{
	return ownsCluster(
	        mesh, self, selfId, hit, (P - hit.point).normalized(),
	        [&](const ElementNodes& oe, Vec3& on) {
		        const Hit h = probe(mesh, oe, P, R);
		        on          = (P - h.point).normalized();
		        return h;
	        },
	        beaten, nBeaten);
}

/// Whether the core of element e (its segment or triangle, without the radius) is surely farther
/// than d from point P: by more than round-off (a relative 1e-9 of d and P's coordinates); false
/// where it cannot tell (a node missing).
template <class Mesh> inline bool coreFartherThan(const Mesh& mesh, const ElementNodes& e, const Vec3& P, double d)
{
	const Vec3* x[3] = { nullptr, nullptr, nullptr };
	for (int k = 0; k < e.nNodes; ++k)
		if (!(x[k] = mesh.pos(e.nodes[k]))) return false;
	const double margin = d + 1e-9 * (d + P.cwiseAbs().maxCoeff());
	// first the sphere about the nodes' mean through the farthest node, which holds the core
	Vec3 c = *x[0];
	for (int k = 1; k < e.nNodes; ++k)
		c += *x[k];
	c /= e.nNodes;
	double r2 = 0;
	for (int k = 0; k < e.nNodes; ++k)
		r2 = std::max(r2, (*x[k] - c).squaredNorm());
	if ((P - c).norm() - std::sqrt(r2) > margin) return true;
	if (e.isSegment()) return (P - closestPointOnSegment(P, *x[0], *x[1]).point).squaredNorm() > margin * margin;
	if (e.isTriangle()) return (P - closestPointOnTriangle(P, *x[0], *x[1], *x[2]).point).squaredNorm() > margin * margin;
	return false;
}

/// Contact of two elements x and y (x on side A, y on side B): the overlap, the closest point on
/// each with its support, and the direction n from x's point to y's (zero when one pierces the
/// other). Computed in ONE canonical order whoever asks (two segments: the lower id first; a
/// segment and a triangle: the segment first), so that every pair of a cluster sees
/// bit-identical overlaps. Triangle-triangle and non-elements: no contact (overlap -inf).
struct PairHit {
	Hit    hx, hy;
	Vec3   n       = Vec3::Zero();
	double overlap = -std::numeric_limits<double>::infinity();
};
/// pairHit's answer from the closest points ss of segments a and b (a: the lower id), once
/// segmentsApart found them not apart; swap: x is b.
inline PairHit segmentsPairHit(const ElementNodes& a, const ElementNodes& b, const SegmentSegment& ss, bool swap)
{
	PairHit      r;
	const double ov = a.radius + b.radius - (ss.p2 - ss.p1).norm();
	const Hit    ha = segmentHit(a, PointSegment { ss.s, ss.p1 }, ov);
	const Hit    hb = segmentHit(b, PointSegment { ss.t, ss.p2 }, ov);
	r.overlap       = ha.overlap;
	r.hx            = swap ? hb : ha;
	r.hy            = swap ? ha : hb;
	r.n             = (r.hy.point - r.hx.point).normalized();
	return r;
}
/// pairHit's answer from the closest points st of segment a and triangle b, once
/// segmentTriangleApart found them not apart; swap: x is the triangle.
inline PairHit segmentTrianglePairHit(const ElementNodes& a, const ElementNodes& b, const SegmentTriangle& st, bool swap)
{
	PairHit      r;
	const double ov = a.radius + b.radius - (st.t.point - st.p1).norm();
	const Hit    ha = segmentHit(a, PointSegment { st.s, st.p1 }, ov);
	// support from the weights: a segment parallel to the triangle over its face gets the
	// face's support (7) also where its stretch ends on an edge (a wire's node above a seam),
	// with that edge's weights and a zero (round-off) for the third node
	PointTriangle t = st.t;
	t.support       = 0;
	for (int k = 0; k < 3; ++k)
		if (t.w[k] > 1e-12) t.support |= 1u << k;
	const Hit hb = triangleHit(b, t, ov);
	r.overlap    = ha.overlap;
	r.hx         = swap ? hb : ha;
	r.hy         = swap ? ha : hb;
	r.n          = (r.hy.point - r.hx.point).normalized();
	return r;
}
template <class Mesh> inline PairHit pairHit(const Mesh& mesh, int idx, const ElementNodes& x, int idy, const ElementNodes& y)
{
	if (!x.nNodes || !y.nNodes || (x.isTriangle() && y.isTriangle())) return PairHit();
	const bool          swap = x.isTriangle() || (x.isSegment() && y.isSegment() && idy < idx);
	const ElementNodes &a = swap ? y : x, &b = swap ? x : y;
	const Vec3*         pa[2] = { mesh.pos(a.nodes[0]), mesh.pos(a.nodes[1]) };
	const Vec3*         pb[3] = { nullptr, nullptr, nullptr };
	for (int k = 0; k < b.nNodes; ++k)
		if (!(pb[k] = mesh.pos(b.nodes[k]))) return PairHit();
	if (!pa[0] || !pa[1]) return PairHit();
	const double reach = a.radius + b.radius;
	if (b.isSegment()) {
		if (segmentsApart(*pa[0], *pa[1], *pb[0], *pb[1], reach)) return PairHit();
		return segmentsPairHit(a, b, closestPointsSegments(*pa[0], *pa[1], *pb[0], *pb[1]), swap);
	}
	if (segmentTriangleApart(*pa[0], *pa[1], *pb[0], *pb[1], *pb[2], reach)) return PairHit();
	return segmentTrianglePairHit(a, b, closestPointsSegmentTriangle(*pa[0], *pa[1], *pb[0], *pb[1], *pb[2]), swap);
}

/// One contact decision per cluster of element-element pairs (a probe-based test, each side
/// probed with the other's closest point, judged a bar S on a convex fold of two facets F1, F2
/// from different probe points for (S, F1) and (S, F2), so both could carry the contact).
///
/// The pairs (a, b) that overlap form clusters of LINKED pairs. Two pairs that differ on one
/// side, (a, b) and (a', b) with a and a' sharing a node, are linked when their contact points on
/// the common element b are closer than the thinner of a, a' plus b's radius AND either closest
/// point on a, a' lies on what they share or their normals are within 15 degrees; or when one
/// has no normal (a pierced element) and their points on a, a' are closer than the thinner
/// radius. Two pairs that differ on both sides, (a, b) and (a', b'), where a' holds the support
/// of a's closest point and b' that of b's (a wire's node above the seam of two facets), are
/// linked when their points are that close on both sides and their normals within 15 degrees.
/// Pairs of elements sharing a node (bonded) have no contact. Each cluster's contact is carried
/// by its pair with the largest overlap (ties: the lower pair of ids).
///
/// The locality bound on the common element keeps distinct contacts apart: a bar lying along a
/// membrane touches several facets at points far apart on the bar (a line contact), and two
/// wires lying on one facet at different places have parallel normals too.
/// Returns whether (idA, idB) carries its cluster's contact; the other pairs are then in
/// `beaten` (A-side id, B-side id; at most 8 kept) for the shear hand-over.
///
/// A pair met by changing one element is evaluated only if its new element comes close enough
/// to the member's contact point to link (coreFartherThan); screen = false evaluates every pair
/// met (the same answer, the reference the tests hold the screen to). selfHit: pairHit(mesh, idA,
/// A, idB, B) where the caller has it already (a contact functor, from the same node positions
/// and the same calls: segmentsPairHit, segmentTrianglePairHit); null: computed here.
template <class Mesh>
inline bool ownsPair(const Mesh& mesh, int idA, const ElementNodes& A, int idB, const ElementNodes& B, std::pair<int, int>* beaten, int& nBeaten,
        bool screen = true, const PairHit* selfHit = nullptr)
{
	nBeaten = 0;
	struct Member {
		int          ia, ib;
		ElementNodes a, b;
		PairHit      h;
	};
	const PairHit self = selfHit ? *selfHit : pairHit(mesh, idA, A, idB, B);
	if (!(self.overlap > 0)) return false;
	auto key   = [](int p, int q) { return std::make_pair(std::min(p, q), std::max(p, q)); };
	auto beats = [&](const Member& m) { return m.h.overlap > self.overlap || (m.h.overlap == self.overlap && key(m.ia, m.ib) < key(idA, idB)); };
	// every pair met is evaluated once: its hit is kept, as member, overlapping candidate (not
	// linked yet: it may link to a later member) or not touching
	struct Met {
		std::pair<int, int> pq;
		int                 member; // index in cl, -1: candidate, -2: not touching
		PairHit             h;
		ElementNodes        ea, eb;
	};
	SlotArray<Member, kMaxCluster>  cl;
	SlotArray<Met, 4 * kMaxCluster> met;
	int                             nCl = 0, nMet = 0;
	cl.put(nCl++, { idA, idB, A, B, self });
	met.put(nMet++, { { idA, idB }, 0, self, A, B });
	// a pair met from a member: evaluated once, then added if `link` says it is the same
	// contact; returns true if it beats self (self then does not carry the contact). A pair that
	// `mayLink` (given its two elements) rules out is neither evaluated nor kept: it may still be
	// met, and link, from another member.
	auto visit = [&](const Member& cur, int ia2, int ib2, auto link, auto mayLink) {
		const std::pair<int, int> pq { ia2, ib2 };
		int                       at = -1;
		for (int i = 0; i < nMet && at < 0; ++i)
			if (met[i].pq == pq) at = i;
		if (at >= 0 && met[at].member != -1) return false; // a member already, or not touching
		if (at < 0) {
			if (nMet == 4 * kMaxCluster) return false; // (full: a cluster this large does not occur)
			const ElementNodes ea  = ia2 == cur.ia ? cur.a : mesh.element(ia2);
			const ElementNodes eb  = ib2 == cur.ib ? cur.b : mesh.element(ib2);
			const bool         can = ea.nNodes && eb.nNodes && !shareNode(ea, eb); // (bonded: no contact)
			if (can && !mayLink(ea, eb)) return false;
			at     = nMet++;
			Met& x = met.put(at, Met {});
			x.pq   = pq;
			x.ea   = ea;
			x.eb   = eb;
			if (can) x.h = pairHit(mesh, ia2, x.ea, ib2, x.eb);
			x.member = x.h.overlap > 0 ? -1 : -2;
			if (x.member == -2) return false; // not touching: never part of a cluster
		}
		if (!link(met[at]) || nCl == kMaxCluster) return false; // may still join through another member
		met[at].member = nCl;
		cl.put(nCl, { ia2, ib2, met[at].ea, met[at].eb, met[at].h });
		return beats(cl[nCl++]);
	};
	auto holds   = [](const ElementNodes& e, const Hit& h) { return onShared(h, e, e); }; // e has every node of h's support
	auto anyPair = [](const ElementNodes&, const ElementNodes&) { return true; };
	for (int m = 0; m < nCl; ++m) {                                                     // breadth-first over linked pairs
		const Member& cur = cl[m];                                                  // (slots stay where they are while members are added)
		// one element changes: (a', b) or (a, b')
		for (int side = 0; side < 2; ++side) {
			const ElementNodes& e       = side == 0 ? cur.a : cur.b;
			const ElementNodes& partner = side == 0 ? cur.b : cur.a;
			const int           eId     = side == 0 ? cur.ia : cur.ib;
			auto                link    = [&](const Met& x) {
                                const ElementNodes& oe = side == 0 ? x.ea : x.eb;
                                const Hit &         hc = side == 0 ? cur.h.hx : cur.h.hy, &ho = side == 0 ? x.h.hx : x.h.hy; // on the elements that change
                                const Hit &         pc = side == 0 ? cur.h.hy : cur.h.hx, &po = side == 0 ? x.h.hy : x.h.hx; // on the common partner
                                const double        thin = std::min(e.radius, oe.radius), patch = thin + partner.radius;
                                return ((pc.point - po.point).squaredNorm() < patch * patch
                                               && (onShared(hc, e, oe) || onShared(ho, e, oe) || cur.h.n.dot(x.h.n) > kMergeCos))
                                        || ((cur.h.n.squaredNorm() == 0 || x.h.n.squaredNorm() == 0) && (hc.point - ho.point).squaredNorm() < thin * thin);
			};
			// a pair (oe, partner) that touches and links has its closest point on oe within
			// `far` of cur's point on the partner: by the first clause of link, cur's and its point
			// on the partner are closer than patch, and its points closer than oe.radius +
			// partner.radius (it touches); by the second, its point on oe is closer than thin to
			// cur's point on e, itself closer than e.radius + partner.radius to cur's point on the
			// partner (cur touches)
			const Vec3& onPartner = side == 0 ? cur.h.hy.point : cur.h.hx.point;
			auto        mayLink   = [&](const ElementNodes& ea2, const ElementNodes& eb2) {
                                const ElementNodes& oe   = side == 0 ? ea2 : eb2;
                                const double        thin = std::min(e.radius, oe.radius);
                                const double        far = std::max(thin + partner.radius + oe.radius + partner.radius, thin + e.radius + partner.radius);
                                return !screen || !coreFartherThan(mesh, oe, onPartner, far);
			};
			for (int k = 0; k < e.nNodes; ++k)
				for (int other : mesh.elementsAt(e.nodes[k]))
					if (other != eId && visit(cur, side == 0 ? other : cur.ia, side == 0 ? cur.ib : other, link, mayLink)) return false;
		}
		// both change, where the contact sits on what each element shares with a neighbour (a
		// wire's node above a seam of two facets: (wire 1, facet 2) and (wire 2, facet 1) touch at
		// the same point)
		const Hit &hx = cur.h.hx, &hy = cur.h.hy;
		if (hx.nSupport < cur.a.nNodes && hy.nSupport < cur.b.nNodes) {
			auto link = [&](const Met& x) {
				const double reach = std::min(cur.a.radius, x.ea.radius) + std::min(cur.b.radius, x.eb.radius);
				return (hx.point - x.h.hx.point).squaredNorm() < reach * reach && (hy.point - x.h.hy.point).squaredNorm() < reach * reach
				        && (cur.h.n.dot(x.h.n) > kMergeCos || cur.h.n.squaredNorm() == 0 || x.h.n.squaredNorm() == 0);
			};
			const IdRange as = mesh.elementsAt(hx.support[0]);
			const IdRange bs = mesh.elementsAt(hy.support[0]);
			if (!bs.empty())
				for (int a2 : as) {
					if (a2 == cur.ia) continue;
					const ElementNodes ea2 = mesh.element(a2);
					if (!holds(ea2, hx)) continue;
					for (int b2 : bs)
						if (b2 != cur.ib && holds(mesh.element(b2), hy) && visit(cur, a2, b2, link, anyPair)) return false;
				}
		}
	}
	for (int m = 1; m < nCl && nBeaten < 8; ++m)
		beaten[nBeaten++] = { cl[m].ia, cl[m].ib };
	return true;
}

} // namespace flex
