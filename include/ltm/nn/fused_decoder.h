// fused_decoder.h: inference-only CPU kernel of the local query decoder (type "attention"): the
// function of QueryDecoderImpl::forward computed a few queries at a time in plain C++ loops, so
// each query's [κ, D] work stays in L1 instead of ~15 eager libtorch passes over [N, κ, D].
#pragma once

#include <cstdint>

#include <vector>

#include <torch/torch.h>

#include "ltm/nn/query_decoder.h"

namespace ltm {

/// Usage: FusedDecoder f(*decoder); f.prepare(latents); z = f.forward(query, anchors, idx).
/// Holds a copy of the weights (~0.1 M floats for the cpu preset): rebuild it after the weights
/// change. Deterministic: every query goes through one fixed code path whatever the thread count.
///
/// Algebra (same function, fewer FLOPs): MLP_w's first Linear W_w1 is linear in A, so with
/// γ(Δp) = W_2·η + b_2, η = relu(W_1·Δp + b_1) (eq. 10):
///   W_w1·A = (W_w1 W_q)·LN(h) − (W_w1 G^k)[idx] + (W_w1 W_2)·η + W_w1·(b_q + b_2)      (eq. 12)
///   Σ_κ w_g (G^v + γ) = Σ_κ w_g G^v[idx] + W_2·(Σ_κ w_g η) + b_2   (Σ_κ w_g = 1)    (eq. 13)
/// so the [κ, D] matrix γ is never formed: per query and block the work is [κ, D]·[D, G] and
/// [G, κ]·[κ, D] instead of γ's [κ, D]·[D, D].
class FusedDecoder {
public:
    /// y = x · wt + b, the weight stored transposed so the inner loop runs over outputs.
    struct Dense {
        int in = 0, out = 0;
        std::vector<float> wt;   ///< [in, out]
        std::vector<float> b;    ///< [out]
    };
    struct Norm {
        std::vector<float> w, b;   ///< LayerNorm affine; eps 1e-5 as torch's default
    };
    struct Block {
        Norm norm;                      ///< LN(D) before the attention
        Dense logit_q;                  ///< D → G: W_w1·W_q, bias W_w1·(b_q + b_2) + b_w1
        Dense logit_pos;                ///< D → G: W_w1·W_2 applied to η, zero bias
        Norm w_norm;                    ///< LN(G) inside MLP_w
        Dense w_out;                    ///< G → G, MLP_w's second Linear
        Norm ffn_norm, ffn_ln;          ///< LN(D) before the FFN and LN(4D) inside it
        Dense ffn1, ffn2;               ///< D → 4D → D
        torch::Tensor to_k_w, to_k_b, to_v_w, to_v_b, w_w1;   ///< for prepare()
        std::vector<float> key_logit;   ///< [m, G] = W_w1·G^k   (prepare)
        std::vector<float> values;      ///< [m, D] = G^v          (prepare)
    };
    /// Everything decode needs, as plain arrays.
    struct Weights {
        int dim = 0, groups = 0, ffn_dim = 0;   ///< ffn_dim = ffn_ratio · dim
        int query_width = 9;                    ///< the query's columns: 9 + the decoder's extra_inputs
        int64_t n_latents = -1;                     ///< -1 until prepare()
        Dense embed1, embed2, pos1, pos2, out1, out2;   ///< pos1/pos2: γ's Linear layers
        Norm embed_ln, out_ln;
        std::vector<float> skip;   ///< [3] DecoderConfig::skip_inputs' weights on the query's last 3 columns; empty without
        std::vector<Block> blocks;
    };

    /// Copies (and pre-multiplies) the weights of an "attention" decoder; throws for "knn-mean".
    explicit FusedDecoder(const QueryDecoderImpl &decoder);
    /// Per-scene projections of the latents, once per block.   latents [m, C]
    void prepare(const torch::Tensor &latents);
    /// query [N, 9 + extra_inputs] (normalised p, n, albedo[, prior features]), anchors [m, 3], idx [N, κ] int64  ->  z [N, 3] (float, CPU)
    torch::Tensor forward(const torch::Tensor &query, const torch::Tensor &anchors, const torch::Tensor &idx) const;

private:
    Weights m_w;
};

}  // namespace ltm
