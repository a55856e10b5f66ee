// fused_decoder.cpp: the decoder for k_tile queries at a time. Row-wise layers (embed, FFN, out)
// run as small GEMMs over the tile so their weights are read once per tile; the κ-wise attention
// runs per query on [κ, D] blocks in L1. Loops are plain C++ for the auto-vectoriser; decode_tile
// is cloned for x86-64-v3 (AVX2 + FMA) and baseline x86-64 and picked at load time (ifunc).
#include "ltm/nn/fused_decoder.h"

#include <ATen/Parallel.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "ltm/core/simd_clones.h"
#include "ltm/nn/cpu_kernels.h"

namespace ltm {
namespace {

using Dense = FusedDecoder::Dense;
using Norm = FusedDecoder::Norm;
using Weights = FusedDecoder::Weights;

constexpr int k_tile = 8;          // queries per tile: FFN weights (128 KB/block) read once per tile
constexpr float k_ln_eps = 1e-5f;  // torch::nn::LayerNorm default

using kernels::exp_inplace;
using kernels::gelu;
using kernels::gemm;
using kernels::Vec8;

// LayerNorm with a layer's affine parameters.   x, y [rows, n] (may alias)
void layer_norm(const float *x, float *y, int rows, int n, const Norm &ln) {
    kernels::layer_norm(x, y, rows, n, ln.w.data(), ln.b.data(), k_ln_eps);
}

//   x [rows, l.in] (row stride ldx)  ->  y [rows, l.out] (row stride ldy)
void linear(const float *x, int ldx, int rows, const Dense &l, float *y, int ldy) {
    gemm(x, ldx, /*ldk=*/1, rows, l.in, l.wt.data(), l.out, l.out, l.b.data(), y, ldy);
}

// ---------------------------------------------------------------------------------------------
// Per-thread buffers for one tile. The attention keeps η and the group logits channel-major
// ([D, κ], [G, κ]) so that its GEMMs and MLP_w's LayerNorm over G run along κ, 8 neighbours a vector.
struct Scratch {
    std::vector<float> h, x, t, c, eta_t, rel_t, logit_t, weight, u_t, col, attn;
    Scratch(const Weights &w, int kappa) {
        const size_t d = size_t(w.dim), g = size_t(w.groups), k = size_t(kappa);
        h.resize(k_tile * d), x.resize(k_tile * d), t.resize(k_tile * size_t(w.ffn_dim)), c.resize(k_tile * g);
        eta_t.resize(k_tile * d * k), rel_t.resize(3 * k), logit_t.resize(g * k), weight.resize(k * g);
        u_t.resize(d * g), col.resize(2 * std::max(k, g)), attn.resize(d);
    }
};

// ηᵀ = relu(W_1·Δpᵀ + b_1) for one query, Δp = p_query − p_anchor (eq. 10).   -> eta_t [D, κ]
void position_hidden(const Weights &w, const float *query, const float *anchors, const int64_t *idx, int kappa,
                     float *__restrict rel_t, float *__restrict eta_t) {
    const int d = w.dim;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < kappa; ++j) rel_t[i * kappa + j] = query[i] - anchors[idx[j] * 3 + i];
    // x(c, t) = W_1[c, t] = pos1.wt[t·D + c]
    gemm(w.pos1.wt.data(), /*ldx=*/1, /*ldk=*/d, d, /*in=*/3, rel_t, kappa, kappa, nullptr, eta_t, kappa);
    for (int c = 0; c < d; ++c)
        for (int j = 0; j < kappa; ++j) eta_t[c * kappa + j] = std::max(eta_t[c * kappa + j] + w.pos1.b[size_t(c)], 0.f);
}

// LayerNorm over the n rows of each column (MLP_w's LN(G) per neighbour).   x [n, cols] in place
void layer_norm_columns(float *__restrict x, int n, int cols, const Norm &ln, float *__restrict mean, float *__restrict inv) {
    for (int j = 0; j < cols; ++j) mean[j] = 0.f, inv[j] = 0.f;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < cols; ++j) mean[j] += x[i * cols + j];
    for (int j = 0; j < cols; ++j) mean[j] /= float(n);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < cols; ++j) inv[j] += (x[i * cols + j] - mean[j]) * (x[i * cols + j] - mean[j]);
    for (int j = 0; j < cols; ++j) inv[j] = 1.f / std::sqrt(inv[j] / float(n) + k_ln_eps);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < cols; ++j) x[i * cols + j] = (x[i * cols + j] - mean[j]) * inv[j] * ln.w[size_t(i)] + ln.b[size_t(i)];
}

