// patch_attention.cpp: pad/unpad arithmetic (verified against Pointcept's
// get_padding_and_inverse in notes §1.4) and the patch attention kernels.
#include "ltm/nn/patch_attention.h"

namespace ltm {

PatchLayout patch_layout(const std::vector<int64_t> &counts, int64_t patch_size,
                         torch::Device device) {
    TORCH_CHECK(patch_size > 0, "patch_layout: patch_size must be > 0, got ", patch_size);
    const auto opts = torch::TensorOptions().dtype(torch::kLong).device(device);
    std::vector<torch::Tensor> pads, unpads;
    PatchLayout layout;
    int64_t off = 0, poff = 0;
    for (const int64_t n : counts) {
        TORCH_CHECK(n >= 0, "patch_layout: negative scene size ", n);
        const int64_t K = patch_size;
        const int64_t n_pad = n > K ? (n + K - 1) / K * K : n;
        const int64_t patch_len = std::min(n, K);
        // pad[poff + q] = off + q for q < n, off + q - K for the padding slots q >= n.
        auto q = torch::arange(n_pad, opts);
        pads.push_back(torch::where(q >= n, q - K, q) + off);
        unpads.push_back(torch::arange(n, opts) + poff);
        for (int64_t s = 0; s < n_pad; s += patch_len) layout.cu_seqlens.push_back(poff + s);
        off += n;
        poff += n_pad;
    }
    layout.cu_seqlens.push_back(poff);
    layout.pad = pads.empty() ? torch::zeros({0}, opts) : torch::cat(pads);
    layout.unpad = unpads.empty() ? torch::zeros({0}, opts) : torch::cat(unpads);
    return layout;
}

namespace {

// CPU timings (2-core machine, libtorch 1.13, fwd / bwd ms, [P·L = N, C, H, L]):
//   N=5120 C=32 H=2 L=256:    batched matmul 43 / 91,  contiguous-per-head mm loop 6.8 / 16,
//                             strided mm loop 7.6 / 14
//   N=5120 C=64 H=4 L=256:    batched 37 / 104, contiguous loop 19 / 50, strided loop 13 / 36
//   N=1280 C=64 H=4 L=256:    all ~3.4 / 5-7
//   N=10240 C=32 H=2 L=1024:  batched 467 / 525, contiguous loop 208 / 118, strided 43 / 69
// (bmm on a pre-permuted contiguous [P·H, L, d] was no better than matmul.) The strided loop
// also skips the permute copies, so it is the CPU kernel.

// qkv [P, L, 3C] -> [P·L, C]
torch::Tensor attention_loop(const torch::Tensor &qkv, int64_t H, double scale) {
    const int64_t P = qkv.size(0), C = qkv.size(2) / 3, d = C / H;
    std::vector<torch::Tensor> patches;
    patches.reserve(P);
    std::vector<torch::Tensor> heads(H);
    for (int64_t p = 0; p < P; ++p) {
        const auto x = qkv[p];  // [L, 3C]
        for (int64_t h = 0; h < H; ++h) {
            const auto q = x.narrow(1, h * d, d) * scale;
            const auto k = x.narrow(1, C + h * d, d);
            const auto v = x.narrow(1, 2 * C + h * d, d);
            heads[h] = torch::mm(torch::softmax(torch::mm(q, k.t()), -1), v);
        }
        patches.push_back(H == 1 ? heads[0] : torch::cat(heads, 1));
    }
    return P == 1 ? patches[0] : torch::cat(patches, 0);
}

// qkv [P, L, 3C] -> [P·L, C]
torch::Tensor attention_batched(const torch::Tensor &qkv, int64_t H, double scale) {
    const int64_t P = qkv.size(0), L = qkv.size(1), C = qkv.size(2) / 3, d = C / H;
    const auto t = qkv.view({P, L, 3, H, d}).permute({2, 0, 3, 1, 4});  // [3, P, H, L, d]
    torch::Tensor out;                                                  // [P, H, L, d]
#if TORCH_VERSION_MAJOR > 2 || (TORCH_VERSION_MAJOR == 2 && TORCH_VERSION_MINOR >= 1)
    // Memory-efficient / flash kernels on CUDA; logits stay in the input dtype (fp32 here).
    out = at::scaled_dot_product_attention(t[0], t[1], t[2], /*attn_mask=*/{}, /*dropout_p=*/0.0,
                                           /*is_causal=*/false, /*scale=*/scale);
#else
    const auto attn = torch::softmax(torch::matmul(t[0] * scale, t[1].transpose(-2, -1)), -1);
    out = torch::matmul(attn, t[2]);
#endif
    return out.permute({0, 2, 1, 3}).reshape({P * L, C});
}

}  // namespace

torch::Tensor patch_multi_head_attention(const torch::Tensor &qkv, int64_t n_heads, double scale,
                                         AttentionKernel kernel) {
    TORCH_CHECK(qkv.dim() == 3 && qkv.size(2) % (3 * n_heads) == 0,
                "patch_multi_head_attention: qkv must be [P, L, 3C] with C divisible by ", n_heads,
                " heads, got ", qkv.sizes());
    if (kernel == AttentionKernel::automatic)
        kernel = qkv.is_cpu() ? AttentionKernel::loop : AttentionKernel::batched;
    return kernel == AttentionKernel::loop ? attention_loop(qkv, n_heads, scale)
                                           : attention_batched(qkv, n_heads, scale);
}

SerializedAttentionImpl::SerializedAttentionImpl(int64_t channels_, int64_t n_heads_,
                                                 int64_t patch_size_)
    : channels(channels_), n_heads(n_heads_), patch_size(patch_size_) {
    TORCH_CHECK(channels > 0 && n_heads > 0 && channels % n_heads == 0,
                "SerializedAttention: channels ", channels,
                " must be a positive multiple of heads ", n_heads);
    scale = 1.0 / std::sqrt(double(channels / n_heads));
    qkv = register_module("qkv", torch::nn::Linear(channels, 3 * channels));
    proj = register_module("proj", torch::nn::Linear(channels, channels));
}

torch::Tensor SerializedAttentionImpl::forward(const torch::Tensor &x, const torch::Tensor &order,
                                               const torch::Tensor &inverse) {
    TORCH_CHECK(x.dim() == 2 && x.size(1) == channels, "SerializedAttention: x must be [n, ",
                channels, "], got ", x.sizes());
    const int64_t n = x.size(0);
    TORCH_CHECK(n > 0, "SerializedAttention: empty scene");
    TORCH_CHECK(order.dim() == 1 && order.size(0) == n && inverse.dim() == 1 &&
                    inverse.size(0) == n,
                "SerializedAttention: order and inverse must be [", n, "], got ", order.sizes(),
                " and ", inverse.sizes());
    const int64_t K = patch_size > 0 ? patch_size : n;
    const PatchLayout layout = patch_layout({n}, K, x.device());
    const int64_t L = std::min(n, K), P = layout.pad.size(0) / L;
    // Linear before the gather (as PTv3): padded slot -> sorted position -> token.
    const auto qkv_padded = qkv->forward(x).index_select(0, order.index_select(0, layout.pad));
    const auto out = patch_multi_head_attention(qkv_padded.view({P, L, 3 * channels}), n_heads,
                                                scale, kernel);
    // token -> sorted position -> own slot; the duplicate padding slots are dropped.
    return proj->forward(out.index_select(0, layout.unpad.index_select(0, inverse)));
}

}  // namespace ltm
