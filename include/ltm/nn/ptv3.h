// ptv3.h: the light transport encoder, a Point Transformer V3 U-Net (Wu et al. 2024; paper §4.2,
// notes §1). One scene at a time: points are voxelised per scene, serialized along 2-4
// space-filling curves, and processed by pre-norm blocks (xCPE, patch attention, MLP) with
// stride-2 grid pooling between stages. LayerNorm everywhere (Sonata style), Linear stem.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <ATen/CPUGeneratorImpl.h>
#include <torch/torch.h>

#include "ltm/nn/patch_attention.h"
#include "ltm/nn/ptv3_config.h"
#include "ltm/nn/serialization.h"
#include "ltm/nn/sparse_conv.h"

namespace ltm {

/// Pre-norm PTv3 block:  x += CPE(x);  x += DropPath(Attn(LN(x)));  x += DropPath(MLP(LN(x))).
struct PTv3BlockImpl : torch::nn::Module {
    PTv3BlockImpl(int64_t channels, int64_t n_heads, int64_t patch_size, int64_t mlp_ratio,
                  double drop_path, bool enable_cpe);

    /// x [n, C], order / inverse [n] int64 (one serialization row), nbr [n, 27] (undefined
    /// when CPE is off)  ->  [n, C]
    /// rng draws the drop-path masks in training (the encoder's own generator, PTv3Impl::rng).
    torch::Tensor forward(const torch::Tensor &x, const torch::Tensor &order,
                          const torch::Tensor &inverse, const torch::Tensor &nbr, at::Generator &rng);

    SubmConv3 cpe_conv{nullptr};
    torch::nn::Linear cpe_linear{nullptr};
    torch::nn::LayerNorm cpe_norm{nullptr}, norm1{nullptr}, norm2{nullptr};
    SerializedAttention attn{nullptr};
    torch::nn::Linear fc1{nullptr}, fc2{nullptr};
    double drop_path = 0.0;
};
TORCH_MODULE(PTv3Block);

/// Child -> parent structure of one stride-2 grid pooling (parents = unique(grid >> 1), ordered
/// by their voxel key, so independent of the children's order).
struct GridPooling {
    torch::Tensor parent_grid;  ///< [n_parents, 3] int64
    torch::Tensor cluster;      ///< [n] int64: child -> parent
    torch::Tensor children;     ///< [n_parents, 8] int64: children of each parent, padded with n
    torch::Tensor head;         ///< [n_parents] int64: one child of each parent (lowest index)
};

/// grid [n, 3] integer, unique rows  ->  GridPooling (same device)
GridPooling grid_pooling(const torch::Tensor &grid);

/// Pooled feature = GELU(LN(max over children of Linear(x))). Linear before the max, as PTv3.
struct SerializedPoolingImpl : torch::nn::Module {
    SerializedPoolingImpl(int64_t in_channels, int64_t out_channels);
    /// x [n, C_in], pooling of the same n voxels  ->  [n_parents, C_out]
    torch::Tensor forward(const torch::Tensor &x, const GridPooling &pooling);
    torch::nn::Linear proj{nullptr};
    torch::nn::LayerNorm norm{nullptr};
};
TORCH_MODULE(SerializedPooling);

/// Fine feature = GELU(LN(Linear(skip))) + GELU(LN(Linear(coarse)))[cluster].
struct SerializedUnpoolingImpl : torch::nn::Module {
    SerializedUnpoolingImpl(int64_t in_channels, int64_t skip_channels, int64_t out_channels);
    /// coarse [n_parents, C_in], skip [n, C_skip], cluster [n] int64  ->  [n, C_out]
    torch::Tensor forward(const torch::Tensor &coarse, const torch::Tensor &skip,
                          const torch::Tensor &cluster);
    torch::nn::Linear proj{nullptr}, proj_skip{nullptr};
    torch::nn::LayerNorm norm{nullptr}, norm_skip{nullptr};
};
TORCH_MODULE(SerializedUnpooling);

/// Voxels of one scene: grid = floor((coord - min coord) / grid_size); points sharing a voxel
/// are merged (PTv3 needs unique voxels, notes pitfall 9).
struct Voxelization {
    torch::Tensor grid;         ///< [n_voxels, 3] int64, unique rows sorted by (x, y, z)
    torch::Tensor point_voxel;  ///< [m] int64: point -> voxel
    torch::Tensor counts;       ///< [n_voxels] int64: points per voxel
    int depth = 0;              ///< serialization bits per axis (<= 16)
};

/// coord [m, 3] float, finite, extent / grid_size < 2^16  ->  Voxelization
Voxelization voxelize(const torch::Tensor &coord, double grid_size);

/// The encoder: Linear stem, U-Net of PTv3 blocks, per-point output.
struct PTv3Impl : torch::nn::Module {
    explicit PTv3Impl(const PTv3Config &cfg);

    /// One scene. feat [m, in_channels], coord [m, 3] (metres, any origin) -> [m, out_channels()]
    /// Points sharing a voxel share the network's output; each point also gets Linear(feat).
    torch::Tensor forward(const torch::Tensor &feat, const torch::Tensor &coord);
    int64_t out_channels() const;   ///< dec_channels[0], or enc_channels[0] without a decoder

    PTv3Config cfg;
    torch::nn::Linear stem_linear{nullptr};
    torch::nn::LayerNorm stem_norm{nullptr};
    torch::nn::Linear point_proj{nullptr};  ///< Linear(in, out): the per-point residual
    std::vector<std::vector<PTv3Block>> enc_blocks, dec_blocks;  ///< [stage][block]
    std::vector<SerializedPooling> pools;      ///< pools[s - 1] enters encoder stage s
    std::vector<SerializedUnpooling> unpools;  ///< unpools[s] enters decoder stage s
    /// The training randomness (order shuffles, drop-path masks) draws from this generator, owned
    /// by the module — never torch's global one. Seed 0 at construction; the trainer reseeds it per
    /// scene draw, so a step's randomness is a function of (seed, step).
    at::Generator rng = at::make_generator<at::CPUGeneratorImpl>(0);
    void reseed(uint64_t seed) { rng.set_current_seed(seed); }

private:
    std::vector<SerializationOrder> m_orders;
    /// Training + shuffle_orders: rows permuted by torch::randperm on rng (notes §1.3 step 4).
    Serialization maybe_shuffle(Serialization s);
};
TORCH_MODULE(PTv3);

}  // namespace ltm
