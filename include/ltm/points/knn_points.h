// knn_points.h: k nearest neighbours among 3-D points, torch-free (a nanoflann k-d tree). The
// model's tensor kNN (nn/knn.h) and its closed-form prior's frame (nn/scene_frame.h) both call it,
// so the two find the same neighbours.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ltm {

/// The k nearest reference points of every query point, nearest first (ties by lower index).
///   query [n, 3], ref [m, 3] (row-major floats) -> [n, k] indices (row-major); 1 ≤ k ≤ m.
/// Deterministic at any thread count.
std::vector<int64_t> knn_points(const float *query, size_t n, const float *ref, size_t m, int64_t k);

}  // namespace ltm
