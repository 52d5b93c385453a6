// yade-flex adapter: deformable elements against YADE's Wall, Box and Facet (GPL-2.0-or-later).
// See FlexSurfaces.hpp; the numerics are in pkg/kernel/Surface.hpp.
#include "FlexSurfaces.hpp"
#include "FlexElementGeom.hpp"
#include "FlexElements.hpp"
#include "FlexOwnership.hpp"
#include "FlexProtocol.hpp"
#include <kernel/Contact.hpp>
#include <kernel/Surface.hpp>

#include <core/Clump.hpp>
#include <core/InteractionLoop.hpp>
#include <lib/factory/ClassFactory.hpp>

#include <algorithm>
#include <sstream>

namespace yade {

YADE_PLUGIN((Ig2_Wall_FlexNode_FlexContactGeom)(Ig2_Box_FlexNode_FlexContactGeom)(Ig2_Box_FlexCylinder_FlexContactGeom)(Ig2_Facet_FlexNode_FlexContactGeom)(
        Ig2_Facet_FlexCylinder_FlexContactGeom)(Ig2_Box_FlexFacet_FlexContactGeom)(Ig2_Facet_FlexFacet_FlexContactGeom));

namespace flexa {
	Real nodeContactRadius(const Scene* scene, const FlexNode& node)
	{
		Real r = 0;
		for (int id : node.elements) {
			const Element e = elementOf(scene, id);
			if (e.nNodes) r = std::max(r, Real(e.radius));
		}
		return r;
	}
} // namespace flexa

namespace {
	bool cannotMove(const Body& b) { return !b.isDynamic() || (b.state->blockedDOFs & State::DOF_XYZ) == State::DOF_XYZ; }

	// The facet's vertices in the world frame.
	void facetVertices(const Facet& f, const State& s, Vector3r v[3])
	{
		for (int k = 0; k < 3; ++k)
			v[k] = s.pos + s.ori * f.vertices[k];
	}
	Vector3r facetNormal(const Vector3r v[3]) { return (v[1] - v[0]).cross(v[2] - v[0]).normalized(); }

	// The side (+1, -1) a contact with previous normal `prev` was pushing towards along n; 0: new.
	int keptSide(bool isNew, const Vector3r& prev, const Vector3r& n) { return isNew ? 0 : (prev.dot(n) < 0 ? -1 : 1); }

	// The contact of a node with a surface, once the surface point is known. Fills g as the other
	// element contacts do (kernel/Surface.hpp: the node is side 2, a zero-length segment on it, so
	// that the law spreads the force and moment to the node alone; the surface is side 1, rigid).
	void fillNodeContact(FlexContactGeom& g, const flex::SurfacePoint& sp, Real r, Body::id_t nodeId, const State& sS, const State& sN)
	{
		const Real overlap = r - sp.distance;
		g.normal           = sp.normal;
		g.penetrationDepth = overlap;
		g.refR1            = r;
		g.refR2            = r;
		g.contactPoint     = sp.point - 0.5 * overlap * sp.normal;
		g.nodes1           = Vector2i(-1, -1);
		g.nodes2           = Vector2i(nodeId, nodeId);
		g.tri1 = g.tri2 = Vector3i(-1, -1, -1);
		g.u1 = g.u2    = 0;
		g.axis1        = sS.pos;
		g.axis2        = sN.pos;
		const Vector3r v1 = sS.vel + sS.angVel.cross(g.contactPoint - sS.pos);
		const Vector3r v2 = sN.vel + sN.angVel.cross(g.contactPoint - sN.pos);
		g.relVel          = v2 - v1;
	}

