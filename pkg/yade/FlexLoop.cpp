// yade-flex adapter: FlexInteractionLoop (GPL-2.0-or-later). Why and what: FlexLoop.hpp.
#include "FlexLoop.hpp"
#include "FlexProtocol.hpp"
#include "FlexTuning.hpp"
#include "FlexSceneCheck.hpp"

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

namespace {
	using flexa::tuning::kMaxBlock;

	struct Bodies {
		const shared_ptr<Body>* p;
		long                    n;
		Body*                   get(Body::id_t id) const { return (id >= 0 && id < n) ? p[id].get() : nullptr; }
	};

	// What the loop and the contact functors read, whole: the interaction, the bodies (id, flags,
	// shape, state, material, clumpId), their states and shapes, the contact's geom and phys
	// (176, 320, 104, 352 and 104 bytes for Body, State, Sphere, FlexContactGeom, FrictPhys).
	inline void fetchTargets(const Interaction* I, const Bodies& b, bool fused)
	{
		if (!fused) {
			if (Body* b1 = b.get(I->getId1())) flexa::prefetch(b1, sizeof(Body));
			if (Body* b2 = b.get(I->getId2())) flexa::prefetch(b2, sizeof(Body));
		}
		if (const IGeom* g = I->geom.get()) flexa::prefetch(g, sizeof(FlexContactGeom)); // (the largest geom of the module's contacts)
		if (const IPhys* p = I->phys.get()) flexa::prefetch(p, sizeof(FrictPhys));
	}

	// compactEvery: copies of the contacts' geometry and physics objects, side by side in one
	// block of memory in the order of the container (which pass 2 follows). Each copy is released
	// on its own (InBlock runs its destructor), the block with its last copy.
	struct ContactBlock {
		std::unique_ptr<unsigned char[]> mem;
	};
	struct InBlock {
		shared_ptr<ContactBlock> block;
		template <class T> void operator()(T* p) const { p->~T(); }
	};
	constexpr size_t kGeomBytes = (sizeof(FlexContactGeom) + 15) & ~size_t(15), kPhysBytes = (sizeof(FrictPhys) + 15) & ~size_t(15);
	// a yade-flex contact with FrictPhys that nothing but its interaction holds (an object that
	// Python or another interaction also holds stays where it is: they must keep seeing it live)
	inline bool movable(const Interaction& I)
	{
		return I.geom && I.phys && I.geom.use_count() == 1 && I.phys.use_count() == 1 && typeid(*I.geom) == typeid(FlexContactGeom)
		        && typeid(*I.phys) == typeid(FrictPhys);
	}
	long compactContacts(const shared_ptr<Interaction>* intrs, long n)
	{
		long count = 0;
		for (long i = 0; i < n; ++i)
			count += movable(*intrs[i]);
		if (count == 0) return 0;
		const shared_ptr<ContactBlock> block(new ContactBlock);
		block->mem.reset(new unsigned char[(size_t)count * (kGeomBytes + kPhysBytes) + 64]);
		unsigned char* at = reinterpret_cast<unsigned char*>((reinterpret_cast<uintptr_t>(block->mem.get()) + 63) & ~uintptr_t(63));
		for (long i = 0; i < n; ++i) {
			Interaction& I = *intrs[i];
			if (!movable(I)) continue;
			// exact copies (the same values bit for bit); a failed allocation of a shared_ptr's
			// count runs the deleter and leaves the interaction with its old object
			FlexContactGeom* g = new (at) FlexContactGeom(static_cast<const FlexContactGeom&>(*I.geom));
			I.geom             = shared_ptr<IGeom>(g, InBlock { block });
			at += kGeomBytes;
			FrictPhys* p = new (at) FrictPhys(static_cast<const FrictPhys&>(*I.phys));
			I.phys       = shared_ptr<IPhys>(p, InBlock { block });
			at += kPhysBytes;
		}
		return count;
	}

