// sharded_counter_test.cpp: many threads (more than the shards) counting at once lose nothing.
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "ltm/core/parallel.h"
#include "ltm/core/sharded_counter.h"

using namespace ltm;

TEST(ShardedCounter, EveryAddIsCountedFromAnyNumberOfThreads) {
    ShardedCounter c;
    EXPECT_EQ(c.total(), 0u);
    std::vector<std::thread> threads;
    for (int t = 0; t < 80; ++t)   // 80 > its 64 shards: some threads share one
        threads.emplace_back([&c, t] {
            for (int i = 0; i < 1000; ++i) c.add(uint64_t(t % 3));
        });
    for (auto &t : threads) t.join();
    uint64_t expected = 0;
    for (int t = 0; t < 80; ++t) expected += 1000u * uint64_t(t % 3);
    EXPECT_EQ(c.total(), expected);
    parallel_for(0, 100000, 64, [&](int64_t a, int64_t b) {
        for (int64_t i = a; i < b; ++i) c.add();
    });
    EXPECT_EQ(c.total(), expected + 100000u);
}
