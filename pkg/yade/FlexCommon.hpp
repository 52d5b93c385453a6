// Helpers shared by the adapter translation units (not part of the Python API).
#pragma once
#include "Flex.hpp"

#include <kernel/Beam.hpp>
#include <kernel/ClosestPoints.hpp>
#include <kernel/Contact.hpp>
#include <kernel/TimeStep.hpp>

#include <cmath>
#include <mutex>
#include <type_traits>
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

	inline flex::BeamSection section(const FlexMat& m, Real radius)
	{
		return flex::BeamSection::circular(m.young, m.young / (2 * (1 + m.beamPoisson)), radius, m.bendingFactor);
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
	/// Live FlexCylinder shape of body id, or nullptr.
	inline FlexCylinder* cylinderOf(const Scene* scene, Body::id_t id)
	{
		if (id < 0 || id >= (Body::id_t)scene->bodies->size()) return nullptr;
		const shared_ptr<Body>& b = (*scene->bodies)[id];
		if (!b || !b->shape) return nullptr;
		return dynamic_cast<FlexCylinder*>(b->shape.get());
	}
	inline const State* stateOf(const Scene* scene, Body::id_t id)
	{
		if (id < 0 || id >= (Body::id_t)scene->bodies->size()) return nullptr;
		const shared_ptr<Body>& b = (*scene->bodies)[id];
		return b ? b->state.get() : nullptr;
	}
	inline bool shareNode(const FlexCylinder& a, const FlexCylinder& b)
	{
		return a.node1 == b.node1 || a.node1 == b.node2 || a.node2 == b.node1 || a.node2 == b.node2;
	}
	/// Overlap of a probe sphere (centre P, radius R) with cylinder c, from its nodes' states.
	inline Real probeOverlap(const Scene* scene, const FlexCylinder& c, const Vector3r& P, Real R)
	{
		const State *s1 = stateOf(scene, c.node1), *s2 = stateOf(scene, c.node2);
		if (!s1 || !s2) return -std::numeric_limits<Real>::infinity();
		const flex::PointSegment ps = flex::closestPointOnSegment(P, s1->pos, s2->pos);
		return R + c.radius - (P - ps.point).norm();
	}
	/// Two contacts of one probe on elements sharing a node are the SAME contact when one of
	/// their closest points is that node (the cap region of a chain), or when their normals are
	/// within 15 degrees (the concave side of a nearly straight chain: the contact patches
	/// merge). Otherwise they are distinct contacts and both count: a sphere resting on a net
	/// cell touches its four wires, a sphere in a sharp kink touches both legs.
	constexpr Real kMergeCos = 0.96592582628906831; // cos(15 deg)

	/// Ownership test of element `self` (body id selfId) for a probe (P, R) whose closest point
	/// on self is at axis parameter selfU, with overlap `own`: false if an element sharing a
	/// node has the same contact (see above) with a larger overlap (ties: lower id wins).
	/// Neighbours that self beats are appended to `beaten` (at most 8 kept).
	inline bool owns(const Scene* scene, const FlexCylinder& self, Body::id_t selfId, const Vector3r& P, Real R, Real own, Real selfU, const Vector3r& selfPoint,
	                 Body::id_t* beaten, int& nBeaten)
	{
		nBeaten              = 0;
		const Vector3r nSelf = (P - selfPoint).normalized();
		for (int end = 0; end < 2; ++end) {
			const int               shared = end ? self.node2 : self.node1;
			const bool              selfAtNode = end ? (selfU >= 1) : (selfU <= 0);
			const shared_ptr<Body>& nb     = Body::byId(shared, const_cast<Scene*>(scene));
			if (!nb) continue;
			const FlexNode* node = static_cast<const FlexNode*>(nb->shape.get());
			for (int other : node->elements) {
				if (other == selfId) continue;
				const FlexCylinder* oc = cylinderOf(scene, other);
				if (!oc) continue;
				const State *s1 = stateOf(scene, oc->node1), *s2 = stateOf(scene, oc->node2);
				if (!s1 || !s2) continue;
				const flex::PointSegment ps = flex::closestPointOnSegment(P, s1->pos, s2->pos);
				const Real               d  = R + oc->radius - (P - ps.point).norm();
				if (d <= 0) continue;
				const bool otherAtNode = (oc->node1 == shared) ? (ps.u <= 0) : (ps.u >= 1);
				const bool same        = selfAtNode || otherAtNode || nSelf.dot((P - ps.point).normalized()) > kMergeCos;
				if (!same) continue;
				if (d > own || (d == own && other < selfId)) return false;
				if (nBeaten < 8) beaten[nBeaten++] = other;
			}
		}
		return true;
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
