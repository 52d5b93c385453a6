// yade-flex adapter: one step of FlexInteractionLoop's prefetching loop, pass by pass
// (GPL-2.0-or-later). Included by FlexLoop.cpp only; why and what: FlexLoop.hpp.
#pragma once
#include "FlexLoop.hpp"
#include "FlexLoopFilters.hpp"
#include "../FlexGrainEngine.hpp"
#include "../FlexProtocol.hpp"
#include "FlexTuning.hpp"

#include <kernel/BlockShares.hpp>

#include <pkg/common/Facet.hpp>
#include <pkg/common/Wall.hpp>
#include <pkg/dem/Ig2_Facet_Sphere_ScGeom.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <typeinfo>
#include <vector>

#ifdef YADE_OPENMP
#include <omp.h>
#endif

namespace yade {
// One step of the prefetching loop: what its passes share, and the passes.
class FlexInteractionLoop::Step {
	using Bodies  = flexa::loop::Bodies;
	using Marked  = flexa::loop::Marked;
	using Apart   = flexa::loop::Apart;
	using Fusable = flexa::loop::Fusable;

public:
	// what the step reads
	FlexInteractionLoop&           L;
	Scene* const                   scene;
	InteractionContainer&          ic;
	const shared_ptr<Interaction>* intrs;
	const long                     n;
	const Bodies                   bodies;
	const Matrix3r                 cellH;
	const long                     block, nBlocks;
	const long                     kFar, kMid, kNear;
	const bool                     streamIn; // (the interaction objects asked for ahead)
	int                            threads = 1;
	// what the step decided before the loop
	bool                                          sameFunctors = false;
	Marked                                        marked;
	Apart                                         apart;
	Fusable                                       fusable;
	Law2_FlexContactGeom_FrictPhys_CundallStrack* fusedLaw = nullptr;
	const SpherePoint*                            pts      = nullptr;
	const SphereMotion*                           mot      = nullptr;
	Remembered*                                   rec      = nullptr;
	unsigned                                      gen[4]   = { 0, 0, 0, 0 }; // by kind
	unsigned                                      genBefore = 0;              // L.genMarkedBefore while the marks hold (markedBefore)
	std::vector<FlexGrainEngine::Gathered>        gathered;                  // (makeSphereTable)
	bool                                          weighted = false;
	std::vector<Real>                             prefix; // prefix[c]: the weight of blocks 0..c-1
	flex::BlockShares                             shares; // the blocks still to run of each thread's share
	int                                           nSums = 0;
	// the first exception of any thread; after it the threads stop calling functors
	std::exception_ptr error;
	std::mutex         errorMutex;
	std::atomic<bool>  failed { false };
	// each thread's interactions reset this step, whose geometry and physics it keeps alive until
	// after the loop (resetEnded): the functors of other threads read neighbouring contacts
	// (flexa::takeOverShear), and InteractionLoop's reset in place would free them under the reader
	struct Ended {
		std::vector<shared_ptr<IGeom>> geoms;
		std::vector<shared_ptr<IPhys>> phys;
	};
	std::vector<Ended> ended;
	// what a thread counts (summed over the threads)
	struct Counts {
		long rejected = 0, candidates = 0, nFusable = 0, nFused = 0, recalled = 0, marked = 0;
	};

	explicit Step(FlexInteractionLoop& loop)
	        : L(loop)
	        , scene(loop.scene)
	        , ic(*loop.scene->interactions)
	        , intrs(&ic[0])
	        , n((long)ic.size())
	        , bodies { scene->bodies->body.data(), (long)scene->bodies->body.size() }
	        , cellH(scene->isPeriodic ? Matrix3r(scene->cell->hSize) : Matrix3r(Matrix3r::Zero()))
	        , block(loop.blockSize)
	        , nBlocks((n + block - 1) / block)
	        , kFar(loop.ahead[0])
	        , kMid(loop.ahead[1])
	        , kNear(loop.ahead[2])
	        , streamIn(n >= flexa::kPrefetchMin)
	{
#ifdef YADE_OPENMP
		threads = L.ompThreads > 0 ? std::min(L.ompThreads, omp_get_max_threads()) : omp_get_max_threads();
#endif
		ended.resize(threads);
	}

