// sparse_conv.cpp: neighbour map by sorted voxel keys + searchsorted, and the gather-GEMM conv.
#include "ltm/nn/sparse_conv.h"

namespace ltm {

namespace {

// Coordinates shifted by +1 fit in 17 bits (0 .. 2^16), so neighbour keys of border voxels
// (coordinate -1 or 2^16) are valid keys that simply never match: no masking needed.
// g [.., 3] int64 -> [..] int64
torch::Tensor voxel_key(const torch::Tensor &g) {
    const auto s = g + 1;
    return s.select(-1, 0).__lshift__(34) | s.select(-1, 1).__lshift__(17) | s.select(-1, 2);
}

}  // namespace

torch::Tensor submanifold_neighbors(const torch::Tensor &grid) {
    TORCH_CHECK(grid.dim() == 2 && grid.size(1) == 3 && !grid.is_floating_point(),
                "submanifold_neighbors: grid must be integer [n, 3], got ", grid.sizes(), " ",
                grid.scalar_type());
    const int64_t n = grid.size(0);
    const auto opts = grid.options().dtype(torch::kLong);
    if (n == 0) return torch::zeros({0, k_conv_offsets}, opts);
    const auto g = grid.to(torch::kLong);
    TORCH_CHECK(g.min().item<int64_t>() >= 0 && g.max().item<int64_t>() < (int64_t(1) << 16),
                "submanifold_neighbors: grid coordinates must lie in [0, 2^16)");
    const auto sorted = torch::sort(voxel_key(g));
    const auto &skeys = std::get<0>(sorted);
    const auto &perm = std::get<1>(sorted);
    // offsets [27, 3] in the documented order o = (ox+1)·9 + (oy+1)·3 + (oz+1)
    const auto r = torch::arange(-1, 2, opts);
    const auto offsets =
        torch::stack(torch::meshgrid({r, r, r}, "ij"), -1).view({k_conv_offsets, 3});
    const auto nkeys = voxel_key(g.unsqueeze(1) + offsets.unsqueeze(0));  // [n, 27]
    const auto pos = torch::searchsorted(skeys, nkeys).clamp_max(n - 1);
    const auto hit = skeys.index_select(0, pos.view(-1)).view_as(nkeys) == nkeys;
    return torch::where(hit, perm.index_select(0, pos.view(-1)).view_as(nkeys),
                        torch::full_like(nkeys, n));
}

SubmConv3Impl::SubmConv3Impl(int64_t in_channels_, int64_t out_channels_, bool with_bias)
    : in_channels(in_channels_), out_channels(out_channels_) {
    TORCH_CHECK(in_channels > 0 && out_channels > 0, "SubmConv3: channels must be > 0, got ",
                in_channels, " -> ", out_channels);
    // Same default as torch::nn::Conv3d / Linear: U(-1/sqrt(fan_in), 1/sqrt(fan_in)).
    const double bound = 1.0 / std::sqrt(double(k_conv_offsets * in_channels));
    weight = register_parameter("weight", torch::empty({k_conv_offsets * in_channels, out_channels})
                                              .uniform_(-bound, bound));
    if (with_bias)
        bias = register_parameter("bias", torch::empty({out_channels}).uniform_(-bound, bound));
}

torch::Tensor SubmConv3Impl::forward(const torch::Tensor &x, const torch::Tensor &nbr) {
    TORCH_CHECK(x.dim() == 2 && x.size(1) == in_channels, "SubmConv3: x must be [n, ",
                in_channels, "], got ", x.sizes());
    TORCH_CHECK(nbr.dim() == 2 && nbr.size(0) == x.size(0) && nbr.size(1) == k_conv_offsets,
                "SubmConv3: nbr must be [", x.size(0), ", 27], got ", nbr.sizes());
    const int64_t n = x.size(0);
    // Row n of x_pad is the zero "absent neighbour"; backward of index_select is an index_add.
    const auto x_pad = torch::cat({x, x.new_zeros({1, in_channels})});
    const auto gathered =
        x_pad.index_select(0, nbr.reshape(-1)).view({n, k_conv_offsets * in_channels});
    return bias.defined() ? torch::addmm(bias, gathered, weight) : torch::mm(gathered, weight);
}

}  // namespace ltm
