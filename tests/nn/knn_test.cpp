// knn_test.cpp: the k-d tree and FPS equal brute force.
#include <gtest/gtest.h>
#include <torch/torch.h>

#include "ltm/nn/knn.h"

using namespace ltm;

TEST(Knn, TreeEqualsBruteForce) {
    torch::manual_seed(1);
    const auto ref = torch::rand({2000, 3}) * 5.f, query = torch::rand({500, 3}) * 5.f;
    const auto a = knn(query, ref, 16), b = knn_brute_force(query, ref, 16);
    ASSERT_EQ(a.sizes(), (std::vector<int64_t>{500, 16}));
    EXPECT_TRUE(torch::equal(a, b));
    // Nearest first.
    const auto d = (query.unsqueeze(1) - ref.index_select(0, a.reshape(-1)).view({500, 16, 3})).pow(2).sum(-1);
    EXPECT_TRUE((d.slice(1, 1, 16) >= d.slice(1, 0, 15)).all().item<bool>());
}

TEST(Knn, RejectsBadShapesAndK) {
    EXPECT_THROW(knn(torch::rand({5, 2}), torch::rand({5, 3}), 1), c10::Error);
    EXPECT_THROW(knn(torch::rand({5, 3}), torch::rand({5, 3}), 6), c10::Error);
}

// Reference FPS in double precision with the same conventions (start at 0, ties to lower index).
TEST(Fps, EqualsBruteForce) {
    torch::manual_seed(2);
    const auto pos = torch::rand({700, 3});
    const auto got = farthest_point_sampling(pos, 100);
    const auto p = pos.to(torch::kFloat64);
    std::vector<int64_t> expect = {0};
    auto dist = torch::full({700}, 1e300, torch::kFloat64);
    for (int i = 1; i < 100; ++i) {
        dist = torch::minimum(dist, (p - p[expect.back()]).pow(2).sum(-1));
        expect.push_back(dist.argmax().item<int64_t>());
    }
    EXPECT_TRUE(torch::equal(got, torch::tensor(expect, torch::kInt64)));
    EXPECT_EQ(std::get<0>(at::_unique(got)).size(0), 100);   // no repeats
}
