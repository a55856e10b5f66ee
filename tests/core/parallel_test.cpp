// parallel_test.cpp: parallel_for covers its range exactly once, and the process-wide thread
// limit is installed once however many threads ask for it first.
#include <atomic>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "ltm/core/parallel.h"

using namespace ltm;

TEST(Parallel, EveryIndexOnceAndTheLimitAgreedAcrossThreads) {
    // Threads that read the limit at the same time (lazy first use) all see one positive value.
    std::vector<int> seen(8, -1);
    std::vector<std::thread> threads;
    for (size_t i = 0; i < seen.size(); ++i) threads.emplace_back([&seen, i] { seen[i] = num_threads(); });
    for (auto &t : threads) t.join();
    for (int n : seen) EXPECT_EQ(n, seen[0]);
    EXPECT_GT(seen[0], 0);

    std::vector<std::atomic<int>> hits(10007);
    parallel_for(0, int64_t(hits.size()), 64, [&](int64_t a, int64_t b) {
        for (int64_t i = a; i < b; ++i) hits[size_t(i)].fetch_add(1);
    });
    for (const auto &h : hits) ASSERT_EQ(h.load(), 1);
    set_num_threads(1);
    EXPECT_EQ(num_threads(), 1);
    set_num_threads(0);   // back to every core
    EXPECT_GE(num_threads(), 1);
}
