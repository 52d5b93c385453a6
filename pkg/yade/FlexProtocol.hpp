// yade-flex adapter: what the engines hand to each other between and within steps
// (GPL-2.0-or-later).
//
// The engines of a yade-flex scene run in this order (yadeflex.engines() builds it):
//
//   ForceResetter, InsertionSortCollider, FlexInteractionLoop (the Ig2 functors and the law),
//   FlexElementEngine, FlexTimeStepper, FlexNewtonIntegrator
//
// and share data besides the scene, all of it in the scene's flexa::SceneState (FlexSceneState.hpp:
// each member with its writer, readers and lifetime). What each hand-over is for:
//
// 1. Neighbour pairs (SceneState::neighbourPairs): the bounds of two elements sharing a node always
//    overlap, so the insertion-sort collider never re-creates such a pair once erased (until it
//    re-initialises): bonded neighbours cost nothing per step. The Ig2 functors report them during
//    the loop; FlexElementEngine erases them after it.
//
// 2. Unreachable marks (SceneState::unreachable): a potential pair that cannot touch before the
//    collider runs again needs no distance computation; the estimate that proves it is the one
//    that bounds the step the integrator takes next (FlexTimeStepper marks, the functors and
//    FlexInteractionLoop read, the collider's next run retires them).
//
// 3. Element erasures (SceneState::elementErasures): FlexNewtonIntegrator rebuilds its node table
//    of the collider trigger when an element ruptured.
//
// 4. The vouched step (SceneState::vouched): the scene check needs no full pass after a step whose
//    states the integrator's fast path vouched for.
//
// The order matters for 1 (the list is consumed after the loop that fills it) and for the step
// estimate (FlexTimeStepper sets the dt the integrator uses in the same step, from the forces and
// contacts of this step's loop, and marks pairs against the positions the integrator moves next).
// checkEngineOrder refuses other orders with an error that names the engines.
#pragma once
#include "Flex.hpp"
#include "FlexSceneState.hpp"

#include <mutex>
#include <utility>
#include <vector>

namespace yade {
class InsertionSortCollider;

namespace flexa {
	// ---- 1. neighbour pairs
	inline void reportNeighbourPair(const Scene* scene, Body::id_t a, Body::id_t b)
	{
		NeighbourPairs&             np = sceneState(scene).neighbourPairs;
		std::lock_guard<std::mutex> lock(np.m);
		np.pairs.emplace_back(a, b);
	}

	// ---- 2. unreachable marks
	/// Whether the mark at index i (pairs[0..n), UnreachableMarks::pair of valid marks) is the pair
	/// of bodies id1 and id2, in either order.
	inline bool markMatches(const IdPair* pairs, size_t n, long i, Body::id_t id1, Body::id_t id2)
	{
		if (i < 0 || (size_t)i >= n) return false;
		const IdPair& p = pairs[i];
		return (p.first == id1 && p.second == id2) || (p.first == id2 && p.second == id1);
	}
	/// Whether the mark at I's index is I's pair.
	inline bool markMatches(const IdPair* pairs, size_t n, const Interaction& I) { return markMatches(pairs, n, I.linIx, I.getId1(), I.getId2()); }
	inline bool markedUnreachable(const Scene* scene, const Interaction& I)
	{
		const UnreachableMarks& m = sceneState(scene).unreachable;
		return m.valid(scene) && markMatches(m.pair.data(), m.pair.size(), I);
	}
	/// Whether this geometry functor skips marked pairs itself (returns false first thing when
	/// `!I->geom && !force && markedUnreachable(scene, *I)`, see FlexFunctors.cpp): the exact
	/// classes, a subclass might override go() without that test. FlexInteractionLoop leaves such
	/// pairs out before reading their bodies; keep this list and the functors in step.
	bool readsUnreachableMarks(const IGeomFunctor* f);
	/// Whether this geometry functor (YADE's own) returns false, changing nothing, for a pair
	/// without geometry whose shapes do not touch: FlexInteractionLoop may then leave out such a
	/// pair while it is marked, as it does for the readers above (Ig2_Facet_Sphere_ScGeom: its
	/// sphere farther than its radius from the facet's triangle; the exact class).
	bool skipsMarkedAsApart(const IGeomFunctor* f);
	/// Whether a body stays where it is unless a script moves it: not dynamic, no velocity.
	inline bool standsStill(const Body& b) { return !b.isDynamic() && b.state && b.state->vel == Vector3r::Zero() && b.state->angVel == Vector3r::Zero(); }
	/// Whether every body of `ids` still stands (standsStill; a body gone does not).
	bool allStandStill(const Scene* scene, const std::vector<Body::id_t>& ids);
	/// Whether the marks hold on this step for the loop: valid, and each body they take as
	/// standing still still stands (one test per such body, once per step).
	bool marksHold(const Scene* scene);

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
