// Helpers shared by the adapter translation units (not part of the Python API).
#pragma once
#include "Flex.hpp"
#include "FlexFacet.hpp"

#include <kernel/Beam.hpp>
#include <kernel/ClosestPoints.hpp>
#include <kernel/Contact.hpp>
#include <kernel/Membrane.hpp>
#include <kernel/TimeStep.hpp>
#include <kernel/Triangle.hpp>

#include <cmath>
#include <mutex>
#include <type_traits>
#include <typeinfo>
#include <utility>

namespace yade {
static_assert(std::is_same<Vector3r, flex::Vec3>::value, "yade-flex expects YADE_REAL_BIT=64 (Real = double)");
static_assert(std::is_same<Quaternionr, flex::Quat>::value, "yade-flex expects YADE_REAL_BIT=64 (Real = double)");

namespace flexa {
	/// Collider pairs of bonded neighbours (elements sharing a node), reported once by the
	/// Ig2 and erased by FlexElementEngine outside the interaction loop. Their bounds always
	/// overlap (both contain the shared node), so the insertion-sort collider never re-creates
	/// them (no min/max inversion between them can occur) until it re-initialises; then they
	/// are reported and erased again. Net effect: no per-step cost at all.
	struct NeighbourPairs {
		std::mutex                                    m;
		const Scene*                                  scene = nullptr;
		std::vector<std::pair<Body::id_t, Body::id_t>> pairs;
	};
	inline NeighbourPairs& neighbourPairs()
	{
		static NeighbourPairs p;
		return p;
	}
	inline void reportNeighbourPair(const Scene* scene, Body::id_t a, Body::id_t b)
	{
		NeighbourPairs&             np = neighbourPairs();
		std::lock_guard<std::mutex> lock(np.m);
		if (np.scene != scene) { // another scene (O.reset, switchScene): its reports are stale
			np.pairs.clear();
			np.scene = scene;
		}
		np.pairs.emplace_back(a, b);
	}

	/// Potential pairs that cannot touch before the collider runs again, found by
	/// FlexTimeStepper's estimate (see FlexTimeStepper.skipUnreachable): the geometry functors
	/// return false for them at once instead of computing their distance. A mark is the pair's
	/// ids at its index in the interaction container (an interaction moved by an erase no longer
	/// matches and is simply tested). The marks hold while no collider has run since they were
	/// made: FlexTimeStepper sets InteractionContainer::iterColliderLastRun to kMarksValid, and
	/// every YADE collider overwrites that field on each run (InsertionSortCollider with -1,
	/// others with the iteration), which retires all marks at once. Read concurrently by the
	/// interaction loop, written only by FlexTimeStepper::action (a serial engine).
	constexpr long kMarksValid = -2;
	struct UnreachableMarks {
		const Scene*                                   scene = nullptr;
		std::vector<std::pair<Body::id_t, Body::id_t>> pair; // by Interaction::linIx; (-1, -1): none
		unsigned long                                  generation = 0; // one more at each new set of marks
	};
	inline UnreachableMarks& unreachableMarks()
	{
		static UnreachableMarks m;
		return m;
	}
	/// Whether the mark at I's index (pairs[0..n), UnreachableMarks::pair of valid marks) is I's pair.
	inline bool markMatches(const std::pair<Body::id_t, Body::id_t>* pairs, size_t n, const Interaction& I)
	{
		if (I.linIx < 0 || (size_t)I.linIx >= n) return false;
		const std::pair<Body::id_t, Body::id_t>& p = pairs[I.linIx];
		return (p.first == I.getId1() && p.second == I.getId2()) || (p.first == I.getId2() && p.second == I.getId1());
	}
	inline bool markedUnreachable(const Scene* scene, const Interaction& I)
	{
		if (scene->interactions->iterColliderLastRun != kMarksValid) return false;
		const UnreachableMarks& m = unreachableMarks();
		return m.scene == scene && markMatches(m.pair.data(), m.pair.size(), I);
	}

	/// Whether this geometry functor skips marked pairs itself (returns false first thing when
	/// `!I->geom && !force && markedUnreachable(scene, *I)`, see FlexFunctors.cpp): the exact
	/// classes, a subclass might override go() without that test. FlexInteractionLoop leaves such
	/// pairs out before reading their bodies; keep this list and the functors in step.
	inline bool readsUnreachableMarks(const IGeomFunctor* f)
	{
		if (!f) return false;
		const std::type_info& t = typeid(*f);
		return t == typeid(Ig2_Sphere_Sphere_FlexContactGeom) || t == typeid(Ig2_Sphere_FlexCylinder_FlexContactGeom)
		        || t == typeid(Ig2_FlexCylinder_FlexCylinder_FlexContactGeom) || t == typeid(Ig2_Sphere_FlexFacet_FlexContactGeom)
		        || t == typeid(Ig2_FlexCylinder_FlexFacet_FlexContactGeom);
	}

