// yade-flex adapter: the state the engines of one scene share, one object per scene
// (GPL-2.0-or-later).
//
// The engines and functors of a scene hand each other data between and within steps (the contract
// and the engine order: FlexProtocol.hpp), and the adapters remember what they last saw of the
// scene to skip work that would find nothing new. All of it lives in the scene's SceneState, found
// with flexa::sceneState(scene): one member per piece of data, each with its writer, readers and
// lifetime. A scene loaded, reset or switched to gets its own state (found by its interaction
// container, whose shared owner no later container can have); two scenes never see each other's.
#pragma once
#include "FlexPch.hpp"

#include <kernel/MeshTable.hpp>

#include <boost/weak_ptr.hpp>
#include <atomic>
#include <mutex>
#include <thread>
#include <typeinfo>
#include <utility>
#include <vector>

namespace yade {
class InsertionSortCollider;

namespace flexa {
	using IdPair = std::pair<Body::id_t, Body::id_t>;

	/// Whether p has the owner w was made from: an object told apart from one allocated later at
	/// its address (w keeps the owner, not the object, from being reused).
	template <class T> inline bool sameOwner(const boost::weak_ptr<T>& w, const shared_ptr<T>& p) { return p && !w.owner_before(p) && !p.owner_before(w); }

	/// 1. Neighbour pairs. Writer: the Ig2 functors of element pairs, from the interaction loop,
	/// concurrently (under the mutex). Reader: FlexElementEngine, after the loop of the same step,
	/// which erases these potential interactions and clears the list. Lifetime: one step.
	struct NeighbourPairs {
		std::mutex          m;
		std::vector<IdPair> pairs;
	};

	/// 2. Unreachable marks: a mark is the pair's ids at its index in the interaction container (an
	/// interaction moved by an erase no longer matches and is simply tested). Writer:
	/// FlexTimeStepper (its estimates, and at the start of FlexInteractionLoop on a step the
	/// collider ran). Readers: the geometry functors and FlexInteractionLoop, on the next steps,
	/// concurrently. Lifetime: until the InsertionSortCollider runs again.
	struct UnreachableMarks {
		bool                                  set = false;       // false: no marks
		std::vector<IdPair>                   pair;              // by Interaction::linIx; (-1, -1): none
		unsigned long                         generation = 0;    // one more at each new set of marks
		boost::weak_ptr<Engine>               collider;          // the InsertionSortCollider whose runs retire them
		const int*                            runs          = nullptr; // its run count (InsertionSortCollider::numAction)
		int                                   runsAtMarking = -1;
		size_t                                colliderIx    = 0; // its place in the scene's engine list
		/// Bodies the marks take as standing still (YADE facets that are not dynamic and have no
		/// velocity: flexa::standsStill), which no sweep bounds: FlexInteractionLoop holds the marks
		/// only while each still stands.
		std::vector<Body::id_t> still;
		/// Marks made at the start of a FlexInteractionLoop (FlexTimeStepper::markBeforeLoop) on a
		/// step the collider ran: the iteration, and the loop's place in the engine list. The
		/// estimate at the end of that step sees the same positions and takes them as its own
		/// (-1: the marks were made by an estimate), unless an element was erased since (the
		/// count of element erasures then).
		long   earlyIter     = -1;
		size_t earlyLoopIx   = 0;
		long   earlyErasures = 0;
		/// Whether the marks hold for their scene s: made, its collider still the one in its engine
		/// list (O.engines replaced: the new list's collider has its own bounds, and the old one's
		/// count would never move again), and that collider has not run since (its count is read
		/// only then: the list holds it). The weak reference keeps the collider's owner, not the
		/// collider, from being reused.
		bool valid(const Scene* s) const
		{
			return set && colliderIx < s->engines.size() && sameOwner(collider, s->engines[colliderIx]) && runs && *runs == runsAtMarking;
		}
	};

	/// 3. Element erasures. Writer: FlexElementEngine, when an element ruptures. Reader:
	/// FlexNewtonIntegrator, which rebuilds its node table of the collider trigger when the count
	/// changed. Lifetime: the scene's (a counter that only grows).
	using ElementErasures = long;

	/// 4. The step the integrator vouches for. Writer: FlexNewtonIntegrator, whose fast path refuses
	/// a position, velocity or angular velocity it makes non-finite: the iteration of each step it
	/// did so for every body it moves. Reader: the scene check, on the next step, which then starts
	/// from states that only a script (or an engine after the integrator) can have spoiled.
	struct VouchedStep {
		long iter = -1;
	};