// Softmax over κ of each of the G columns.   x [κ, G] in place; col_max, col_sum [G] scratch
void softmax_columns(float *__restrict x, int kappa, int groups, float *__restrict col_max, float *__restrict col_sum) {
    for (int g = 0; g < groups; ++g) col_max[g] = x[g], col_sum[g] = 0.f;
    for (int j = 1; j < kappa; ++j)
        for (int g = 0; g < groups; ++g) col_max[g] = std::max(col_max[g], x[j * groups + g]);
    for (int j = 0; j < kappa; ++j)
        for (int g = 0; g < groups; ++g) x[j * groups + g] -= col_max[g];
    exp_inplace(x, kappa * groups);
    for (int j = 0; j < kappa; ++j)
        for (int g = 0; g < groups; ++g) col_sum[g] += x[j * groups + g];
    for (int j = 0; j < kappa; ++j)
        for (int g = 0; g < groups; ++g) x[j * groups + g] /= col_sum[g];
}

// out[c] += Σ_κ w[κ, g(c)]·v[idx_κ, c], g(c) = c / gs.   w [κ, G], values [m, D]  ->  out [D]
void value_sum(const float *__restrict wgt, const float *__restrict values, const int64_t *idx, int kappa, int d,
               int g_n, float *__restrict out) {
    const int gs = d / g_n;
    if (d == 64 && gs % 8 == 0) {   // cpu preset: 8 accumulators in registers, 8 channels share a weight
        Vec8 acc[8];
        int group[8];
        for (int v = 0; v < 8; ++v) std::memcpy(&acc[v], out + 8 * v, sizeof(Vec8)), group[v] = 8 * v / gs;
        for (int j = 0; j < kappa; ++j) {
            const float *__restrict row = values + idx[j] * 64;
            for (int v = 0; v < 8; ++v) {
                Vec8 vv;
                std::memcpy(&vv, row + 8 * v, sizeof vv);
                acc[v] += wgt[j * g_n + group[v]] * vv;
            }
        }
        for (int v = 0; v < 8; ++v) std::memcpy(out + 8 * v, &acc[v], sizeof(Vec8));
        return;
    }
    for (int j = 0; j < kappa; ++j) {
        const float *__restrict row = values + idx[j] * d;
        for (int g = 0; g < g_n; ++g)
            for (int c = g * gs; c < (g + 1) * gs; ++c) out[c] += wgt[j * g_n + g] * row[c];
    }
}

// out[c] += Σ_k u[k, g(c)]·wt[k, c], g(c) = c / gs: each output group takes its own column of u.
//   u_t [in, G], wt [in, n_out] (n_out = G·gs)  ->  out [n_out]
void grouped_gemv(const float *__restrict u_t, int in, int g_n, const float *__restrict wt, int n_out, float *__restrict out) {
    const int gs = n_out / g_n;
    if (n_out == 64 && gs % 8 == 0) {   // cpu preset: 8 accumulators in registers
        Vec8 acc[8];
        for (int v = 0; v < 8; ++v) acc[v] = Vec8{};
        for (int k = 0; k < in; ++k)
            for (int v = 0; v < 8; ++v) {
                Vec8 w;
                std::memcpy(&w, wt + size_t(k) * 64 + 8 * v, sizeof w);
                acc[v] += u_t[k * g_n + 8 * v / gs] * w;
            }
        for (int v = 0; v < 8; ++v)
            for (int l = 0; l < 8; ++l) out[8 * v + l] += acc[v][l];
        return;
    }
    for (int c = 0; c < n_out; ++c) {
        float acc = 0.f;
        for (int k = 0; k < in; ++k) acc += u_t[k * g_n + c / gs] * wt[size_t(k) * size_t(n_out) + size_t(c)];
        out[c] += acc;
    }
}

