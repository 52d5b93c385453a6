// yade-flex adapter: every tuning constant of the engines in one place (GPL-2.0-or-later).
//
// None of these changes a result: they set how the work is cut (threads, blocks) and how far
// ahead memory is asked for. The engine attributes that expose them to Python take their
// defaults from here. bench/ holds the measurements behind each value (bench/README.md).
#pragma once
#include <cstddef>
#include <cstdint>

namespace yade {
namespace flexa {
	namespace tuning {
		// ---- parallel thresholds: below these counts OpenMP's fork and join cost more than
		// the split saves (2-core measurements, bench/README.md "Two threads")
		/// FlexElementEngine.parallelMin: elements (cylinders, facets) per loop.
		constexpr int kElementParallelMin = 500;
		/// FlexNewtonIntegrator.parallelMin: bodies.
		constexpr int kIntegratorParallelMin = 4000;
		/// FlexTimeStepper: interactions for the parallel contact pass.
		constexpr long kStepperParallelMin = 4096;
		/// FlexInteractionLoop: spheres for the parallel pass that fills the table of centres.
		constexpr long kSphereTableParallelMin = 1024;
		/// FlexGrainEngine: grains for the parallel pass that reads their bodies.
		constexpr long kGrainBodiesParallelMin = 1024;
		/// FlexTimeStepper: bodies for the parallel pass that gathers what the estimate needs of each.
		constexpr long kStepperBodiesParallelMin = 1024;
		/// FlexInteractionLoop.threadSumsMin: interactions for per-thread force sums.
		constexpr long kThreadSumsMin = 4096;
		/// FlexInteractionLoop (compactEvery): interactions for the copy of the contacts on every thread.
		constexpr long kCompactParallelMin = 1024;

		// ---- blocks and prefetch distances
		/// FlexInteractionLoop.blockSize (interactions per block) and its largest allowed value.
		constexpr int  kBlockSize = 256;
		constexpr long kMaxBlock  = 4096;
		/// FlexInteractionLoop.ahead: interaction objects (pass 1), their bodies, geom and phys,
		/// the bodies' states and shapes (pass 2) [iterations]. Work per pair ~20 ns (potential) to
		/// ~150 ns (real contact), a miss to DRAM ~100 ns.
		constexpr int kAheadObjects = 12, kAheadTargets = 6, kAheadStates = 3;
		/// For a pass over bodies: the body asked for this far ahead, what it points to (state,
		/// shape, bound) half as far. Such passes do 10-30 ns per body.
		constexpr long kAheadBodies = 16, kAheadBodyParts = 8;
		/// The same in the integrator's pass over the moving bodies (each gets a few arithmetic
		/// operations: nearer), in the scene check's pass (only a few fields read: farther), and in
		/// the element loop (the element's shape and node states).
		constexpr long kAheadIntegratorBodies = 8, kAheadIntegratorParts = 4;
		constexpr long kAheadCheckBodies = 32, kAheadCheckParts = 16;
		constexpr long kAheadElements = 4;
		/// The time stepper's pass over the interactions: the objects, what they point to.
		constexpr long kAheadStepperObjects = 12, kAheadStepperTargets = 6;
		/// Below this many items a pass's data (a body, its state, bound and shape: ~700 bytes; an
		/// interaction object) stays in the core's cache from one step to the next, and asking for
		/// it ahead only costs (a third of the wire net's interaction loop, 298 pairs).
		constexpr long kPrefetchMin = 512;
		/// FlexInteractionLoop.compactEvery: steps between copies of the contacts into one block.
		constexpr long kCompactEvery = 100;

		// ---- the scene check (FlexSceneCheck.hpp)
		/// Steps between two full checks when nothing says a script can have run: how long a value
		/// a script sets from another thread while O.run() runs (an interactive session), or a hook
		/// run by a non-periodic engine, can go unchecked.
		constexpr long kFullCheckPeriod = 32;
	} // namespace tuning

	using tuning::kPrefetchMin;

	/// Ask the memory system for the `bytes` bytes from p on (every 64-byte line they touch: heap
	/// objects are 16-byte aligned, so an object of 104 bytes may span three lines), to be read
	/// soon. A prefetch never faults: p may be null or stale.
	///
	/// The prefetch instruction is an asm volatile statement, not __builtin_prefetch: GCC treats
	/// the builtin as having no effect, so that a function that only prefetches (a helper that asks
	/// for what a loop reads next) is taken for a call without effect, and where it is not inlined
	/// first, the call is removed with its prefetches. An asm volatile statement always stays.
	inline void prefetchLine(const void* p)
	{
#if defined(__x86_64__) || defined(__i386__)
		asm volatile("prefetcht0 (%0)" : : "r"(p));
#else
		__builtin_prefetch(p, 0, 3);
#endif
	}
	inline void prefetch(const void* p, size_t bytes)
	{
		const uintptr_t a = reinterpret_cast<uintptr_t>(p), end = a + bytes;
		for (uintptr_t line = a & ~uintptr_t(63); line < end; line += 64)
			prefetchLine(reinterpret_cast<const void*>(line));
	}
	/// For a pass over all bodies in id order (body[0..n)), at body `id`: asks for the body
	/// kAheadBodies ahead and, through parts(const Body&), for what the body kAheadBodyParts ahead
	/// points to (read from a body asked for before).
	template <class BodyPtr, class Parts> inline void prefetchBodiesAhead(const BodyPtr* body, long n, long id, Parts&& parts)
	{
		if (id + tuning::kAheadBodies < n) prefetch(body[id + tuning::kAheadBodies].get(), sizeof(*body[0]));
		if (id + tuning::kAheadBodyParts < n)
			if (const auto* c = body[id + tuning::kAheadBodyParts].get()) parts(*c);
	}
	/// The same for a pass over a list of body ids (ids[0..n)), at its k-th entry.
	template <class BodyPtr, class Id, class Parts> inline void prefetchBodiesAhead(const BodyPtr* body, const Id* ids, long n, long k, Parts&& parts)
	{
		if (k + tuning::kAheadBodies < n) prefetch(body[ids[k + tuning::kAheadBodies]].get(), sizeof(*body[0]));
		if (k + tuning::kAheadBodyParts < n)
			if (const auto* c = body[ids[k + tuning::kAheadBodyParts]].get()) parts(*c);
	}
	/// For a pass that reads a sphere's position, velocities, mass and blocked DOFs from its state
	/// and its radius (FlexInteractionLoop's sphere table, FlexGrainEngine): asks for those lines
	/// of body c's state, and for its shape (a SphereShape).
	template <class SphereShape, class BodyT> inline void prefetchSphereParts(const BodyT& c)
	{
		if (const auto* st = c.state.get()) {
			prefetch(&st->se3.position, sizeof(st->se3.position));  // (pos is a reference: reading it would wait)
			prefetch(&st->vel, sizeof(st->vel) + sizeof(st->mass)); // (and mass)
			prefetch(&st->angVel, sizeof(st->angVel));
			prefetch(&st->blockedDOFs, sizeof(st->blockedDOFs));
		}
		prefetch(c.shape.get(), sizeof(SphereShape));
	}
	/// The same for a sphere's centre and radius only.
	template <class SphereShape, class BodyT> inline void prefetchSphereCentre(const BodyT& c)
	{
		if (const auto* st = c.state.get()) prefetch(&st->se3.position, sizeof(st->se3.position));
		prefetch(c.shape.get(), sizeof(SphereShape));
	}
} // namespace flexa
} // namespace yade