	// The steps of the three functors: the node's radius, the surface point (where(isNew, prev
	// normal) -> SurfacePoint), the ownership (owns(sp, overlap, beaten, nb)), the geometry.
	template <class Where, class Owns>
	bool nodeGeom(Scene* scene, const shared_ptr<Interaction>& I, const State& sS, const FlexNode& node, const State& sN, bool force, Where where, Owns owns)
	{
		const bool isNew = !I->geom;
		const Real r     = flexa::nodeContactRadius(scene, node);
		if (!(r > 0)) { // every element on the node is gone
			if (isNew) return false;
			static_cast<FlexContactGeom&>(*I->geom).active = false;
			return true;
		}
		const flex::SurfacePoint sp      = where(isNew, isNew ? Vector3r::Zero() : Vector3r(static_cast<FlexContactGeom&>(*I->geom).normal), r);
		const Real               overlap = r - sp.distance;
		if (isNew && overlap <= 0 && !force) return false;
		Body::id_t beaten[8];
		int        nb  = 0;
		const bool own = overlap > 0 && owns(sp, r, beaten, nb);
		if (isNew && !own) return false;
		if (isNew) I->geom = shared_ptr<FlexContactGeom>(new FlexContactGeom);
		FlexContactGeom& g = static_cast<FlexContactGeom&>(*I->geom);
		fillNodeContact(g, sp, r, I->getId2(), sS, sN);
		flexa::finishGeom(scene, g, own, I.get(), I->getId2(), beaten, nb);
		return true;
	}
	bool alone(const flex::SurfacePoint&, Real, Body::id_t*, int& nb)
	{
		nb = 0;
		return true;
	}

