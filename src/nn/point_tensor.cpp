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

}  // namespace ltm
