// query_decoder.cpp: pre-norm residual blocks (h += Attn(LN h); h += FFN(LN h)), softplus output
// so z = log1p(E⁺) is never negative and the loss denominator stays positive.
#include "ltm/nn/query_decoder.h"

#include "ltm/nn/nn_embedding.h"
#include "ltm/nn/point_tensor.h"

namespace ltm {

VectorCrossAttentionImpl::VectorCrossAttentionImpl(int64_t dim, int64_t latent_dim, int64_t g) : groups(g) {
    to_q = register_module("to_q", torch::nn::Linear(dim, dim));
    to_k = register_module("to_k", torch::nn::Linear(latent_dim, dim));
    to_v = register_module("to_v", torch::nn::Linear(latent_dim, dim));
    weight_mlp = register_module("weight_mlp", make_mlp(dim, groups, groups));
}

std::pair<torch::Tensor, torch::Tensor> VectorCrossAttentionImpl::project_latents(const torch::Tensor &latents) {
    return {to_k->forward(latents), to_v->forward(latents)};
}

torch::Tensor VectorCrossAttentionImpl::forward(const torch::Tensor &h, const torch::Tensor &keys,
                                                const torch::Tensor &values, const torch::Tensor &idx,
                                                const torch::Tensor &pos) {
    TORCH_CHECK(h.dim() == 2 && idx.dim() == 2 && idx.size(0) == h.size(0), "VectorCrossAttention: h [N, D] and idx [N, κ] expected, got ",
                h.sizes(), " and ", idx.sizes());
    TORCH_CHECK(pos.dim() == 3 && pos.size(0) == h.size(0) && pos.size(1) == idx.size(1) && pos.size(2) == h.size(1),
                "VectorCrossAttention: pos must be [N, κ, D], got ", pos.sizes());
    const int64_t n = idx.size(0), kappa = idx.size(1), d = h.size(1);
    const auto flat = idx.reshape(-1);
    const auto gk = keys.index_select(0, flat).view({n, kappa, d});     // G^k  [N, κ, D]
    const auto gv = values.index_select(0, flat).view({n, kappa, d});   // G^v  [N, κ, D]
    const auto a = to_q->forward(h).unsqueeze(1) - gk + pos;             // A    (eq. 12)
    const auto w = torch::softmax(weight_mlp->forward(a), /*dim=*/1);    // [N, κ, G], sums to 1 over κ
    // Contiguous groups: channel c uses weight group c / (D/G).
    const auto val = (gv + pos).view({n, kappa, groups, d / groups});
    return (val * w.unsqueeze(-1)).sum(1).reshape({n, d});   // (eq. 13)
}

std::vector<torch::Tensor> QueryDecoderImpl::output_parameters() {
    auto *last = out[out->size() - 1]->as<torch::nn::LinearImpl>();
    TORCH_CHECK(last != nullptr, "the decoder's output layer is not a Linear");
    if (skip.defined()) return {last->weight, last->bias, skip};
    return {last->weight, last->bias};
}

void QueryDecoderImpl::start_at_prior() {
    torch::NoGradGuard no_grad;
    for (auto &t : output_parameters()) t.zero_();
}

bool QueryDecoderImpl::body_silent() const {
    const auto *last = out->ptr(out->size() - 1)->as<torch::nn::LinearImpl>();
    if (last == nullptr) return false;
    torch::NoGradGuard no_grad;
    return !last->weight.any().item<bool>() && !last->bias.any().item<bool>();
}

bool QueryDecoderImpl::skip_silent() const {
    torch::NoGradGuard no_grad;
    return !(skip.defined() && skip.any().item<bool>());
}

bool QueryDecoderImpl::at_prior() const { return body_silent() && skip_silent(); }

torch::Tensor QueryDecoderImpl::output(const torch::Tensor &h, const torch::Tensor &query) {
    auto u = out->forward(h);   // [N, 3]
    if (skip.defined()) u = u + skip * query.slice(1, query.size(1) - cfg.skip_inputs, query.size(1));
    return torch::softplus(u);   // z = log1p(E⁺ / scale) >= 0  (eq. 14)
}

QueryDecoderImpl::QueryDecoderImpl(const DecoderConfig &c, int64_t latent_dim) : cfg(c) {
    embed = register_module("embed", make_mlp(9 + cfg.extra_inputs, cfg.dim, cfg.dim));
    out = register_module("out", torch::nn::Sequential(torch::nn::LayerNorm(torch::nn::LayerNormOptions({cfg.dim})),
                                                       torch::nn::Linear(cfg.dim, cfg.dim), torch::nn::GELU(),
                                                       torch::nn::Linear(cfg.dim, 3)));
    if (cfg.skip_inputs > 0) {
        TORCH_CHECK(cfg.skip_inputs == 3 && cfg.extra_inputs >= 3, "QueryDecoder: skip_inputs must be 3 of the extra inputs, got ",
                    cfg.skip_inputs, " of ", cfg.extra_inputs);
        skip = register_parameter("skip", torch::zeros({3}));
    }
    if (cfg.type == "knn-mean") {
        latent_proj = register_module("latent_proj", torch::nn::Linear(latent_dim, cfg.dim));
        ffn = register_module("ffn", torch::nn::ModuleList(make_mlp(2 * cfg.dim, cfg.dim, cfg.dim)));
        return;
    }
    // No LayerNorm inside γ: it runs on [N, κ, D] and normalising there costs more than the MLP.
    pos_mlp = register_module("pos_mlp", torch::nn::Sequential(torch::nn::Linear(3, cfg.dim), torch::nn::ReLU(),
                                                               torch::nn::Linear(cfg.dim, cfg.dim)));
    blocks = CrossAttentionBlocks(*this, cfg.n_layers, cfg.dim, latent_dim, cfg.groups, cfg.ffn_ratio);
}

CrossAttentionBlocks::CrossAttentionBlocks(torch::nn::Module &owner, int n_layers, int64_t dim, int64_t latent_dim,
                                           int64_t groups, int64_t ffn_ratio) {
    attention = owner.register_module("attention", torch::nn::ModuleList());
    norms = owner.register_module("norms", torch::nn::ModuleList());
    ffn = owner.register_module("ffn", torch::nn::ModuleList());
    ffn_norms = owner.register_module("ffn_norms", torch::nn::ModuleList());
    for (int l = 0; l < n_layers; ++l) {
        attention->push_back(VectorCrossAttention(dim, latent_dim, groups));
        norms->push_back(torch::nn::LayerNorm(torch::nn::LayerNormOptions({dim})));
        ffn->push_back(make_mlp(dim, ffn_ratio * dim, dim));
        ffn_norms->push_back(torch::nn::LayerNorm(torch::nn::LayerNormOptions({dim})));
    }
}

torch::Tensor CrossAttentionBlocks::forward(torch::Tensor h, const torch::Tensor &latents, const torch::Tensor &idx,
                                            const torch::Tensor &pos) {
    for (size_t l = 0; l < attention->size(); ++l) {
        auto attn = attention[l]->as<VectorCrossAttentionImpl>();
        const auto [keys, values] = attn->project_latents(latents);
        h = h + attn->forward(norms[l]->as<torch::nn::LayerNormImpl>()->forward(h), keys, values, idx, pos);
        h = h + ffn[l]->as<torch::nn::SequentialImpl>()->forward(ffn_norms[l]->as<torch::nn::LayerNormImpl>()->forward(h));
    }
    return h;
}

torch::Tensor anchor_offsets(const torch::Tensor &query, const torch::Tensor &anchors, const torch::Tensor &idx) {
    const int64_t n = idx.size(0), kappa = idx.size(1);
    return query.slice(1, 0, 3).unsqueeze(1) - anchors.index_select(0, idx.reshape(-1)).view({n, kappa, 3});
}

torch::Tensor QueryDecoderImpl::forward(const torch::Tensor &query, const torch::Tensor &latents,
                                        const torch::Tensor &anchors, const torch::Tensor &idx) {
    TORCH_CHECK(query.dim() == 2 && query.size(1) == 9 + cfg.extra_inputs, "QueryDecoder: query must be [N, ", 9 + cfg.extra_inputs,
                "], got ", query.sizes());
    TORCH_CHECK(latents.dim() == 2 && anchors.dim() == 2 && anchors.size(1) == 3 && anchors.size(0) == latents.size(0),
                "QueryDecoder: latents [m, C] and anchors [m, 3] expected, got ", latents.sizes(), " and ", anchors.sizes());
    TORCH_CHECK(idx.dim() == 2 && idx.size(0) == query.size(0), "QueryDecoder: idx must be [N, κ], got ", idx.sizes());
    const int64_t n = idx.size(0), kappa = idx.size(1);
    auto h = embed->forward(cfg.absolute_position ? query : without_position(query));   // G̃_j (eq. 9)
    if (cfg.type == "knn-mean") {
        const auto lat = latent_proj->forward(latents).index_select(0, idx.reshape(-1)).view({n, kappa, -1}).mean(1);
        h = h + ffn[0]->as<torch::nn::SequentialImpl>()->forward(torch::cat({h, lat}, 1));
        return output(h, query);
    }
    // Δp = p_j − p_k, query minus neighbour (paper eq. 10); γ(Δp) [N, κ, D] shared by the blocks.
    const auto pos = pos_mlp->forward(anchor_offsets(query, anchors, idx));
    return output(blocks.forward(h, latents, idx, pos), query);
}

}  // namespace ltm
