// knn.cpp: nanoflann on CPU (points/knn_points.h); torch brute force elsewhere. FPS: an O(M·m) loop on CPU (0.1 s for
// 8192 → 4096), a tensor loop on other devices.
#include "ltm/nn/knn.h"

#include <algorithm>
#include <limits>
#include <numeric>

#include "ltm/points/farthest_points.h"
#include "ltm/points/knn_points.h"

namespace ltm {

namespace {
void check_positions(const torch::Tensor &t, const char *name) {
    TORCH_CHECK(t.dim() == 2 && t.size(1) == 3, "knn: ", name, " must be [n, 3], got ", t.sizes());
    TORCH_CHECK(t.scalar_type() == torch::kFloat32, "knn: ", name, " must be float32, got ", t.scalar_type());
}
}  // namespace

torch::Tensor knn_brute_force(const torch::Tensor &query, const torch::Tensor &ref, int64_t k) {
    check_positions(query, "query");
    check_positions(ref, "ref");
    TORCH_CHECK(k >= 1 && k <= ref.size(0), "knn: k = ", k, " but only ", ref.size(0), " reference points");
    const int64_t n = query.size(0), chunk = std::max<int64_t>(1, (int64_t(1) << 24) / std::max<int64_t>(1, ref.size(0)));
    std::vector<torch::Tensor> parts;
    for (int64_t s = 0; s < n; s += chunk) {
        const auto q = query.slice(0, s, std::min(n, s + chunk));
        // |q - r|² expanded; exactness of ordering is what matters, not of the value.
        const auto d2 = (q.unsqueeze(1) - ref.unsqueeze(0)).pow(2).sum(-1);   // [c, m]
        parts.push_back(std::get<1>(d2.topk(k, /*dim=*/1, /*largest=*/false, /*sorted=*/true)));
    }
    return torch::cat(parts, 0);
}

torch::Tensor knn(const torch::Tensor &query, const torch::Tensor &ref, int64_t k) {
    if (!query.device().is_cpu()) return knn_brute_force(query, ref, k);
    check_positions(query, "query");
    check_positions(ref, "ref");
    TORCH_CHECK(k >= 1 && k <= ref.size(0), "knn: k = ", k, " but only ", ref.size(0), " reference points");
    const auto r = ref.contiguous(), q = query.contiguous();
    std::vector<int64_t> idx = knn_points(q.data_ptr<float>(), size_t(q.size(0)), r.data_ptr<float>(), size_t(r.size(0)), k);
    return torch::from_blob(idx.data(), {q.size(0), k}, torch::kInt64).clone();
}

torch::Tensor farthest_point_sampling(const torch::Tensor &pos, int64_t m) {
    check_positions(pos, "pos");
    const int64_t M = pos.size(0);
    TORCH_CHECK(m >= 1 && m <= M, "farthest_point_sampling: m = ", m, " for ", M, " points");
    if (!pos.device().is_cpu()) {
        auto dist = torch::full({M}, std::numeric_limits<float>::infinity(), pos.options());
        auto out = torch::zeros({m}, pos.options().dtype(torch::kInt64));
        int64_t last = 0;
        for (int64_t i = 1; i < m; ++i) {
            dist = torch::minimum(dist, (pos - pos[last]).pow(2).sum(-1));
            last = dist.argmax().item<int64_t>();
            out[i] = last;
        }
        return out;
    }
    const auto p = pos.contiguous();
    const std::vector<int64_t> idx = farthest_points(p.data_ptr<float>(), size_t(M), size_t(m));   // points/farthest_points.h
    return torch::tensor(idx, torch::kInt64);
}

}  // namespace ltm
