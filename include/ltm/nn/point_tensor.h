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

}  // namespace ltm
