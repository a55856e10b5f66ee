// patch_attention.h: PTv3 serialized patch attention (notes §1.4). Tokens sorted along a
// space-filling curve are cut into patches of K; attention is full multi-head softmax attention
// inside each patch. Padding reuses real tokens (never masks), so any scene size works.
#pragma once

#include <cstdint>
#include <vector>

#include <torch/torch.h>

namespace ltm {

/// Index maps between sorted positions and padded patch slots for a batch of scenes laid out
/// one after another (scene i holds sorted positions [off_i, off_i + n_i)).
/// Per scene: n_pad = ceil(n/K)·K if n > K, else n (one n-token patch: a small scene never
/// shrinks K for the others, pitfall 6). Padding slot q >= n repeats position q - K, i.e. the
/// last patch holds each of the last K real tokens exactly once.
struct PatchLayout {
    torch::Tensor pad;    ///< [n_padded] int64: padded slot -> sorted position
    torch::Tensor unpad;  ///< [n] int64: sorted position -> its own padded slot
    /// Patch boundaries in padded slots: patch j is [cu_seqlens[j], cu_seqlens[j+1]).
    std::vector<int64_t> cu_seqlens;
};

/// counts [B] points per scene (>= 0), patch_size K > 0  ->  PatchLayout (tensors on `device`)
PatchLayout patch_layout(const std::vector<int64_t> &counts, int64_t patch_size,
                         torch::Device device = torch::kCPU);

/// How the per-patch products are computed; all give the same values.
enum class AttentionKernel {
    automatic,  ///< CPU: loop; other devices: batched (SDPA on libtorch >= 2.1)
    loop,       ///< torch::mm per (patch, head) on strided slices (fastest on CPU, see .cpp)
    batched,    ///< one matmul over [P, H, L, d]
};

/// softmax(scale · q kᵀ) v per patch and head.
///   qkv [P, L, 3C] with channels [q | k | v], head h at channels h·d .. h·d+d-1 of each part
///   ->  [P·L, C] (channel h·d + j)
torch::Tensor patch_multi_head_attention(const torch::Tensor &qkv, int64_t n_heads, double scale,
                                         AttentionKernel kernel = AttentionKernel::automatic);

/// qkv = Linear(C, 3C), H heads of d = C/H channels, scale d^-1/2, proj = Linear(C, C).
/// patch_size <= 0 means one patch per scene: global attention (the "vanilla" ablation).
struct SerializedAttentionImpl : torch::nn::Module {
    SerializedAttentionImpl(int64_t channels, int64_t n_heads, int64_t patch_size);

    /// One scene.  x [n, C], order [n] (sorted position -> token), inverse [n]
    /// (token -> sorted position), both int64  ->  [n, C]
    torch::Tensor forward(const torch::Tensor &x, const torch::Tensor &order,
                          const torch::Tensor &inverse);

    torch::nn::Linear qkv{nullptr}, proj{nullptr};
    int64_t channels = 0;
    int64_t n_heads = 1;
    int64_t patch_size = 0;
    double scale = 1.0;
    AttentionKernel kernel = AttentionKernel::automatic;
};
TORCH_MODULE(SerializedAttention);

}  // namespace ltm