	// The node's contact with facet body b as the ownership compares it: the same arithmetic
	// whoever asks (the side the node is on now).
	flex::FacetHit facetHit(const Body& b, const Facet& f, const Vector3r& x, Real r)
	{
		flex::FacetHit h;
		h.id = b.id;
		facetVertices(f, *b.state, h.v);
		const flex::SurfacePoint sp = flex::nodeOnTriangle(x, h.v[0], h.v[1], h.v[2], 0);
		h.overlap                   = r - sp.distance;
		h.support                   = sp.support;
		return h;
	}
	// The facets paired with element body `element` (its interactions: the loop does not change the
	// maps it reads), at most kMaxFacets, in tri (world vertices) and ids; me: the index of facet
	// `self` among them (-1: not paired).
	constexpr int kMaxFacets = 64;
	int           facetsPairedWith(const Scene* scene, const Body* element, Body::id_t self, Vector3r (*tri)[3], int* ids, int& me)
	{
		int n = 0;
		me    = -1;
		if (!element) return 0;
		for (const auto& kv : element->intrs) {
			const Body* b = flexa::bodyAt(scene, kv.first);
			if (!b || !b->shape) continue;
			const Facet* f = flexa::fastCast<Facet>(b->shape.get());
			if (!f) continue;
			if (n == kMaxFacets) {
				if (me >= 0) break;
				n = kMaxFacets - 1; // (keep a slot for this facet)
			}
			if (b->id == self) me = n;
			facetVertices(*f, *b->state, tri[n]);
			ids[n++] = b->id;
		}
		return n;
	}
	// The clump rule (kernel/Surface.hpp, ownsOnUnion) for a contact of Box body `box` with probe x
	// (a node's centre, a wire's or a membrane's nearest point) at point (world), at distance from x:
	// whether the box carries it among the clump's boxes (a standalone box does); the members at the
	// same point in beaten (at most 8).
	bool clumpOwns(const Scene* scene, const Body* box, const Vector3r& x, const Vector3r& point, Real distance, Body::id_t* beaten, int& nb)
	{
		nb = 0;
		if (!box || !box->isClumpMember()) return true;
		const Body*  clump = flexa::bodyAt(scene, box->clumpId);
		const Clump* cl    = clump && clump->shape ? dynamic_cast<const Clump*>(clump->shape.get()) : nullptr;
		const Box*   own   = flexa::fastCast<Box>(box->shape.get());
		if (!cl || !own) return true;
		constexpr int     kMax = 64;
		flex::MemberPoint others[kMax];
		int               n    = 0;
		Real              size = own->extents.norm();
		for (const auto& m : cl->members) {
			if (m.first == box->id || n == kMax) continue;
			const Body* b  = flexa::bodyAt(scene, m.first);
			const Box*  bx = b && b->shape ? flexa::fastCast<Box>(b->shape.get()) : nullptr;
			if (!bx) continue;
			const flex::SurfacePoint sp = flex::nodeOnBox(b->state->ori.conjugate() * (x - b->state->pos), bx->extents);
			others[n].id                = b->id;
			others[n].distance          = sp.distance;
			others[n].point             = b->state->pos + b->state->ori * sp.point;
			others[n++].onRim           = flex::onBoxRim(sp.point, bx->extents, flex::kNodeTie * bx->extents.norm());
			size                        = std::max(size, bx->extents.norm());
		}
		flex::MemberPoint self;
		self.id       = box->id;
		self.distance = distance;
		self.point    = point;
		self.onRim    = flex::onBoxRim(box->state->ori.conjugate() * (point - box->state->pos), own->extents, flex::kNodeTie * own->extents.norm());
		int        got[8];
		const bool o = flex::ownsOnUnion(self, others, n, flex::kNodeTie * size, got, nb);
		for (int k = 0; k < nb; ++k)
			beaten[k] = got[k];
		return o;
	}
} // namespace

bool Ig2_Wall_FlexNode_FlexContactGeom::go(const shared_ptr<Shape>& cm1, const shared_ptr<Shape>& cm2, const State& sS, const State& sN,
        const Vector3r& shift2, const bool& force, const shared_ptr<Interaction>& I)
{
	if (scene->isPeriodic) throw std::runtime_error("Ig2_Wall_FlexNode_FlexContactGeom: periodic scenes are not supported by yade-flex yet.");
	const Wall& w     = static_cast<const Wall&>(*cm1);
	const auto  where = [&](bool isNew, const Vector3r& prev, Real) {
                const Vector3r e = Vector3r::Unit(w.axis);
                return flex::nodeOnPlane(sN.pos, w.axis, sS.pos[w.axis], w.sense, keptSide(isNew, prev, e));
	};
	return nodeGeom(scene, I, sS, static_cast<const FlexNode&>(*cm2), sN, force, where, alone);
}

bool Ig2_Box_FlexNode_FlexContactGeom::go(const shared_ptr<Shape>& cm1, const shared_ptr<Shape>& cm2, const State& sS, const State& sN,
        const Vector3r& shift2, const bool& force, const shared_ptr<Interaction>& I)
{
	if (scene->isPeriodic) throw std::runtime_error("Ig2_Box_FlexNode_FlexContactGeom: periodic scenes are not supported by yade-flex yet.");
	const Box& box   = static_cast<const Box&>(*cm1);
	const auto where = [&](bool, const Vector3r&, Real) {
		flex::SurfacePoint sp = flex::nodeOnBox(sS.ori.conjugate() * (sN.pos - sS.pos), box.extents);
		sp.point              = sS.pos + sS.ori * sp.point;
		sp.normal             = sS.ori * sp.normal;
		return sp;
	};
	const auto owns = [&](const flex::SurfacePoint& sp, Real, Body::id_t* beaten, int& nb) {
		return clumpOwns(scene, flexa::bodyAt(scene, I->getId1()), sN.pos, sp.point, sp.distance, beaten, nb);
	};
	return nodeGeom(scene, I, sS, static_cast<const FlexNode&>(*cm2), sN, force, where, owns);
}

namespace {
	// A cylinder's interior against a surface's edge or vertex (e in the world frame; own: e valid,
	// overlapping and carried by this pair). Where e is not valid the interaction keeps the
	// geometry of its last step: the contact has passed to a node at the same overlap, or apart.
	bool cylinderEdgeGeom(Scene* scene, const shared_ptr<Interaction>& I, const State& sS, const FlexCylinder& c, const State* sa, const State* sb,
	        const flex::SegmentEdge& e, bool own, bool force, const Body::id_t* beaten, int nb)
	{
		if (!I->geom && !own && !force) return false;
		if (!I->geom) I->geom = shared_ptr<FlexContactGeom>(new FlexContactGeom);
		FlexContactGeom& g = static_cast<FlexContactGeom&>(*I->geom);
		if (e.valid) {
			const Real overlap = c.radius - e.distance;
			g.normal           = e.normal;
			g.penetrationDepth = overlap;
			g.refR1 = g.refR2  = c.radius;
			g.contactPoint     = e.point - 0.5 * overlap * e.normal;
			g.nodes1           = Vector2i(-1, -1);
			g.nodes2           = Vector2i(c.node1, c.node2);
			g.tri1 = g.tri2 = Vector3i(-1, -1, -1);
			g.u1            = 0;
			g.u2            = e.u;
			g.axis1         = sS.pos;
			g.axis2         = e.onSegment;
			const Vector3r v1 = sS.vel + sS.angVel.cross(g.contactPoint - sS.pos);
			const Vector3r v2 = flex::segmentPointVelocity(e.u, e.onSegment, g.contactPoint, sa->vel, sa->angVel, sb->vel, sb->angVel);
			g.relVel          = v2 - v1;
		}
		flexa::finishGeom(scene, g, own, I.get(), I->getId2(), beaten, nb);
		return true;
	}

} // namespace

bool Ig2_Box_FlexCylinder_FlexContactGeom::go(const shared_ptr<Shape>& cm1, const shared_ptr<Shape>& cm2, const State& sS, const State&,
        const Vector3r& shift2, const bool& force, const shared_ptr<Interaction>& I)
{
	if (scene->isPeriodic) throw std::runtime_error("Ig2_Box_FlexCylinder_FlexContactGeom: periodic scenes are not supported by yade-flex yet.");
	const Box&          box = static_cast<const Box&>(*cm1);
	const FlexCylinder& c   = static_cast<const FlexCylinder&>(*cm2);
	const State *       sa = flexa::stateOf(scene, c.node1), *sb = flexa::stateOf(scene, c.node2);
	flex::SegmentEdge   e;
	if (sa && sb) {
		const Quaternionr q = sS.ori.conjugate();
		e                   = flex::segmentOnBoxEdges(q * (sa->pos - sS.pos), q * (sb->pos - sS.pos), box.extents);
		e.normal            = sS.ori * e.normal;
		e.point             = sS.pos + sS.ori * e.point;
		e.onSegment         = sS.pos + sS.ori * e.onSegment;
	}
	Body::id_t beaten[8];
	int        nb  = 0;
	const bool own = e.valid && c.radius - e.distance > 0 && clumpOwns(scene, flexa::bodyAt(scene, I->getId1()), e.onSegment, e.point, e.distance, beaten, nb);
	return cylinderEdgeGeom(scene, I, sS, c, sa, sb, e, own, force, beaten, nb);
}

bool Ig2_Facet_FlexCylinder_FlexContactGeom::go(const shared_ptr<Shape>&, const shared_ptr<Shape>& cm2, const State& sS, const State&,
        const Vector3r& shift2, const bool& force, const shared_ptr<Interaction>& I)
{
	if (scene->isPeriodic) throw std::runtime_error("Ig2_Facet_FlexCylinder_FlexContactGeom: periodic scenes are not supported by yade-flex yet.");
	const FlexCylinder& c  = static_cast<const FlexCylinder&>(*cm2);
	const State *       sa = flexa::stateOf(scene, c.node1), *sb = flexa::stateOf(scene, c.node2);
	const Body*         cyl = flexa::bodyAt(scene, I->getId2());
	// the cylinder against every facet it is paired with (the surface around this one; the loop
	// does not change the maps it reads), computed from the geometry alone: the edge point of this
	// facet only where no other facet is nearer, one contact per point (kernel/Surface.hpp)
	Vector3r          tri[kMaxFacets][3];
	int               ids[kMaxFacets];
	flex::SegmentEdge edge[kMaxFacets];
	flex::FacetHit    hit[kMaxFacets];
	int               me = -1;
	const int         n  = (sa && sb) ? facetsPairedWith(scene, cyl, I->getId1(), tri, ids, me) : 0;
	flex::SegmentEdge e;
	Body::id_t        beaten[8];
	int               nb  = 0;
	bool              own = false;
	if (me >= 0) {
		flex::segmentOnFacets(sa->pos, sb->pos, c.radius, tri, ids, n, edge, hit);
		e = edge[me];
		if (hit[me].overlap > 0) {
			int got[8];
			own = flex::ownsFacetCluster(hit, n, me, got, nb);
			for (int k = 0; k < nb; ++k)
				beaten[k] = got[k];
		}
	}
	return cylinderEdgeGeom(scene, I, sS, c, sa, sb, e, own, force, beaten, nb);
}

bool Ig2_Facet_FlexNode_FlexContactGeom::go(const shared_ptr<Shape>& cm1, const shared_ptr<Shape>& cm2, const State& sS, const State& sN,
        const Vector3r& shift2, const bool& force, const shared_ptr<Interaction>& I)
{
	if (scene->isPeriodic) throw std::runtime_error("Ig2_Facet_FlexNode_FlexContactGeom: periodic scenes are not supported by yade-flex yet.");
	const Facet& f = static_cast<const Facet&>(*cm1);
	Vector3r     v[3];
	facetVertices(f, sS, v);
	const auto where = [&](bool isNew, const Vector3r& prev, Real) {
		return flex::nodeOnTriangle(sN.pos, v[0], v[1], v[2], keptSide(isNew, prev, facetNormal(v)));
	};
	// one contact per point of the facet surface: among the node's facet pairs (its other
	// interactions: the loop does not change the maps it reads), computed from the geometry alone
	const auto owns = [&](const flex::SurfacePoint& sp, Real r, Body::id_t* beaten, int& nb) {
		nb                  = 0;
		const Body* nodeB   = flexa::bodyAt(scene, I->getId2());
		const Body* surface = flexa::bodyAt(scene, I->getId1());
		if (!nodeB || !surface) return true;
		constexpr int  kMax = 64;
		flex::FacetHit hit[kMax];
		int            n = 0, self = -1;
		for (const auto& kv : nodeB->intrs) {
			if (n == kMax) break;
			const Body* b = flexa::bodyAt(scene, kv.first);
			if (!b || !b->shape) continue;
			const Facet* of = flexa::fastCast<Facet>(b->shape.get());
			if (!of) continue;
			hit[n] = facetHit(*b, *of, sN.pos, r);
			if (b->id == surface->id) {
				self = n;
				// a node pushed past the facet's plane: its own contact's overlap
				if (!(hit[n].overlap > 0)) hit[n].overlap = r - sp.distance;
			}
			if (hit[n].overlap > 0 || b->id == surface->id) ++n;
		}
		if (self < 0) return true;
		int ids[8];
		const bool o = flex::ownsFacetCluster(hit, n, self, ids, nb);
		for (int k = 0; k < nb; ++k)
			beaten[k] = ids[k];
		return o;
	};
	return nodeGeom(scene, I, sS, static_cast<const FlexNode&>(*cm2), sN, force, where, owns);
}

namespace {
	// A rigid surface (side 1) against a membrane facet (side 2) at the surface's edge or vertex
	// (kernel/Surface.hpp, TriangleEdge), as an element pair of flexa::elementGeom. where(x):
	// the surface's contact with the membrane (x: its nodes' positions) in the world frame;
	// rimOwns(e, beaten, nb): the surface's side of the ownership (a surface of facets).
	template <class Where, class RimOwns, class Apart> struct SurfaceMembrane {
		Scene*             scene;
		const Interaction& I;
		const State&       sS;
		const FlexFacet&   fa;
		Where              where;
		RimOwns            rimOwns;
		Apart              apartFrom; // apartFrom(x): a conservative separation test (a new pair only)
		flexa::FacetNodes  fn;
		flex::TriangleEdge e;
		// the contacts this one may take over (flexa::takeOverPairShear: surface id, membrane id):
		// this surface with the membrane's beaten neighbours, the beaten surfaces with this
		// membrane, and with those neighbours
		std::pair<Body::id_t, Body::id_t> pairs[8];
		int                               nPairs = 0;
		bool               bonded() const { return false; }
		bool               apart() const { return apartFrom(fn.x); }
		bool               load() { return fn.load(scene, fa, Vector3r::Zero()); }
		Real               closest()
		{
			e = where(fn.x);
			return e.valid ? fa.radius - e.distance : Real(-1);
		}
		flex::PointTriangle onMembrane() const
		{
			flex::PointTriangle pt;
			pt.point   = e.onTriangle;
			pt.support = e.triSupport;
			for (int k = 0; k < 3; ++k)
				pt.w[k] = e.w[k];
			return pt;
		}
		bool owns(Real)
		{
			Body::id_t rim[8], other[8];
			int        nRim = 0, nOther = 0;
			if (!rimOwns(e, rim, nRim)) return false;
			const flexa::Element self = flexa::elementOf(&fa);
			// (self's contact with the probe arithmetic the neighbours are compared with: its surface point, radius 0)
			const flex::Hit hit = flex::probe(flexa::passMesh(scene), self, e.point, 0);
			if (!(hit.overlap > 0) || !flexa::owns(scene, self, I.getId2(), e.point, 0, hit, other, nOther)) return false;
			nPairs = 0;
			for (int k = 0; k < nOther && nPairs < 8; ++k)
				pairs[nPairs++] = { I.getId1(), other[k] };
			for (int j = 0; j < nRim && nPairs < 8; ++j) {
				pairs[nPairs++] = { rim[j], I.getId2() };
				for (int k = 0; k < nOther && nPairs < 8; ++k)
					pairs[nPairs++] = { rim[j], other[k] };
			}
			return true;
		}
		void fill(FlexContactGeom& g, bool isNew)
		{
			if (!e.valid) return; // the contact has passed to a node at the same overlap, or apart: as it was
			const flex::PointTriangle pt = onMembrane();
			Real                      dist;
			g.normal           = flexa::facetNormal(fn, pt, e.point, sS.pos, isNew, g.normal, dist);
			g.penetrationDepth = fa.radius - dist;
			g.pierced          = e.pierced;
			g.refR1 = g.refR2  = fa.radius;
			g.contactPoint     = e.point - 0.5 * g.penetrationDepth * g.normal;
			g.nodes1 = g.nodes2 = Vector2i(-1, -1);
			g.tri1              = Vector3i(-1, -1, -1);
			g.tri2              = Vector3i(fa.node1, fa.node2, fa.node3);
			g.bary2             = Vector3r(e.w[0], e.w[1], e.w[2]);
			g.u1 = g.u2         = 0;
			g.axis1             = sS.pos;
			g.axis2             = e.onTriangle;
			const Vector3r v1   = sS.vel + sS.angVel.cross(g.contactPoint - sS.pos);
			const Vector3r v2   = flex::trianglePointVelocity(fn.x, fn.v, e.w, flex::cappedFacetOffset(fn.x, g.contactPoint - e.onTriangle));
			g.relVel            = v2 - v1;
		}
		void finish(FlexContactGeom& g, bool own) { flexa::finishGeom(scene, g, own, &I, I.getId2(), nullptr, 0, pairs, nPairs); }
	};
	template <class Where, class RimOwns, class Apart>
	SurfaceMembrane<Where, RimOwns, Apart>
	surfaceMembrane(Scene* scene, const Interaction& I, const State& sS, const FlexFacet& fa, Where where, RimOwns rimOwns, Apart apart)
	{
		return SurfaceMembrane<Where, RimOwns, Apart> { scene, I, sS, fa, where, rimOwns, apart };
	}
} // namespace

bool Ig2_Box_FlexFacet_FlexContactGeom::go(const shared_ptr<Shape>& cm1, const shared_ptr<Shape>& cm2, const State& sS, const State&,
        const Vector3r& shift2, const bool& force, const shared_ptr<Interaction>& I)
{
	if (scene->isPeriodic) throw std::runtime_error("Ig2_Box_FlexFacet_FlexContactGeom: periodic scenes are not supported by yade-flex yet.");
	const Box& box   = static_cast<const Box&>(*cm1);
	const auto where = [&](const Vector3r* x) {
		const Quaternionr  q = sS.ori.conjugate();
		flex::TriangleEdge e = flex::boxEdgesOnTriangle(q * (x[0] - sS.pos), q * (x[1] - sS.pos), q * (x[2] - sS.pos), box.extents);
		e.point              = sS.pos + sS.ori * e.point;
		e.onTriangle         = sS.pos + sS.ori * e.onTriangle;
		e.normal             = sS.ori * e.normal;
		return e;
	};
	const auto inClump = [&](const flex::TriangleEdge& e, Body::id_t* beaten, int& nb) {
		return clumpOwns(scene, flexa::bodyAt(scene, I->getId1()), e.onTriangle, e.point, e.distance, beaten, nb);
	};
	const FlexFacet& fa    = static_cast<const FlexFacet&>(*cm2);
	const auto       apart = [&](const Vector3r* x) {
                const Quaternionr q = sS.ori.conjugate();
                return flex::membraneApartFromBox(q * (x[0] - sS.pos), q * (x[1] - sS.pos), q * (x[2] - sS.pos), box.extents, fa.radius);
	};
	auto p = surfaceMembrane(scene, *I, sS, fa, where, inClump, apart);
	return flexa::elementGeom(scene, I, force, p);
}

bool Ig2_Facet_FlexFacet_FlexContactGeom::go(const shared_ptr<Shape>& cm1, const shared_ptr<Shape>& cm2, const State& sS, const State&,
        const Vector3r& shift2, const bool& force, const shared_ptr<Interaction>& I)
{
	if (scene->isPeriodic) throw std::runtime_error("Ig2_Facet_FlexFacet_FlexContactGeom: periodic scenes are not supported by yade-flex yet.");
	const FlexFacet& fa       = static_cast<const FlexFacet&>(*cm2);
	const Body*      membrane = flexa::bodyAt(scene, I->getId2());
	// the membrane against every facet it is paired with (the surface around this one), from the
	// geometry alone: this facet's edge point only where no other facet is nearer, one contact per
	// point (kernel/Surface.hpp)
	Vector3r           tri[kMaxFacets][3];
	int                ids[kMaxFacets];
	flex::TriangleEdge edge[kMaxFacets];
	flex::FacetHit     hit[kMaxFacets];
	int                me = -1, n = 0;
	const auto         where = [&](const Vector3r* x) { // (after the separation test of a new pair)
                n = facetsPairedWith(scene, membrane, I->getId1(), tri, ids, me);
                if (me < 0) return flex::TriangleEdge();
		flex::membraneOnFacets(x[0], x[1], x[2], fa.radius, tri, ids, n, edge, hit);
		return edge[me];
	};
	const auto rimOwns = [&](const flex::TriangleEdge&, Body::id_t* beaten, int& nb) {
		nb = 0;
		if (me < 0 || !(hit[me].overlap > 0)) return false;
		int        got[8];
		const bool o = flex::ownsFacetCluster(hit, n, me, got, nb);
		for (int k = 0; k < nb; ++k)
			beaten[k] = got[k];
		return o;
	};
	Vector3r v[3];
	facetVertices(static_cast<const Facet&>(*cm1), sS, v);
	const auto apart = [&](const Vector3r* x) { return flex::membraneApartFromTriangle(x[0], x[1], x[2], v[0], v[1], v[2], fa.radius); };
	auto       p     = surfaceMembrane(scene, *I, sS, fa, where, rimOwns, apart);
	return flexa::elementGeom(scene, I, force, p);
}

namespace flexa {
	namespace {
		enum class SurfaceKind { none, wall, box, facet, other };
		SurfaceKind kindOf(const Shape* sh)
		{
			if (!sh) return SurfaceKind::none;
			if (fastCast<Sphere>(sh) || fastCast<FlexNode>(sh) || elementOf(sh).nNodes) return SurfaceKind::none;
			if (fastCast<Wall>(sh)) return SurfaceKind::wall;
			if (fastCast<Box>(sh)) return SurfaceKind::box;
			if (fastCast<Facet>(sh)) return SurfaceKind::facet;
			return SurfaceKind::other;
		}
	} // namespace