	/// Ask the memory system for the `bytes` bytes from p on (every 64-byte line they touch: heap
	/// objects are 16-byte aligned, so an object of 104 bytes may span three lines), to be read
	/// soon. A prefetch never faults: p may be null or stale. The loops over interactions and
	/// bodies wait on cache misses (objects scattered on the heap); they ask a few iterations ahead.
	/// Below this many items, a pass's data (a body, its state, bound and shape: ~700 bytes; an
	/// interaction object) stays in the core's cache from one step to the next, and asking for it
	/// ahead only costs: the prefetches were 10% of the wire-net panel's instructions (188 nodes,
	/// 336 links; bench/instructions_wire.py) and a third of its interaction loop's time (298
	/// pairs, perf). The element loop, the integrator and FlexInteractionLoop ask ahead only in
	/// larger passes (the damping module: 660 legs and ring segments, ~4,600 moving bodies,
	/// 26,000 interactions).
	constexpr long kPrefetchMin = 512;
	inline void prefetch(const void* p, size_t bytes)
	{
		const uintptr_t a = reinterpret_cast<uintptr_t>(p), end = a + bytes;
		for (uintptr_t line = a & ~uintptr_t(63); line < end; line += 64)
			__builtin_prefetch(reinterpret_cast<const void*>(line), 0, 3);
	}
	/// For a pass over all bodies in id order, at body `id`: asks for the body 16 ahead and, through
	/// parts(const Body&), for what the body 8 ahead points to (its state, shape, bound: read from
	/// a body asked for 8 bodies before). Such passes do 10-30 ns per body; a miss costs ~100 ns.
	template <class Parts> inline void prefetchBodiesAhead(const shared_ptr<Body>* body, long n, long id, Parts&& parts)
	{
		if (id + 16 < n) prefetch(body[id + 16].get(), sizeof(Body));
		if (id + 8 < n)
			if (const Body* c = body[id + 8].get()) parts(*c);
	}
	/// The same for a pass over a list of body ids (ids[0..n)), at its k-th entry.
	template <class Parts> inline void prefetchBodiesAhead(const shared_ptr<Body>* body, const Body::id_t* ids, long n, long k, Parts&& parts)
	{
		if (k + 16 < n) prefetch(body[ids[k + 16]].get(), sizeof(Body));
		if (k + 8 < n)
			if (const Body* c = body[ids[k + 8]].get()) parts(*c);
	}
	/// Body `id` of the scene, or null (no such id, or erased). Reads the container's vector
	/// directly: BodyContainer::size, operator[] and Body::byId are out-of-line calls into
	/// libyade, two per lookup, made for every neighbour an ownership search probes.
	inline const Body* bodyAt(const Scene* scene, Body::id_t id)
	{
		const std::vector<shared_ptr<Body>>& v = scene->bodies->body;
		return (id < 0 || (size_t)id >= v.size()) ? nullptr : v[id].get();
	}

	/// How many times the scene's InsertionSortCollider has run (-1: the scene has none): bounds
	/// and potential interactions change only when it runs (FlexTimeStepper, FlexNewtonIntegrator).
	long insertionSortColliderRuns(const Scene* scene);

	/// Counts the elements FlexElementEngine has erased (rupture), in any scene: FlexNewtonIntegrator
	/// rebuilds its node table of the collider trigger when it changes.
	inline long& elementErasures()
	{
		static long n = 0;
		return n;
	}

	/// scene->energy->add without building a std::string from the name at every call (the hot
	/// path, once the term has its index), called per contact, element and body.
	inline void addEnergy(Scene* scene, Real val, const char* name, int& ix, bool reset)
	{
		if (ix >= 0) scene->energy->energies.add(ix, val);
		else scene->energy->add(val, name, ix, reset);
	}

