// point_tensor.h: point data (PointSet, record columns) as libtorch tensors — the one place that
// copies our row-major float buffers into tensors.
#pragma once

#include <cstdint>
#include <vector>

#include <torch/torch.h>

#include "ltm/points/point_set.h"

namespace ltm {

/// values (row-major, a multiple of cols floats) -> owned float32 tensor [values.size() / cols, cols].
torch::Tensor rows_tensor(const std::vector<float> &values, int64_t cols);

/// PointSet -> owned float32 tensor [p.size(), p.n_columns()] (e.g. scene points [M, 12]).
torch::Tensor point_tensor(const PointSet &p);

/// Point rows [N, C] (C >= 3, position in columns 0..2) with the position zeroed: what a layer
/// that must not see absolute positions gets (PhysicsConfig::translation_invariant).
torch::Tensor without_position(const torch::Tensor &rows);

}  // namespace ltm
