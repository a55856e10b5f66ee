// serialization.h: space-filling-curve codes of voxel grids (PTv3 "serialization", notes §1.3).
// Z-order and Skilling's Hilbert curve, bit-identical to Pointcept's encoders, plus the sorted
// order / inverse permutations that patch attention gathers with.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <torch/torch.h>

namespace ltm {

/// Largest bits per axis a code may use: 3·16 = 48 bits, and grid coords < 2^16 (pitfall 3).
constexpr int k_max_serialization_depth = 16;

/// Morton code: bit i of x, y, z goes to bit 3i+2, 3i+1, 3i (x most significant in a triple).
/// Only the low `depth` bits of each axis are used.
uint64_t z_encode(uint32_t x, uint32_t y, uint32_t z, int depth);

/// Hilbert code (Skilling 2004, as Pointcept's hilbert.py): depth-dependent, a bijection of the
/// 2^depth cube onto [0, 8^depth) whose consecutive codes are face neighbours, and
/// hilbert_encode(g, D) >> 3 == hilbert_encode(g >> 1, D - 1).
uint64_t hilbert_encode(uint32_t x, uint32_t y, uint32_t z, int depth);

/// The four PTv3 orders; "-trans" swaps x and y before encoding.
enum class SerializationOrder { z, z_trans, hilbert, hilbert_trans };

/// "z" | "z-trans" | "hilbert" | "hilbert-trans"; anything else throws ltm::Error.
SerializationOrder parse_serialization_order(const std::string &name);
std::string to_string(SerializationOrder order);

/// Bits per axis for a grid whose largest coordinate (any axis) is `max_coord`: the smallest D
/// with max_coord < 2^D, i.e. bit_length(max_coord) (PTv3's original rule; Sonata's
/// bit_length(max + 1) only differs at powers of two minus one). 0 for a single voxel.
int serialization_depth(int64_t max_coord);

/// Codes of every voxel for one order, tensorised (any device).
///   grid [n, 3] integer, coords in [0, 2^depth)  ->  [n] int64
torch::Tensor encode_grid(const torch::Tensor &grid, int depth, SerializationOrder order);

/// Serialization of one scene for S orders. order[s] maps sorted position -> voxel index
/// (sorted by (code, index): stable), inverse[s] maps voxel index -> sorted position.
struct Serialization {
    torch::Tensor code;     ///< [S, n] int64
    torch::Tensor order;    ///< [S, n] int64
    torch::Tensor inverse;  ///< [S, n] int64
    int depth = 0;          ///< bits per axis the codes were computed with
};

/// grid [n, 3] integer (one scene, coords in [0, 2^depth)), depth in [0, 16]  ->  Serialization
Serialization serialize(const torch::Tensor &grid, int depth,
                        const std::vector<SerializationOrder> &orders);

/// Stable sort of each row of `code` and the matching inverse permutation.
///   code [S, n] int64  ->  {order [S, n], inverse [S, n]}
std::pair<torch::Tensor, torch::Tensor> sort_codes(const torch::Tensor &code);

/// Permutes the rows (orders) of a serialization together (PTv3 shuffle_orders).
///   perm [S] int64 (a permutation of 0..S-1)
Serialization permute_orders(const Serialization &s, const torch::Tensor &perm);

}  // namespace ltm
