// parallel.cpp: TBB with a process-wide concurrency limit (tbb::global_control), so Embree's
// BVH builds, which also use TBB, obey --threads too.
#include "ltm/core/parallel.h"

#include <atomic>
#include <memory>
#include <mutex>
#include <thread>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

namespace ltm {
namespace {
// The limit is process-wide state: set once by the CLI (--threads), or lazily on first use by any
// thread. The mutex serialises installing it; the atomic makes the common read lock-free.
std::mutex g_mutex;
std::unique_ptr<tbb::global_control> g_control;   // guarded by g_mutex
std::atomic<int> g_threads{0};

int hardware_threads() { return int(std::max(1u, std::thread::hardware_concurrency())); }

void install(int n) {   // caller holds g_mutex
    g_control = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, size_t(n));
    g_threads.store(n);
}
}  // namespace

void set_num_threads(int n) {
    std::lock_guard<std::mutex> lock(g_mutex);
    install(n <= 0 ? hardware_threads() : n);
}

int num_threads() {
    if (const int n = g_threads.load(); n > 0) return n;
    std::lock_guard<std::mutex> lock(g_mutex);
    if (g_threads.load() == 0) install(hardware_threads());
    return g_threads.load();
}

void parallel_for(int64_t begin, int64_t end, int64_t grain,
                  const std::function<void(int64_t, int64_t)> &body) {
    if (end <= begin) return;
    if (grain < 1) grain = 1;
    if (num_threads() == 1 || end - begin <= grain) {
        for (int64_t i = begin; i < end; i += grain) body(i, std::min(end, i + grain));
        return;
    }
    tbb::parallel_for(tbb::blocked_range<int64_t>(begin, end, size_t(grain)),
                      [&](const tbb::blocked_range<int64_t> &r) { body(r.begin(), r.end()); },
                      tbb::simple_partitioner());
}

}  // namespace ltm