	// InteractionLoop's requestErase (the interaction reset in place, at once, as there), its
	// geometry and physics released only after the loop (Ended)
	static void endContact(const shared_ptr<Interaction>& I, Ended& e)
	{
		if (I->geom) e.geoms.push_back(I->geom);
		if (I->phys) e.phys.push_back(I->phys);
		I->reset();
	}
	// after the loop, on one thread: the geometry and physics of the contacts reset during it go
	void releaseEnded()
	{
		for (Ended& e : ended) {
			e.geoms.clear();
			e.phys.clear();
		}
	}

	// the functors that read the marks and the sphere functors, found again only when the
	// dispatcher's list changes
	void findReaders()
	{
		sameFunctors = L.seenFunctors.size() == L.geomDispatcher->functors.size();
		for (size_t k = 0; sameFunctors && k < L.seenFunctors.size(); ++k) {
			const IGeomFunctor* g = L.geomDispatcher->functors[k].get();
			sameFunctors          = L.seenFunctors[k].first == g && g && L.seenFunctors[k].second == &typeid(*g);
		}
		if (!sameFunctors) {
			L.seenFunctors.clear();
			L.markReaders.clear();
			L.sphereReaders.clear();
			L.sideReaders.clear();
			for (const auto& f : L.geomDispatcher->functors) {
				const IGeomFunctor* g = f.get();
				L.seenFunctors.emplace_back(g, g ? &typeid(*g) : nullptr);
				if (flexa::readsUnreachableMarks(g) || flexa::skipsMarkedAsApart(g)) L.markReaders.push_back(g);
				if (g && typeid(*g) == typeid(Ig2_Sphere_Sphere_FlexContactGeom)) L.sphereReaders.push_back(g);
				if (g && (typeid(*g) == typeid(Ig2_Facet_Sphere_ScGeom) || typeid(*g) == typeid(Ig2_Wall_Sphere_ScGeom)))
					L.sideReaders.push_back(g);
			}
		}
		marked = Marked(scene, &L.markReaders);
	}

	// the functors of the fused sphere-sphere path (fuseSpheres), and quickReject's readers
	void chooseShortcuts()
	{
		if (L.fuseSpheres && !L.sphereReaders.empty() && !scene->isPeriodic) {
			for (const auto& f : L.physDispatcher->functors)
				if (f && typeid(*f) == typeid(Ip2_FrictMat_FrictMat_FrictPhys)) {
					fusable.phys = f.get();
					break;
				}
			for (const auto& f : L.lawDispatcher->functors)
				if (f && typeid(*f) == typeid(Law2_FlexContactGeom_FrictPhys_CundallStrack)) {
					fusable.law = f.get();
					break;
				}
			if (fusable.phys && fusable.law) fusable.geoms = &L.sphereReaders;
		}
		fusedLaw = const_cast<Law2_FlexContactGeom_FrictPhys_CundallStrack*>(
		        static_cast<const Law2_FlexContactGeom_FrictPhys_CundallStrack*>(fusable.law));
		// (the sphere functor throws in periodic scenes: not used there; the sides' tests assume no shift)
		if (L.quickReject && !L.sphereReaders.empty() && !scene->isPeriodic) apart.readers = &L.sphereReaders;
		if (L.quickReject && !L.sideReaders.empty() && !scene->isPeriodic) apart.sides = &L.sideReaders;
		if (apart.on() || fusable.geoms) listSpheres();
		apart.sphere  = L.isSphereId.data();
		apart.nIds    = (long)L.isSphereId.size();
		apart.sideIx  = L.sideIx.data();
		apart.nSideIx = (long)L.sideIx.size();
	}

