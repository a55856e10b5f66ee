// farthest_points.h: exact farthest point sampling on 3-D positions, torch-free — the one loop
// behind the model's anchors (nn/knn.h, CPU) and the transport prior's visibility clusters
// (transport/point_visibility.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ltm {

/// The first sample is point 0, each next one maximises the squared distance to the samples so far
/// (ties to the lower index). xyz: n rows of 3 floats; 1 <= m <= n (not checked here: callers do).
/// O(n·m), deterministic.   -> indices [m]
std::vector<int64_t> farthest_points(const float *xyz, size_t n, size_t m);

}  // namespace ltm
