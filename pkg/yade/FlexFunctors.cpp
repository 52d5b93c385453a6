// yade-flex adapter: contact geometry and contact law (GPL-2.0-or-later).
// The numerics are in pkg/kernel; this file unpacks YADE state, calls them, writes back.
#include "FlexContactSide.hpp"
#include "FlexElementGeom.hpp"
#include "FlexOwnership.hpp"
#include "FlexProtocol.hpp"
#include <kernel/ClosestPoints.hpp>
#include <kernel/Contact.hpp>
#include <kernel/Crossing.hpp>
#include <kernel/Crushing.hpp>
#include <kernel/Onset.hpp>
#include <kernel/Triangle.hpp>

#include <lib/factory/ClassFactory.hpp>

namespace yade {

YADE_PLUGIN((
        Ig2_Sphere_FlexCylinder_FlexContactGeom)(Ig2_FlexCylinder_FlexCylinder_FlexContactGeom)(Ig2_Sphere_FlexFacet_FlexContactGeom)(Ig2_FlexCylinder_FlexFacet_FlexContactGeom)(Ig2_FlexFacet_FlexFacet_FlexContactGeom)(Ig2_Sphere_Sphere_FlexContactGeom)(Law2_FlexContactGeom_FrictPhys_CundallStrack));

namespace {
	// One more deep onset or ending and its spring energy (rare: one lock per event)
	void tally(long& count, Real& energy, Real e)
	{
#ifdef YADE_OPENMP
#pragma omp critical(flexDeepOnset)
#endif
		{
			++count;
			energy += e;
		}
	}

} // namespace

namespace {
	using flexa::elementGeom;
	using flexa::FacetNodes;
	using flexa::facetNormal;

	// A sphere (side 1) and an element (side 2): ownership among the elements the sphere touches.
	struct SphereSide {
		Scene*             scene;
		const Interaction& I;
		const State&       st1;
		Real               R;
		Vector3r           P;
		Body::id_t         beaten[8];
		int                nb = 0;
		bool               bonded() const { return false; }
		bool               apart() const { return false; }
		void               finish(FlexContactGeom& g, bool own) { flexa::finishGeom(scene, g, own, &I, I.getId1(), beaten, nb); }
		Vector3r           velocityAt(const Vector3r& c) const { return st1.vel + st1.angVel.cross(c - P); }
	};
	// Two elements: one decision per cluster of element pairs.
	struct ElementPair {
		Scene*                            scene;
		const Interaction&                I;
		std::pair<Body::id_t, Body::id_t> beaten[8];
		int                               nPairs = 0;
		void                              finish(FlexContactGeom& g, bool own) { flexa::finishGeom(scene, g, own, &I, -1, nullptr, 0, beaten, nPairs); }
		bool                              ownsPair(const flexa::Element& A, const flexa::Element& B, const flex::PairHit* self = nullptr)
		{
			return flexa::ownsPair(scene, I.getId1(), A, I.getId2(), B, beaten, nPairs, self);
		}
	};

	struct SphereCylinder : SphereSide {
		const FlexCylinder& cyl;
		const Vector3r&     shift2;
		const State *       sa = nullptr, *sb = nullptr;
		Vector3r            xa, xb;
		flex::PointSegment  ps;
		bool                load()
		{
			sa = flexa::stateOf(scene, cyl.node1);
			sb = flexa::stateOf(scene, cyl.node2);
			if (!sa || !sb) return false;
			xa = sa->pos + shift2;
			xb = sb->pos + shift2;
			return true;
		}
		Real closest()
		{
			ps = flex::closestPointOnSegment(P, xa, xb);
			return R + cyl.radius - (P - ps.point).norm();
		}
		// `overlap` is bit-identical to what a neighbour's test computes for this element (same
		// closest-point call on the same node positions: shift2 is zero, periodic cells are refused)
		bool owns(Real overlap)
		{
			const flexa::Element self = flexa::elementOf(&cyl);
			return flexa::owns(scene, self, I.getId2(), P, R, flexa::segmentHit(self, ps, overlap), beaten, nb);
		}
		void fill(FlexContactGeom& g, bool isNew)
		{
			const Real overlap = R + cyl.radius - (P - ps.point).norm();
			g.normal           = flex::contactNormal(P, ps.point, Vector3r::Zero(), xb - xa, isNew ? Vector3r::Zero() : g.normal);
			g.penetrationDepth = overlap;
			g.refR1            = R;
			g.refR2            = cyl.radius;
			g.contactPoint     = P + (R - 0.5 * overlap) * g.normal;
			g.nodes1           = Vector2i(-1, -1);
			g.nodes2           = Vector2i(cyl.node1, cyl.node2);
			g.u1               = 0;
			g.u2               = ps.u;
			g.axis1            = P;
			g.axis2            = ps.point;
			const Vector3r v1  = velocityAt(g.contactPoint);
			const Vector3r v2  = flex::segmentPointVelocity(ps.u, ps.point, g.contactPoint, sa->vel, sa->angVel, sb->vel, sb->angVel);
			g.relVel           = v2 - v1;
		}
	};