	// the lists of the bodies that are plain Spheres and of the Facets and Walls, again when the
	// scene or the body count changed
	void listSpheres()
	{
		const long nb = bodies.n;
		if (scene == L.sphereIdsScene && nb == L.sphereIdsBodies) return;
		L.sphereIds.clear();
		L.sideIds.clear();
		L.isSphereId.assign(nb, 0);
		L.sideIx.assign(nb, -1);
		L.spherePoints.assign(nb, SpherePoint());
		for (long id = 0; id < nb; ++id) {
			L.spherePoints[id].r = -1;
			const Body* b        = bodies.p[id].get();
			if (!b || !b->shape) continue;
			const std::type_info& t = typeid(*b->shape);
			if (t == typeid(Sphere)) {
				L.sphereIds.push_back((Body::id_t)id);
				L.isSphereId[id] = 1;
			} else if (t == typeid(Facet) || t == typeid(Wall)) {
				L.sideIx[id] = (int)L.sideIds.size();
				L.sideIds.push_back((Body::id_t)id);
			}
		}
		L.sidePoints.resize(L.sideIds.size());
		L.sphereIdsScene  = scene;
		L.sphereIdsBodies = nb;
	}

	// this step's table of sphere centres and radii (quickReject, fuseSpheres) and motion (only
	// for fuseSpheres)
	void makeSphereTable()
	{
		const bool fuse = fusable.geoms && L.lastFusable != 0;
		if (!((apart.on() && L.lastCandidates != 0) || fuse)) return;
		L.spherePoints.resize(bodies.n);
		if (fuse) L.sphereMotion.resize(bodies.n);
		SpherePoint*  p  = L.spherePoints.data();
		SphereMotion* mv = L.sphereMotion.data();
		const long    nb = bodies.n;
		// the listed grains from their engines' arrays
		findGathered();
		const char* listed  = L.isSphereId.data();
		const long  nListed = (long)L.isSphereId.size();
		for (const FlexGrainEngine::Gathered& g : gathered) {
#ifdef YADE_OPENMP
#pragma omp parallel for schedule(static) num_threads(threads) if (g.n >= flexa::tuning::kSphereTableParallelMin)
#endif
			for (long k = 0; k < g.n; ++k) {
				const Body::id_t id = g.ids[k];
				if (id < 0 || id >= nListed || !listed[id]) continue;
				SpherePoint&    q = p[id];
				const Vector3r& x = g.pos[k];
				q.x               = x[0];
				q.y               = x[1];
				q.z               = x[2];
				q.r               = g.radius[k];
				if (!fuse) continue;
				mv[id].vel     = g.vel[k];
				mv[id].angVel  = g.angVel[k];
				mv[id].invMass = g.invMass[k];
			}
		}
		// the other listed bodies (each still checked: erased, or its shape replaced: r = -1)
		const Body::id_t* ids = L.sphereIds.data();
		long              ns  = (long)L.sphereIds.size();
		if (!gathered.empty()) {
			L.otherSphereIds.clear();
			for (long k = 0; k < ns; ++k) {
				const Body::id_t id    = ids[k];
				bool             grain = false;
				for (const FlexGrainEngine::Gathered& g : gathered)
					grain = grain || (id < g.nIds && g.indexOf[id] >= 0);
				if (!grain) L.otherSphereIds.push_back(id);
			}
			ids = L.otherSphereIds.data();
			ns  = (long)L.otherSphereIds.size();
		}
#ifdef YADE_OPENMP
#pragma omp parallel for schedule(static) num_threads(threads) if (ns >= flexa::tuning::kSphereTableParallelMin)
#endif
		for (long k = 0; k < ns; ++k) {
			if (fuse)
				flexa::prefetchBodiesAhead(bodies.p, ids, ns, k, [](const Body& c) { flexa::prefetchSphereParts<Sphere>(c); });
			else
				flexa::prefetchBodiesAhead(bodies.p, ids, ns, k, [](const Body& c) { flexa::prefetchSphereCentre<Sphere>(c); });
			const Body::id_t id = ids[k];
			SpherePoint&     q  = p[id];
			q.r                 = -1;
			const Body* b       = bodies.p[id].get();
			if (!b) continue;
			const Shape* sh = b->shape.get();
			const State* st = b->state.get();
			if (!sh || !st || typeid(*sh) != typeid(Sphere)) continue;
			const Vector3r& x = st->se3.position; // (not pos, a reference read from the State's first line)
			q.x               = x[0];
			q.y               = x[1];
			q.z               = x[2];
			q.r               = static_cast<const Sphere*>(sh)->radius;
			if (!fuse) continue;
			mv[id].vel        = st->vel;
			mv[id].angVel     = st->angVel;
			// (flexa::ContactSide::invMass of a rigid side, for the crossing correction)
			mv[id].invMass = (!b->isDynamic() || (st->blockedDOFs & State::DOF_XYZ) == State::DOF_XYZ || !(st->mass > 0)) ? Real(0) : 1 / st->mass;
		}
		if (apart.on()) {
			apart.p = p;
			apart.n = nb;
		}
		if (apart.sides) makeSideTable();
		if (fuse) {
			fusable.p = p;
			fusable.n = nb;
		}
		pts = fusable.p;
		mot = fusable.p ? L.sphereMotion.data() : nullptr;
	}

