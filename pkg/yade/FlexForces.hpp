#pragma once
// yade-flex adapter: what the engines add to the scene, forces (with per-thread sums for loops
// on several threads) and energies (GPL-2.0-or-later).
#include "FlexPch.hpp"

#include <vector>

#ifdef YADE_OPENMP
#include <omp.h>
#endif

namespace yade {
namespace flexa {

	/// Per-thread sums of forces and torques by body id, for loops that run on several threads.
	/// ForceContainer::addForce and addTorque write, at every call, two fields every thread
	/// writes: the container's `synced` flag and its table of per-thread largest ids (the
	/// threads' entries 4 bytes apart). Two threads adding forces at once then take turns at
	/// those cache lines, and on a 2-vCPU VM FlexInteractionLoop took longer
	/// on two threads than on one (bench/README.md, "Two threads"). A loop that uses these
	/// sums points each of its threads at its own arrays (ForceSinkScope); the contact law adds
	/// there (flexa::addForce / addTorque) and the loop adds the sums to the container once per
	/// body after its pass (mergeThreadSums). One thread never uses them: there nothing
	/// contends, and -j1 stays the same bit for bit.
	struct ForceSink {
		Vector3r* f = nullptr;
		Vector3r* t = nullptr;
		long      n = 0;
	};
	/// This thread's sink (null: add to scene->forces directly)
	inline ForceSink*& currentSink()
	{
		thread_local ForceSink* s = nullptr;
		return s;
	}
	/// Points this thread at a sink for the scope's lifetime (null: none), then back to none
	struct ForceSinkScope {
		explicit ForceSinkScope(ForceSink* k) { currentSink() = k; }
		~ForceSinkScope() { currentSink() = nullptr; }
		ForceSinkScope(const ForceSinkScope&)            = delete;
		ForceSinkScope& operator=(const ForceSinkScope&) = delete;
	};
	inline void addForce(Scene* scene, const ForceSink* k, Body::id_t id, const Vector3r& f)
	{
		if (k && id >= 0 && id < k->n)
			k->f[id] += f;
		else
			scene->forces.addForce(id, f);
	}
	inline void addTorque(Scene* scene, const ForceSink* k, Body::id_t id, const Vector3r& t)
	{
		if (k && id >= 0 && id < k->n)
			k->t[id] += t;
		else
			scene->forces.addTorque(id, t);
	}
	/// The arrays of `threads` sinks over n bodies: sized (new entries zero; the rest are zero
	/// since the last merge) and the sink of thread k
	struct ThreadForceSums {
		std::vector<std::vector<Vector3r>> f, t;
		void                               prepare(int threads, long n)
		{
			f.resize(threads);
			t.resize(threads);
			for (int k = 0; k < threads; ++k) {
				f[k].resize(n, Vector3r::Zero());
				t[k].resize(n, Vector3r::Zero());
			}
		}
		ForceSink sink(int k) { return ForceSink { f[k].data(), t[k].data(), (long)f[k].size() }; }
	};
	/// Adds the sums to scene->forces: the container's own per-thread sums first (sync: forces
	/// that other functors added with addForce), then, per body, the threads' sums in thread order
	/// (addForceUnsynced), and zeroes them. A later addForce marks the container unsynced again
	/// and the next sync adds on top (ForceContainer::sync accumulates). Only the ids in
	/// [from, to) are visited (to < 0: every body): the caller's promise that its sinks wrote no
	/// other id since the last merge. Defined in speed/FlexLoop.cpp.
	void mergeThreadSums(Scene* scene, ThreadForceSums& sums, int threads, long from = 0, long to = -1);

	/// A term's first value inside a parallel region, kept until bookDeferredEnergies names the
	/// term and adds it, on one thread. EnergyTracker::findId cannot run on several threads: it
	/// reads its map of names outside its critical section while another thread may insert, two
	/// threads can both name the term (two slots, one of them left out of O.energy.keys()), and a
	/// new term reallocates every thread's sums while the other threads add to them.
	void deferEnergy(Scene* scene, Real val, const char* name, int& ix, bool reset);
	/// After a parallel region, on one thread: the deferred terms named (their indices set) and
	/// their values added. Defined in speed/FlexLoop.cpp.
	void bookDeferredEnergies(Scene* scene);

	/// scene->energy->add without building a std::string from the name at every call (the hot
	/// path, once the term has its index), called per contact, element and body. A term not yet
	/// named, inside a parallel region: deferEnergy.
	inline void addEnergy(Scene* scene, Real val, const char* name, int& ix, bool reset)
	{
		if (ix >= 0)
			scene->energy->energies.add(ix, val);
#ifdef YADE_OPENMP
		else if (omp_in_parallel())
			deferEnergy(scene, val, name, ix, reset);
#endif
		else
			scene->energy->add(val, name, ix, reset);
	}

} // namespace flexa
} // namespace yade