// One query's attention output of one block (eqs. 12–13, folded as in the header).
//   c [G] (= logit_q(LN h)), eta_t [D, κ], idx [κ]  ->  out [D]
void attend(const Weights &w, const FusedDecoder::Block &blk, const float *c, const float *eta_t, const int64_t *idx,
            int kappa, Scratch &s, float *out) {
    const int d = w.dim, g_n = w.groups;
    float *logit_t = s.logit_t.data(), *wgt = s.weight.data();
    // Group logits W_w1·A, [G, κ] = (W_w1 W_2)[G, D]·ηᵀ + c − (W_w1 G^k)[idx]; x(g, k) = logit_pos.wt[k·G + g].
    gemm(blk.logit_pos.wt.data(), /*ldx=*/1, /*ldk=*/g_n, g_n, d, eta_t, kappa, kappa, nullptr, logit_t, kappa);
    for (int j = 0; j < kappa; ++j) {
        const float *kl = blk.key_logit.data() + idx[j] * g_n;
        for (int g = 0; g < g_n; ++g) logit_t[g * kappa + j] += c[g] - kl[g];
    }
    // Rest of MLP_w (LN → GELU → Linear), back to [κ, G]; softmax over κ per group.
    layer_norm_columns(logit_t, g_n, kappa, blk.w_norm, s.col.data(), s.col.data() + kappa);
    gelu(logit_t, g_n * kappa);
    gemm(logit_t, /*ldx=*/1, /*ldk=*/kappa, kappa, g_n, blk.w_out.wt.data(), g_n, g_n, blk.w_out.b.data(), wgt, g_n);
    softmax_columns(wgt, kappa, g_n, s.col.data(), s.col.data() + g_n);
    // u_g = Σ_κ w_g η, channel-major [D, G] = ηᵀ [D, κ]·w [κ, G].
    gemm(eta_t, kappa, 1, d, kappa, wgt, g_n, g_n, nullptr, s.u_t.data(), g_n);
    // out = b_2 + Σ_κ w_g(c) G^v[idx] + W_2·u_g(c), channel c in contiguous group g(c) = c / (D/G).
    for (int i = 0; i < d; ++i) out[i] = w.pos2.b[size_t(i)];
    value_sum(wgt, blk.values.data(), idx, kappa, d, g_n, out);
    grouped_gemv(s.u_t.data(), d, g_n, w.pos2.wt.data(), d, out);
}

// The whole decoder for rows ≤ k_tile queries.   query [rows, w.query_width], idx [rows, κ]  ->  z [rows, 3]
// Each target clone gets its own vectorised copy of every helper (core/simd_clones.h).
LTM_SIMD_CLONES
void decode_tile(const Weights &w, Scratch &s, const float *query, const float *anchors, const int64_t *idx,
                 int kappa, int rows, float *z) {
    const int d = w.dim, g_n = w.groups, n_ffn = w.ffn_dim, qw = w.query_width;
    float *h = s.h.data(), *x = s.x.data(), *t = s.t.data();
    // 𝓗 (eq. 9): h = Linear(GELU(LN(Linear(q))))   [rows, D]
    linear(query, qw, rows, w.embed1, x, d);
    layer_norm(x, x, rows, d, w.embed_ln);
    gelu(x, rows * d);
    linear(x, d, rows, w.embed2, h, d);
    for (int r = 0; r < rows; ++r)
        position_hidden(w, query + r * qw, anchors, idx + r * kappa, kappa, s.rel_t.data(), s.eta_t.data() + r * d * kappa);
    for (const auto &blk : w.blocks) {
        // h += Attn(LN h)
        layer_norm(h, x, rows, d, blk.norm);
        linear(x, d, rows, blk.logit_q, s.c.data(), g_n);
        for (int r = 0; r < rows; ++r) {
            attend(w, blk, s.c.data() + r * g_n, s.eta_t.data() + r * d * kappa, idx + r * kappa, kappa, s, s.attn.data());
            for (int i = 0; i < d; ++i) h[r * d + i] += s.attn[size_t(i)];
        }
        // h += FFN(LN h), FFN = Linear → LN → GELU → Linear
        layer_norm(h, x, rows, d, blk.ffn_norm);
        linear(x, d, rows, blk.ffn1, t, n_ffn);
        layer_norm(t, t, rows, n_ffn, blk.ffn_ln);
        gelu(t, rows * n_ffn);
        linear(t, n_ffn, rows, blk.ffn2, x, d);
        for (int i = 0; i < rows * d; ++i) h[i] += x[i];
    }
    // 𝓦_out (eq. 14): softplus(Linear(GELU(Linear(LN h))))
    layer_norm(h, x, rows, d, w.out_ln);
    linear(x, d, rows, w.out1, t, d);
    gelu(t, rows * d);
    linear(t, d, rows, w.out2, z, 3);
    if (!w.skip.empty())   // u_c += skip_c · x_c, x the query's last 3 columns (QueryDecoderImpl::output)
        for (int r = 0; r < rows; ++r)
            for (int c = 0; c < 3; ++c) z[r * 3 + c] += w.skip[size_t(c)] * query[r * qw + qw - 3 + c];
    for (int i = 0; i < rows * 3; ++i) z[i] = z[i] > 20.f ? z[i] : std::log1p(std::exp(z[i]));   // torch threshold 20
}