	struct CylinderCylinder : ElementPair {
		const FlexCylinder & c1, &c2;
		const Vector3r&      shift2;
		const State *        a0 = nullptr, *a1 = nullptr, *b0 = nullptr, *b1 = nullptr;
		Vector3r             xb0, xb1;
		flex::SegmentSegment ss;
		bool                 bonded() const { return flexa::shareNode(c1, c2); }
		bool                 load()
		{
			a0 = flexa::stateOf(scene, c1.node1);
			a1 = flexa::stateOf(scene, c1.node2);
			b0 = flexa::stateOf(scene, c2.node1);
			b1 = flexa::stateOf(scene, c2.node2);
			if (!a0 || !a1 || !b0 || !b1) return false;
			xb0 = b0->pos + shift2;
			xb1 = b1->pos + shift2;
			return true;
		}
		// (most pairs of a mesh are apart)
		bool apart() const { return flex::segmentsApart(a0->pos, a1->pos, xb0, xb1, c1.radius + c2.radius); }
		Real closest()
		{
			ss = flex::closestPointsSegments(a0->pos, a1->pos, xb0, xb1);
			return c1.radius + c2.radius - (ss.p2 - ss.p1).norm();
		}
		// the pair's hit as the ownership search computes it (flex::pairHit: its separation test,
		// then these closest points: the same call on the same positions, shift2 being zero), where
		// the lower id is body 1; else computed there
		bool owns(Real)
		{
			const flexa::Element A = flexa::elementOf(&c1), B = flexa::elementOf(&c2);
			if (I.getId2() < I.getId1()) return ownsPair(A, B);
			const flex::PairHit self = flex::segmentsApart(a0->pos, a1->pos, xb0, xb1, c1.radius + c2.radius)
			        ? flex::PairHit()
			        : flex::segmentsPairHit(A, B, ss, false);
			return ownsPair(A, B, &self);
		}
		void fill(FlexContactGeom& g, bool isNew)
		{
			const Real overlap = c1.radius + c2.radius - (ss.p2 - ss.p1).norm();
			g.normal           = flex::contactNormal(ss.p1, ss.p2, a1->pos - a0->pos, xb1 - xb0, isNew ? Vector3r::Zero() : g.normal);
			g.penetrationDepth = overlap;
			g.refR1            = c1.radius;
			g.refR2            = c2.radius;
			g.contactPoint     = ss.p1 + (c1.radius - 0.5 * overlap) * g.normal;
			g.nodes1           = Vector2i(c1.node1, c1.node2);
			g.nodes2           = Vector2i(c2.node1, c2.node2);
			g.u1               = ss.s;
			g.u2               = ss.t;
			g.axis1            = ss.p1;
			g.axis2            = ss.p2;
			const Vector3r v1  = flex::segmentPointVelocity(ss.s, ss.p1, g.contactPoint, a0->vel, a0->angVel, a1->vel, a1->angVel);
			const Vector3r v2  = flex::segmentPointVelocity(ss.t, ss.p2, g.contactPoint, b0->vel, b0->angVel, b1->vel, b1->angVel);
			g.relVel           = v2 - v1;
		}
	};