	// The grains that the FlexGrainEngines running right before this loop (dead engines aside) read
	// from their bodies at this step (FlexGrainEngine::gatheredAt): their gather reads the same
	// fields as the table and computes the inverse mass alike, and no other engine ran since, so
	// the table takes the same values from their arrays instead of the bodies.
	void findGathered()
	{
		gathered.clear();
		const auto& es = scene->engines;
		long        at = -1;
		for (size_t i = 0; i < es.size() && at < 0; ++i)
			if (es[i].get() == &L) at = (long)i;
		for (long i = at - 1; i >= 0; --i) {
			const Engine* e = es[i].get();
			if (e && e->dead) continue;
			const FlexGrainEngine* ge = dynamic_cast<const FlexGrainEngine*>(e);
			if (!ge) break;
			const FlexGrainEngine::Gathered g = ge->gatheredAt(scene->iter);
			if (g.ids) gathered.push_back(g);
		}
	}

	// this step's planes of the listed Facets and Walls (apart.sides; each still checked: erased, or
	// its shape replaced: kind 0)
	void makeSideTable()
	{
		for (size_t k = 0; k < L.sideIds.size(); ++k) {
			SidePoint&  f = L.sidePoints[k];
			const Body* b = bodies.get(L.sideIds[k]);
			f.kind        = 0;
			if (!b || !b->shape || !b->state) continue;
			const Shape*    sh = b->shape.get();
			const Vector3r& x  = b->state->se3.position;
			for (int i = 0; i < 3; ++i)
				f.x[i] = x[i];
			if (typeid(*sh) == typeid(Facet)) {
				const Matrix3r  R   = b->state->se3.orientation.toRotationMatrix();
				const Vector3r& nl  = static_cast<const Facet*>(sh)->normal;
				const Vector3r  nw  = R * nl;
				Real            sum = 0;
				for (int i = 0; i < 3; ++i) {
					f.n[i] = nw[i];
					for (int j = 0; j < 3; ++j)
						sum += std::abs(R(i, j));
				}
				f.scale = sum * (std::abs(nl[0]) + std::abs(nl[1]) + std::abs(nl[2]));
				f.kind  = 1;
			} else if (typeid(*sh) == typeid(Wall)) {
				const int ax = static_cast<const Wall*>(sh)->axis;
				if (ax < 0 || ax > 2) continue;
				f.axis = ax;
				f.kind = 2;
			}
		}
		apart.side = L.sidePoints.data();
	}

