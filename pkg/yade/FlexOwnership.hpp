// yade-flex adapter: which element carries a contact, on the scene's bodies, and the shear a
// contact takes over from the one that carried it before (GPL-2.0-or-later). The rule and its
// reasons: kernel/Ownership.hpp.
#pragma once
#include "FlexElements.hpp"
#include "FlexSceneState.hpp"

#include <utility>

namespace yade {
namespace flexa {
	using flex::Hit;
	using flex::segmentHit;
	using flex::triangleHit;

	/// The scene's mesh as the ownership rule reads it: through the table of the interaction
	/// loop's pass while one runs (MeshPass), else through the bodies.
	using PassMesh = flex::TabledMesh<SceneMesh>;
	inline PassMesh passMesh(const Scene* scene)
	{
		const MeshTableMemo& mt = sceneState(scene).meshTable;
		return PassMesh { mt.on ? &mt.table : nullptr, SceneMesh { scene } };
	}

	/// For the life of this object (a pass of the interaction loop, made before its threads start,
	/// in which no body moves, changes or is erased), the ownership tests read the elements and
	/// their nodes from a table filled once here. Which ids it holds is found again when the
	/// number of bodies or of element erasures changed.
	class MeshPass {
		MeshTableMemo& mt;

	public:
		explicit MeshPass(const Scene* scene)
		        : mt(sceneState(scene).meshTable)
		{
			BodyContainer& bodies   = *scene->bodies;
			const long     erasures = sceneState(scene).elementErasures;
			if (!mt.built || mt.bodies != bodies.size() || mt.erasures != erasures) {
				mt.table.clear((long)bodies.size());
				for (const auto& b : bodies) {
					if (!b) continue;
					const Element e = elementOf(b->shape.get());
					if (!e.nNodes) continue;
					mt.table.addElement(b->id);
					for (int k = 0; k < e.nNodes; ++k)
						mt.table.addNode(e.nodes[k]);
				}
				mt.built    = true;
				mt.bodies   = bodies.size();
				mt.erasures = erasures;
			}
			mt.table.refresh(SceneMesh { scene });
			mt.on = mt.table.elements() > 0;
		}
		~MeshPass() { mt.on = false; }
		MeshPass(const MeshPass&)            = delete;
		MeshPass& operator=(const MeshPass&) = delete;
	};

	/// Whether element `self` (body selfId) carries the contact of a probe sphere (P, R) whose
	/// closest point on self is `hit`; if so, the other elements of its cluster are in `beaten`
	/// (at most 8).
	inline bool owns(
	        const Scene* scene, const Element& self, Body::id_t selfId, const Vector3r& P, Real R, const Hit& hit, Body::id_t* beaten, int& nBeaten)
	{
		return flex::owns(passMesh(scene), self, selfId, P, R, hit, beaten, nBeaten);
	}
	/// Whether the element pair (idA, idB) carries its cluster's contact; if so, the other pairs
	/// are in `beaten` (A-side id, B-side id; at most 8). selfHit: the pair's flex::pairHit, where
	/// the caller has it (null: computed).
	inline bool ownsPair(const Scene* scene, Body::id_t idA, const Element& A, Body::id_t idB, const Element& B, std::pair<Body::id_t, Body::id_t>* beaten,
	        int& nBeaten, const flex::PairHit* selfHit = nullptr)
	{
		return flex::ownsPair(passMesh(scene), idA, A, idB, B, beaten, nBeaten, true, selfHit);
	}

	/// A neighbouring contact's geometry and physics, read by another thread's functor while its
	/// own thread may reset it: each pointer is loaded once (a copy of the shared_ptr would read
	/// a pointer and a count that may be changing); the objects stay alive until the end of the
	/// loop (FlexInteractionLoop, Step::Ended).
	inline bool readContact(const Interaction& J, const FlexContactGeom*& jg, const FrictPhys*& jp)
	{
		const IGeom* g = J.geom.get();
		const IPhys* p = J.phys.get();
		if (!g || !p) return false;
		jg = dynamic_cast<const FlexContactGeom*>(g);
		jp = dynamic_cast<const FrictPhys*>(p);
		return jg && jp;
	}

