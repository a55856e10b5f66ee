// augment.cpp: the D4 symmetries of the horizontal plane as signed permutation matrices.
#include "ltm/train/augment.h"

namespace ltm {

torch::Tensor symmetry_matrix(int s) {
    TORCH_CHECK(s >= 0 && s < k_n_symmetries, "symmetry index ", s, " outside [0, ", k_n_symmetries, ")");
    // A quarter turn about +y (right-handed): (x, y, z) → (z, y, −x).
    const auto quarter = torch::tensor({0.f, 0.f, 1.f, 0.f, 1.f, 0.f, -1.f, 0.f, 0.f}).view({3, 3});
    auto r = torch::eye(3);
    for (int k = 0; k < (s & 3); ++k) r = quarter.mm(r);
    if (s & 4) r = torch::diag(torch::tensor({-1.f, 1.f, 1.f})).mm(r);
    return r;
}

torch::Tensor apply_symmetry(const torch::Tensor &points, int s) {
    TORCH_CHECK(points.dim() == 2 && points.size(1) >= 6 && points.scalar_type() == torch::kFloat,
                "apply_symmetry: points must be float [N, C >= 6], got ", points.sizes(), " ", points.scalar_type());
    if (s == 0) return points;
    // Row vectors: v' = v·Rᵀ. Each output is one ±input plus exact zeros, so no rounding occurs.
    const auto rt = symmetry_matrix(s).t().to(points.device());
    return torch::cat({points.slice(1, 0, 3).mm(rt), points.slice(1, 3, 6).mm(rt), points.slice(1, 6)}, 1);
}

SceneNormalization apply_symmetry(const SceneNormalization &frame, int s) {
    SceneNormalization f = frame;
    f.transport.reset(), f.regather.reset();
    if (s != 0) f.center = f.center.view({1, 3}).mm(symmetry_matrix(s).t().to(f.center.device())).view({3});
    return f;
}

}  // namespace ltm