	// rememberSkips: a new generation of records whenever what they were judged against changes.
	// A sphere pair apart (kind 2) depends only on its interaction object (no contact, the sphere
	// functor cached; the table is asked again each step), so its records last until the functors,
	// quickReject, the scene or the container change; a marked pair (kind 1) also on the marks, so
	// its records also end when the marks are made again or retired, or a collider runs.
	void startRecords()
	{
		if (L.rememberSkips) {
			const unsigned long marksGen = marked.valid ? flexa::sceneState(scene).unreachable.generation : 0;
			const bool          quick    = apart.on();
			const bool          newQuick = !sameFunctors || scene != L.recScene || &ic != L.recContainer || quick != L.recQuick;
			const bool          newMarked
			        = newQuick || marked.valid != L.recMarksValid || marksGen != L.recMarks || ic.iterColliderLastRun != L.recColliderRun;
			if (newQuick && (scene != L.recScene || &ic != L.recContainer)) L.held.clear(); // (let the old scene's objects go)
			if (newMarked) {
				const bool wrap = L.recGen > std::numeric_limits<unsigned>::max() - 2;
				if (wrap) { // (no old record may match by chance)
					L.remembered.assign(L.remembered.size(), Remembered());
					L.recGen = 0;
				}
				// only the marks made again (both sets valid): the old marked records are asked
				// against the new marks (markedBefore)
				const bool onlyMarks = !newQuick && !wrap && marked.valid && L.recMarksValid && ic.iterColliderLastRun == L.recColliderRun;
				L.genMarkedBefore    = onlyMarks ? L.genMarked : 0;
				L.genMarked          = ++L.recGen;
				if (newQuick || wrap) L.genQuick = ++L.recGen;
				L.recScene       = scene;
				L.recContainer   = &ic;
				L.recMarksValid  = marked.valid;
				L.recMarks       = marksGen;
				L.recColliderRun = ic.iterColliderLastRun;
				L.recQuick       = quick;
			}
			L.remembered.resize(n);
			L.held.resize(n);
			rec = L.remembered.data();
		} else if (!L.remembered.empty()) {
			L.remembered.clear();
			L.held.clear();
			L.recScene = nullptr;
		}
		gen[1]    = L.genMarked;
		gen[2]    = L.genQuick;
		gen[3]    = L.genQuick;
		genBefore = rec && marked.valid ? L.genMarkedBefore : 0;
	}
	// whether pass 1 can leave out the pair at i from its record alone (kind 1 still asks whether
	// its bodies exist, kind 2 the table)
	const Remembered* recordOf(long i) const
	{
		const Remembered& r = rec[i];
		return (r.kind && r.gen == gen[r.kind] && r.ptr == intrs[i].get()) ? &r : nullptr;
	}
	// A record of a marked pair from the marks before these (genBefore), its object still in its
	// place: the pair was left out on every step since, untouched, so it is still left out if
	// these marks hold it at its place (what marked(J) would find, without reading J).
	const Remembered* markedBefore(long i) const
	{
		if (!genBefore) return nullptr;
		const Remembered& r = rec[i];
		return (r.kind == 1 && r.gen == genBefore && r.ptr == intrs[i].get() && marked.holds(i, r.id1, r.id2)) ? &r : nullptr;
	}
	// whether pass 1 leaves the object at i unread (its record decides, or sends it to pass 2)
	bool unread(long i) const { return rec && (recordOf(i) || markedBefore(i)); }