	/// Shear force (on body 2 of I) that one of the `beaten` pairs (A-side id, B-side id; see
	/// ownsPair) carried at the previous step; aIs1: whether I's body 1 is its A-side element.
	inline bool takeOverPairShear(Scene* scene, bool aIs1, const std::pair<Body::id_t, Body::id_t>* beaten, int nBeaten, Vector3r& shear, Real& normal)
	{
		for (int k = 0; k < nBeaten; ++k) {
			const shared_ptr<Interaction> J = scene->interactions->find(beaten[k].first, beaten[k].second);
			if (!J) continue;
			const FlexContactGeom* jg = nullptr;
			const FrictPhys*       jp = nullptr;
			if (!readContact(*J, jg, jp)) continue;
			if (!jg || !jp || jg->lastActiveIter != scene->iter - 1) continue;
			const bool same = (J->getId1() == beaten[k].first) == aIs1;
			shear           = same ? jp->shearForce : Vector3r(-jp->shearForce);
			normal          = jp->normalForce.norm();
			return true;
		}
		return false;
	}
	/// Shear force (on body 2 of I) that the interaction between `otherBody` and one of the
	/// `beaten` neighbours carried at the previous step, expressed for an interaction whose body 1
	/// is id1. Only reads data its owner does not write this step (see FlexContactGeom.hpp).
	inline bool takeOverShear(Scene* scene, Body::id_t otherBody, Body::id_t id1, const Body::id_t* beaten, int nBeaten, Vector3r& shear, Real& normal)
	{
		for (int k = 0; k < nBeaten; ++k) {
			const shared_ptr<Interaction> J = scene->interactions->find(otherBody, beaten[k]);
			if (!J) continue;
			const FlexContactGeom* jg = nullptr;
			const FrictPhys*       jp = nullptr;
			if (!readContact(*J, jg, jp)) continue;
			if (!jg || !jp || jg->lastActiveIter != scene->iter - 1) continue;
			// shear is stored as the force on body 2: flip it if the other body sits on opposite sides
			const bool same = (J->getId1() == otherBody) == (id1 == otherBody);
			shear           = same ? jp->shearForce : Vector3r(-jp->shearForce);
			normal          = jp->normalForce.norm();
			return true;
		}
		return false;
	}
	/// Common tail of every contact geometry functor: activity bookkeeping and shear take-over
	/// (see FlexContactGeom.hpp).
	// Sphere contacts: the elements beaten in the sphere's cluster (their contacts with
	// otherBody). Element-element contacts: the pairs of its cluster (A side = I's body 1; see
	// flexa::ownsPair).
	inline void finishGeom(Scene* scene, FlexContactGeom& g, bool own, const Interaction* I, Body::id_t otherBody, const Body::id_t* beaten, int nb,
	        const std::pair<Body::id_t, Body::id_t>* pairs = nullptr, int nPairs = 0)
	{
		const bool wasActive = g.lastActiveIter == scene->iter - 1;
		g.active             = own;
		g.handover           = false;
		g.onsetDepth         = 0;
		if (!own) return; // lastActiveIter untouched: neighbours may read this interaction now
		if (!wasActive) {
			// a contact (re)starting: it takes over the shear of the neighbour that carried it
			// last step, or starts from zero (separation ends the shear history; never reuse a
			// stale spring, which would bring back energy that was no longer booked)
			Vector3r sh    = Vector3r::Zero();
			Real     fn    = 0;
			bool     found = false;
			if (nPairs)
				found = flexa::takeOverPairShear(scene, true, pairs, nPairs, sh, fn);
			else if (nb)
				found = flexa::takeOverShear(scene, otherBody, I->getId1(), beaten, nb, sh, fn);
			g.handover      = true;
			g.handoverShear = sh;
			// -1: a contact of the scene as built (its first step) with no neighbour handing it
			// over: its overlap is taken as it is (see Law2_FlexContactGeom_FrictPhys_CundallStrack)
			g.handoverNormal = found || scene->iter > 0 ? fn : -1;
			g.onsetDepth    = g.penetrationDepth; // judged by the law (Law2_FlexContactGeom_FrictPhys_CundallStrack.onsetFactor)
		}
		g.lastActiveIter = scene->iter;
	}
} // namespace flexa
} // namespace yade
