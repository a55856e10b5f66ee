// query_decoder.h: the local query decoder (paper eqs. 9–14): each query attends to its κ
// nearest latent anchors with grouped vector cross-attention (PTv2), and predicts
// z = log1p(E⁺) ≥ 0. Also the knn-mean ablation (mean of the κ latents + MLP, Fig. 14).
#pragma once

#include <cstdint>

#include <torch/torch.h>

#include "ltm/nn/model_config.h"

namespace ltm {

/// One cross-attention block. G^q = W_q h, relation A = G^q − G^k + P (eq. 12) with
/// P = γ(Δp) computed once per query by the decoder and shared by all blocks (it depends only on
/// geometry; sharing it halves the [N, κ, D] work), weights = softmax_κ(MLP_w(A)) per group,
/// out = Σ_κ w ⊙ (G^v + P) (eq. 13).
struct VectorCrossAttentionImpl : torch::nn::Module {
    VectorCrossAttentionImpl(int64_t dim, int64_t latent_dim, int64_t groups);
    /// W_k, W_v applied to all m latents once (linear maps commute with the gather).
    ///   latents [m, C] -> (keys [m, D], values [m, D])
    std::pair<torch::Tensor, torch::Tensor> project_latents(const torch::Tensor &latents);
    //   h [N, D], keys/values [m, D], idx [N, κ], pos [N, κ, D] (= γ(Δp))  ->  [N, D]
    torch::Tensor forward(const torch::Tensor &h, const torch::Tensor &keys, const torch::Tensor &values,
                          const torch::Tensor &idx, const torch::Tensor &pos);
    int64_t groups;
    torch::nn::Linear to_q{nullptr}, to_k{nullptr}, to_v{nullptr};
    torch::nn::Sequential weight_mlp{nullptr};   // A → per-group weights
};
TORCH_MODULE(VectorCrossAttention);

/// The residual blocks both decoder heads stack (pre-norm): h += Attn(LN h); h += FFN(LN h).
/// Registered on the owning module as "attention", "norms", "ffn", "ffn_norms" (weight names).
struct CrossAttentionBlocks {
    torch::nn::ModuleList attention{nullptr}, norms{nullptr}, ffn{nullptr}, ffn_norms{nullptr};
    CrossAttentionBlocks() = default;
    CrossAttentionBlocks(torch::nn::Module &owner, int n_layers, int64_t dim, int64_t latent_dim, int64_t groups, int64_t ffn_ratio);
    //   h [N, D], latents [m, C], idx [N, κ], pos [N, κ, D] (= γ(Δp))  ->  [N, D]
    torch::Tensor forward(torch::Tensor h, const torch::Tensor &latents, const torch::Tensor &idx, const torch::Tensor &pos);
};

/// Δp = p_query − p_anchor of each query's κ anchors (paper eq. 10).
///   query [N, ≥3] (position first), anchors [m, 3], idx [N, κ] -> [N, κ, 3]
torch::Tensor anchor_offsets(const torch::Tensor &query, const torch::Tensor &anchors, const torch::Tensor &idx);

struct QueryDecoderImpl : torch::nn::Module {
    QueryDecoderImpl(const DecoderConfig &cfg, int64_t latent_dim);
    //   query [N, 9 + extra_inputs] (normalised p, n, albedo[, prior features][, ln(R / Ê)]), latents [m, C], anchors [m, 3], idx [N, κ]  ->  z [N, 3]
    torch::Tensor forward(const torch::Tensor &query, const torch::Tensor &latents, const torch::Tensor &anchors,
                          const torch::Tensor &idx);
    DecoderConfig cfg;
    /// Zeroes 𝓦_out's last Linear (and the skip): z = softplus(0) = ln 2 for every query, so expm1(z) = 1 and the
    /// model predicts exactly its prior (output_scale) — a start at the closed form, from which
    /// training only has to learn the correction. Gradients still reach every layer after the first step.
    void start_at_prior();
    /// The output layer's weight and bias (and the skip's weights): the tensors start_at_prior zeroes
    /// (trainer's output_decay).
    std::vector<torch::Tensor> output_parameters();
    /// Is 𝓦_out's last Linear exactly zero (weight and bias), and the skip if there is one? Then z = softplus(0) for every query,
    /// whatever the latents: the model is its prior (LtmModelImpl folds that constant).
    bool at_prior() const;
    /// Is 𝓦_out's last Linear exactly zero (weight and bias)? Then z = softplus(skip ⊙ x) whatever the
    /// latents and the attention: the body is silent, and only the skip (if any) moves the output.
    bool body_silent() const;
    /// Is there no skip, or is it exactly zero?
    bool skip_silent() const;
    torch::nn::Sequential embed{nullptr}, out{nullptr};            // 𝓗 (eq. 9) and 𝓦_out (eq. 14)
    torch::nn::Sequential pos_mlp{nullptr};                        // γ(Δp) (eq. 10): Linear → ReLU → Linear
    CrossAttentionBlocks blocks;                                   // attention decoder only
    torch::nn::ModuleList ffn{nullptr};                            // knn-mean ablation's one FFN
    torch::nn::Linear latent_proj{nullptr};                       // knn-mean ablation only
    /// [3] DecoderConfig::skip_inputs: the weights of the query's last columns added to 𝓦_out's
    /// pre-activation (zero at the prior); undefined without.
    torch::Tensor skip;
    /// 𝓦_out and the skip: z = softplus(𝓦_out(h) + skip ⊙ query[:, -skip_inputs:]).   h [N, D], query [N, W] -> [N, 3]
    torch::Tensor output(const torch::Tensor &h, const torch::Tensor &query);
};
TORCH_MODULE(QueryDecoder);

}  // namespace ltm
