// parallel.h: the one place that decides how many threads ltm uses (TBB underneath).
// Parallel loops must write results indexed by item, never accumulate in scheduling order,
// so outputs are identical at any thread count.
#pragma once

#include <cstdint>
#include <functional>

namespace ltm {

/// Sets the worker count for all later parallel work (0 = number of cores).
void set_num_threads(int n);
int num_threads();

/// Calls body(begin_i, end_i) over disjoint chunks covering [begin, end), chunks of ≤ grain items.
void parallel_for(int64_t begin, int64_t end, int64_t grain,
                  const std::function<void(int64_t, int64_t)> &body);

}  // namespace ltm