	// The split of the blocks among the threads: by each block's time on the last step (a block
	// new since then at the mean), because the work is uneven along the container (the contacts
	// of the settled fill first, the pairs made during the impact last, element contacts costing
	// several times a sphere pair). Timings set only which thread sums which forces: the forces
	// are the same up to round-off, as with any split.
	void splitByWeight()
	{
#ifdef YADE_OPENMP
		weighted = threads > 1;
#endif
		if (!weighted) return;
		std::vector<Real>& w = L.blockWeight;
		if ((long)w.size() != nBlocks) { // (a collider run changed the count: new blocks at the mean)
			Real mean = 0;
			for (Real x : w)
				mean += x;
			mean = w.empty() ? 1 : mean / w.size();
			w.resize(nBlocks, mean);
		}
		prefix.resize(nBlocks + 1);
		prefix[0] = 0;
		for (long c = 0; c < nBlocks; ++c)
			prefix[c + 1] = prefix[c] + w[c];
	}
	// the first block of part k of nt (k = nt: nBlocks)
	long blockAtWeight(int k, int nt) const
	{
		if (k <= 0) return 0;
		if (k >= nt) return nBlocks;
		if (!weighted) return nBlocks * k / nt;
		const Real w = prefix[nBlocks] * k / nt;
		return std::lower_bound(prefix.begin(), prefix.end(), w) - prefix.begin();
	}
	// several threads: the yade-flex law's forces into each thread's own sums (flexa::ThreadForceSums)
	void prepareThreadSums()
	{
#ifdef YADE_OPENMP
		if (L.threadSums && threads > 1 && n >= L.threadSumsMin) nSums = threads;
#endif
		if (nSums) L.sums.prepare(nSums, bodies.n);
		L.usedThreadSums = nSums > 0;
	}

	void fail(std::exception_ptr e)
	{
		std::lock_guard<std::mutex> lock(errorMutex);
		if (!error) error = e;
		failed = true;
	}

	// the threads' shares: contiguous runs of blocks of about equal work by the last step's weights
	void makeShares()
	{
		std::vector<long> starts(threads + 1);
		for (int k = 0; k <= threads; ++k)
			starts[k] = blockAtWeight(k, threads);
		shares.reset(starts);
	}

	// One thread's work (flex::BlockShares): its own share, one contiguous run of blocks (handed out
	// one by one, the threads would work on neighbouring blocks and share their cache lines), then
	// blocks left in the others' shares, so that a share that takes longer than on the last step
	// (a collider run, another process on the core) is finished by the threads that are done.
	void runThread(Counts& cnt)
	{
		flexa::ForceSink sink;
		int              tid = 0;
#ifdef YADE_OPENMP
		tid = omp_get_thread_num();
		if (nSums) sink = L.sums.sink(tid);
#endif
		flexa::ForceSinkScope sinkScope(nSums ? &sink : nullptr);
		long                  live[flexa::tuning::kMaxBlock];
		bool                  fused[flexa::tuning::kMaxBlock]; // the fused path (fuseSpheres)
		shares.run(
		        tid,
		        [&](long c) {
			        const auto blockStart = weighted ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point();
			        const long lo = c * block, hi = std::min(n, lo + block);
			        const int  nLive = listLive(lo, hi, live, fused, cnt);
			        runLive(live, fused, nLive, ended[tid]);
			        if (weighted) // this block's time, for the next step's split
				        L.blockWeight[c] = std::chrono::duration<Real>(std::chrono::steady_clock::now() - blockStart).count();
		        },
		        [&]() { return failed.load(std::memory_order_relaxed); });
	}

