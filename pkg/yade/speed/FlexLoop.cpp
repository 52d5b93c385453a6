// yade-flex adapter: FlexInteractionLoop (GPL-2.0-or-later). Why and what: FlexLoop.hpp.
#include "FlexLoop.hpp"
#include "FlexLoopCompaction.hpp"
#include "FlexLoopFilters.hpp"
#include "FlexLoopStep.hpp"
#include "../FlexOwnership.hpp"
#include "../FlexProtocol.hpp"
#include "../FlexSceneState.hpp"
#include "FlexTuning.hpp"
#include "../FlexSceneCheck.hpp"
#include "../FlexSurfaces.hpp"
#include "../FlexTimeStepper.hpp"

#include <lib/factory/ClassFactory.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <new>
#include <stdexcept>
#include <string>
#include <typeinfo>

#ifdef YADE_OPENMP
#include <omp.h>
#endif

namespace yade {

YADE_PLUGIN((FlexInteractionLoop));

using namespace flexa::loop;

void flexa::mergeThreadSums(Scene* scene, ThreadForceSums& sums, int threads, long from, long to)
{
	const long n = sums.f.empty() ? 0 : (long)sums.f[0].size();
	if (n == 0) return;
	ForceContainer& fc = scene->forces;
	fc.addMaxId((Body::id_t)n - 1); // so that sync() sizes the sums to every body
	fc.sync();
	std::vector<Vector3r>*f = sums.f.data(), *t = sums.t.data();
	const long            lo = std::max(from, 0L), hi = to < 0 ? n : std::min(to, n);
#ifdef YADE_OPENMP
#pragma omp parallel for schedule(static) num_threads(threads)
#endif
	for (long id = lo; id < hi; ++id) {
		Vector3r F = f[0][id], T = t[0][id];
		f[0][id] = Vector3r::Zero();
		t[0][id] = Vector3r::Zero();
		for (int k = 1; k < threads; ++k) {
			F += f[k][id];
			T += t[k][id];
			f[k][id] = Vector3r::Zero();
			t[k][id] = Vector3r::Zero();
		}
		if (F != Vector3r::Zero()) fc.addForceUnsynced((Body::id_t)id, F);
		if (T != Vector3r::Zero()) fc.addTorqueUnsynced((Body::id_t)id, T);
	}
}

void flexa::deferEnergy(Scene* scene, Real val, const char* name, int& ix, bool reset)
{
	DeferredEnergies&           d = sceneState(scene).deferred;
	std::lock_guard<std::mutex> lock(d.m);
	d.terms.push_back(DeferredEnergies::Term { name, &ix, reset, val });
}

void flexa::bookDeferredEnergies(Scene* scene)
{
	DeferredEnergies&           d = sceneState(scene).deferred;
	std::lock_guard<std::mutex> lock(d.m);
	for (const DeferredEnergies::Term& t : d.terms) {
		if (*t.ix < 0) scene->energy->findId(t.name, *t.ix, t.reset);
		scene->energy->energies.add(*t.ix, t.val);
	}
	d.terms.clear();
}

namespace {
	// On a step the collider ran (it retires the marks of the pairs that cannot touch before it
	// runs again), the first FlexTimeStepper after this loop in O.engines makes them now, from the
	// positions its estimate at the end of the step will see, so that this step leaves those pairs
	// out too (FlexTimeStepper.marksBeforeLoop).
	void marksFirst(Scene* scene, const Engine* loop)
	{
		if (flexa::sceneState(scene).unreachable.valid(scene)) return;
		const auto& E  = scene->engines;
		size_t      me = E.size();
		for (size_t k = 0; k < E.size(); ++k) {
			if (E[k].get() == loop)
				me = k;
			else if (me < E.size() && E[k] && !E[k]->dead)
				if (FlexTimeStepper* st = dynamic_cast<FlexTimeStepper*>(E[k].get())) {
					st->markBeforeLoop(me);
					return;
				}
		}
	}
} // namespace

// Whether this step needs InteractionLoop's own loop (and runs it): callbacks, sorted
// interactions, the collider's removal of unseen interactions, settings out of range.
bool FlexInteractionLoop::fallBack()
{
	InteractionContainer& ic = *scene->interactions;
	// the collider asks for unseen potential interactions to go on this step (some colliders only)
	const bool removeUnseen = ic.iterColliderLastRun >= 0 && ic.iterColliderLastRun == scene->iter;
	if (prefetch && !removeUnseen && callbacks.empty() && !loopOnSortedInteractions && blockSize >= 1 && blockSize <= kMaxBlock && ahead[0] >= ahead[1]
	        && ahead[1] >= ahead[2] && ahead[2] >= 1)
		return false;
	usedFastPath    = false;
	usedThreadSums  = false;
	quickRejected   = 0;
	quickCandidates = 0;
	fusedContacts   = 0;
	recalledSkips   = 0;
	markedSkips     = 0;
	lastCandidates  = -1;
	lastFusable     = -1;
	recScene        = nullptr; // (InteractionLoop may give any pair a geometry: the records start again)
#ifdef YADE_OPENMP
	// on one thread: InteractionLoop frees the geometry of a contact that ends while the functors
	// of other threads may read it (flexa::takeOverShear; the fast path keeps it alive, Step::Ended)
	const int nt = omp_get_max_threads();
	omp_set_num_threads(1);
	try {
		InteractionLoop::action();
	} catch (...) {
		omp_set_num_threads(nt);
		throw;
	}
	omp_set_num_threads(nt);
#else
	InteractionLoop::action();
#endif
	return true;
}

void FlexInteractionLoop::action()
{
	flexa::checkScene(scene, this);
	flexa::addSurfaceNodePairs(scene); // (the collider does not pair nodes: FlexSurfaces.hpp)
	if (fallBack()) return;
	marksFirst(scene, this);
	usedFastPath          = true;
	lawDispatcher->scene  = scene;
	physDispatcher->scene = scene;
	geomDispatcher->scene = scene;
	geomDispatcher->updateScenePtr();
	physDispatcher->updateScenePtr();
	lawDispatcher->updateScenePtr();
	quickRejected   = 0;
	quickCandidates = 0;
	fusedContacts   = 0;
	recalledSkips   = 0;
	markedSkips     = 0;
	if (scene->interactions->size() == 0) {
		lastCandidates = 0;
		lastFusable    = 0;
		usedThreadSums = false;
		return;
	}
	Step step(*this);
	if (compactEvery > 0 && (scene->iter - lastCompact >= compactEvery || scene->iter < lastCompact)) {
		compactedContacts = compactContacts(&(*scene->interactions)[0], (long)scene->interactions->size(), step.threads, compactedBlocks);
		lastCompact       = scene->iter;
	}
	step.findReaders();
	step.chooseShortcuts();
	step.makeSphereTable();
	step.startRecords();
	step.splitByWeight();
	step.makeShares();
	step.prepareThreadSums();
	const flexa::MeshPass meshPass(scene); // (nothing moves until the threads end)
	long                  rejected = 0, candidates = 0, nFusable = 0, nFused = 0, recalled = 0, nMarked = 0;
#ifdef YADE_OPENMP
#pragma omp parallel num_threads(step.threads) reduction(+ : rejected, candidates, nFusable, nFused, recalled, nMarked)
#endif
	{
		Step::Counts cnt;
		step.runThread(cnt);
		rejected += cnt.rejected;
		candidates += cnt.candidates;
		nFusable += cnt.nFusable;
		nFused += cnt.nFused;
		recalled += cnt.recalled;
		nMarked += cnt.marked;
	}
	step.releaseEnded();
	flexa::bookDeferredEnergies(scene);
	if (step.nSums) flexa::mergeThreadSums(scene, sums, step.nSums); // (also after an error: the forces added so far stay, as in InteractionLoop)
	quickRejected   = rejected;
	quickCandidates = candidates;
	fusedContacts   = nFused;
	recalledSkips   = recalled;
	markedSkips     = nMarked;
	lastFusable     = step.fusable.geoms ? nFusable : -1;
	lastCandidates  = step.apart.on() ? candidates : -1; // (not counted: count on the next step)
	if (step.error) std::rethrow_exception(step.error);
}

} // namespace yade
