// ptv3_blocks.cpp: PTv3's pre-norm block and the stride-2 grid pooling / unpooling of its U-Net
// (notes §1.6, §1.7; Sonata-style LayerNorm instead of BatchNorm).
#include "ltm/nn/ptv3.h"

#include <limits>

namespace ltm {

namespace {

// Stochastic depth per point (timm DropPath on [n, C]): keep a row with probability 1 - rate and
// rescale by 1 / (1 - rate), so the expectation is unchanged.  x [n, C] -> [n, C]
// The mask is drawn on the CPU generator rng and moved to x's device.
torch::Tensor apply_drop_path(const torch::Tensor &x, double rate, bool training, at::Generator &rng) {
    if (!training || rate <= 0.0) return x;
    const double keep = 1.0 - rate;
    const auto mask = torch::empty({x.size(0), 1}, torch::kFloat32).bernoulli_(keep, rng).to(x.options());
    return x * mask / keep;
}

torch::nn::LayerNorm layer_norm(int64_t c) {
    return torch::nn::LayerNorm(torch::nn::LayerNormOptions({c}));  // eps 1e-5, affine
}

}  // namespace

PTv3BlockImpl::PTv3BlockImpl(int64_t channels, int64_t n_heads, int64_t patch_size,
                             int64_t mlp_ratio, double drop_path_rate, bool enable_cpe)
    : drop_path(drop_path_rate) {
    if (enable_cpe) {
        cpe_conv = register_module("cpe_conv", SubmConv3(channels, channels));
        cpe_linear = register_module("cpe_linear", torch::nn::Linear(channels, channels));
        cpe_norm = register_module("cpe_norm", layer_norm(channels));
    }
    norm1 = register_module("norm1", layer_norm(channels));
    attn = register_module("attn", SerializedAttention(channels, n_heads, patch_size));
    norm2 = register_module("norm2", layer_norm(channels));
    fc1 = register_module("fc1", torch::nn::Linear(channels, mlp_ratio * channels));
    fc2 = register_module("fc2", torch::nn::Linear(mlp_ratio * channels, channels));
}

torch::Tensor PTv3BlockImpl::forward(const torch::Tensor &x_in, const torch::Tensor &order,
                                     const torch::Tensor &inverse, const torch::Tensor &nbr, at::Generator &rng) {
    auto x = x_in;
    // The CPE residual is not pre-normed and has no drop path (PTv3 Block.forward).
    if (cpe_conv) x = x + cpe_norm->forward(cpe_linear->forward(cpe_conv->forward(x, nbr)));
    x = x + apply_drop_path(attn->forward(norm1->forward(x), order, inverse), drop_path,
                            is_training(), rng);
    // Exact (erf) GELU, nn.GELU's default.
    const auto h = fc2->forward(torch::gelu(fc1->forward(norm2->forward(x))));
    return x + apply_drop_path(h, drop_path, is_training(), rng);
}

GridPooling grid_pooling(const torch::Tensor &grid) {
    TORCH_CHECK(grid.dim() == 2 && grid.size(1) == 3 && !grid.is_floating_point(),
                "grid_pooling: grid must be integer [n, 3], got ", grid.sizes());
    const int64_t n = grid.size(0);
    TORCH_CHECK(n > 0, "grid_pooling: empty grid");
    const auto coarse = grid.to(torch::kLong).__rshift__(1);
    // Coarse coords < 2^15: 16 bits per axis keep keys ordered by (x, y, z).
    const auto key = coarse.select(1, 0).__lshift__(32) | coarse.select(1, 1).__lshift__(16) |
                     coarse.select(1, 2);
    auto [uniq, cluster, counts] = torch::_unique2(key, /*sorted=*/true, /*return_inverse=*/true,
                                                   /*return_counts=*/true);
    const int64_t n_parents = uniq.size(0);
    // Unique fine voxels give at most 2³ children per parent.
    TORCH_CHECK(counts.max().item<int64_t>() <= 8,
                "grid_pooling: a parent has more than 8 children: the grid has duplicate voxels");
    // Children grouped by parent (stable, so lowest index first), then the rank inside a group.
    const auto grouped = torch::sort(cluster, /*stable=*/true, /*dim=*/0, /*descending=*/false);
    const auto &sorted_parent = std::get<0>(grouped);
    const auto &child = std::get<1>(grouped);
    const auto starts = counts.cumsum(0) - counts;
    const auto rank = torch::arange(n, cluster.options()) - starts.index_select(0, sorted_parent);
    GridPooling p;
    p.children = torch::full({n_parents * 8}, n, cluster.options())
                     .index_put_({sorted_parent * 8 + rank}, child)
                     .view({n_parents, 8});
    p.head = child.index_select(0, starts);
    p.parent_grid = coarse.index_select(0, p.head);
    p.cluster = cluster;
    return p;
}

SerializedPoolingImpl::SerializedPoolingImpl(int64_t in_channels, int64_t out_channels) {
    proj = register_module("proj", torch::nn::Linear(in_channels, out_channels));
    norm = register_module("norm", layer_norm(out_channels));
}

torch::Tensor SerializedPoolingImpl::forward(const torch::Tensor &x, const GridPooling &pooling) {
    TORCH_CHECK(x.dim() == 2 && x.size(0) == pooling.cluster.size(0),
                "SerializedPooling: x must be [", pooling.cluster.size(0), ", C], got ", x.sizes());
    const auto y = proj->forward(x);
    const int64_t c = y.size(1), n_parents = pooling.children.size(0);
    // Segment max as a padded gather: absent children read a -inf row, so max ignores them
    // (every parent has >= 1 child). The gradient goes to the argmax child, as torch_scatter.
    const auto y_pad =
        torch::cat({y, torch::full({1, c}, -std::numeric_limits<float>::infinity(), y.options())});
    const auto pooled = std::get<0>(
        y_pad.index_select(0, pooling.children.view(-1)).view({n_parents, 8, c}).max(1));
    return torch::gelu(norm->forward(pooled));
}

SerializedUnpoolingImpl::SerializedUnpoolingImpl(int64_t in_channels, int64_t skip_channels,
                                                 int64_t out_channels) {
    proj = register_module("proj", torch::nn::Linear(in_channels, out_channels));
    norm = register_module("norm", layer_norm(out_channels));
    proj_skip = register_module("proj_skip", torch::nn::Linear(skip_channels, out_channels));
    norm_skip = register_module("norm_skip", layer_norm(out_channels));
}

torch::Tensor SerializedUnpoolingImpl::forward(const torch::Tensor &coarse,
                                               const torch::Tensor &skip,
                                               const torch::Tensor &cluster) {
    TORCH_CHECK(cluster.dim() == 1 && skip.dim() == 2 && skip.size(0) == cluster.size(0) &&
                    coarse.dim() == 2,
                "SerializedUnpooling: skip [n, C] and cluster [n] must agree, got ", skip.sizes(),
                " and ", cluster.sizes());
    const auto up = torch::gelu(norm->forward(proj->forward(coarse)));
    return torch::gelu(norm_skip->forward(proj_skip->forward(skip))) + up.index_select(0, cluster);
}

}  // namespace ltm
