// point_tensor.cpp: copies into tensors (from_blob + clone: the tensor owns its memory).
#include "ltm/nn/point_tensor.h"

#include "ltm/core/error.h"

namespace ltm {

torch::Tensor rows_tensor(const std::vector<float> &values, int64_t cols) {
    LTM_CHECK(cols > 0 && int64_t(values.size()) % cols == 0);
    return torch::from_blob(const_cast<float *>(values.data()), {int64_t(values.size()) / cols, cols}, torch::kFloat32)
        .clone();
}

torch::Tensor point_tensor(const PointSet &p) { return rows_tensor(p.values, int64_t(p.n_columns())); }

torch::Tensor without_position(const torch::Tensor &rows) {
    TORCH_CHECK(rows.dim() == 2 && rows.size(1) >= 3, "without_position: rows must be [N, C >= 3], got ", rows.sizes());
    return torch::cat({torch::zeros_like(rows.slice(1, 0, 3)), rows.slice(1, 3)}, 1);
}

}  // namespace ltm