	// The pairs the time stepper marked as unable to touch before the collider runs again
	// (flexa::UnreachableMarks), for the functors that read these marks: such a pair, while it
	// has no geometry, is skipped here before its bodies are touched, which is exactly what
	// happens inside the functor (it returns false first thing) and after it in the loop
	// (nothing for a pair that was not real).
	struct Marked {
		bool                                     valid = false;
		const std::vector<const IGeomFunctor*>*  readers = nullptr; // flexa::readsUnreachableMarks, of this loop's functors
		const std::pair<Body::id_t, Body::id_t>* pairs  = nullptr; // the marks, by Interaction::linIx
		size_t                                   nPairs = 0;
		Marked() = default;
		Marked(const Scene* scene, const std::vector<const IGeomFunctor*>* r)
		        : readers(r)
		{
			const flexa::UnreachableMarks& m = flexa::unreachableMarks();
			valid = m.valid(scene);
			if (valid) {
				pairs  = m.pair.data();
				nPairs = m.pair.size();
			}
		}
		// flexa::markedUnreachable and the functor's membership among the readers, inline, the
		// cheap tests first (it was a call to std::find and one to the marks' accessor per pair;
		// on the wire net, where every pair is marked, the loop took 1.09x less time)
		bool operator()(const Interaction& I) const
		{
			if (!valid || I.geom) return false;
			if (!flexa::markMatches(pairs, nPairs, I)) return false;
			const IGeomFunctor* f = I.functorCache.geom.get();
			for (const IGeomFunctor* g : *readers)
				if (g == f) return true;
			return false;
		}
	};

	// Whether a pair is left out by FlexInteractionLoop.quickReject: no contact yet, the
	// sphere-sphere functor, two plain spheres that are apart. The functor returns false for it
	// first thing (R1 + R2 - |x2 - x1| <= 0 for a new contact), changing nothing; the test here
	// asks for more, |x2 - x1|^2 > (R1 + R2)^2 (1 + 1e-12), so that round-off can never make the
	// two disagree (the pairs in between go to the functor).
	struct Apart {
		const std::vector<const IGeomFunctor*>*   readers = nullptr; // the sphere-sphere functors (null: quickReject off)
		const FlexInteractionLoop::SpherePoint*   p       = nullptr; // this step's table (null: not made)
		long                                      n       = 0;
		// 0: not a candidate; 1: a candidate the table does not leave out (or no table); 2: left out.
		// A candidate: no contact and the sphere-sphere functor, or no functor cached yet (a new
		// pair, which may become one).
		int operator()(const Interaction& I) const
		{
			if (!readers || I.geom || !I.functorCache.geomExists) return 0;
			const IGeomFunctor* f = I.functorCache.geom.get();
			if (!f) return 1;
			if (std::find(readers->begin(), readers->end(), f) == readers->end()) return 0;
			return byIds(I.getId1(), I.getId2());
		}
		// the table's part: 1 or 2 as above, for a candidate of these ids
		int byIds(Body::id_t i1, Body::id_t i2) const
		{
			if (!p) return 1;
			if (i1 < 0 || i2 < 0 || i1 >= n || i2 >= n) return 1;
			const FlexInteractionLoop::SpherePoint &a = p[i1], &b = p[i2];
			if (a.r < 0 || b.r < 0) return 1;
			const Real dx = b.x - a.x, dy = b.y - a.y, dz = b.z - a.z, s = a.r + b.r;
			return dx * dx + dy * dy + dz * dz > s * s * (1 + 1e-12) ? 2 : 1;
		}
	};

	// Whether a contact takes the fused path (fuseSpheres): it exists (geom and phys), and its cached
	// functors are the sphere-sphere geometry, Ip2_FrictMat_FrictMat_FrictPhys (which returns at
	// once when the physics exists) and the yade-flex law, each of exactly that class (a subclass
	// could override go); its bodies are plain spheres in this step's table. The generic path would
	// then call exactly Ig2_Sphere_Sphere_FlexContactGeom::update and the law's apply, on the same
	// values read from the bodies' states and shapes instead of the table.
	struct Fusable {
		const std::vector<const IGeomFunctor*>*   geoms = nullptr; // the sphere-sphere functors (null: fuseSpheres off)
		const IPhysFunctor*                       phys  = nullptr;
		const LawFunctor*                         law   = nullptr;
		const FlexInteractionLoop::SpherePoint*   p     = nullptr; // this step's table (null: not made)
		long                                      n     = 0;
		// 0: not fusable; 1: fusable but not on this step (no table, or a body not a plain sphere); 2: fused
		int operator()(const Interaction& I) const
		{
			if (!geoms || !law || !phys || !I.geom || !I.phys) return 0;
			const auto& c = I.functorCache;
			if (!c.geomExists || c.constLaw.get() != law || c.phys.get() != phys) return 0;
			if (std::find(geoms->begin(), geoms->end(), c.geom.get()) == geoms->end()) return 0;
			if (!p) return 1;
			const Body::id_t i1 = I.getId1(), i2 = I.getId2();
			if (i1 < 0 || i2 < 0 || i1 >= n || i2 >= n || p[i1].r < 0 || p[i2].r < 0) return 1;
			return 2;
		}
	};