	// Pass 1: the block's interaction objects [lo, hi) (streamed in, kFar ahead), and which of
	// them are left (not marked unreachable, not apart), in their order, into live; fused[j]: the
	// fused path. The objects are asked for kFar READ objects ahead: those a record leaves out are
	// neither asked for nor counted. pf: the next place to consider; ahead: the objects asked for
	// at places in (i, pf).
	int listLive(long lo, long hi, long* live, bool* fused, Counts& cnt)
	{
		int  nLive = 0;
		long pf = lo, ahead = 0;
		auto stream = [&]() {
			for (; ahead < kFar && pf < hi; ++pf)
				if (!unread(pf)) {
					flexa::prefetch(intrs[pf].get(), sizeof(Interaction));
					++ahead;
				}
		};
		if (streamIn) stream();
		for (long i = lo; i < hi; ++i) {
			if (rec && genBefore)
				if (const Remembered* r = markedBefore(i))
					if (bodies.get(r->id1) && bodies.get(r->id2)) {
						rec[i].gen = gen[1]; // (a record of these marks now)
						++cnt.recalled;
						++cnt.marked;
						continue;
					}
			if (rec)
				if (const Remembered* r = recordOf(i)) {
					if (r->kind == 1) {
						if (bodies.get(r->id1) && bodies.get(r->id2)) {
							++cnt.recalled;
							++cnt.marked;
							continue;
						}
					} else if (apart.p) { // kinds 2 and 3: what apart(J) would find, from the ids
						++cnt.candidates;
						if ((r->kind == 2 ? apart.byIds(r->id1, r->id2) : apart.sideByIds(r->id1, r->id2)) == r->kind) {
							++cnt.rejected;
							++cnt.recalled;
							continue;
						}
						// the bodies close: to pass 2 (no contact yet, so not fusable), and read
						// again on the next step
						rec[i].kind   = 0;
						fused[nLive]  = false;
						live[nLive++] = i;
						continue;
					}
				}
			if (streamIn) {
				if (i < pf && !unread(i)) --ahead; // (this one was asked for)
				stream();
			}
			// (a pair whose body vanished goes to the full path, which erases it as InteractionLoop does)
			const Interaction& J = *intrs[i];
			if (marked(J) && bodies.get(J.getId1()) && bodies.get(J.getId2())) {
				++cnt.marked;
				if (rec) remember(i, J, 1);
				continue;
			}
			if (const int a = apart(J)) {
				++cnt.candidates;
				if (a >= 2) {
					++cnt.rejected;
					if (rec) remember(i, J, (unsigned char)a);
					continue;
				}
			}
			if (rec) rec[i].kind = 0;
			const int fz = fusable(J);
			cnt.nFusable += fz > 0;
			cnt.nFused += fz == 2;
			fused[nLive]  = fz == 2;
			live[nLive++] = i;
		}
		return nLive;
	}
	// remember the pair at i, left out without its bodies (rememberSkips)
	void remember(long i, const Interaction& J, unsigned char kind)
	{
		Remembered& r = rec[i];
		r.ptr         = &J;
		r.id1         = J.getId1();
		r.id2         = J.getId2();
		r.gen         = gen[kind];
		r.kind        = kind;
		if (L.held[i].get() != &J) L.held[i] = intrs[i];
	}

