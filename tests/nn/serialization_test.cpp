// serialization_test.cpp: space-filling-curve codes against known values and their invariants
// (notes §7.1), and the order / inverse permutations.
#include <gtest/gtest.h>
#include <torch/torch.h>

#include <cstdlib>
#include <random>
#include <set>

#include "ltm/core/error.h"
#include "ltm/nn/serialization.h"

using namespace ltm;

// Sanity values from Pointcept's hilbert.py (notes §1.3).
TEST(Serialization, HilbertKnownValuesAtDepthOne) {
    EXPECT_EQ(hilbert_encode(0, 0, 0, 1), 0u);
    EXPECT_EQ(hilbert_encode(1, 0, 0, 1), 7u);
    EXPECT_EQ(hilbert_encode(0, 1, 0, 1), 3u);
    EXPECT_EQ(hilbert_encode(0, 0, 1, 1), 1u);
}

// A Hilbert curve visits every cell of the 8³ cube once, moving to a face neighbour each step;
// it starts at the origin and ends at (7, 0, 0).
TEST(Serialization, HilbertIsABijectionWithFaceNeighbourStepsAtDepthThree) {
    std::vector<std::array<int, 3>> cell_of(512, {-1, -1, -1});
    for (int x = 0; x < 8; ++x)
        for (int y = 0; y < 8; ++y)
            for (int z = 0; z < 8; ++z) {
                const uint64_t c = hilbert_encode(x, y, z, 3);
                ASSERT_LT(c, 512u);
                ASSERT_EQ(cell_of[c][0], -1) << "code " << c << " used twice";
                cell_of[c] = {x, y, z};
            }
    for (int c = 1; c < 512; ++c) {
        const int d = std::abs(cell_of[c][0] - cell_of[c - 1][0]) +
                      std::abs(cell_of[c][1] - cell_of[c - 1][1]) +
                      std::abs(cell_of[c][2] - cell_of[c - 1][2]);
        EXPECT_EQ(d, 1) << "step " << c - 1 << " -> " << c;
    }
    EXPECT_EQ(cell_of[0], (std::array<int, 3>{0, 0, 0}));
    EXPECT_EQ(cell_of[511], (std::array<int, 3>{7, 0, 0}));
}

TEST(Serialization, ZOrderIsTheBitInterleaveAndABijection) {
    EXPECT_EQ(z_encode(1, 0, 0, 1), 4u);
    EXPECT_EQ(z_encode(0, 1, 0, 1), 2u);
    EXPECT_EQ(z_encode(0, 0, 1, 1), 1u);
    EXPECT_EQ(z_encode(2, 0, 0, 2), 32u);
    std::set<uint64_t> codes;
    for (uint32_t x = 0; x < 8; ++x)
        for (uint32_t y = 0; y < 8; ++y)
            for (uint32_t z = 0; z < 8; ++z) codes.insert(z_encode(x, y, z, 3));
    EXPECT_EQ(codes.size(), 512u);
    EXPECT_EQ(*codes.rbegin(), 511u);
}

// The pooling trick: a parent voxel's code is its children's codes shifted by 3 bits.
TEST(Serialization, ParentCodeIsChildCodeShiftedByThree) {
    std::mt19937 rng(7);
    for (int depth = 1; depth <= 16; ++depth) {
        std::uniform_int_distribution<uint32_t> coord(0, (1u << depth) - 1);
        for (int i = 0; i < 200; ++i) {
            const uint32_t x = coord(rng), y = coord(rng), z = coord(rng);
            ASSERT_EQ(z_encode(x, y, z, depth) >> 3, z_encode(x >> 1, y >> 1, z >> 1, depth - 1));
            ASSERT_EQ(hilbert_encode(x, y, z, depth) >> 3,
                      hilbert_encode(x >> 1, y >> 1, z >> 1, depth - 1))
                << "depth " << depth << " at (" << x << ", " << y << ", " << z << ")";
        }
    }
}

