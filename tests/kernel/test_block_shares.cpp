// flex::BlockShares: every block run exactly once, a thread's own share first and in order, the
// shares of absent or slow threads finished by the others (GPL-2.0-or-later).
#include <kernel/BlockShares.hpp>

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <random>
#include <thread>
#include <vector>

namespace {

const auto never = [] { return false; };

// counts of the runs of each block by `threads` threads on shares `starts`; thread k waits
// delay(k) before it starts, and each block takes work(block)
template <class Delay, class Work> std::vector<int> runCounts(const std::vector<long>& starts, int threads, Delay delay, Work work)
{
	flex::BlockShares shares;
	shares.reset(starts);
	std::vector<std::atomic<int>> count(starts.back());
	for (auto& c : count)
		c = 0;
	std::vector<std::thread> pool;
	for (int k = 0; k < threads; ++k)
		pool.emplace_back([&, k] {
			delay(k);
			shares.run(
			        k,
			        [&](long c) {
				        work(c);
				        ++count[c];
			        },
			        never);
		});
	for (auto& t : pool)
		t.join();
	std::vector<int> out;
	for (auto& c : count)
		out.push_back(c.load());
	return out;
}

} // namespace

TEST(BlockShares, OneThreadRunsItsShareFrontFirstThenTheOthersFromTheBack)
{
	flex::BlockShares shares;
	shares.reset({ 0, 4, 7, 10 });
	std::vector<long> order;
	shares.run(
	        1, [&](long c) { order.push_back(c); }, never);
	// its own share 4..6 in order; then always the back of the share with the most left, the first
	// of them on a tie: share 0 (4 left): 3; shares 0 and 2 (3 each): 2; share 2: 9; ...
	const std::vector<long> expected { 4, 5, 6, 3, 2, 9, 1, 8, 0, 7 };
	EXPECT_EQ(order, expected);
	for (int k = 0; k < shares.shares(); ++k)
		EXPECT_EQ(shares.remaining(k), 0);
}

TEST(BlockShares, AThreadOutsideTheSharesOnlyTakesWhatIsLeft)
{
	flex::BlockShares shares;
	shares.reset({ 0, 3 });
	std::vector<long> order;
	shares.run(
	        5, [&](long c) { order.push_back(c); }, never);
	EXPECT_EQ(order, (std::vector<long> { 2, 1, 0 }));
}

TEST(BlockShares, StopIsAskedBeforeEachBlock)
{
	flex::BlockShares shares;
	shares.reset({ 0, 10, 20 });
	int runs = 0;
	shares.run(
	        0, [&](long) { ++runs; }, [&] { return runs >= 3; });
	EXPECT_EQ(runs, 3);
	EXPECT_EQ(shares.remaining(0), 7);
	EXPECT_EQ(shares.remaining(1), 10);
}

TEST(BlockShares, EmptySharesAndNoBlocks)
{
	flex::BlockShares shares;
	shares.reset({ 0, 0, 0 });
	int runs = 0;
	shares.run(
	        0, [&](long) { ++runs; }, never);
	EXPECT_EQ(runs, 0);
	shares.reset({ 0, 0, 2, 2 });
	shares.run(
	        0, [&](long) { ++runs; }, never);
	EXPECT_EQ(runs, 2);
}

TEST(BlockShares, BadStartsAreRefused)
{
	flex::BlockShares shares;
	EXPECT_THROW(shares.reset({}), std::invalid_argument);
	EXPECT_THROW(shares.reset({ 0 }), std::invalid_argument);
	EXPECT_THROW(shares.reset({ 1, 4 }), std::invalid_argument);
	EXPECT_THROW(shares.reset({ 0, 4, 3 }), std::invalid_argument);
	EXPECT_THROW(shares.reset({ 0, 1L << 31 }), std::invalid_argument);
}

TEST(BlockShares, ReusedWithMoreShares)
{
	flex::BlockShares shares;
	shares.reset({ 0, 2 });
	shares.reset({ 0, 1, 2, 3, 4, 5 });
	EXPECT_EQ(shares.shares(), 5);
	int runs = 0;
	shares.run(
	        0, [&](long) { ++runs; }, never);
	EXPECT_EQ(runs, 5);
}