	inline flex::BeamSection section(const FlexMat& m, Real radius)
	{
		const Real E = std::isfinite(m.elementYoung) ? m.elementYoung : m.young;
		return flex::BeamSection::circular(E, E / (2 * (1 + m.beamPoisson)), radius, m.bendingFactor);
	}
	inline flex::AxialLaw axialLaw(const FlexMat& m, Real radius)
	{
		const Real     A = M_PI * radius * radius;
		flex::AxialLaw law;
		law.tensionOnly   = m.tensionOnly;
		law.yieldForce    = m.yieldStress * A;
		law.hardening     = m.hardening;
		law.ruptureForce  = m.tensileStrength * A;
		law.ruptureStrain = m.ruptureStrain;
		return law;
	}
	inline flex::MembraneLaw membraneLaw(const FlexMembraneMat& m)
	{
		flex::MembraneLaw law;
		law.Et          = m.stiffness;
		law.nu          = m.membranePoisson;
		law.tensionOnly = m.tensionOnly;
		law.strength    = m.strength;
		return law;
	}
	/// Rest state of a facet from its stored rest shape.
	inline flex::MembraneRest membraneRest(const FlexFacet& f)
	{
		flex::MembraneRest r;
		r.A0 = f.area0;
		Eigen::Matrix2d Dm;
		Dm << f.restEdges[0], f.restEdges[1], 0, f.restEdges[2];
		r.DmInv = Dm.inverse();
		return r;
	}
	inline const State* stateOf(const Scene* scene, Body::id_t id)
	{
		const Body* b = bodyAt(scene, id);
		return b ? b->state.get() : nullptr;
	}
	inline bool shareNode(const FlexCylinder& a, const FlexCylinder& b)
	{
		return a.node1 == b.node1 || a.node1 == b.node2 || a.node2 == b.node1 || a.node2 == b.node2;
	}

	/// A deformable element seen generically: its nodes and contact radius.
	struct Element {
		const FlexCylinder* cyl = nullptr;
		const FlexFacet*    fac = nullptr;
		int                 nodes[3] { -1, -1, -1 };
		int                 nNodes = 0;
		Real                radius = 0;
	};
	// from the static type: no dynamic_cast (the contact functors know their shapes' types)
	inline Element elementOf(const FlexCylinder* c)
	{
		Element e;
		e.cyl      = c;
		e.nodes[0] = c->node1;
		e.nodes[1] = c->node2;
		e.nNodes   = 2;
		e.radius   = c->radius;
		return e;
	}
	inline Element elementOf(const FlexFacet* f)
	{
		Element e;
		e.fac      = f;
		e.nodes[0] = f->node1;
		e.nodes[1] = f->node2;
		e.nodes[2] = f->node3;
		e.nNodes   = 3;
		e.radius   = f->radius;
		return e;
	}
	/// dynamic_cast with a fast path for the exact type: one type_info comparison (a pointer
	/// comparison when both sides use the same type_info object) instead of a walk of the
	/// hierarchy with string comparisons, measured as 18% of a time-step estimate.
	template <class T, class B> inline const T* fastCast(const B* p)
	{
		if (!p) return nullptr;
		if (typeid(*p) == typeid(T)) return static_cast<const T*>(p);
		return dynamic_cast<const T*>(p);
	}
	inline Element elementOf(const Shape* sh)
	{
		Element e;
		if (!sh) return e;
		const std::type_info& t = typeid(*sh);
		if (t == typeid(FlexCylinder)) return elementOf(static_cast<const FlexCylinder*>(sh));
		if (t == typeid(FlexFacet)) return elementOf(static_cast<const FlexFacet*>(sh));
		if (t == typeid(Sphere) || t == typeid(FlexNode)) return e; // the common non-elements
		if (const FlexCylinder* c = dynamic_cast<const FlexCylinder*>(sh)) return elementOf(c);
		if (const FlexFacet* f = dynamic_cast<const FlexFacet*>(sh)) return elementOf(f);
		return e;
	}
	inline Element elementOf(const Scene* scene, Body::id_t id)
	{
		const Body* b = bodyAt(scene, id);
		return b ? elementOf(b->shape.get()) : Element();
	}
	inline bool shareNode(const Element& a, const Element& b)
	{
		for (int i = 0; i < a.nNodes; ++i)
			for (int j = 0; j < b.nNodes; ++j)
				if (a.nodes[i] == b.nodes[j]) return true;
		return false;
	}