// ---------------------------------------------------------------------------------------------
// Weight extraction.

std::vector<float> to_vector(const torch::Tensor &t) {
    const auto c = t.detach().to(torch::kFloat32).contiguous();
    return std::vector<float>(c.data_ptr<float>(), c.data_ptr<float>() + c.numel());
}
Dense dense(const torch::Tensor &weight, const torch::Tensor &bias) {   // weight [out, in] as torch
    Dense l;
    l.out = int(weight.size(0)), l.in = int(weight.size(1));
    l.wt = to_vector(weight.t()), l.b = to_vector(bias);
    return l;
}
Norm norm(const torch::Tensor &weight, const torch::Tensor &bias) { return Norm{to_vector(weight), to_vector(bias)}; }

}  // namespace

FusedDecoder::FusedDecoder(const QueryDecoderImpl &dec) {
    TORCH_CHECK(dec.cfg.type == "attention", "FusedDecoder: only the \"attention\" decoder is fused, got \"", dec.cfg.type, "\"");
    TORCH_CHECK(dec.cfg.dim % dec.cfg.groups == 0, "FusedDecoder: dim ", dec.cfg.dim, " not divisible by groups ", dec.cfg.groups);
    torch::NoGradGuard no_grad;
    const auto params = dec.named_parameters();
    const auto p = [&](const std::string &name) {
        const torch::Tensor *t = params.find(name);
        TORCH_CHECK(t != nullptr, "FusedDecoder: decoder has no parameter '", name, "'");
        return t->detach().to(torch::kCPU, torch::kFloat64);
    };
    const auto lin = [&](const std::string &n) { return dense(p(n + ".weight"), p(n + ".bias")); };
    const auto ln = [&](const std::string &n) { return norm(p(n + ".weight"), p(n + ".bias")); };
    m_w.dim = int(dec.cfg.dim), m_w.groups = int(dec.cfg.groups), m_w.ffn_dim = int(dec.cfg.ffn_ratio * dec.cfg.dim);
    m_w.query_width = 9 + dec.cfg.extra_inputs;
    // Without absolute positions 𝓗 sees (0, 0, 0, n, albedo): the same as zero weight columns for p.
    auto embed1_w = p("embed.0.weight");
    if (!dec.cfg.absolute_position) embed1_w.slice(1, 0, 3).zero_();
    m_w.embed1 = dense(embed1_w, p("embed.0.bias")), m_w.embed_ln = ln("embed.1"), m_w.embed2 = lin("embed.3");
    m_w.pos1 = lin("pos_mlp.0"), m_w.pos2 = lin("pos_mlp.2");
    m_w.out_ln = ln("out.0"), m_w.out1 = lin("out.1"), m_w.out2 = lin("out.3");
    if (dec.cfg.skip_inputs > 0) m_w.skip = to_vector(p("skip"));
    const auto w2 = p("pos_mlp.2.weight"), b2 = p("pos_mlp.2.bias");
    for (int l = 0; l < dec.cfg.n_layers; ++l) {
        const std::string a = "attention." + std::to_string(l), n = std::to_string(l);
        Block blk;
        const auto w_w1 = p(a + ".weight_mlp.0.weight");   // [G, D]
        blk.norm = ln("norms." + n);
        blk.logit_q = dense(w_w1.matmul(p(a + ".to_q.weight")),
                            w_w1.matmul(p(a + ".to_q.bias") + b2) + p(a + ".weight_mlp.0.bias"));
        blk.logit_pos = dense(w_w1.matmul(w2), torch::zeros({w_w1.size(0)}, torch::kFloat64));
        blk.w_norm = ln(a + ".weight_mlp.1"), blk.w_out = lin(a + ".weight_mlp.3");
        blk.ffn_norm = ln("ffn_norms." + n);
        blk.ffn1 = lin("ffn." + n + ".0"), blk.ffn_ln = ln("ffn." + n + ".1"), blk.ffn2 = lin("ffn." + n + ".3");
        blk.to_k_w = p(a + ".to_k.weight"), blk.to_k_b = p(a + ".to_k.bias");
        blk.to_v_w = p(a + ".to_v.weight"), blk.to_v_b = p(a + ".to_v.bias");
        blk.w_w1 = w_w1;
        m_w.blocks.push_back(std::move(blk));
    }
}