	struct SphereFacet : SphereSide {
		const FlexFacet&    fa;
		const Vector3r&     shift2;
		FacetNodes          fn;
		flex::PointTriangle pt;
		bool                load() { return fn.load(scene, fa, shift2); }
		Real                closest()
		{
			pt = flex::closestPointOnTriangle(P, fn.x[0], fn.x[1], fn.x[2]);
			return R + fa.radius - (P - pt.point).norm(); // for ownership (probe arithmetic)
		}
		bool owns(Real overlap)
		{
			const flexa::Element self = flexa::elementOf(&fa);
			return flexa::owns(scene, self, I.getId2(), P, R, flexa::triangleHit(self, pt, overlap), beaten, nb);
		}
		void fill(FlexContactGeom& g, bool isNew)
		{
			Real dist;
			g.normal           = facetNormal(fn, pt, P, P, isNew, g.normal, dist);
			g.penetrationDepth = R + fa.radius - dist;
			g.refR1            = R;
			g.refR2            = fa.radius;
			g.contactPoint     = P + (R - 0.5 * g.penetrationDepth) * g.normal;
			g.nodes1 = g.nodes2 = Vector2i(-1, -1);
			g.tri1              = Vector3i(-1, -1, -1);
			g.tri2              = Vector3i(fa.node1, fa.node2, fa.node3);
			g.bary2             = Vector3r(pt.w[0], pt.w[1], pt.w[2]);
			g.axis1             = P;
			g.axis2             = pt.point;
			const Vector3r v1   = velocityAt(g.contactPoint);
			const Vector3r v2   = flex::trianglePointVelocity(fn.x, fn.v, pt.w, flex::cappedFacetOffset(fn.x, g.contactPoint - pt.point));
			g.relVel            = v2 - v1;
		}
	};

