// ptv3.cpp: per-scene voxelisation and the PTv3 U-Net forward (the config: nn/ptv3_config.h):
// stem -> encoder stages (pooling + blocks) -> decoder stages (unpooling + blocks) -> points.
#include "ltm/nn/ptv3.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "ltm/core/error.h"

namespace ltm {

namespace {


// Voxel key with 16 bits per axis: ordered by (x, y, z), decodable.  g [n, 3] int64 -> [n]
torch::Tensor pack_key(const torch::Tensor &g) {
    return g.select(1, 0).__lshift__(32) | g.select(1, 1).__lshift__(16) | g.select(1, 2);
}

// linspace(0, max_rate, n) as doubles (timm/PTv3 stochastic-depth schedule).
std::vector<double> drop_path_schedule(double max_rate, int64_t n) {
    std::vector<double> r(size_t(std::max<int64_t>(n, 0)), 0.0);
    for (int64_t i = 0; i < n && n > 1; ++i) r[size_t(i)] = max_rate * double(i) / double(n - 1);
    return r;
}

int64_t sum(const std::vector<int64_t> &v) {
    int64_t s = 0;
    for (auto x : v) s += x;
    return s;
}

}  // namespace


// ---------------------------------------------------------------------------------------------
// Voxelisation

Voxelization voxelize(const torch::Tensor &coord, double grid_size) {
    TORCH_CHECK(coord.dim() == 2 && coord.size(1) == 3 && coord.is_floating_point(),
                "voxelize: coord must be float [m, 3], got ", coord.sizes(), " ",
                coord.scalar_type());
    TORCH_CHECK(coord.size(0) > 0, "voxelize: empty scene");
    TORCH_CHECK(grid_size > 0.0, "voxelize: grid_size must be > 0, got ", grid_size);
    TORCH_CHECK(torch::isfinite(coord).all().item<bool>(),
                "voxelize: coord has NaN or Inf entries (pitfall 3)");
    const auto rel = (coord - std::get<0>(coord.min(0))).to(torch::kDouble);
    const auto cells = torch::floor(rel / grid_size);
    const double max_cells = cells.max().item<double>();
    // Codes use 16 bits per axis (3·16 = 48 bits), notes pitfall 3.
    // Reachable from user data (a scene whose parts lie far apart for its point density), so an
    // ltm::Error in the user's terms, not a TORCH_CHECK.
    if (!(max_cells < 65536.0))
        LTM_THROW("scene too large for the encoder's grid: it spans ", max_cells + 1,
                  " grid cells on one axis, at most 65536 (parts of the scene lie too far apart for its point density)");
    const auto grid = cells.to(torch::kLong);
    auto [uniq, point_voxel, counts] = torch::_unique2(pack_key(grid), /*sorted=*/true,
                                                       /*return_inverse=*/true,
                                                       /*return_counts=*/true);
    Voxelization v;
    v.grid = torch::stack({uniq.__rshift__(32), uniq.__rshift__(16) & 0xFFFF, uniq & 0xFFFF}, 1);
    v.point_voxel = point_voxel;
    v.counts = counts;
    v.depth = serialization_depth(int64_t(max_cells));
    TORCH_CHECK(v.depth <= k_max_serialization_depth, "voxelize: depth ", v.depth, " > 16");
    return v;
}

// ---------------------------------------------------------------------------------------------
// PTv3

PTv3Impl::PTv3Impl(const PTv3Config &config) : cfg(config) {
    cfg.validate("PTv3Config");
    for (const auto &name : cfg.orders) m_orders.push_back(parse_serialization_order(name));
    const int64_t S = cfg.n_stages();
    const bool vanilla = cfg.attention == "vanilla";
    auto patch = [&](int64_t k) { return vanilla ? int64_t(0) : k; };  // 0: one patch per scene

    stem_linear = register_module("stem_linear",
                                  torch::nn::Linear(cfg.in_channels, cfg.enc_channels[0]));
    stem_norm = register_module(
        "stem_norm", torch::nn::LayerNorm(torch::nn::LayerNormOptions({cfg.enc_channels[0]})));

    const auto enc_rates = drop_path_schedule(cfg.drop_path, sum(cfg.enc_depths));
    size_t i_rate = 0;
    enc_blocks.resize(size_t(S));
    for (int64_t s = 0; s < S; ++s) {
        if (s > 0)
            pools.push_back(register_module(
                "pool" + std::to_string(s),
                SerializedPooling(cfg.enc_channels[size_t(s - 1)], cfg.enc_channels[size_t(s)])));
        for (int64_t i = 0; i < cfg.enc_depths[size_t(s)]; ++i)
            enc_blocks[size_t(s)].push_back(register_module(
                "enc" + std::to_string(s) + "_block" + std::to_string(i),
                PTv3Block(cfg.enc_channels[size_t(s)], cfg.enc_heads[size_t(s)],
                          patch(cfg.enc_patch_size[size_t(s)]), cfg.mlp_ratio,
                          enc_rates[i_rate++], cfg.enable_cpe)));
    }

    // Decoder stage s: unpool from the stage below (s + 1) with the encoder stage-s skip. Drop
    // rates are linspace over all decoder blocks, sliced by stage, reversed within the stage.
    const auto dec_rates = drop_path_schedule(cfg.drop_path, sum(cfg.dec_depths));
    dec_blocks.resize(size_t(std::max<int64_t>(S - 1, 0)));
    unpools.resize(dec_blocks.size(), nullptr);
    for (int64_t s = S - 2; s >= 0; --s) {
        const size_t us = size_t(s);
        const int64_t in_c = s == S - 2 ? cfg.enc_channels[us + 1] : cfg.dec_channels[us + 1];
        unpools[us] = register_module(
            "unpool" + std::to_string(s),
            SerializedUnpooling(in_c, cfg.enc_channels[us], cfg.dec_channels[us]));
        int64_t first = 0;
        for (int64_t t = 0; t < s; ++t) first += cfg.dec_depths[size_t(t)];
        const int64_t depth = cfg.dec_depths[us];
        for (int64_t i = 0; i < depth; ++i)
            dec_blocks[us].push_back(register_module(
                "dec" + std::to_string(s) + "_block" + std::to_string(i),
                PTv3Block(cfg.dec_channels[us], cfg.dec_heads[us], patch(cfg.dec_patch_size[us]),
                          cfg.mlp_ratio, dec_rates[size_t(first + depth - 1 - i)],
                          cfg.enable_cpe)));
    }
    point_proj = register_module("point_proj", torch::nn::Linear(cfg.in_channels, out_channels()));
}

int64_t PTv3Impl::out_channels() const {
    return cfg.dec_channels.empty() ? cfg.enc_channels[0] : cfg.dec_channels[0];
}

Serialization PTv3Impl::maybe_shuffle(Serialization s) {
    const int64_t n_orders = s.code.size(0);
    if (!is_training() || !cfg.shuffle_orders || n_orders < 2) return s;
    return permute_orders(s, torch::randperm(n_orders, rng, torch::kLong));
}

torch::Tensor PTv3Impl::forward(const torch::Tensor &feat, const torch::Tensor &coord) {
    TORCH_CHECK(feat.dim() == 2 && feat.size(1) == cfg.in_channels, "PTv3: feat must be [m, ",
                cfg.in_channels, "], got ", feat.sizes());
    TORCH_CHECK(coord.dim() == 2 && coord.size(1) == 3 && coord.size(0) == feat.size(0),
                "PTv3: coord must be [", feat.size(0), ", 3], got ", coord.sizes());
    const Voxelization vox = voxelize(coord, cfg.grid_size);
    const int64_t n_voxels = vox.grid.size(0), S = cfg.n_stages();

    // Merge points sharing a voxel: mean feature (PTv3 assumes unique voxels, pitfall 9).
    const auto summed = torch::zeros({n_voxels, feat.size(1)}, feat.options())
                            .index_add(0, vox.point_voxel, feat);
    auto x = summed / vox.counts.to(feat.scalar_type()).unsqueeze(1);
    x = torch::gelu(stem_norm->forward(stem_linear->forward(x)));

    // Per-stage structure: grid, serialization (all orders), CPE neighbour map; shared by the
    // encoder and decoder blocks of a stage (the decoder restores the stage's voxels exactly).
    struct Level {
        torch::Tensor grid, nbr;
        Serialization ser;
    };
    auto make_level = [&](const torch::Tensor &grid, Serialization ser) {
        return Level{grid, cfg.enable_cpe ? submanifold_neighbors(grid) : torch::Tensor(),
                     maybe_shuffle(std::move(ser))};
    };
    auto run_blocks = [&](std::vector<PTv3Block> &blocks, const Level &level, torch::Tensor h) {
        const int64_t n_orders = level.ser.order.size(0);
        for (size_t i = 0; i < blocks.size(); ++i) {
            const int64_t r = int64_t(i) % n_orders;  // block i uses order row i % S
            h = blocks[i]->forward(h, level.ser.order[r], level.ser.inverse[r], level.nbr, rng);
        }
        return h;
    };

    std::vector<Level> levels;
    std::vector<GridPooling> poolings;  // poolings[s - 1]: stage s - 1 -> stage s
    std::vector<torch::Tensor> skips;
    levels.push_back(make_level(vox.grid, serialize(vox.grid, vox.depth, m_orders)));
    for (int64_t s = 0; s < S; ++s) {
        if (s > 0) {
            const Level &fine = levels.back();
            poolings.push_back(grid_pooling(fine.grid));
            const GridPooling &gp = poolings.back();
            x = pools[size_t(s - 1)]->forward(x, gp);
            // encode(g, D) >> 3 == encode(g >> 1, D - 1) for every order (notes §1.3), so the
            // parents' codes are the children's shifted: no re-encoding, rows stay aligned.
            Serialization ser;
            ser.code = fine.ser.code.index_select(1, gp.head).__rshift__(3);
            std::tie(ser.order, ser.inverse) = sort_codes(ser.code);
            ser.depth = std::max(fine.ser.depth - 1, 0);
            levels.push_back(make_level(gp.parent_grid, std::move(ser)));
        }
        x = run_blocks(enc_blocks[size_t(s)], levels[size_t(s)], x);
        skips.push_back(x);
    }
    for (int64_t s = S - 2; s >= 0; --s) {
        const size_t us = size_t(s);
        x = unpools[us]->forward(x, skips[us], poolings[us].cluster);
        x = run_blocks(dec_blocks[us], levels[us], x);
    }
    // Every input point (duplicates included) gets its voxel's latent plus its own projection.
    return x.index_select(0, vox.point_voxel) + point_proj->forward(feat);
}

}  // namespace ltm