	/// Closest point of an element to a probe sphere (centre P, radius R): the overlap and
	/// the nodes that carry the closest point (its support: one node in a cap or vertex
	/// region, two on a cylinder's side or a facet's edge, three on a facet's face).
	struct Hit {
		Real     overlap = -std::numeric_limits<Real>::infinity();
		Vector3r point   = Vector3r::Zero();
		int      support[3] { -1, -1, -1 };
		int      nSupport = 0;
	};
	inline Hit segmentHit(const Element& e, const flex::PointSegment& ps, Real overlap)
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
	inline Hit triangleHit(const Element& e, const flex::PointTriangle& pt, Real overlap)
	{
		Hit h;
		h.point = pt.point;
		for (int k = 0; k < 3; ++k)
			if (pt.support & (1u << k)) h.support[h.nSupport++] = e.nodes[k];
		h.overlap = overlap;
		return h;
	}
	/// The SAME arithmetic as the Ig2 functors use for the element's own contact (same
	/// kernel call, same node order), so that overlaps compare bit-identically.
	inline Hit probe(const Scene* scene, const Element& e, const Vector3r& P, Real R)
	{
		const State* s[3] = { nullptr, nullptr, nullptr };
		for (int k = 0; k < e.nNodes; ++k)
			if (!(s[k] = stateOf(scene, e.nodes[k]))) return Hit();
		if (e.cyl) {
			const flex::PointSegment ps = flex::closestPointOnSegment(P, s[0]->pos, s[1]->pos);
			return segmentHit(e, ps, R + e.radius - (P - ps.point).norm());
		}
		if (e.fac) {
			const flex::PointTriangle pt = flex::closestPointOnTriangle(P, s[0]->pos, s[1]->pos, s[2]->pos);
			return triangleHit(e, pt, R + e.radius - (P - pt.point).norm());
		}
		return Hit();
	}
	/// Two contacts of one probe on elements sharing a node are LINKED (the same contact)
	/// when the closest point on either lies on what the two share (the cap region at a
	/// chain's shared node, a facet's shared edge or vertex), or when their normals are
	/// within 15 degrees (the concave side of a nearly straight chain or a nearly flat
	/// membrane: the contact patches merge). Otherwise they are distinct contacts and both
	/// count: a sphere resting on a net cell touches its four wires, a sphere in a sharp
	/// kink touches both legs.
	///
	/// The links are closed transitively: the elements a probe touches fall into clusters
	/// (equivalence classes), and each cluster gives ONE contact, carried by its element with
	/// the largest overlap (ties: lower id). Every member computes the same cluster from the
	/// same bit-identical overlaps, so exactly one owns it. The contact's potential is then
	/// that of the largest overlap, a continuous function of the positions: hand-overs inside
	/// a cluster neither create nor destroy energy. (A pairwise rule, "lose to a linked
	/// neighbour with a larger overlap", is not transitive: in a shallow dent A > B > C with
	/// A-B and B-C linked but not A-C, C is suppressed by B, which itself is inactive, and C's
	/// contact later appears with a finite overlap. Measured: a sphere dropped into a rigid
	/// 13-degree cone of facets gained 31 J.) A cluster splits or merges only when a link
	/// changes while both sides overlap: the angle between two touched neighbours crossing 15
	/// degrees.
	constexpr Real kMergeCos = 0.96592582628906831; // cos(15 deg)
	/// Whether the closest point `h` lies on what elements a and b share (every node of its
	/// support belongs to both: a shared node, edge or vertex).
	inline bool onShared(const Hit& h, const Element& a, const Element& b)
	{
		for (int k = 0; k < h.nSupport; ++k) {
			bool inA = false, inB = false;
			for (int i = 0; i < a.nNodes; ++i) inA |= a.nodes[i] == h.support[k];
			for (int j = 0; j < b.nNodes; ++j) inB |= b.nodes[j] == h.support[k];
			if (!(inA && inB)) return false;
		}
		return true;
	}
	constexpr int  kMaxCluster = 48;