	struct CylinderFacet : ElementPair {
		const FlexCylinder&   c;
		const FlexFacet&      fa;
		const Vector3r&       shift2;
		const flexa::Element  ec, ef;
		const State *         a0 = nullptr, *a1 = nullptr;
		FacetNodes            fn;
		flex::SegmentTriangle st;
		bool                  bonded() const { return flexa::shareNode(ec, ef); }
		bool                  load()
		{
			a0 = flexa::stateOf(scene, c.node1);
			a1 = flexa::stateOf(scene, c.node2);
			return a0 && a1 && fn.load(scene, fa, shift2);
		}
		// box and plane tests (a mesh wire outside a lining)
		bool apart() const { return flex::segmentTriangleApart(a0->pos, a1->pos, fn.x[0], fn.x[1], fn.x[2], c.radius + fa.radius); }
		Real closest()
		{
			st = flex::closestPointsSegmentTriangle(a0->pos, a1->pos, fn.x[0], fn.x[1], fn.x[2]);
			return c.radius + fa.radius - (st.p1 - st.t.point).norm();
		}
		// (it also settles a facet piercing a wire at a mesh node, where every wire of the node overlaps it)
		// (the pair's hit as for two cylinders: the segment first)
		bool owns(Real)
		{
			const flex::PairHit self = flex::segmentTriangleApart(a0->pos, a1->pos, fn.x[0], fn.x[1], fn.x[2], c.radius + fa.radius)
			        ? flex::PairHit()
			        : flex::segmentTrianglePairHit(ec, ef, st, false);
			return ownsPair(ec, ef, &self);
		}
		void fill(FlexContactGeom& g, bool isNew)
		{
			Real dist;
			g.normal           = facetNormal(fn, st.t, st.p1, 0.5 * (a0->pos + a1->pos), isNew, g.normal, dist);
			g.penetrationDepth = c.radius + fa.radius - dist;
			g.pierced          = st.intersect; // (see FlexContactGeom.pierced)
			g.refR1            = c.radius;
			g.refR2            = fa.radius;
			g.contactPoint     = st.p1 + (c.radius - 0.5 * g.penetrationDepth) * g.normal;
			g.nodes1           = Vector2i(c.node1, c.node2);
			g.nodes2           = Vector2i(-1, -1);
			g.tri1             = Vector3i(-1, -1, -1);
			g.tri2             = Vector3i(fa.node1, fa.node2, fa.node3);
			g.u1               = st.s;
			g.bary2            = Vector3r(st.t.w[0], st.t.w[1], st.t.w[2]);
			g.axis1            = st.p1;
			g.axis2            = st.t.point;
			const Vector3r v1  = flex::segmentPointVelocity(st.s, st.p1, g.contactPoint, a0->vel, a0->angVel, a1->vel, a1->angVel);
			const Vector3r v2  = flex::trianglePointVelocity(fn.x, fn.v, st.t.w, flex::cappedFacetOffset(fn.x, g.contactPoint - st.t.point));
			g.relVel           = v2 - v1;
		}
	};
} // namespace

bool Ig2_Sphere_FlexCylinder_FlexContactGeom::go(const shared_ptr<Shape>& cm1, const shared_ptr<Shape>& cm2, const State& st1, const State&,
        const Vector3r& shift2, const bool& force, const shared_ptr<Interaction>& I)
{
	SphereCylinder p { { scene, *I, st1, static_cast<const Sphere&>(*cm1).radius, st1.pos }, static_cast<const FlexCylinder&>(*cm2), shift2 };
	return elementGeom(scene, I, force, p);
}

bool Ig2_FlexCylinder_FlexCylinder_FlexContactGeom::go(const shared_ptr<Shape>& cm1, const shared_ptr<Shape>& cm2, const State&, const State&,
        const Vector3r& shift2, const bool& force, const shared_ptr<Interaction>& I)
{
	CylinderCylinder p { { scene, *I }, static_cast<const FlexCylinder&>(*cm1), static_cast<const FlexCylinder&>(*cm2), shift2 };
	return elementGeom(scene, I, force, p);
}

bool Ig2_Sphere_FlexFacet_FlexContactGeom::go(const shared_ptr<Shape>& cm1, const shared_ptr<Shape>& cm2, const State& st1, const State&,
        const Vector3r& shift2, const bool& force, const shared_ptr<Interaction>& I)
{
	SphereFacet p { { scene, *I, st1, static_cast<const Sphere&>(*cm1).radius, st1.pos }, static_cast<const FlexFacet&>(*cm2), shift2 };
	return elementGeom(scene, I, force, p);
}

bool Ig2_FlexCylinder_FlexFacet_FlexContactGeom::go(const shared_ptr<Shape>& cm1, const shared_ptr<Shape>& cm2, const State&, const State&,
        const Vector3r& shift2, const bool& force, const shared_ptr<Interaction>& I)
{
	const FlexCylinder& c  = static_cast<const FlexCylinder&>(*cm1);
	const FlexFacet&    fa = static_cast<const FlexFacet&>(*cm2);
	CylinderFacet       p { { scene, *I }, c, fa, shift2, flexa::elementOf(&c), flexa::elementOf(&fa) };
	return elementGeom(scene, I, force, p);
}

bool Ig2_FlexFacet_FlexFacet_FlexContactGeom::go(
        const shared_ptr<Shape>&, const shared_ptr<Shape>&, const State&, const State&, const Vector3r&, const bool&, const shared_ptr<Interaction>& I)
{
	// neighbours or not: no facet-facet contact (see the class doc); switch the pair off now and
	// have FlexElementEngine erase it after the loop
	I->functorCache.geomExists = false;
	flexa::reportNeighbourPair(scene, I->getId1(), I->getId2());
	return false;
}

bool Ig2_Sphere_Sphere_FlexContactGeom::go(const shared_ptr<Shape>& cm1, const shared_ptr<Shape>& cm2, const State& st1, const State& st2,
        const Vector3r& shift2, const bool& force, const shared_ptr<Interaction>& I)
{
	if (!I->geom && !force && flexa::markedUnreachable(scene, *I)) return false; // cannot touch before the collider runs again
	if (scene->isPeriodic) throw std::runtime_error("Ig2_Sphere_Sphere_FlexContactGeom: periodic scenes are not supported by yade-flex yet.");
	const Real     R1 = static_cast<const Sphere&>(*cm1).radius, R2 = static_cast<const Sphere&>(*cm2).radius;
	const Vector3r x2    = st2.pos + shift2;
	const bool     isNew = !I->geom;
	if (isNew && !force && R1 + R2 - (x2 - st1.pos).norm() <= 0) return false; // (the overlap as update computes it)
	if (isNew) I->geom = shared_ptr<FlexContactGeom>(new FlexContactGeom);
	update(scene, static_cast<FlexContactGeom&>(*I->geom), isNew, R1, R2, st1.pos, x2, st1.vel, st1.angVel, st2.vel, st2.angVel);
	return true;
}

void Ig2_Sphere_Sphere_FlexContactGeom::update(Scene* scene, FlexContactGeom& g, bool isNew, Real R1, Real R2, const Vector3r& x1, const Vector3r& x2,
        const Vector3r& vel1, const Vector3r& angVel1, const Vector3r& vel2, const Vector3r& angVel2)
{
	const Vector3r d    = x2 - x1;
	const Real     dist = d.norm(), overlap = R1 + R2 - dist;
	g.normal           = dist > 0 ? Vector3r(d / dist) : (isNew ? Vector3r(Vector3r::UnitZ()) : Vector3r(g.normal));
	g.penetrationDepth = overlap;
	g.refR1            = R1;
	g.refR2            = R2;
	g.contactPoint     = x1 + (R1 - 0.5 * overlap) * g.normal;
	g.axis1            = x1;
	g.axis2            = x2;
	const Vector3r v1  = vel1 + angVel1.cross(g.contactPoint - x1);
	const Vector3r v2  = vel2 + angVel2.cross(g.contactPoint - x2);
	g.relVel           = v2 - v1;
	// no element: the contact is always its own owner (separation ends it, see flexa::finishGeom)
	flexa::finishGeom(scene, g, overlap > 0, nullptr, -1, nullptr, 0);
}

namespace {
	// The crossing correction's state of g: continued from the last step, or started anew (a
	// new contact, one that was not followed last step: inactive while overlapping, or handed
	// over), at overlap d and overlap rate `rate`.
	flex::CrossingState crossingOf(const Scene* scene, const FlexContactGeom& g, Real kn, Real rate)
	{
		if (g.crossIter != scene->iter - 1) return flex::crossingStart(kn, g.penetrationDepth, rate, scene->dt);
		flex::CrossingState st;
		st.prevDepth = g.crossDepth;
		st.prevForce = g.crossForce;
		st.prevRate  = g.crossRate;
		st.defect    = g.crossDefect;
		st.outSteps  = g.crossOut;
		return st;
	}
	void keepCrossing(const Scene* scene, FlexContactGeom& g, const flex::CrossingState& st)
	{
		g.crossIter   = scene->iter;
		g.crossDepth  = st.prevDepth;
		g.crossForce  = st.prevForce;
		g.crossRate   = st.prevRate;
		g.crossDefect = st.defect;
		g.crossOut    = st.outSteps;
	}
	// One step of the correction for contact g (normal spring kn): the extra normal force on
	// side 2, repulsive positive [N]
	Real crossingStep(const Scene* scene, FlexContactGeom& g, Real kn, Body::id_t id1, Body::id_t id2,
	                  const Law2_FlexContactGeom_FrictPhys_CundallStrack::KnownSpheres* known)
	{
		const Real          rate = -g.normal.dot(g.relVel); // d(overlap)/dt
		flex::CrossingState st   = crossingOf(scene, g, kn, rate);
		const Real          c    = flex::crossingStep(st, kn, g.penetrationDepth, rate, scene->dt, [&] {
                        if (known) return known->invMass1 + known->invMass2;
                        return flexa::ContactSide::of(g, 1, id1).invMass(scene) + flexa::ContactSide::of(g, 2, id2).invMass(scene);
                });
		keepCrossing(scene, g, st);
		return c;
	}
} // namespace

bool Law2_FlexContactGeom_FrictPhys_CundallStrack::go(shared_ptr<IGeom>& ig, shared_ptr<IPhys>& ip, Interaction* I)
{
	return apply(static_cast<FlexContactGeom&>(*ig), static_cast<FrictPhys&>(*ip), I->getId1(), I->getId2(), nullptr);
}

void Law2_FlexContactGeom_FrictPhys_CundallStrack::noteOverlap(Real ratio, Body::id_t id1, Body::id_t id2)
{
	Real seen;
#ifdef YADE_OPENMP
#pragma omp atomic read
#endif
	seen = maxOverlapRatio;
	if (ratio <= seen) return; // (almost always: the lock only when the maximum grows)
#ifdef YADE_OPENMP
#pragma omp critical(flexMaxOverlap)
#endif
	if (ratio > maxOverlapRatio) {
		maxOverlapIds = Vector2i(id1, id2);
#ifdef YADE_OPENMP
#pragma omp atomic write
#endif
		maxOverlapRatio = ratio;
	}
}

bool Law2_FlexContactGeom_FrictPhys_CundallStrack::apply(FlexContactGeom& g, FrictPhys& p, Body::id_t id1, Body::id_t id2, const KnownSpheres* known)
{
	const bool track = scene->trackEnergy && p.ks > 0;
	if (!g.active) {
		// Writes nothing to the interaction: a neighbour may take over this contact's shear
		// force this step. Kept one step after its last active step, then erased.
		// Energy: the shear spring's stored energy leaves this contact now. It is booked as
		// dissipated (separation: the Coulomb cone closes as the normal force vanishes); a
		// neighbour taking the shear over books the same amount back (below), so a hand-over
		// nets to zero.
		if (g.lastActiveIter == scene->iter - 1 && track) {
			flexa::addEnergy(scene, 0.5 * p.shearForce.squaredNorm() / p.ks, "flexFriction", frictIx, false);
			const Real kr = rollingK(g, p);
			if (kr > 0) flexa::addEnergy(scene, 0.5 * g.rollMoment.squaredNorm() / kr, "flexRolling", rollIx, false);
		}
		if (g.lastActiveIter == scene->iter - 1 && g.penetrationDepth > 0) { // ended while overlapping (see deepEndings)
			const Real e = flex::normalSpring(p.kn, g.penetrationDepth, g.plasticOverlap, g.pierced).energy;
			tally(deepEndings, deepEndingEnergy, e);
			// its spring leaves with it (kernel/Onset.hpp; p holds its last step's force): lost,
			// unless a neighbour takes its force over and books it back (below)
			if (scene->trackEnergy)
				flexa::addEnergy(scene, g.pierced ? e : flex::releasedEnergy(p.normalForce.norm(), g.penetrationDepth - g.plasticOverlap), "flexHandover",
				                 handIx, false);
		}
		// separated (not handed over): the crossing correction runs on for two steps, its force
		// on the bodies only (the interaction's own data stay as they were, for the neighbours)
		bool crossingOn = false;
		if (crossing && g.crossIter == scene->iter - 1 && g.penetrationDepth <= 0) {
			const Real c = crossingStep(scene, g, p.kn, id1, id2, known);
			if (c != 0) {
				const flexa::ForceSink* sink = flexa::currentSink();
				flexa::ContactSide::of(g, 1, id1).applyForce(scene, sink, g.contactPoint, -c * g.normal);
				flexa::ContactSide::of(g, 2, id2).applyForce(scene, sink, g.contactPoint, c * g.normal);
			}
			crossingOn = !flex::crossingDone(flex::CrossingState { g.crossDepth, g.crossForce, g.crossRate, g.crossDefect, g.crossOut });
		}
		return g.lastActiveIter >= scene->iter - 1 || crossingOn;
	}
	if (g.handover && track) flexa::addEnergy(scene, -0.5 * g.handoverShear.squaredNorm() / p.ks, "flexFriction", frictIx, false);
	// a contact with an element (re)starting deep takes over its predecessor's spring and no more
	// (kernel/Onset.hpp; the offset is plasticOverlap); with no predecessor (a contact held back by
	// a cluster's ownership that now stands alone, one found late) it starts unloaded. A contact
	// that starts from a gap, or one of the scene as built (its first step), starts with none.
	const bool element = g.nodes1[0] >= 0 || g.nodes2[0] >= 0 || g.tri1[0] >= 0 || g.tri2[0] >= 0;
	if (g.handover && element) g.plasticOverlap = 0;
	bool takesOver = false; // a deep onset taking over a neighbour's force
	if (g.onsetDepth > 0) {
		const Real approach = std::max(Real(0), -g.normal.dot(g.relVel)) * scene->dt;
		if (g.onsetDepth > onsetFactor * approach) {
			if (element && g.handoverNormal >= 0) g.plasticOverlap = flex::onsetOffset(p.kn, g.onsetDepth, g.handoverNormal);
			takesOver = element && g.handoverNormal > 0;
			tally(deepOnsets, deepOnsetEnergy, flex::normalSpring(p.kn, g.onsetDepth, g.plasticOverlap, false).energy);
		} else
			g.onsetDepth = 0; // a normal onset
	}
	if (element) g.plasticOverlap = flex::shrinkOffset(g.plasticOverlap, g.penetrationDepth);
	const Real reach = g.refR1 + g.refR2;
	if (reach > 0) noteOverlap(g.penetrationDepth / reach, id1, id2);
	const Vector3r&               n     = g.normal;
	const Vector3r                shear = flex::rotateShear(g.handover ? g.handoverShear : Vector3r(p.shearForce), n);
	const Vector3r                dus   = (g.relVel - n.dot(g.relVel) * n) * scene->dt;
	const flex::FrictionalContact fc { p.kn, p.ks, p.tangensOfFrictionAngle };
	const flex::NormalSpring      spring = flex::normalSpring(p.kn, g.penetrationDepth, element ? g.plasticOverlap : 0, g.pierced);
	// a contact that took over a neighbour's force books back what it brings (kernel/Onset.hpp)
	if (takesOver && scene->trackEnergy) {
		const Real d       = g.penetrationDepth - g.plasticOverlap;
		const Real brought = g.pierced ? spring.energy : flex::takenOverEnergy(spring.force, d, -g.normal.dot(g.relVel), scene->dt);
		flexa::addEnergy(scene, -brought, "flexHandover", handIx, false);
	}
	Real                          Fn     = spring.force, crushWork = 0;
	if (crushingIs50 > 0 && g.nodes1[0] < 0 && g.nodes2[0] < 0 && g.tri1[0] < 0 && g.tri2[0] < 0) { // two spheres
		const Real              limit = flex::pointLoadFailure(2 * std::min(g.refR1, g.refR2), crushingIs50);
		const flex::NormalYield y     = flex::yieldingNormalStep(p.kn, limit, g.penetrationDepth, g.plasticOverlap, p.normalForce.norm());
		Fn                            = y.force;
		g.plasticOverlap              = y.plastic;
		crushWork                     = y.dissipated;
	}
	const flex::FrictionalResult r  = flex::frictionalStepWithNormal(fc, Fn, n, shear, dus);
	p.normalForce                   = r.normalForce;
	p.shearForce                    = r.shearForce;
	// the crossing correction (a linear spring only: not a crushed sphere pair); not part of the
	// normal force the friction and the outputs see
	const Real              cross   = (crossing && crushWork == 0 && g.plasticOverlap == 0 && !g.pierced) ? crossingStep(scene, g, p.kn, id1, id2, known) : 0;
	const Vector3r          F       = r.normalForce + r.shearForce + cross * n; // on side 2
	const flexa::ForceSink* sink    = flexa::currentSink();         // (set by FlexInteractionLoop on several threads)
	flexa::ContactSide::of(g, 1, id1).applyForce(scene, sink, g.contactPoint, -F);
	flexa::ContactSide::of(g, 2, id2).applyForce(scene, sink, g.contactPoint, F);
	Real       rollEnergy = 0;
	const Real kr         = rollingK(g, p);
	if (kr > 0) { // rolling resistance between two spheres (both sides rigid)
		const Vector3r& w1 = known ? *known->angVel1 : Body::byId(id1, scene)->state->angVel;
		const Vector3r& w2 = known ? *known->angVel2 : Body::byId(id2, scene)->state->angVel;
		const Vector3r  dw = w2 - w1;
		const Vector3r           dth  = (dw - n.dot(dw) * n) * scene->dt;
		const Real               Reff = g.refR1 * g.refR2 / (g.refR1 + g.refR2);
		// a contact (re)starting starts with no rolling moment, as with no shear: the moment it
		// had left it when it separated (booked as released above)
		const Vector3r           roll = flex::rotateShear(g.handover ? Vector3r(Vector3r::Zero()) : g.rollMoment, n);
		const flex::CappedSpring rs   = flex::cappedSpringStep(kr, rollingFriction * Reff * r.normalForce.norm(), roll, dth);
		g.rollMoment = rs.value;
		flexa::addTorque(scene, sink, id1, -rs.value);
		flexa::addTorque(scene, sink, id2, rs.value);
		rollEnergy = rs.energy;
		if (scene->trackEnergy && rs.dissipated != 0) flexa::addEnergy(scene, rs.dissipated, "flexRolling", rollIx, false);
	}
	if (scene->trackEnergy) {
		const Real held = g.pierced ? spring.energy : 0; // (pierced: the spring's energy, without a force)
		flexa::addEnergy(scene, r.elasticEnergy + rollEnergy + held, "flexContactElastic", elastIx, /*reset every step*/ true);
		flexa::addEnergy(scene, r.frictionWork, "flexFriction", frictIx, false);
		if (crushWork != 0) flexa::addEnergy(scene, crushWork, "flexCrushing", crushIx, false);
	}
	return true;
}

Real Law2_FlexContactGeom_FrictPhys_CundallStrack::rollingK(const FlexContactGeom& g, const FrictPhys& p) const
{
	if (!(rollingStiffness > 0) || g.nodes1[0] >= 0 || g.nodes2[0] >= 0 || g.tri1[0] >= 0 || g.tri2[0] >= 0) return 0;
	const Real Reff = g.refR1 * g.refR2 / (g.refR1 + g.refR2);
	return rollingStiffness * p.ks * Reff * Reff;
}

} // namespace yade