TEST(Serialization, TensorEncodersMatchScalarOnes) {
    torch::manual_seed(1);
    for (int depth : {1, 5, 11, 16}) {
        const auto grid = torch::randint(0, int64_t(1) << depth, {300, 3}, torch::kLong);
        const auto g = grid.accessor<int64_t, 2>();
        for (auto order : {SerializationOrder::z, SerializationOrder::z_trans,
                           SerializationOrder::hilbert, SerializationOrder::hilbert_trans}) {
            const auto codes = encode_grid(grid, depth, order);
            const auto c = codes.accessor<int64_t, 1>();
            for (int64_t i = 0; i < grid.size(0); ++i) {
                uint32_t x = uint32_t(g[i][0]), y = uint32_t(g[i][1]), z = uint32_t(g[i][2]);
                const bool trans = order == SerializationOrder::z_trans ||
                                   order == SerializationOrder::hilbert_trans;
                const bool zorder =
                    order == SerializationOrder::z || order == SerializationOrder::z_trans;
                if (trans) std::swap(x, y);
                const uint64_t expected =
                    zorder ? z_encode(x, y, z, depth) : hilbert_encode(x, y, z, depth);
                ASSERT_EQ(uint64_t(c[i]), expected) << to_string(order) << " depth " << depth;
            }
        }
    }
}

// order sorts by (code, index) — ties from duplicate voxels keep index order — and inverse
// is its inverse permutation.
TEST(Serialization, OrderSortsStablyAndInverseInvertsIt) {
    torch::manual_seed(2);
    auto grid = torch::randint(0, 8, {200, 3}, torch::kLong);  // many duplicate voxels
    const std::vector<SerializationOrder> orders{SerializationOrder::z, SerializationOrder::hilbert,
                                                 SerializationOrder::hilbert_trans};
    const Serialization s = serialize(grid, /*depth=*/3, orders);
    ASSERT_EQ(s.code.sizes(), (std::vector<int64_t>{3, 200}));
    for (int64_t r = 0; r < 3; ++r) {
        const auto order = s.order[r], inverse = s.inverse[r], code = s.code[r];
        const auto sorted = code.index_select(0, order);
        const auto o = order.accessor<int64_t, 1>();
        const auto c = sorted.accessor<int64_t, 1>();
        for (int64_t j = 1; j < 200; ++j) {
            ASSERT_LE(c[j - 1], c[j]);
            if (c[j - 1] == c[j]) {
                ASSERT_LT(o[j - 1], o[j]) << "tie not broken by index";
            }
        }
        EXPECT_TRUE(inverse.index_select(0, order).equal(torch::arange(200, torch::kLong)));
    }
    const Serialization p = permute_orders(s, torch::tensor({2, 0, 1}, torch::kLong));
    EXPECT_TRUE(p.order[0].equal(s.order[2]));
    EXPECT_TRUE(p.inverse[1].equal(s.inverse[0]));
    EXPECT_TRUE(p.code[2].equal(s.code[1]));
}

TEST(Serialization, OrderNamesRoundTripAndUnknownNamesThrow) {
    for (const char *name : {"z", "z-trans", "hilbert", "hilbert-trans"})
        EXPECT_EQ(to_string(parse_serialization_order(name)), name);
    EXPECT_THROW(parse_serialization_order("peano"), ltm::Error);
}

// Depth = smallest D with every coordinate < 2^D.
TEST(Serialization, DepthIsBitLengthOfMaxCoordinate) {
    EXPECT_EQ(serialization_depth(0), 0);
    EXPECT_EQ(serialization_depth(1), 1);
    EXPECT_EQ(serialization_depth(2), 2);
    EXPECT_EQ(serialization_depth(3), 2);
    EXPECT_EQ(serialization_depth(4), 3);
    EXPECT_EQ(serialization_depth(65535), 16);
}
