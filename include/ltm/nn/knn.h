// knn.h: k nearest neighbours and farthest point sampling on 3-D positions. Both depend only on
// geometry, so callers compute them once per scene and cache them (ARCHITECTURE.md §6).
#pragma once

#include <cstdint>

#include <torch/torch.h>

namespace ltm {

/// k nearest reference points of every query point, nearest first (ties by lower index).
///   query [n, 3], ref [m, 3] (same device, float)  ->  indices [n, k] int64
/// CPU: a nanoflann k-d tree over `ref`; other devices: chunked brute force (cdist + topk).
torch::Tensor knn(const torch::Tensor &query, const torch::Tensor &ref, int64_t k);

/// The chunked brute-force path on any device (the reference the tree is tested against).
torch::Tensor knn_brute_force(const torch::Tensor &query, const torch::Tensor &ref, int64_t k);

/// Exact farthest point sampling: the first sample is point 0, each next one maximises the
/// distance to the samples so far (ties to the lower index).  pos [M, 3] -> indices [m] int64
torch::Tensor farthest_point_sampling(const torch::Tensor &pos, int64_t m);

}  // namespace ltm
