// serialization.cpp: z-order and Hilbert codes (scalar reference + tensorised, any device) and
// the stable sort that turns codes into PTv3's order / inverse permutations (notes §1.3).
#include "ltm/nn/serialization.h"

#include "ltm/core/error.h"

namespace ltm {

uint64_t z_encode(uint32_t x, uint32_t y, uint32_t z, int depth) {
    uint64_t k = 0;
    for (int i = 0; i < depth; ++i)
        k |= (uint64_t((x >> i) & 1u) << (3 * i + 2)) | (uint64_t((y >> i) & 1u) << (3 * i + 1)) |
             (uint64_t((z >> i) & 1u) << (3 * i));
    return k;
}

uint64_t hilbert_encode(uint32_t x, uint32_t y, uint32_t z, int depth) {
    uint32_t X[3] = {x, y, z};
    // Skilling's "inverse undo": from the top bit down, Q = 1<<b, P = Q-1.
    for (int b = depth - 1; b >= 1; --b) {
        const uint32_t Q = 1u << b, P = Q - 1;
        for (int i = 0; i < 3; ++i) {
            if (X[i] & Q) {
                X[0] ^= P;
            } else {
                const uint32_t t = (X[0] ^ X[i]) & P;
                X[0] ^= t;
                X[i] ^= t;
            }
        }
    }
    // Interleave MSB-first as (x, y, z) per level, with Gray -> binary as a running prefix xor.
    uint64_t code = 0;
    uint32_t acc = 0;
    for (int b = depth - 1; b >= 0; --b)
        for (int d = 0; d < 3; ++d) {
            acc ^= (X[d] >> b) & 1u;
            code = (code << 1) | acc;
        }
    return code;
}

SerializationOrder parse_serialization_order(const std::string &name) {
    if (name == "z") return SerializationOrder::z;
    if (name == "z-trans") return SerializationOrder::z_trans;
    if (name == "hilbert") return SerializationOrder::hilbert;
    if (name == "hilbert-trans") return SerializationOrder::hilbert_trans;
    LTM_THROW("parse_serialization_order(): unknown order '", name,
              "' (known: z, z-trans, hilbert, hilbert-trans)");
}

std::string to_string(SerializationOrder order) {
    switch (order) {
    case SerializationOrder::z: return "z";
    case SerializationOrder::z_trans: return "z-trans";
    case SerializationOrder::hilbert: return "hilbert";
    case SerializationOrder::hilbert_trans: return "hilbert-trans";
    }
    return "?";
}

int serialization_depth(int64_t max_coord) {
    TORCH_CHECK(max_coord >= 0, "serialization_depth(): negative grid coordinate ", max_coord);
    int bits = 0;
    for (uint64_t v = uint64_t(max_coord); v != 0; v >>= 1) ++bits;
    return bits;
}

namespace {

// The tensor versions below are line-by-line ports of the scalar encoders (tested equal);
// every op is elementwise on int64 [n], so they run on any device.

// x, y, z [n] int64 -> [n] int64
torch::Tensor z_encode_tensor(const torch::Tensor &x, const torch::Tensor &y,
                              const torch::Tensor &z, int depth) {
    auto k = torch::zeros_like(x);
    for (int i = 0; i < depth; ++i) {
        k = k | (x.__rshift__(i) & 1).__lshift__(3 * i + 2) |
            (y.__rshift__(i) & 1).__lshift__(3 * i + 1) | (z.__rshift__(i) & 1).__lshift__(3 * i);
    }
    return k;
}

// x, y, z [n] int64 -> [n] int64
torch::Tensor hilbert_encode_tensor(const torch::Tensor &x, const torch::Tensor &y,
                                    const torch::Tensor &z, int depth) {
    torch::Tensor X[3] = {x, y, z};
    for (int b = depth - 1; b >= 1; --b) {
        const int64_t Q = int64_t(1) << b, P = Q - 1;
        for (int i = 0; i < 3; ++i) {
            const auto hit = (X[i] & Q) != 0;
            const auto flipped = X[0] ^ P;
            if (i == 0) {  // the swap branch is a no-op when i == 0
                X[0] = torch::where(hit, flipped, X[0]);
                continue;
            }
            const auto t = (X[0] ^ X[i]) & P;
            X[0] = torch::where(hit, flipped, X[0] ^ t);
            X[i] = torch::where(hit, X[i], X[i] ^ t);
        }
    }
    auto code = torch::zeros_like(x);
    auto acc = torch::zeros_like(x);
    for (int b = depth - 1; b >= 0; --b)
        for (int d = 0; d < 3; ++d) {
            acc = acc ^ (X[d].__rshift__(b) & 1);
            code = code.__lshift__(1) | acc;
        }
    return code;
}

}  // namespace

torch::Tensor encode_grid(const torch::Tensor &grid, int depth, SerializationOrder order) {
    TORCH_CHECK(grid.dim() == 2 && grid.size(1) == 3, "encode_grid: grid must be [n, 3], got ",
                grid.sizes());
    TORCH_CHECK(!grid.is_floating_point(), "encode_grid: grid must be integer, got ",
                grid.scalar_type());
    TORCH_CHECK(depth >= 0 && depth <= k_max_serialization_depth, "encode_grid: depth ", depth,
                " outside [0, ", k_max_serialization_depth, "]");
    const auto g = grid.to(torch::kLong);
    auto x = g.select(1, 0), y = g.select(1, 1), z = g.select(1, 2);
    if (order == SerializationOrder::z_trans || order == SerializationOrder::hilbert_trans)
        std::swap(x, y);
    if (order == SerializationOrder::z || order == SerializationOrder::z_trans)
        return z_encode_tensor(x, y, z, depth);
    return hilbert_encode_tensor(x, y, z, depth);
}

std::pair<torch::Tensor, torch::Tensor> sort_codes(const torch::Tensor &code) {
    TORCH_CHECK(code.dim() == 2, "sort_codes: code must be [S, n], got ", code.sizes());
    // Stable: ties (only possible with duplicate voxels) keep index order, so the result is
    // deterministic (pitfall 9) and equals a sort by (code, index).
    auto order = std::get<1>(torch::sort(code, /*stable=*/true, /*dim=*/1, /*descending=*/false));
    const auto n = code.size(1);
    auto positions = torch::arange(n, code.options().dtype(torch::kLong)).expand_as(order);
    auto inverse = torch::empty_like(order).scatter_(1, order, positions);
    return {order, inverse};
}

Serialization serialize(const torch::Tensor &grid, int depth,
                        const std::vector<SerializationOrder> &orders) {
    TORCH_CHECK(!orders.empty(), "serialize: no orders given");
    std::vector<torch::Tensor> codes;
    codes.reserve(orders.size());
    for (auto o : orders) codes.push_back(encode_grid(grid, depth, o));
    Serialization s;
    s.code = torch::stack(codes);
    std::tie(s.order, s.inverse) = sort_codes(s.code);
    s.depth = depth;
    return s;
}

Serialization permute_orders(const Serialization &s, const torch::Tensor &perm) {
    TORCH_CHECK(perm.dim() == 1 && perm.size(0) == s.code.size(0),
                "permute_orders: perm must be [S] with S = ", s.code.size(0), ", got ",
                perm.sizes());
    const auto p = perm.to(s.code.device(), torch::kLong);
    return {s.code.index_select(0, p), s.order.index_select(0, p), s.inverse.index_select(0, p),
            s.depth};
}

}  // namespace ltm
