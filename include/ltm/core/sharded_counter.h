// sharded_counter.h: a counter that many threads bump without sharing a cache line. One atomic
// bumped by every thread of a render (EmbreeAccel's rays) made the cores take turns owning its line:
// on 2 cores the `lock add` was 30 % of a frame with the prior's rays (perf, session 29). Each thread
// bumps its own shard instead; total() sums them.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>

namespace ltm {

class ShardedCounter {
public:
    void add(uint64_t n = 1) { m_shards[slot()].count.fetch_add(n, std::memory_order_relaxed); }
    /// The sum of every shard: exact once the threads that added have finished (relaxed reads).
    uint64_t total() const {
        uint64_t sum = 0;
        for (const Shard &s : m_shards) sum += s.count.load(std::memory_order_relaxed);
        return sum;
    }

private:
    static constexpr unsigned k_shards = 64;
    struct alignas(64) Shard {
        std::atomic<uint64_t> count{0};
    };
    // A thread's shard, fixed at its first use: the first 64 threads each get their own (later ones
    // share, which costs contention, never a count).
    static unsigned slot() {
        static std::atomic<unsigned> next{0};
        thread_local const unsigned mine = next.fetch_add(1, std::memory_order_relaxed) % k_shards;
        return mine;
    }
    std::array<Shard, k_shards> m_shards{};
};

}  // namespace ltm
