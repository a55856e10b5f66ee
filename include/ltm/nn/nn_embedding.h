// nn_embedding.h: the nearest-neighbour embedding of paper eqs. 5–7 (PCT's sample-and-group):
// 𝓕 lifts every scene point, FPS picks m centres, each centre groups its k nearest points,
// 𝓖 maps cat(X_j − X̃_l, X̃_l[, p_j − p̃_l]) and a max over the group gives the centre's token.
#pragma once

#include <cstdint>

#include <torch/torch.h>

#include "ltm/nn/model_config.h"

namespace ltm {

/// Linear → LayerNorm → GELU → Linear: the small MLP used throughout the model.
torch::nn::Sequential make_mlp(int64_t in, int64_t hidden, int64_t out);

struct NNEmbeddingImpl : torch::nn::Module {
    explicit NNEmbeddingImpl(const EmbeddingConfig &cfg);
    //   x [M, 12 + extra_inputs] (normalised scene points[, prior features]), centers [m] int64, groups [m, k] int64  ->  [m, D]
    torch::Tensor forward(const torch::Tensor &x, const torch::Tensor &centers, const torch::Tensor &groups);
    EmbeddingConfig cfg;
    torch::nn::Sequential f{nullptr}, g{nullptr};   // 𝓕 (eq. 5) and 𝓖 (eq. 7)
};
TORCH_MODULE(NNEmbedding);

}  // namespace ltm
