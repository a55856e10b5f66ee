// directional_decoder.cpp: the irradiance decoder's structure with a direction in its input.
#include "ltm/nn/directional_decoder.h"

#include <cmath>

#include "ltm/core/error.h"

#include "ltm/nn/nn_embedding.h"
#include "ltm/nn/point_tensor.h"

namespace ltm {

void check_directional_record(const SceneRecord &r, const DirectionalConfig &cfg) {
    if (r.bin_resolution != cfg.bin_resolution)
        LTM_THROW(r.path, ": ", r.bin_resolution ? "L_in over " + std::to_string(r.bin_resolution) + "² bins" : std::string("no L_in bins"),
                  ", the directional head expects ", cfg.bin_resolution, "² (a glossy preset, e.g. configs/data/glossy.json)");
    // Records from before the key hold the paper's L_in.
    const std::string held = r.metadata.value("preset", OrderedJson::object()).value("bin_radiance", std::string("incident"));
    if (held != cfg.radiance)
        LTM_THROW(r.path, ": bins hold \"", held, "\" radiance, the directional head predicts \"", cfg.radiance,
                  "\" (data preset bin_radiance / model directional.radiance)");
}

torch::Tensor direction_features(const torch::Tensor &d, const torch::Tensor &n, int frequencies) {
    TORCH_CHECK(d.dim() == 2 && d.size(1) == 3 && n.sizes() == d.sizes(), "direction_features: direction and normal must be [N, 3], got ",
                d.sizes(), " and ", n.sizes());
    std::vector<torch::Tensor> parts = {d, (d * n).sum(1, /*keepdim=*/true)};
    for (int k = 0; k < frequencies; ++k) {
        const auto x = d * (std::ldexp(M_PI, k));
        parts.push_back(torch::sin(x));
        parts.push_back(torch::cos(x));
    }
    return torch::cat(parts, 1);
}

DirectionalDecoderImpl::DirectionalDecoderImpl(const DirectionalConfig &c, int64_t latent_dim, bool abs_pos)
    : cfg(c), absolute_position(abs_pos) {
    embed = register_module("embed", make_mlp(cfg.input_width(), cfg.dim, cfg.dim));
    out = register_module("out", torch::nn::Sequential(torch::nn::LayerNorm(torch::nn::LayerNormOptions({cfg.dim})),
                                                       torch::nn::Linear(cfg.dim, cfg.dim), torch::nn::GELU(),
                                                       torch::nn::Linear(cfg.dim, 3)));
    pos_mlp = register_module("pos_mlp", torch::nn::Sequential(torch::nn::Linear(3, cfg.dim), torch::nn::ReLU(),
                                                               torch::nn::Linear(cfg.dim, cfg.dim)));
    blocks = CrossAttentionBlocks(*this, cfg.n_layers, cfg.dim, latent_dim, cfg.groups, cfg.ffn_ratio);
    start_uniform();
}

void DirectionalDecoderImpl::start_uniform() {
    torch::NoGradGuard no_grad;
    auto *last = out[out->size() - 1]->as<torch::nn::LinearImpl>();
    last->weight.zero_();
    last->bias.zero_();
}

torch::Tensor DirectionalDecoderImpl::forward(const torch::Tensor &query, const torch::Tensor &direction,
                                              const torch::Tensor &latents, const torch::Tensor &anchors,
                                              const torch::Tensor &idx) {
    TORCH_CHECK(query.dim() == 2 && query.size(1) == 9, "DirectionalDecoder: query must be [N, 9], got ", query.sizes());
    TORCH_CHECK(direction.dim() == 2 && direction.size(0) == query.size(0) && direction.size(1) == 3,
                "DirectionalDecoder: direction must be [N, 3] for N = ", query.size(0), " queries, got ", direction.sizes());
    TORCH_CHECK(latents.dim() == 2 && anchors.dim() == 2 && anchors.size(1) == 3 && anchors.size(0) == latents.size(0),
                "DirectionalDecoder: latents [m, C] and anchors [m, 3] expected, got ", latents.sizes(), " and ", anchors.sizes());
    TORCH_CHECK(idx.dim() == 2 && idx.size(0) == query.size(0), "DirectionalDecoder: idx must be [N, κ], got ", idx.sizes());
    const auto q = absolute_position ? query : without_position(query);
    auto h = embed->forward(torch::cat({q, direction_features(direction, query.slice(1, 3, 6), cfg.direction_frequencies)}, 1));
    const auto pos = pos_mlp->forward(anchor_offsets(query, anchors, idx));
    return torch::softplus(out->forward(blocks.forward(h, latents, idx, pos)));
}

}  // namespace ltm
