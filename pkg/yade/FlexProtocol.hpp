// yade-flex adapter: what the engines hand to each other between and within steps
// (GPL-2.0-or-later).
//
// The engines of a yade-flex scene run in this order (yadeflex.engines() builds it):
//
//   ForceResetter, InsertionSortCollider, FlexInteractionLoop (the Ig2 functors and the law),
//   FlexElementEngine, FlexTimeStepper, FlexNewtonIntegrator
//
// and share three pieces of data besides the scene. Each is written by one engine and read by
// others, and lives as long as stated:
//
// 1. Neighbour pairs (NeighbourPairs). Writer: the Ig2 functors of element pairs, from the
//    interaction loop, concurrently (under the mutex). Reader: FlexElementEngine, after the loop
//    of the same step, which erases these potential interactions and clears the list. Lifetime:
//    one step; a report of another scene is dropped. Why: the bounds of two elements sharing a
//    node always overlap, so the insertion-sort collider never re-creates such a pair once erased
//    (until it re-initialises): bonded neighbours cost nothing per step.
//
// 2. Unreachable marks (UnreachableMarks). Writer: FlexTimeStepper (a serial engine), when it
//    estimates the step. Readers: the geometry functors and FlexInteractionLoop, on the next
//    steps, concurrently. Lifetime: until the InsertionSortCollider runs again (the marks keep
//    the collider and its run count at marking; a run retires them all at once). Why: a potential
//    pair that cannot touch before the collider runs again needs no distance computation; the
//    estimate that proves it is the one that bounds the step the integrator takes next.
//
// 3. Element erasures (elementErasures). Writer: FlexElementEngine, when an element ruptures.
//    Reader: FlexNewtonIntegrator, which rebuilds its node table of the collider trigger when
//    the count changed. Lifetime: the process (a counter that only grows).
//
// The order matters for 1 (the list is consumed after the loop that fills it) and for the step
// estimate (FlexTimeStepper sets the dt the integrator uses in the same step, from the forces and
// contacts of this step's loop, and marks pairs against the positions the integrator moves next).
// checkEngineOrder refuses other orders with an error that names the engines.
#pragma once
#include "Flex.hpp"

#include <boost/weak_ptr.hpp>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

namespace yade {
class InsertionSortCollider;

namespace flexa {
	// ---- 1. neighbour pairs
	struct NeighbourPairs {
		std::mutex                                     m;
		const Scene*                                   scene = nullptr;
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

	/// Whether p has the owner w was made from: an object told apart from one allocated later at
	/// its address (w keeps the owner, not the object, from being reused).
	template <class T> inline bool sameOwner(const boost::weak_ptr<T>& w, const shared_ptr<T>& p) { return p && !w.owner_before(p) && !p.owner_before(w); }

	// ---- 2. unreachable marks
	/// A mark is the pair's ids at its index in the interaction container (an interaction moved
	/// by an erase no longer matches and is simply tested).
	struct UnreachableMarks {
		const Scene*                                   scene = nullptr;         // null: no marks
		boost::weak_ptr<InteractionContainer>          interactions;            // the container they index
		std::vector<std::pair<Body::id_t, Body::id_t>> pair;                    // by Interaction::linIx; (-1, -1): none
		unsigned long                                  generation = 0;          // one more at each new set of marks
		boost::weak_ptr<Engine>                        collider;                // the InsertionSortCollider whose runs retire them
		const int*                                     runs          = nullptr; // its run count (InsertionSortCollider::numAction)
		int                                            runsAtMarking = -1;
		size_t                                         colliderIx    = 0; // its place in the scene's engine list
		/// Whether the marks hold for scene s: made for it, its collider still the one in its engine
		/// list (O.engines replaced: the new list's collider has its own bounds, and the old one's
		/// count would never move again), and that collider has not run since (its count is read
		/// only then: the list holds it). A scene loaded later (O.load, O.loadTmp, O.reset) may be
		/// allocated where the marked one was: the container and the collider are compared by
		/// their shared owner, which the weak references keep from being reused (they keep neither
		/// object alive: released with their scene, under Python's lock, as before).
		bool valid(const Scene* s) const
		{
			return scene == s && sameOwner(interactions, s->interactions) && colliderIx < s->engines.size()
			        && sameOwner(collider, s->engines[colliderIx]) && runs && *runs == runsAtMarking;
		}
	};
	inline UnreachableMarks& unreachableMarks()
	{
		static UnreachableMarks* m = new UnreachableMarks; // (never destroyed: no engine released after YADE's own teardown)
		return *m;
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
		const UnreachableMarks& m = unreachableMarks();
		return m.valid(scene) && markMatches(m.pair.data(), m.pair.size(), I);
	}
	/// Whether this geometry functor skips marked pairs itself (returns false first thing when
	/// `!I->geom && !force && markedUnreachable(scene, *I)`, see FlexFunctors.cpp): the exact
	/// classes, a subclass might override go() without that test. FlexInteractionLoop leaves such
	/// pairs out before reading their bodies; keep this list and the functors in step.
	bool readsUnreachableMarks(const IGeomFunctor* f);

	// ---- 3. element erasures
	inline long& elementErasures()
	{
		static long n = 0;
		return n;
	}

	// ---- 4. states the integrator vouches for
	/// FlexNewtonIntegrator's fast path refuses a position, velocity or angular velocity it makes
	/// non-finite; it records here the scene and iteration of each step it did so for every body
	/// it moves. The scene check reads it: a step after a vouched one starts from states that only
	/// a script (or an engine after the integrator) can have spoiled since.
	struct VouchedStep {
		const Scene* scene = nullptr;
		long         iter  = -1;
	};
	inline VouchedStep& vouchedStep()
	{
		thread_local VouchedStep v; // (a step's engines run in one thread; O.run's thread is new each call)
		return v;
	}

	// ---- the collider and the order
	/// How many times the scene's InsertionSortCollider (the last one in O.engines) has run (-1:
	/// the scene has none): bounds and potential interactions change only when it runs.
	long insertionSortColliderRuns(const Scene* scene);
	/// The scene's InsertionSortCollider (the last one in O.engines), or null.
	shared_ptr<Engine> insertionSortCollider(const Scene* scene);
	/// Throws std::invalid_argument naming the engines when the yade-flex engines of the scene
	/// are not in the order above (engines absent from the list are not required). Checked again
	/// only when the engine list changes.
	void checkEngineOrder(const Scene* scene);
	/// Whether a periodic engine other than yade-flex's (a PyRunner, a recorder, a DomainLimiter:
	/// the engines that run scripts, nested in ParallelEngine too) has run at an iteration >= `iter`,
	/// or the engine list is not the one of the last call (true then: anything may have changed).
	bool foreignEngineRanSince(const Scene* scene, long iter);
} // namespace flexa
} // namespace yade
