// farthest_points.h: exact farthest point sampling on 3-D positions, torch-free — the one loop
// behind the model's anchors (nn/knn.h, CPU) and the path guide's clusters (infer/guide_builder.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ltm {

/// The first sample is point 0, each next one maximises the squared distance to the samples so far
/// (ties to the lower index). xyz: n rows of 3 floats; 1 <= m <= n (not checked here: callers do).
/// Deterministic, and equal index for index to farthest_points_reference: a k-d tree over the points
/// keeps each subtree's largest distance, and a new sample visits only the subtrees its ball can
/// lower (late samples touch a few leaves), so the cost falls from O(n·m) to about O(n log n + m·(touched)).
///   -> indices [m]
std::vector<int64_t> farthest_points(const float *xyz, size_t n, size_t m);

/// The plain O(n·m) loop, the definition farthest_points is tested against.
std::vector<int64_t> farthest_points_reference(const float *xyz, size_t n, size_t m);

}  // namespace ltm