	/// 5. Energy terms first met inside a parallel region. Writers: the contact law, the element
	/// engine, the integrator (flexa::addEnergy, concurrently, under the mutex). Reader:
	/// flexa::bookDeferredEnergies, on one thread, after the region (FlexForces.hpp).
	struct DeferredEnergies {
		struct Term {
			const char* name;
			int*        ix;
			bool        reset;
			Real        val;
		};
		std::mutex        m;
		std::vector<Term> terms; // (a few entries, on the steps a term first appears)
	};

	/// What the adapters last saw of the engine list (FlexProtocol.cpp): each engine's address and
	/// dynamic type, and where the InsertionSortCollider, the periodic and the parallel engines sit
	/// in it. Searched again with dynamic_cast only when the list changed.
	struct EngineListMemo {
		std::vector<std::pair<const Engine*, const std::type_info*>> seen;
		bool                                                         filled       = false;
		const Engine*                                                collider     = nullptr; // (the list holds it)
		bool                                                         orderChecked = false;
		std::vector<size_t>                                          periodic, parallel;
		unsigned long                                                generation = 0; // one more at each change of the list
		unsigned long                                                foreignSeen = 0; // the generation of the last foreignEngineRanSince
		bool                                                         foreignAsked = false;
	};

	/// What the scene check last saw (FlexSceneCheck.cpp), and its per-body tables.
	struct SceneCheckMemo {
		std::thread::id   thread;              // of the last check: O.run's thread is new at each call
		bool              checked  = false;    // false: the next step is checked in full
		long              iter     = -1;       // of the last step checked, in full or not
		const void*       checker  = nullptr;  // the engine that asked for it
		long              fullIter = -1;       // of the last full check
		size_t            bodies   = 0;
		std::vector<char> isNode, isElement;   // per body id, filled by the full pass over the bodies
		struct Element {
			int  nodes[3];
			int  nNodes;
			Real radius;
		};
		std::vector<Element> elements; // per body id, valid where isElement
	};

	/// What the pairing of rigid surfaces with nodes last saw (FlexSurfaces.cpp): the surfaces'
	/// ids, made again when the number of bodies changed.
	struct SurfacePairsMemo {
		bool                    filled = false;
		long                    runs = -2, bodies = -1;
		size_t                  size = 0;
		std::vector<Body::id_t> surfaces;
	};

	/// The mesh as the ownership rule reads it (kernel/MeshTable.hpp), for one pass of the
	/// interaction loop. Writer: FlexInteractionLoop, before its threads start (flexa::MeshPass).
	/// Readers: the contact functors' ownership tests, concurrently, during that pass (`on`).
	/// Lifetime: the pass; which ids it holds, until the bodies change.
	struct MeshTableMemo {
		flex::MeshTable table;
		bool            on       = false;
		bool            built    = false;
		size_t          bodies   = 0;
		long            erasures = -1;
	};

	/// Everything the yade-flex engines of one scene share.
	struct SceneState {
		NeighbourPairs   neighbourPairs;
		UnreachableMarks unreachable;
		ElementErasures  elementErasures = 0;
		VouchedStep      vouched;
		DeferredEnergies deferred;
		EngineListMemo   engineList;
		SceneCheckMemo   check;
		SurfacePairsMemo surfacePairs;
		MeshTableMemo    meshTable;
	};

	/// A scene's state with what tells its scene apart: the scene's address and its interaction
	/// container's owner (a scene loaded later at the same address has another container). Kept
	/// for the life of the process (a few dozen bytes per scene); the state goes with its scene.
	struct SceneEntry {
		const Scene*                          scene = nullptr;
		boost::weak_ptr<InteractionContainer> container;
		SceneState*                           state = nullptr;
	};
	/// The entry of the scene asked for last (null at first), read by every thread.
	extern std::atomic<const SceneEntry*> lastSceneEntry;
	/// sceneState when the scene is not the one asked for last: finds or makes its state.
	SceneState& sceneStateOf(const Scene* scene);

	/// The scene's state, made at the first call for a scene. Any thread may ask, at any time (the
	/// scene asked for last is a load and two comparisons away). States of scenes released are
	/// freed when a new scene asks for its own.
	inline SceneState& sceneState(const Scene* scene)
	{
		const SceneEntry* e = lastSceneEntry.load(std::memory_order_acquire);
		if (e && e->scene == scene && sameOwner(e->container, scene->interactions)) return *e->state;
		return sceneStateOf(scene);
	}
} // namespace flexa
} // namespace yade
