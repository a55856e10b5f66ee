// parallel.cpp: TBB with a process-wide concurrency limit (tbb::global_control), so Embree's
// BVH builds, which also use TBB, obey --threads too.
#include "ltm/core/parallel.h"

#include <memory>
#include <thread>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

namespace ltm {
namespace {
std::unique_ptr<tbb::global_control> g_control;
int g_threads = 0;
}  // namespace

void set_num_threads(int n) {
    if (n <= 0) n = int(std::max(1u, std::thread::hardware_concurrency()));
    g_threads = n;
    g_control = std::make_unique<tbb::global_control>(
        tbb::global_control::max_allowed_parallelism, size_t(n));
}

int num_threads() {
    if (g_threads == 0) set_num_threads(0);
    return g_threads;
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