void FusedDecoder::prepare(const torch::Tensor &latents) {
    TORCH_CHECK(latents.dim() == 2 && !m_w.blocks.empty() && latents.size(1) == m_w.blocks[0].to_k_w.size(1),
                "FusedDecoder::prepare: latents must be [m, C] with C of the decoder, got ", latents.sizes());
    torch::NoGradGuard no_grad;
    const auto lat = latents.detach().to(torch::kCPU, torch::kFloat64);
    for (auto &blk : m_w.blocks) {
        const auto keys = torch::addmm(blk.to_k_b, lat, blk.to_k_w.t());   // G^k [m, D]
        blk.key_logit = to_vector(keys.matmul(blk.w_w1.t()));              // [m, G]
        blk.values = to_vector(torch::addmm(blk.to_v_b, lat, blk.to_v_w.t()));
    }
    m_w.n_latents = latents.size(0);
}

torch::Tensor FusedDecoder::forward(const torch::Tensor &query, const torch::Tensor &anchors, const torch::Tensor &idx) const {
    TORCH_CHECK(m_w.n_latents >= 0, "FusedDecoder::forward: call prepare(latents) first");
    TORCH_CHECK(query.dim() == 2 && query.size(1) == m_w.query_width, "FusedDecoder: query must be [N, ", m_w.query_width, "], got ",
                query.sizes());
    TORCH_CHECK(anchors.dim() == 2 && anchors.size(1) == 3 && anchors.size(0) == m_w.n_latents,
                "FusedDecoder: anchors must be [m, 3] with m = ", m_w.n_latents, ", got ", anchors.sizes());
    TORCH_CHECK(idx.dim() == 2 && idx.size(0) == query.size(0) && idx.size(1) > 0 && idx.scalar_type() == torch::kInt64,
                "FusedDecoder: idx must be int64 [N, κ], got ", idx.sizes(), " ", idx.scalar_type());
    const int64_t n = query.size(0);
    const int kappa = int(idx.size(1));
    auto z = torch::empty({n, 3});
    if (n == 0) return z;
    const auto q = query.to(torch::kCPU, torch::kFloat32).contiguous();
    const auto a = anchors.to(torch::kCPU, torch::kFloat32).contiguous();
    const auto ix = idx.to(torch::kCPU).contiguous();
    TORCH_CHECK(ix.min().item<int64_t>() >= 0 && ix.max().item<int64_t>() < m_w.n_latents,
                "FusedDecoder: idx out of range [0, ", m_w.n_latents, ")");
    const float *qp = q.data_ptr<float>(), *ap = a.data_ptr<float>();
    const int64_t *ip = ix.data_ptr<int64_t>();
    float *zp = z.data_ptr<float>();
    at::parallel_for(0, (n + k_tile - 1) / k_tile, /*grain_size=*/1, [&](int64_t begin, int64_t end) {
        Scratch s(m_w, kappa);
        for (int64_t tile = begin; tile < end; ++tile) {
            const int64_t r0 = tile * k_tile;
            decode_tile(m_w, s, qp + r0 * m_w.query_width, ap, ip + r0 * kappa, kappa, int(std::min<int64_t>(k_tile, n - r0)), zp + r0 * 3);
        }
    });
    return z;
}

}  // namespace ltm