	long addSurfaceNodePairs(Scene* scene)
	{
		SurfacePairsMemo& m      = sceneState(scene).surfacePairs;
		const long        runs   = insertionSortColliderRuns(scene);
		const long        bodies = (long)scene->bodies->size();
		const bool        same   = m.filled && m.bodies == bodies;
		if (same && runs >= 0 && runs == m.runs && m.size == scene->interactions->size()) return 0;
		if (!same) {
			m.surfaces.clear();
			for (const auto& b : *scene->bodies)
				if (b) {
					const SurfaceKind k = kindOf(b->shape.get());
					if (k == SurfaceKind::wall || k == SurfaceKind::box || k == SurfaceKind::facet) m.surfaces.push_back(b->id);
				}
		}
		std::vector<std::pair<Body::id_t, Body::id_t>> want;
		std::vector<shared_ptr<Interaction>>           stale;
		for (Body::id_t sid : m.surfaces) {
			const Body* s = bodyAt(scene, sid);
			if (!s) continue;
			const bool sFixed = cannotMove(*s);
			const auto first  = want.size();
			for (const auto& kv : s->intrs) {
				const Body* b = bodyAt(scene, kv.first);
				if (!b) continue;
				const Element e = elementOf(b->shape.get());
				for (int k = 0; k < e.nNodes; ++k) {
					const Body* nb = bodyAt(scene, e.nodes[k]);
					if (nb && !(sFixed && cannotMove(*nb))) want.emplace_back(sid, e.nodes[k]);
				}
			}
			std::sort(want.begin() + first, want.end());
			want.erase(std::unique(want.begin() + first, want.end()), want.end());
			for (const auto& kv : s->intrs) {
				const Body* b = bodyAt(scene, kv.first);
				if (!b || !fastCast<FlexNode>(b->shape.get()) || kv.second->isReal()) continue;
				if (!std::binary_search(want.begin() + first, want.end(), std::make_pair(sid, kv.first))) stale.push_back(kv.second);
			}
		}
		long made = 0;
		for (const auto& I : stale) // (an erasure moves the last interaction to its place: linIx read now)
			scene->interactions->erase(I->getId1(), I->getId2(), I->linIx);
		for (const auto& p : want)
			if (!scene->interactions->found(p.first, p.second)) {
				const shared_ptr<Interaction> I(new Interaction(p.first, p.second));
				I->iterLastSeen = scene->iter; // (as the collider marks the pairs it sees)
				scene->interactions->insert(I);
				++made;
			}
		m.filled    = true;
		m.runs      = runs;
		m.bodies    = bodies;
		m.size      = scene->interactions->size();
		return made;
	}

