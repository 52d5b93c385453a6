// yade-flex kernel: blocks of work handed to threads in contiguous shares, with the shares of
// late threads finished by the others (GPL-2.0-or-later).
//
// A loop over blocks [0, n) on several threads: each thread first takes the blocks of its own
// share, one contiguous run [starts[k], starts[k+1]), from the front, so that a thread works on
// neighbouring data; then, its share done, blocks from the back of the share with the most blocks
// left, until none is left anywhere. A share that takes longer than planned (a thread started
// late, the core taken by another process, the work heavier than the split assumed) is finished
// by the threads that are done, and a share no thread owns (fewer threads than shares) is taken
// that way entirely. Every block is taken exactly once: a share's front and back are one atomic
// word, so the owner at the front and a thread at the back never both get its last block.
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

namespace flex {

class BlockShares {
public:
	// shares k = 0 .. starts.size() - 2 of blocks [starts[k], starts[k + 1]); starts ascending
	// from 0, below 2^31. Not while a thread runs.
	void reset(const std::vector<long>& starts)
	{
		if (starts.size() < 2 || starts.front() != 0) throw std::invalid_argument("BlockShares: starts must begin at 0 and give at least one share");
		for (size_t k = 1; k < starts.size(); ++k)
			if (starts[k] < starts[k - 1] || starts[k] >= (1L << 31)) throw std::invalid_argument("BlockShares: starts must ascend, below 2^31");
		n_ = (int)starts.size() - 1;
		if (n_ > cap_) {
			share_.reset(new Share[n_]);
			cap_ = n_;
		}
		for (int k = 0; k < n_; ++k)
			share_[k].fb.store(pack(starts[k], starts[k + 1]), std::memory_order_relaxed);
	}
	int shares() const { return n_; }

	// Thread `self`'s work: f(block) for the blocks of its share (self outside [0, shares): none),
	// then for blocks taken from the back of the others, until no block is left or stop() is
	// true (checked before each block). Any number of threads may call it at once. f must not
	// throw: a block taken counts as run (a caller inside an OpenMP region catches in f).
	template <class F, class Stop> void run(int self, F&& f, Stop&& stop)
	{
		long c = 0;
		if (self >= 0 && self < n_)
			while (!stop() && take(share_[self], false, c))
				f(c);
		while (!stop()) {
			int  most = -1;
			long left = 0;
			for (int k = 0; k < n_; ++k) {
				const long r = remaining(k);
				if (r > left) {
					left = r;
					most = k;
				}
			}
			if (most < 0) return;
			if (take(share_[most], true, c)) f(c);
		}
	}
	// blocks not taken yet of share k
	long remaining(int k) const
	{
		const std::uint64_t v = share_[k].fb.load(std::memory_order_relaxed);
		return (long)(v & 0xffffffffULL) - (long)(v >> 32);
	}

private:
	struct alignas(64) Share {
		std::atomic<std::uint64_t> fb { 0 }; // front << 32 | back
	};
	static std::uint64_t pack(long f, long b) { return ((std::uint64_t)f << 32) | (std::uint64_t)b; }
	// the block at the front or the back of s, into c; false: none left
	static bool take(Share& s, bool fromBack, long& c)
	{
		std::uint64_t v = s.fb.load(std::memory_order_relaxed);
		for (;;) {
			const long f = (long)(v >> 32), b = (long)(v & 0xffffffffULL);
			if (f >= b) return false;
			if (s.fb.compare_exchange_weak(v, fromBack ? pack(f, b - 1) : pack(f + 1, b), std::memory_order_relaxed)) {
				c = fromBack ? b - 1 : f;
				return true;
			}
		}
	}
	std::unique_ptr<Share[]> share_;
	int                      n_ = 0, cap_ = 0;
};

} // namespace flex
