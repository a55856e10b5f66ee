// sparse_conv_test.cpp: the xCPE neighbour map and the gather-GEMM submanifold conv against
// dense torch::conv3d read back at the active voxels (notes §7.4).
#include <gtest/gtest.h>
#include <torch/torch.h>

#include <map>
#include <tuple>

#include "ltm/nn/sparse_conv.h"

using namespace ltm;

namespace {

// n distinct random voxels in [0, X) × [0, Y) × [0, Z).  -> [n, 3] int64
torch::Tensor random_unique_voxels(int64_t n, int64_t X, int64_t Y, int64_t Z) {
    const auto cells = torch::randperm(X * Y * Z, torch::kLong).slice(0, 0, n);
    return torch::stack({cells.div(Y * Z, "floor"), cells.div(Z, "floor") % Y, cells % Z}, 1);
}

}  // namespace

TEST(SubmanifoldNeighbors, FindsExactlyThePresentOffsets) {
    torch::manual_seed(5);
    const auto grid = random_unique_voxels(120, 6, 5, 7);
    const auto nbr = submanifold_neighbors(grid);
    ASSERT_EQ(nbr.sizes(), (std::vector<int64_t>{120, 27}));
    std::map<std::tuple<int64_t, int64_t, int64_t>, int64_t> row_of;
    const auto g = grid.accessor<int64_t, 2>();
    for (int64_t i = 0; i < 120; ++i) row_of[{g[i][0], g[i][1], g[i][2]}] = i;
    const auto a = nbr.accessor<int64_t, 2>();
    for (int64_t i = 0; i < 120; ++i)
        for (int ox = -1; ox <= 1; ++ox)
            for (int oy = -1; oy <= 1; ++oy)
                for (int oz = -1; oz <= 1; ++oz) {
                    const int o = (ox + 1) * 9 + (oy + 1) * 3 + (oz + 1);
                    const auto it = row_of.find({g[i][0] + ox, g[i][1] + oy, g[i][2] + oz});
                    ASSERT_EQ(a[i][o], it == row_of.end() ? 120 : it->second);
                }
    for (int64_t i = 0; i < 120; ++i) EXPECT_EQ(a[i][13], i);  // the centre is the voxel itself
}

// Voxels at the edges of the 16-bit range have no phantom neighbours across the boundary.
TEST(SubmanifoldNeighbors, GridBoundaryHasNoWrapAround) {
    const auto grid = torch::tensor({0, 0, 0, 65535, 0, 0, 0, 65535, 65535, 1, 0, 0},
                                    torch::kLong).view({4, 3});
    const auto nbr = submanifold_neighbors(grid);
    EXPECT_EQ((nbr < 4).sum().item<int64_t>(), 4 + 2);  // 4 centres + the (0,0,0)-(1,0,0) pair
    EXPECT_EQ(nbr[0][22].item<int64_t>(), 3);            // offset (+1, 0, 0)
    EXPECT_EQ(nbr[3][4].item<int64_t>(), 0);             // offset (-1, 0, 0)
}

// Submanifold conv = dense conv3d (padding 1) with inactive voxels zero, read at active ones,
// under W_o[c_in, c_out] = w[c_out, c_in, ox+1, oy+1, oz+1].
TEST(SubmConv3, GatherGemmEqualsDenseConv3dAtActiveVoxels) {
    torch::manual_seed(6);
    const int64_t X = 9, Y = 7, Z = 8, n = 200, c_in = 3, c_out = 5;
    const auto grid = random_unique_voxels(n, X, Y, Z);
    const auto x = torch::randn({n, c_in});
    const auto w = torch::randn({c_out, c_in, 3, 3, 3});
    const auto b = torch::randn({c_out});

    SubmConv3 conv(c_in, c_out);
    {
        torch::NoGradGuard no_grad;
        // weight row o·C_in + c_in, column c_out  <-  w[c_out, c_in, ox+1, oy+1, oz+1]
        conv->weight.copy_(w.permute({2, 3, 4, 1, 0}).reshape({27 * c_in, c_out}));
        conv->bias.copy_(b);
    }
    const auto sparse = conv->forward(x, submanifold_neighbors(grid));

    auto dense = torch::zeros({1, c_in, X, Y, Z});
    const auto gx = grid.select(1, 0), gy = grid.select(1, 1), gz = grid.select(1, 2);
    dense.index_put_({0, torch::indexing::Slice(), gx, gy, gz}, x.t());
    const auto out = torch::conv3d(dense, w, b, /*stride=*/1, /*padding=*/1);
    const auto expected = out.index({0, torch::indexing::Slice(), gx, gy, gz}).t();
    EXPECT_TRUE(torch::allclose(sparse, expected, 1e-4, 1e-5))
        << (sparse - expected).abs().max().item<float>();
}

TEST(SubmConv3, GradientsReachWeightsAndInputs) {
    torch::manual_seed(7);
    const auto grid = random_unique_voxels(50, 4, 4, 4);
    const auto x = torch::randn({50, 4}, torch::requires_grad());
    SubmConv3 conv(4, 6);
    conv->forward(x, submanifold_neighbors(grid)).pow(2).sum().backward();
    EXPECT_TRUE(torch::isfinite(x.grad()).all().item<bool>());
    EXPECT_GT(conv->weight.grad().abs().sum().item<float>(), 0.f);
    EXPECT_GT(conv->bias.grad().abs().sum().item<float>(), 0.f);
}