	/// Ownership of a contact by element `self` (body selfId) among the elements sharing its
	/// nodes (see above). `hit` is self's contact and `n` its direction (from the element's
	/// closest point towards the other body); hitOf(element, normal out) gives a neighbour's
	/// contact the same way, with the same arithmetic as that neighbour's own functor.
	/// A contact without a normal (the probe's centre exactly on the element's axis or plane:
	/// Eigen's normalized() then gives zero) is also LINKED to a neighbour's whose closest
	/// point lies closer than the thinner element's radius: one contact patch. Only there:
	/// applied to every pair, the same distance rule also merged and split contacts of grains
	/// on mesh wires and broke the main job's energy balance (residual 2.2% instead of 0.32%).
	/// Returns true if self carries its cluster's contact; the other members of the
	/// cluster are then returned in `beaten` (at most 8 kept) for shear hand-over (on false,
	/// `beaten` means nothing: the search stops at the first member that beats self).
	/// For contacts of a sphere (the probe) with an element; contacts between two elements are
	/// decided per cluster of element pairs (ownsPair).
	template <class HitOf>
	inline bool ownsCluster(const Scene* scene, const Element& self, Body::id_t selfId, const Hit& hit, const Vector3r& n, HitOf hitOf, Body::id_t* beaten, int& nBeaten)
	{
		nBeaten = 0;
		struct Member {
			Body::id_t id;
			Element    e;
			Hit        h;
			Vector3r   n;
		};
		Member     cl[kMaxCluster];
		Body::id_t seen[4 * kMaxCluster];
		int        nCl = 0, nSeen = 0;
		cl[nCl++]      = { selfId, self, hit, n };
		seen[nSeen++]  = selfId;
		for (int m = 0; m < nCl; ++m) { // breadth-first over linked neighbours
			const Member cur = cl[m];
			for (int k = 0; k < cur.e.nNodes; ++k) {
				const Body* nb = bodyAt(scene, cur.e.nodes[k]);
				const FlexNode* node = nb ? fastCast<FlexNode>(nb->shape.get()) : nullptr;
				if (!node) continue;
				for (int other : node->elements) {
					bool dup = false;
					for (int i = 0; i < nSeen && !dup; ++i) dup = seen[i] == other;
					if (dup) continue;
					const Element oe = elementOf(scene, other);
					if (!oe.nNodes) continue;
					Vector3r  on;
					const Hit oh = hitOf(oe, on);
					if (!(oh.overlap > 0)) { // not touching: never part of a cluster
						if (nSeen < 4 * kMaxCluster) seen[nSeen++] = other;
						continue;
					}
					const Real near   = std::min(cur.e.radius, oe.radius);
					const bool linked = onShared(cur.h, cur.e, oe) || onShared(oh, cur.e, oe) || cur.n.dot(on) > kMergeCos
					        || ((cur.n.squaredNorm() == 0 || on.squaredNorm() == 0) && (cur.h.point - oh.point).squaredNorm() < near * near);
					if (!linked) continue; // may still join through another member
					if (nSeen < 4 * kMaxCluster) seen[nSeen++] = other;
					if (nCl < kMaxCluster) {
						cl[nCl++] = { other, oe, oh, on };
						// a member that beats self settles it: self does not carry the contact
						// (the loop below would return false on it; the callers read `beaten`
						// only from an owner). Most pairs that overlap are losers, found here
						// after a probe or two instead of the whole cluster.
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
	/// Ownership test of element `self` for a probe sphere (P, R), e.g. a grain or the
	/// closest point of a partner element, with closest point `hit` on self: every neighbour
	/// is probed with the same sphere.
	inline bool owns(const Scene* scene, const Element& self, Body::id_t selfId, const Vector3r& P, Real R, const Hit& hit, Body::id_t* beaten, int& nBeaten)
	{
		return ownsCluster(
		        scene, self, selfId, hit, (P - hit.point).normalized(),
		        [&](const Element& oe, Vector3r& on) {
			        const Hit h = probe(scene, oe, P, R);
			        on          = (P - h.point).normalized();
			        return h;
		        },
		        beaten, nBeaten);
	}
	/// Contact of two elements x and y (x on side A, y on side B): the overlap, the closest
	/// point on each with its support, and the direction n from x's point to y's (zero when
	/// one pierces the other). Computed in ONE canonical order whoever asks (two cylinders:
	/// the lower id first; a cylinder and a facet: the cylinder first), so that every
	/// interaction of a cluster of pairs (ownsPair) sees bit-identical overlaps. Facet-facet
	/// and non-elements: no contact (overlap -inf).
	struct PairHit {
		Hit      hx, hy;
		Vector3r n       = Vector3r::Zero();
		Real     overlap = -std::numeric_limits<Real>::infinity();
	};
	inline PairHit pairHit(const Scene* scene, Body::id_t idx, const Element& x, Body::id_t idy, const Element& y)
	{
		PairHit r;
		if (!x.nNodes || !y.nNodes || (x.fac && y.fac)) return r;
		const bool     swap = x.fac || (x.cyl && y.cyl && idy < idx);
		const Element &a = swap ? y : x, &b = swap ? x : y;
		const State*   sa[2] = { stateOf(scene, a.nodes[0]), stateOf(scene, a.nodes[1]) };
		const State*   sb[3] = { nullptr, nullptr, nullptr };
		for (int k = 0; k < b.nNodes; ++k)
			if (!(sb[k] = stateOf(scene, b.nodes[k]))) return r;
		if (!sa[0] || !sa[1]) return r;
		const Real reach = a.radius + b.radius;
		Hit        ha, hb;
		if (b.cyl) {
			if (flex::segmentsApart(sa[0]->pos, sa[1]->pos, sb[0]->pos, sb[1]->pos, reach)) return r;
			const flex::SegmentSegment ss = flex::closestPointsSegments(sa[0]->pos, sa[1]->pos, sb[0]->pos, sb[1]->pos);
			const Real                 ov = reach - (ss.p2 - ss.p1).norm();
			ha                            = segmentHit(a, flex::PointSegment { ss.s, ss.p1 }, ov);
			hb                            = segmentHit(b, flex::PointSegment { ss.t, ss.p2 }, ov);
		} else {
			if (flex::segmentTriangleApart(sa[0]->pos, sa[1]->pos, sb[0]->pos, sb[1]->pos, sb[2]->pos, reach)) return r;
			const flex::SegmentTriangle st = flex::closestPointsSegmentTriangle(sa[0]->pos, sa[1]->pos, sb[0]->pos, sb[1]->pos, sb[2]->pos);
			const Real                  ov = reach - (st.t.point - st.p1).norm();
			ha                             = segmentHit(a, flex::PointSegment { st.s, st.p1 }, ov);
			// support from the weights: a segment parallel to the facet over its face gets the
			// face's support (7) also where its stretch ends on an edge (a wire's node above a
			// seam), with that edge's weights and a zero (round-off) for the third node
			flex::PointTriangle t = st.t;
			t.support             = 0;
			for (int k = 0; k < 3; ++k)
				if (t.w[k] > 1e-12) t.support |= 1u << k;
			hb = triangleHit(b, t, ov);
		}
		r.overlap = ha.overlap;
		r.hx      = swap ? hb : ha;
		r.hy      = swap ? ha : hb;
		r.n       = (r.hy.point - r.hx.point).normalized();
		return r;
	}
	/// One contact decision per cluster of element-element pairs. Why: a probe-based test
	/// (owns, each side probed with the other's closest point) judged the pair (S, F1) and the
	/// pair (S, F2) of a bar S on a convex fold of two facets from different probe points, so
	/// both could carry the contact at once (twice the force).
	///
	/// What: the pairs (a, b) that overlap form clusters of LINKED pairs (one contact). Two
	/// pairs that differ on one side, (a, b) and (a', b) with a and a' sharing a node, are
	/// linked when their contact points on the common element b are closer than the thinner of
	/// a, a' plus b's radius AND either closest point on a, a' lies on what they share (a
	/// chain's shared node, a facet's shared edge or vertex) or their normals are within 15
	/// degrees; or when one has no normal (a pierced element) and their points on a, a' are
	/// closer than the thinner radius. Two pairs that differ on both sides, (a, b) and
	/// (a', b'), where a' holds the support of a's closest point and b' that of b's (a wire's
	/// node above the seam of two facets), are linked when their points are that close on both
	/// sides and their normals within 15 degrees. Pairs of bonded elements have no contact.
	/// Each cluster's contact is carried by its pair with the largest overlap (ties: the lower
	/// pair of ids), every pair computing the same overlaps with pairHit, so exactly one pair
	/// carries it.
	///
	/// The locality bound on the common element keeps apart what are distinct contacts. A bar
	/// lying along a membrane touches several facets at points far apart on the bar (a line
	/// contact, one closest point per pair): linked through the facets' shared edge alone, only
	/// the deepest pushed and the rest of the bar sank in with no force until the link broke
	/// and that contact started at its full depth (the main job's ring and wire pairs on the
	/// lining: +12.6 J net from hand-overs in the first 2,500 impact steps, -0.3 J with the
	/// bound; bench/handover_events.py). Two wires lying on one facet at different places have
	/// parallel normals too: merging them broke the main job's energy balance (2026-11-23).
	/// Returns whether (idA, idB) carries its cluster's contact; the other pairs are then in
	/// `beaten` (A-side id, B-side id; at most 8 kept) for the shear hand-over.
	inline bool ownsPair(const Scene* scene, Body::id_t idA, const Element& A, Body::id_t idB, const Element& B, std::pair<Body::id_t, Body::id_t>* beaten, int& nBeaten)
	{
		nBeaten = 0;
		struct Member {
			Body::id_t ia, ib;
			Element    a, b;
			PairHit    h;
		};
		const PairHit self = pairHit(scene, idA, A, idB, B);
		if (!(self.overlap > 0)) return false;
		auto key  = [](Body::id_t p, Body::id_t q) { return std::make_pair(std::min(p, q), std::max(p, q)); };
		auto beats = [&](const Member& m) {
			return m.h.overlap > self.overlap || (m.h.overlap == self.overlap && key(m.ia, m.ib) < key(idA, idB));
		};
		// every pair met is evaluated once: its hit is kept, as member, overlapping candidate
		// (not linked yet: it may link to a later member) or not touching
		struct Met {
			std::pair<Body::id_t, Body::id_t> pq;
			int                               member; // index in cl, -1: candidate, -2: not touching
			PairHit                           h;
			Element                           ea, eb;
		};
		Member cl[kMaxCluster];
		Met    met[4 * kMaxCluster];
		int    nCl = 0, nMet = 0;
		cl[nCl++] = { idA, idB, A, B, self };
		met[nMet++] = { { idA, idB }, 0, self, A, B };
		// a pair met from a member: evaluated once, then added if `link` says it is the same
		// contact; returns true if it beats self (self then does not carry the contact)
		auto visit = [&](const Member& cur, Body::id_t ia2, Body::id_t ib2, auto link) {
			const std::pair<Body::id_t, Body::id_t> pq { ia2, ib2 };
			int                                     at = -1;
			for (int i = 0; i < nMet && at < 0; ++i)
				if (met[i].pq == pq) at = i;
			if (at >= 0 && met[at].member != -1) return false; // a member already, or not touching
			if (at < 0) {
				if (nMet == 4 * kMaxCluster) return false; // (full: a cluster this large does not occur)
				at              = nMet++;
				Met& x          = met[at];
				x.pq            = pq;
				x.ea            = ia2 == cur.ia ? cur.a : elementOf(scene, ia2);
				x.eb            = ib2 == cur.ib ? cur.b : elementOf(scene, ib2);
				x.h             = PairHit();
				if (x.ea.nNodes && x.eb.nNodes && !shareNode(x.ea, x.eb)) x.h = pairHit(scene, ia2, x.ea, ib2, x.eb); // (bonded: no contact)
				x.member = x.h.overlap > 0 ? -1 : -2;
				if (x.member == -2) return false; // not touching: never part of a cluster
			}
			if (!link(met[at]) || nCl == kMaxCluster) return false; // may still join through another member
			met[at].member = nCl;
			cl[nCl]        = { ia2, ib2, met[at].ea, met[at].eb, met[at].h };
			return beats(cl[nCl++]);
		};
		auto elementsOf = [&](Body::id_t nodeId) -> const std::vector<int>* {
			const Body*     nb   = bodyAt(scene, nodeId);
			const FlexNode* node = nb ? fastCast<FlexNode>(nb->shape.get()) : nullptr;
			return node ? &node->elements : nullptr;
		};
		auto holds = [](const Element& e, const Hit& h) { return onShared(h, e, e); }; // e has every node of h's support
		for (int m = 0; m < nCl; ++m) { // breadth-first over linked pairs
			const Member cur = cl[m];
			// one element changes: (a', b) or (a, b')
			for (int side = 0; side < 2; ++side) {
				const Element&   e       = side == 0 ? cur.a : cur.b;
				const Element&   partner = side == 0 ? cur.b : cur.a;
				const Body::id_t eId     = side == 0 ? cur.ia : cur.ib;
				auto             link    = [&](const Met& x) {
                                        const Element& oe = side == 0 ? x.ea : x.eb;
                                        const Hit &hc = side == 0 ? cur.h.hx : cur.h.hy, &ho = side == 0 ? x.h.hx : x.h.hy; // on the elements that change
                                        const Hit &pc = side == 0 ? cur.h.hy : cur.h.hx, &po = side == 0 ? x.h.hy : x.h.hx; // on the common partner
                                        const Real thin = std::min(e.radius, oe.radius), patch = thin + partner.radius;
                                        return ((pc.point - po.point).squaredNorm() < patch * patch && (onShared(hc, e, oe) || onShared(ho, e, oe) || cur.h.n.dot(x.h.n) > kMergeCos))
                                                || ((cur.h.n.squaredNorm() == 0 || x.h.n.squaredNorm() == 0) && (hc.point - ho.point).squaredNorm() < thin * thin);
				};
				for (int k = 0; k < e.nNodes; ++k)
					if (const std::vector<int>* els = elementsOf(e.nodes[k]))
						for (int other : *els)
							if (other != eId && visit(cur, side == 0 ? other : cur.ia, side == 0 ? cur.ib : other, link)) return false;
			}
			// both change, where the contact sits on what each element shares with a neighbour
			// (a wire's node above a seam of two facets: (wire 1, facet 2) and (wire 2, facet 1)
			// touch at the same point)
			const Hit &hx = cur.h.hx, &hy = cur.h.hy;
			if (hx.nSupport < cur.a.nNodes && hy.nSupport < cur.b.nNodes) {
				auto link = [&](const Met& x) {
					const Real reach = std::min(cur.a.radius, x.ea.radius) + std::min(cur.b.radius, x.eb.radius);
					return (hx.point - x.h.hx.point).squaredNorm() < reach * reach && (hy.point - x.h.hy.point).squaredNorm() < reach * reach
					        && (cur.h.n.dot(x.h.n) > kMergeCos || cur.h.n.squaredNorm() == 0 || x.h.n.squaredNorm() == 0);
				};
				const std::vector<int>* as = elementsOf(hx.support[0]);
				const std::vector<int>* bs = elementsOf(hy.support[0]);
				if (as && bs)
					for (int a2 : *as) {
						if (a2 == cur.ia) continue;
						const Element ea2 = elementOf(scene, a2);
						if (!holds(ea2, hx)) continue;
						for (int b2 : *bs)
							if (b2 != cur.ib && holds(elementOf(scene, b2), hy) && visit(cur, a2, b2, link)) return false;
					}
			}
		}
		for (int m = 1; m < nCl && nBeaten < 8; ++m)
			beaten[nBeaten++] = { cl[m].ia, cl[m].ib };
		return true;
	}
	/// Shear force (on body 2 of I, whose body 1 is id1) that one of the `beaten` pairs (A-side
	/// id, B-side id; see ownsPair) carried at the previous step; aIs1: whether I's body 1 is
	/// its A-side element.
	inline bool takeOverPairShear(Scene* scene, bool aIs1, const std::pair<Body::id_t, Body::id_t>* beaten, int nBeaten, Vector3r& shear)
	{
		for (int k = 0; k < nBeaten; ++k) {
			const shared_ptr<Interaction> J = scene->interactions->find(beaten[k].first, beaten[k].second);
			if (!J || !J->geom || !J->phys) continue;
			const FlexContactGeom* jg = dynamic_cast<const FlexContactGeom*>(J->geom.get());
			const FrictPhys*       jp = dynamic_cast<const FrictPhys*>(J->phys.get());
			if (!jg || !jp || jg->lastActiveIter != scene->iter - 1) continue;
			const bool same = (J->getId1() == beaten[k].first) == aIs1;
			shear           = same ? jp->shearForce : Vector3r(-jp->shearForce);
			return true;
		}
		return false;
	}
	/// Shear force (on body 2 of I) that interaction between `otherBody` and one of the
	/// `beaten` neighbours carried at the previous step, expressed for an interaction whose
	/// body 1 is id1. Only reads data its owner does not write this step (see Flex.hpp).
	inline bool takeOverShear(Scene* scene, Body::id_t otherBody, Body::id_t id1, const Body::id_t* beaten, int nBeaten, Vector3r& shear)
	{
		for (int k = 0; k < nBeaten; ++k) {
			const shared_ptr<Interaction> J = scene->interactions->find(otherBody, beaten[k]);
			if (!J || !J->geom || !J->phys) continue;
			const FlexContactGeom* jg = dynamic_cast<const FlexContactGeom*>(J->geom.get());
			const FrictPhys*       jp = dynamic_cast<const FrictPhys*>(J->phys.get());
			if (!jg || !jp || jg->lastActiveIter != scene->iter - 1) continue;
			// shear is stored as the force on body 2: flip it if the other body sits on opposite sides
			const bool same = (J->getId1() == otherBody) == (id1 == otherBody);
			shear           = same ? jp->shearForce : Vector3r(-jp->shearForce);
			return true;
		}
		return false;
	}
} // namespace flexa
} // namespace yade