	void checkSurfaceSupport(const Scene* scene)
	{
		const Body* element = nullptr;
		const Body* surface[3] { nullptr, nullptr, nullptr };
		bool membranes = false;
		for (const auto& b : *scene->bodies)
			if (b && b->shape && elementOf(b->shape.get()).nNodes) {
				if (!element) element = b.get();
				if (fastCast<FlexFacet>(b->shape.get())) {
					membranes = true;
					break;
				}
			}
		if (!element) return;
		const InteractionLoop* loop = nullptr;
		for (const auto& e : scene->engines)
			if ((loop = dynamic_cast<const InteractionLoop*>(e.get()))) break;
		const auto has = [&](const char* name) {
			if (!loop || !loop->geomDispatcher) return false;
			for (const auto& f : loop->geomDispatcher->functors)
				if (f && f->getClassName() == name) return true;
			return false;
		};
		const char* names[3] = { "Ig2_Wall_FlexNode_FlexContactGeom", "Ig2_Box_FlexNode_FlexContactGeom", "Ig2_Facet_FlexNode_FlexContactGeom" };
		const char* extra[3] = { nullptr, "Ig2_Box_FlexCylinder_FlexContactGeom", "Ig2_Facet_FlexCylinder_FlexContactGeom" };
		const char* membrane[3] = { nullptr, "Ig2_Box_FlexFacet_FlexContactGeom", "Ig2_Facet_FlexFacet_FlexContactGeom" };
		for (const auto& b : *scene->bodies) {
			if (!b || !b->shape || b->isClump()) continue;
			const SurfaceKind k = kindOf(b->shape.get());
			std::ostringstream os;
			if (k == SurfaceKind::other) {
				os << "body #" << b->id << " is a " << b->shape->getClassName() << ", which yade-flex elements cannot touch (element #" << element->id
				   << " would pass through it): use Wall, Box, Facet or Sphere bodies for what the elements meet";
				throw std::invalid_argument(os.str());
			}
			const int i = k == SurfaceKind::wall ? 0 : k == SurfaceKind::box ? 1 : k == SurfaceKind::facet ? 2 : -1;
			if (i < 0 || surface[i]) continue;
			surface[i] = b.get();
			for (const char* name : { names[i], extra[i], membranes ? membrane[i] : nullptr })
				if (name && !has(name)) {
					os << "body #" << b->id << " is a " << b->shape->getClassName() << " and the interaction loop has no " << name << ": element #"
					   << element->id << " would pass through it; use yadeflex.engines(), or add " << name << "() to the loop's geometry functors";
					throw std::invalid_argument(os.str());
				}
		}
	}
} // namespace flexa
} // namespace yade