	// Pass 2: the live ones, with their bodies, geom and phys asked for kMid live interactions
	// ahead and the bodies' states and shapes kNear ahead (a fused contact reads only its geom and
	// phys, and the tables).
	void runLive(const long* live, const bool* fused, int nLive, Ended& e)
	{
		for (int j = 0; j < std::min(nLive, (int)kMid); ++j)
			flexa::loop::fetchTargets(intrs[live[j]].get(), bodies, fused[j]);
		for (int j = 0; j < std::min(nLive, (int)kNear); ++j)
			if (!fused[j]) flexa::loop::fetchStates(intrs[live[j]].get(), bodies);
		for (int j = 0; j < nLive && !failed; ++j) {
			if (j + kMid < nLive) flexa::loop::fetchTargets(intrs[live[j + kMid]].get(), bodies, fused[j + kMid]);
			if (j + kNear < nLive && !fused[j + kNear]) flexa::loop::fetchStates(intrs[live[j + kNear]].get(), bodies);
			try {
				if (fused[j])
					runFused(intrs[live[j]], e);
				else
					runFunctors(intrs[live[j]], e);
			} catch (...) {
				fail(std::current_exception());
			}
		}
	}
	// what the functors do for a fused contact (Fusable): the geometry's update, the physics
	// functor returns at once, the law; shift2 is zero (not periodic)
	void runFused(const shared_ptr<Interaction>& I, Ended& e)
	{
		const Body::id_t   i1 = I->getId1(), i2 = I->getId2();
		const SpherePoint &a = pts[i1], &b = pts[i2];
		FlexContactGeom&   g = static_cast<FlexContactGeom&>(*I->geom);
		Ig2_Sphere_Sphere_FlexContactGeom::update(scene, g, false, a.r, b.r, Vector3r(a.x, a.y, a.z),
		        Vector3r(Vector3r(b.x, b.y, b.z) + Vector3r::Zero()), mot[i1].vel, mot[i1].angVel, mot[i2].vel, mot[i2].angVel);
		const Law2_FlexContactGeom_FrictPhys_CundallStrack::KnownSpheres known { &mot[i1].angVel, &mot[i2].angVel, mot[i1].invMass, mot[i2].invMass };
		if (!fusedLaw->apply(g, static_cast<FrictPhys&>(*I->phys), i1, i2, &known)) endContact(I, e);
	}
	// the geometry, physics and law functors of one interaction, as InteractionLoop calls them
	void runFunctors(const shared_ptr<Interaction>& I, Ended& e)
	{
		Body* b1_ = bodies.get(I->getId1());
		Body* b2_ = bodies.get(I->getId2());
		if (!b1_ || !b2_) {
			endContact(I, e); // a body vanished
			return;
		}
#ifdef YADE_MPI
		if (scene->subdomain != b1_->subdomain && scene->subdomain != b2_->subdomain) {
			endContact(I, e);
			return;
		}
#endif
		if (b1_->isClump() || b2_->isClump()) return;
		if (!I->functorCache.geomExists) return; // no Ig2 functor for this pair of shapes
		if (!b1_->shape || !b2_->shape) return;
		bool swap = false;
		if (!I->functorCache.geom) {
			I->functorCache.geom = L.geomDispatcher->getFunctor2D(b1_->shape, b2_->shape, swap);
			if (!I->functorCache.geom) {
				I->functorCache.geomExists = false;
				return;
			}
		}
		// the functor takes the bodies in its own order: the interaction is swapped once (its
		// geom and phys do not exist yet), as InteractionLoop does
		if (swap) I->swapOrder();
		Body* const    b1      = swap ? b2_ : b1_;
		Body* const    b2      = swap ? b1_ : b2_;
		const bool     wasReal = I->isReal();
		const Vector3r shift2  = scene->isPeriodic ? Vector3r(cellH * I->cellDist.cast<Real>()) : Vector3r(Vector3r::Zero());
		if (!I->functorCache.geom->go(b1->shape, b2->shape, *b1->state, *b2->state, shift2, /*force*/ false, I)) {
			if (wasReal) endContact(I, e); // the geometry ended: the interaction is reset
			return;
		}
		if (!I->functorCache.phys) {
			bool swapPhys        = false;
			I->functorCache.phys = L.physDispatcher->getFunctor2D(b1->material, b2->material, swapPhys);
			if (!I->functorCache.phys)
				throw std::runtime_error("FlexInteractionLoop: no Ip2 functor for materials " + b1->material->getClassName() + " and "
				        + b2->material->getClassName() + " (bodies #" + std::to_string(b1->id) + " and #" + std::to_string(b2->id) + ")");
		}
		I->functorCache.phys->go(b1->material, b2->material, I);
		if (!wasReal) I->iterMadeReal = scene->iter;
		if (!I->functorCache.constLaw) {
			bool swapLaw             = false;
			I->functorCache.constLaw = L.lawDispatcher->getFunctor2D(I->geom, I->phys, swapLaw);
			if (!I->functorCache.constLaw)
				throw std::runtime_error("FlexInteractionLoop: no Law2 functor for " + I->geom->getClassName() + " and "
				        + I->phys->getClassName() + " (bodies #" + std::to_string(b1->id) + " and #" + std::to_string(b2->id) + ")");
		}
		if (!I->functorCache.constLaw->go(I->geom, I->phys, I.get())) endContact(I, e);
	}
};

} // namespace yade
