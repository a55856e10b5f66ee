// nn_embedding.cpp: eqs. 5–7. LayerNorm instead of BatchNorm: batches are one scene, and
// train/eval must behave the same.
#include "ltm/nn/nn_embedding.h"

#include "ltm/nn/point_tensor.h"

namespace ltm {

torch::nn::Sequential make_mlp(int64_t in, int64_t hidden, int64_t out) {
    return torch::nn::Sequential(torch::nn::Linear(in, hidden), torch::nn::LayerNorm(torch::nn::LayerNormOptions({hidden})),
                                 torch::nn::GELU(), torch::nn::Linear(hidden, out));
}

NNEmbeddingImpl::NNEmbeddingImpl(const EmbeddingConfig &c) : cfg(c) {
    f = register_module("f", make_mlp(12 + cfg.extra_inputs, cfg.dim, cfg.dim));
    const int64_t g_in = 2 * cfg.dim + (cfg.relative_position ? 3 : 0);
    g = register_module("g", make_mlp(g_in, cfg.dim, cfg.dim));
}

torch::Tensor NNEmbeddingImpl::forward(const torch::Tensor &x, const torch::Tensor &centers, const torch::Tensor &groups) {
    TORCH_CHECK(x.dim() == 2 && x.size(1) == 12 + cfg.extra_inputs, "NNEmbedding: x must be [M, ", 12 + cfg.extra_inputs, "], got ", x.sizes());
    TORCH_CHECK(centers.dim() == 1 && groups.dim() == 2 && groups.size(0) == centers.size(0),
                "NNEmbedding: centers [m] and groups [m, k] expected, got ", centers.sizes(), " and ", groups.sizes());
    const int64_t m = centers.size(0), k = groups.size(1);
    const auto fx = f->forward(cfg.absolute_position ? x : without_position(x));   // [M, D]      (eq. 5)
    const auto fc = fx.index_select(0, centers);                       // [m, D]      X̃_l
    const auto fg = fx.index_select(0, groups.reshape(-1)).view({m, k, -1});   // [m, k, D]
    std::vector<torch::Tensor> parts = {fg - fc.unsqueeze(1), fc.unsqueeze(1).expand({m, k, fc.size(1)})};   // (eq. 6)
    if (cfg.relative_position) {
        const auto p = x.slice(1, 0, 3);
        parts.push_back(p.index_select(0, groups.reshape(-1)).view({m, k, 3}) - p.index_select(0, centers).unsqueeze(1));
    }
    return std::get<0>(g->forward(torch::cat(parts, -1)).max(1));   // [m, D]  (eq. 7)
}

}  // namespace ltm
