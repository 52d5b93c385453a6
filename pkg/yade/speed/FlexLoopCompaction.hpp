// yade-flex adapter: FlexInteractionLoop's compaction of the contacts (compactEvery): copies of
// their geometry and physics side by side in one block of memory (one per thread), in the order
// the loop visits them (GPL-2.0-or-later). Included by FlexLoop.cpp only.
#pragma once
#include "../Flex.hpp"
#include "FlexTuning.hpp"

#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <new>
#include <typeinfo>
#ifdef YADE_OPENMP
#include <omp.h>
#endif

namespace yade {
namespace flexa {
	namespace loop {
		// compactEvery: copies of the contacts' geometry and physics objects, side by side in one
		// block of memory (per thread) in the order of the container (which pass 2 follows). Each
		// copy is released on its own (InBlock runs its destructor), the block with its last copy.
		struct ContactBlock {
			std::unique_ptr<unsigned char[]> mem;
		};
		struct InBlock {
			shared_ptr<ContactBlock> block;
			template <class T> void  operator()(T* p) const { p->~T(); }
		};
		constexpr size_t kGeomBytes = (sizeof(FlexContactGeom) + 15) & ~size_t(15), kPhysBytes = (sizeof(FrictPhys) + 15) & ~size_t(15);
		// a yade-flex contact with FrictPhys that nothing but its interaction holds (an object that
		// Python or another interaction also holds stays where it is: they must keep seeing it live)
		inline bool movable(const Interaction& I)
		{
			return I.geom && I.phys && I.geom.use_count() == 1 && I.phys.use_count() == 1 && typeid(*I.geom) == typeid(FlexContactGeom)
			        && typeid(*I.phys) == typeid(FrictPhys);
		}
		// the contacts of intrs[lo, hi) into a block of their own (one allocation: while a thread
		// fills its block, that block's count of owners is touched by that thread only); the count
		// copied. A failed allocation of a shared_ptr's count runs the deleter and leaves the
		// interaction with its old object, and the exception goes on.
		inline long compactRange(const shared_ptr<Interaction>* intrs, long lo, long hi)
		{
			long count = 0;
			for (long i = lo; i < hi; ++i)
				count += movable(*intrs[i]);
			if (count == 0) return 0;
			const shared_ptr<ContactBlock> block(new ContactBlock);
			block->mem.reset(new unsigned char[(size_t)count * (kGeomBytes + kPhysBytes) + 64]);
			unsigned char* at = reinterpret_cast<unsigned char*>((reinterpret_cast<uintptr_t>(block->mem.get()) + 63) & ~uintptr_t(63));
			for (long i = lo; i < hi; ++i) {
				Interaction& I = *intrs[i];
				if (!movable(I)) continue;
				// exact copies (the same values bit for bit)
				FlexContactGeom* g = new (at) FlexContactGeom(static_cast<const FlexContactGeom&>(*I.geom));
				I.geom             = shared_ptr<IGeom>(g, InBlock { block });
				at += kGeomBytes;
				FrictPhys* p = new (at) FrictPhys(static_cast<const FrictPhys&>(*I.phys));
				I.phys       = shared_ptr<IPhys>(p, InBlock { block });
				at += kPhysBytes;
			}
			return count;
		}
		// All contacts of intrs[0, n); on several threads (from tuning::kCompactParallelMin
		// interactions) each thread copies one contiguous part of the container into its own block,
		// in the order of the container as on one thread. The count copied (blocks: the blocks
		// filled); the first exception goes on once every thread has stopped.
		inline long compactContacts(const shared_ptr<Interaction>* intrs, long n, int threads, long& blocks)
		{
			if (threads < 2 || n < tuning::kCompactParallelMin) {
				const long count = compactRange(intrs, 0, n);
				blocks           = count > 0;
				return count;
			}
			long               count = 0, filled = 0;
			std::exception_ptr error;
			std::mutex         errorMutex;
#ifdef YADE_OPENMP
#pragma omp parallel num_threads(threads) reduction(+ : count, filled)
#endif
			{
				int t = 0, nt = 1;
#ifdef YADE_OPENMP
				t  = omp_get_thread_num();
				nt = omp_get_num_threads();
#endif
				try {
					const long mine = compactRange(intrs, n * t / nt, n * (t + 1) / nt);
					count += mine;
					filled += mine > 0;
				} catch (...) {
					const std::lock_guard<std::mutex> lock(errorMutex);
					if (!error) error = std::current_exception();
				}
			}
			blocks = filled;
			if (error) std::rethrow_exception(error);
			return count;
		}

	} // namespace loop
} // namespace flexa
} // namespace yade