	inline void fetchStates(const Interaction* I, const Bodies& b)
	{
		for (Body::id_t id : { I->getId1(), I->getId2() })
			if (const Body* body = b.get(id)) {
				if (const State* s = body->state.get()) flexa::prefetch(s, sizeof(State));
				if (const Shape* sh = body->shape.get()) flexa::prefetch(sh, sizeof(Sphere)); // (the radius is its last field)
			}
	}
}

void flexa::mergeThreadSums(Scene* scene, ThreadForceSums& sums, int threads)
{
	const long n = sums.f.empty() ? 0 : (long)sums.f[0].size();
	if (n == 0) return;
	ForceContainer& fc = scene->forces;
	fc.addMaxId((Body::id_t)n - 1); // so that sync() sizes the sums to every body
	fc.sync();
	std::vector<Vector3r>*f = sums.f.data(), *t = sums.t.data();
#ifdef YADE_OPENMP
#pragma omp parallel for schedule(static) num_threads(threads)
#endif
	for (long id = 0; id < n; ++id) {
		Vector3r F = f[0][id], T = t[0][id];
		f[0][id]   = Vector3r::Zero();
		t[0][id]   = Vector3r::Zero();
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

// One step of the prefetching loop: what its passes share, and the passes.
class FlexInteractionLoop::Step {
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
	unsigned                                      gen[3]   = { 0, 0, 0 }; // by kind
	bool                                          weighted = false;
	std::vector<Real>                             prefix; // prefix[c]: the weight of blocks 0..c-1
	int                                           nSums = 0;
	// the first exception of any thread; after it the threads stop calling functors
	std::exception_ptr error;
	std::mutex         errorMutex;
	std::atomic<bool>  failed { false };
	// what a thread counts (summed over the threads)
	struct Counts {
		long rejected = 0, candidates = 0, nFusable = 0, nFused = 0, recalled = 0;
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
			for (const auto& f : L.geomDispatcher->functors) {
				const IGeomFunctor* g = f.get();
				L.seenFunctors.emplace_back(g, g ? &typeid(*g) : nullptr);
				if (flexa::readsUnreachableMarks(g)) L.markReaders.push_back(g);
				if (g && typeid(*g) == typeid(Ig2_Sphere_Sphere_FlexContactGeom)) L.sphereReaders.push_back(g);
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
		fusedLaw = const_cast<Law2_FlexContactGeom_FrictPhys_CundallStrack*>(static_cast<const Law2_FlexContactGeom_FrictPhys_CundallStrack*>(fusable.law));
		// (the sphere functor throws in periodic scenes: not used there)
		if (L.quickReject && !L.sphereReaders.empty() && !scene->isPeriodic) apart.readers = &L.sphereReaders;
	}

	// this step's table of sphere centres and radii (quickReject) and motion (fuseSpheres)
	void makeSphereTable()
	{
		if (!((apart.readers && L.lastCandidates != 0) || (fusable.geoms && L.lastFusable != 0))) return;
		L.spherePoints.resize(bodies.n);
		L.sphereMotion.resize(bodies.n);
		SpherePoint*  p  = L.spherePoints.data();
		SphereMotion* mv = L.sphereMotion.data();
		const long    nb = bodies.n;
		if (scene != L.sphereIdsScene || nb != L.sphereIdsBodies) { // the list of spheres, again
			L.sphereIds.clear();
			for (long id = 0; id < nb; ++id) {
				p[id].r       = -1;
				const Body* b = bodies.p[id].get();
				if (b && b->shape && typeid(*b->shape) == typeid(Sphere)) L.sphereIds.push_back((Body::id_t)id);
			}
			L.sphereIdsScene  = scene;
			L.sphereIdsBodies = nb;
		}
		// the listed bodies (each still checked: erased, or its shape replaced: r = -1)
		const Body::id_t* ids = L.sphereIds.data();
		const long        ns  = (long)L.sphereIds.size();
#ifdef YADE_OPENMP
#pragma omp parallel for schedule(static) num_threads(threads) if (ns >= flexa::tuning::kSphereTableParallelMin)
#endif
		for (long k = 0; k < ns; ++k) {
			flexa::prefetchBodiesAhead(bodies.p, ids, ns, k, [](const Body& c) { // (of the state, only the lines of pos, vel and angVel)
				if (const State* st = c.state.get()) {
					flexa::prefetch(&st->pos, sizeof(Vector3r));
					flexa::prefetch(&st->vel, sizeof(Vector3r));
					flexa::prefetch(&st->angVel, sizeof(Vector3r));
				}
				flexa::prefetch(c.shape.get(), sizeof(Sphere));
			});
			const Body::id_t id = ids[k];
			SpherePoint&     q  = p[id];
			q.r                 = -1;
			const Body* b       = bodies.p[id].get();
			if (!b) continue;
			const Shape* sh = b->shape.get();
			const State* st = b->state.get();
			if (!sh || !st || typeid(*sh) != typeid(Sphere)) continue;
			q.x           = st->pos[0];
			q.y           = st->pos[1];
			q.z           = st->pos[2];
			q.r           = static_cast<const Sphere*>(sh)->radius;
			mv[id].vel    = st->vel;
			mv[id].angVel = st->angVel;
		}
		if (apart.readers) {
			apart.p = p;
			apart.n = nb;
		}
		if (fusable.geoms) {
			fusable.p = p;
			fusable.n = nb;
		}
		pts = fusable.p;
		mot = fusable.p ? L.sphereMotion.data() : nullptr;
	}

	// rememberSkips: a new generation of records whenever what they were judged against changes.
	// A sphere pair apart (kind 2) depends only on its interaction object (no contact, the sphere
	// functor cached; the table is asked again each step), so its records last until the functors,
	// quickReject, the scene or the container change; a marked pair (kind 1) also on the marks, so
	// its records also end when the marks are made again or retired, or a collider runs.
	void startRecords()
	{
		if (L.rememberSkips) {
			const unsigned long marksGen  = marked.valid ? flexa::unreachableMarks().generation : 0;
			const bool          quick     = apart.readers != nullptr;
			const bool          newQuick  = !sameFunctors || scene != L.recScene || &ic != L.recContainer || quick != L.recQuick;
			const bool          newMarked = newQuick || marked.valid != L.recMarksValid || marksGen != L.recMarks || ic.iterColliderLastRun != L.recColliderRun;
			if (newQuick && (scene != L.recScene || &ic != L.recContainer)) L.held.clear(); // (let the old scene's objects go)
			if (newMarked) {
				const bool wrap = L.recGen > std::numeric_limits<unsigned>::max() - 2;
				if (wrap) { // (no old record may match by chance)
					L.remembered.assign(L.remembered.size(), Remembered());
					L.recGen = 0;
				}
				L.genMarked = ++L.recGen;
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
		gen[1] = L.genMarked;
		gen[2] = L.genQuick;
	}
	// whether pass 1 can leave out the pair at i from its record alone (kind 1 still asks whether
	// its bodies exist, kind 2 the table)
	const Remembered* recordOf(long i) const
	{
		const Remembered& r = rec[i];
		return (r.kind && r.gen == gen[r.kind] && r.ptr == intrs[i].get()) ? &r : nullptr;
	}

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

	// One thread's share: one contiguous run of blocks, of about equal work by the last step's
	// weights (handed out one by one, the threads would work on neighbouring blocks and share
	// their cache lines).
	void runThread(Counts& cnt)
	{
		flexa::ForceSink sink;
#ifdef YADE_OPENMP
		if (nSums) sink = L.sums.sink(omp_get_thread_num());
#endif
		flexa::ForceSinkScope sinkScope(nSums ? &sink : nullptr);
		long                  cBegin = 0, cEnd = nBlocks;
#ifdef YADE_OPENMP
		{
			const int nt = omp_get_num_threads(), tid = omp_get_thread_num();
			cBegin       = blockAtWeight(tid, nt);
			cEnd         = blockAtWeight(tid + 1, nt);
		}
#endif
		long live[kMaxBlock];
		bool fused[kMaxBlock]; // the fused path (fuseSpheres)
		for (long c = cBegin; c < cEnd; ++c) {
			if (failed) continue;
			const auto blockStart = weighted ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point();
			const long lo = c * block, hi = std::min(n, lo + block);
			const int  nLive = listLive(lo, hi, live, fused, cnt);
			runLive(live, fused, nLive);
			if (weighted) // this block's time, for the next step's split
				L.blockWeight[c] = std::chrono::duration<Real>(std::chrono::steady_clock::now() - blockStart).count();
		}
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
				if (!rec || !recordOf(pf)) {
					flexa::prefetch(intrs[pf].get(), sizeof(Interaction));
					++ahead;
				}
		};
		if (streamIn) stream();
		for (long i = lo; i < hi; ++i) {
			if (rec)
				if (const Remembered* r = recordOf(i)) {
					if (r->kind == 1) {
						if (bodies.get(r->id1) && bodies.get(r->id2)) {
							++cnt.recalled;
							continue;
						}
					} else if (apart.p) { // kind 2: what apart(J) would find, from the ids
						++cnt.candidates;
						if (apart.byIds(r->id1, r->id2) == 2) {
							++cnt.rejected;
							++cnt.recalled;
							continue;
						}
						// the spheres close: to pass 2 (no contact yet, so not fusable), and read
						// again on the next step
						rec[i].kind   = 0;
						fused[nLive]  = false;
						live[nLive++] = i;
						continue;
					}
				}
			if (streamIn) {
				if (i < pf && !(rec && recordOf(i))) --ahead; // (this one was asked for)
				stream();
			}
			// (a pair whose body vanished goes to the full path, which erases it as InteractionLoop does)
			const Interaction& J = *intrs[i];
			if (marked(J) && bodies.get(J.getId1()) && bodies.get(J.getId2())) {
				if (rec) remember(i, J, 1);
				continue;
			}
			if (const int a = apart(J)) {
				++cnt.candidates;
				if (a == 2) {
					++cnt.rejected;
					if (rec) remember(i, J, 2);
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
	void runLive(const long* live, const bool* fused, int nLive)
	{
		for (int j = 0; j < std::min(nLive, (int)kMid); ++j)
			fetchTargets(intrs[live[j]].get(), bodies, fused[j]);
		for (int j = 0; j < std::min(nLive, (int)kNear); ++j)
			if (!fused[j]) fetchStates(intrs[live[j]].get(), bodies);
		for (int j = 0; j < nLive && !failed; ++j) {
			if (j + kMid < nLive) fetchTargets(intrs[live[j + kMid]].get(), bodies, fused[j + kMid]);
			if (j + kNear < nLive && !fused[j + kNear]) fetchStates(intrs[live[j + kNear]].get(), bodies);
			try {
				if (fused[j]) runFused(intrs[live[j]]);
				else
					runFunctors(intrs[live[j]]);
			} catch (...) {
				fail(std::current_exception());
			}
		}
	}
	// what the functors do for a fused contact (Fusable): the geometry's update, the physics
	// functor returns at once, the law; shift2 is zero (not periodic)
	void runFused(const shared_ptr<Interaction>& I)
	{
		const Body::id_t   i1 = I->getId1(), i2 = I->getId2();
		const SpherePoint &a = pts[i1], &b = pts[i2];
		FlexContactGeom&   g = static_cast<FlexContactGeom&>(*I->geom);
		Ig2_Sphere_Sphere_FlexContactGeom::update(
		        scene, g, false, a.r, b.r, Vector3r(a.x, a.y, a.z), Vector3r(Vector3r(b.x, b.y, b.z) + Vector3r::Zero()), mot[i1].vel, mot[i1].angVel,
		        mot[i2].vel, mot[i2].angVel);
		if (!fusedLaw->apply(g, static_cast<FrictPhys&>(*I->phys), I.get(), &mot[i1].angVel, &mot[i2].angVel)) ic.requestErase(I);
	}
	// the geometry, physics and law functors of one interaction, as InteractionLoop calls them
	void runFunctors(const shared_ptr<Interaction>& I)
	{
		Body* b1_ = bodies.get(I->getId1());
		Body* b2_ = bodies.get(I->getId2());
		if (!b1_ || !b2_) {
			ic.requestErase(I); // a body vanished
			return;
		}
#ifdef YADE_MPI
		if (scene->subdomain != b1_->subdomain && scene->subdomain != b2_->subdomain) {
			ic.requestErase(I->getId1(), I->getId2());
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
			if (wasReal) ic.requestErase(I); // the geometry ended: the interaction is reset
			return;
		}
		if (!I->functorCache.phys) {
			bool swapPhys        = false;
			I->functorCache.phys = L.physDispatcher->getFunctor2D(b1->material, b2->material, swapPhys);
			if (!I->functorCache.phys)
				throw std::runtime_error(
				        "FlexInteractionLoop: no Ip2 functor for materials " + b1->material->getClassName() + " and " + b2->material->getClassName()
				        + " (bodies #" + std::to_string(b1->id) + " and #" + std::to_string(b2->id) + ")");
		}
		I->functorCache.phys->go(b1->material, b2->material, I);
		if (!wasReal) I->iterMadeReal = scene->iter;
		if (!I->functorCache.constLaw) {
			bool swapLaw             = false;
			I->functorCache.constLaw = L.lawDispatcher->getFunctor2D(I->geom, I->phys, swapLaw);
			if (!I->functorCache.constLaw)
				throw std::runtime_error(
				        "FlexInteractionLoop: no Law2 functor for " + I->geom->getClassName() + " and " + I->phys->getClassName() + " (bodies #"
				        + std::to_string(b1->id) + " and #" + std::to_string(b2->id) + ")");
		}
		if (!I->functorCache.constLaw->go(I->geom, I->phys, I.get())) ic.requestErase(I);
	}
};

// Whether this step needs InteractionLoop's own loop (and runs it): callbacks, sorted
// interactions, the collider's removal of unseen interactions, settings out of range.
bool FlexInteractionLoop::fallBack()
{
	InteractionContainer& ic = *scene->interactions;
	// the collider asks for unseen potential interactions to go on this step (some colliders only)
	const bool removeUnseen = ic.iterColliderLastRun >= 0 && ic.iterColliderLastRun == scene->iter;
	if (prefetch && !removeUnseen && callbacks.empty() && !loopOnSortedInteractions && blockSize >= 1 && blockSize <= kMaxBlock
	    && ahead[0] >= ahead[1] && ahead[1] >= ahead[2] && ahead[2] >= 1)
		return false;
	usedFastPath    = false;
	usedThreadSums  = false;
	quickRejected   = 0;
	quickCandidates = 0;
	fusedContacts   = 0;
	recalledSkips   = 0;
	lastCandidates  = -1;
	lastFusable     = -1;
	recScene        = nullptr; // (InteractionLoop may give any pair a geometry: the records start again)
	InteractionLoop::action();
	return true;
}

void FlexInteractionLoop::action()
{
	flexa::checkScene(scene);
	if (fallBack()) return;
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
	if (scene->interactions->size() == 0) {
		lastCandidates = 0;
		lastFusable    = 0;
		usedThreadSums = false;
		return;
	}
	if (compactEvery > 0 && (scene->iter - lastCompact >= compactEvery || scene->iter < lastCompact)) {
		compactedContacts = compactContacts(&(*scene->interactions)[0], (long)scene->interactions->size());
		lastCompact       = scene->iter;
	}
	Step step(*this);
	step.findReaders();
	step.chooseShortcuts();
	step.makeSphereTable();
	step.startRecords();
	step.splitByWeight();
	step.prepareThreadSums();
	long rejected = 0, candidates = 0, nFusable = 0, nFused = 0, recalled = 0;
#ifdef YADE_OPENMP
#pragma omp parallel num_threads(step.threads) reduction(+ : rejected, candidates, nFusable, nFused, recalled)
#endif
	{
		Step::Counts cnt;
		step.runThread(cnt);
		rejected += cnt.rejected;
		candidates += cnt.candidates;
		nFusable += cnt.nFusable;
		nFused += cnt.nFused;
		recalled += cnt.recalled;
	}
	if (step.nSums) flexa::mergeThreadSums(scene, sums, step.nSums); // (also after an error: the forces added so far stay, as in InteractionLoop)
	quickRejected   = rejected;
	quickCandidates = candidates;
	fusedContacts   = nFused;
	recalledSkips   = recalled;
	lastFusable     = step.fusable.geoms ? nFusable : -1;
	lastCandidates  = step.apart.readers ? candidates : -1; // (not counted: count on the next step)
	if (step.error) std::rethrow_exception(step.error);
}

} // namespace yade