TEST(BlockShares, EveryBlockRunsOnceOnManyThreads)
{
	std::mt19937 rng(7);
	for (int round = 0; round < 200; ++round) {
		const int         threads = 1 + (int)(rng() % 8);
		const int         nShares = 1 + (int)(rng() % 8);
		std::vector<long> starts { 0 };
		for (int k = 0; k < nShares; ++k)
			starts.push_back(starts.back() + (long)(rng() % 40));
		// threads starting at different times, some blocks slower: each share is taken from both ends
		const auto counts = runCounts(
		        starts, threads, [](int k) { std::this_thread::sleep_for(std::chrono::microseconds(100 * (k % 3))); },
		        [](long c) {
			        if (c % 5 == 0) std::this_thread::sleep_for(std::chrono::microseconds(20));
		        });
		for (size_t c = 0; c < counts.size(); ++c)
			ASSERT_EQ(counts[c], 1) << "round " << round << ", block " << c << ", " << threads << " threads, " << nShares << " shares";
	}
}

TEST(BlockShares, TheLastBlockOfAShareGoesToOneThreadOnly)
{
	// two threads racing for the last blocks of tiny shares, with no pause between the blocks: the
	// owner from the front and the other from the back meet on the same block every few rounds
	for (const std::vector<long>& starts : { std::vector<long> { 0, 1, 2 }, std::vector<long> { 0, 2, 4 }, std::vector<long> { 0, 3, 3 } }) {
		for (int round = 0; round < 3000; ++round) {
			const auto counts = runCounts(
			        starts, 2, [](int) {}, [](long) {});
			for (size_t c = 0; c < counts.size(); ++c)
				ASSERT_EQ(counts[c], 1) << "round " << round << ", block " << c;
		}
	}
}

TEST(BlockShares, StopIsAskedWhileTakingFromOthers)
{
	flex::BlockShares shares;
	shares.reset({ 0, 2, 10 });
	std::vector<long> order;
	shares.run(
	        0, [&](long c) { order.push_back(c); }, [&] { return order.size() >= 4; });
	EXPECT_EQ(order, (std::vector<long> { 0, 1, 9, 8 }));
	EXPECT_EQ(shares.remaining(1), 6);
}

TEST(BlockShares, ABusyThreadsShareIsTakenByTheOther)
{
	// thread 0 starts its first block and stays in it until every other block is taken; thread 1
	// starts then: its own share 8..15 in order, then share 0 from the back, 7 down to 1
	flex::BlockShares shares;
	shares.reset({ 0, 8, 16 });
	std::vector<int>  by(16, -1);
	std::vector<long> order1;
	std::atomic<bool> inBlock0 { false }, timedOut { false };
	auto              waitFor = [&](auto cond) {
                const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
                while (!cond())
                        if (std::chrono::steady_clock::now() > end) {
                                timedOut = true;
                                return;
                        }
	};
	std::thread t0([&] {
		shares.run(
		        0,
		        [&](long c) {
			        by[c] = 0;
			        if (c == 0) {
				        inBlock0 = true;
				        waitFor([&] { return shares.remaining(0) == 0 && shares.remaining(1) == 0; });
			        }
		        },
		        never);
	});
	std::thread t1([&] {
		waitFor([&] { return inBlock0.load(); });
		shares.run(
		        1,
		        [&](long c) {
			        by[c] = 1;
			        order1.push_back(c);
		        },
		        never);
	});
	t0.join();
	t1.join();
	ASSERT_FALSE(timedOut);
	EXPECT_EQ(by[0], 0);
	for (int c = 1; c < 16; ++c)
		EXPECT_EQ(by[c], 1) << c;
	EXPECT_EQ(order1, (std::vector<long> { 8, 9, 10, 11, 12, 13, 14, 15, 7, 6, 5, 4, 3, 2, 1 }));
}
