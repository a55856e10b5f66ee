// sparse_conv.h: submanifold 3×3×3 convolution on unique voxels as neighbour gather + one GEMM
// (PTv3's xCPE without spconv, notes §1.5). Deterministic and device-agnostic.
#pragma once

#include <cstdint>

#include <torch/torch.h>

namespace ltm {

/// Kernel offsets: index o = (ox+1)·9 + (oy+1)·3 + (oz+1) for (ox, oy, oz) ∈ {-1,0,1}³, where
/// x, y, z are the grid columns 0, 1, 2. o = 13 is the centre.
constexpr int64_t k_conv_offsets = 27;

/// For every voxel, the row of the voxel at each of the 27 offsets, or n if that voxel is absent
/// (callers append a zero row at index n). Built with sort + searchsorted, so any device.
///   grid [n, 3] integer, unique rows, coords in [0, 2^16)  ->  nbr [n, 27] int64
torch::Tensor submanifold_neighbors(const torch::Tensor &grid);

/// y_i = b + Σ_o W_oᵀ x_{nbr[i,o]} over present neighbours: a submanifold conv (outputs only at
/// active voxels, absent inputs read as zero). weight [27·C_in, C_out] stacks W_o by offset o,
/// so it equals torch::conv3d(dense, w, b, /*stride=*/1, /*padding=*/1) read at the active
/// voxels with W_o[c_in, c_out] = w[c_out, c_in, ox+1, oy+1, oz+1] (conv3d is a
/// cross-correlation; dense dims (X, Y, Z) = grid columns 0, 1, 2).
struct SubmConv3Impl : torch::nn::Module {
    SubmConv3Impl(int64_t in_channels, int64_t out_channels, bool bias = true);

    /// x [n, C_in], nbr [n, 27] int64 (from submanifold_neighbors)  ->  [n, C_out]
    torch::Tensor forward(const torch::Tensor &x, const torch::Tensor &nbr);

    torch::Tensor weight;  ///< [27·C_in, C_out]
    torch::Tensor bias;    ///< [C_out], undefined when built without bias
    int64_t in_channels = 0, out_channels = 0;
};
TORCH_MODULE(SubmConv3);

}  // namespace ltm
