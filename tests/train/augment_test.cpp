// augment_test.cpp: the 8 horizontal symmetries are distinct, exact, keep "up" and leave the
// cached FPS centres and kNN groups valid (the property that lets the trainer augment for free).
#include <gtest/gtest.h>

#include "ltm/nn/knn.h"
#include "ltm/train/augment.h"

namespace ltm {
namespace {

torch::Tensor random_points(int64_t n) {
    torch::manual_seed(5);
    auto p = torch::rand({n, 3}) * 6.f - 3.f;
    auto nrm = torch::randn({n, 3});
    nrm = nrm / nrm.norm(2, 1, true);
    return torch::cat({p, nrm, torch::rand({n, 6})}, 1);   // [n, 12] like scene points
}

TEST(Augment, SymmetriesAreTheEightDistinctIsometriesThatKeepUp) {
    for (int s = 0; s < k_n_symmetries; ++s) {
        const auto r = symmetry_matrix(s);
        EXPECT_TRUE(torch::equal(r.mm(r.t()), torch::eye(3))) << "orthogonal, s = " << s;
        EXPECT_TRUE(torch::equal(r.select(0, 1), torch::tensor({0.f, 1.f, 0.f}))) << "y stays up, s = " << s;
        EXPECT_FLOAT_EQ(torch::det(r).item<float>(), (s & 4) ? -1.f : 1.f);
        for (int t = 0; t < s; ++t) EXPECT_FALSE(torch::equal(r, symmetry_matrix(t))) << s << " vs " << t;
    }
    EXPECT_TRUE(torch::equal(symmetry_matrix(0), torch::eye(3)));
    // Four quarter turns are the identity: the group closes.
    const auto q = symmetry_matrix(1);
    EXPECT_TRUE(torch::equal(q.mm(q).mm(q).mm(q), torch::eye(3)));
    EXPECT_THROW(symmetry_matrix(8), c10::Error);
    EXPECT_THROW(apply_symmetry(torch::zeros({4, 5}), 1), c10::Error);
}

TEST(Augment, ExactAndFpsKnnInvariant) {
    const auto pts = random_points(600);
    const auto centers = farthest_point_sampling(pts.slice(1, 0, 3).contiguous(), 64);
    const auto groups = knn(pts.slice(1, 0, 3).index_select(0, centers), pts.slice(1, 0, 3).contiguous(), 8);
    auto distances = [](const torch::Tensor &p) { return (p.unsqueeze(0) - p.unsqueeze(1)).pow(2).sum(2).sqrt(); };
    const auto d0 = distances(pts.slice(1, 0, 3));
    for (int s = 1; s < k_n_symmetries; ++s) {
        const auto t = apply_symmetry(pts, s);
        ASSERT_EQ(t.sizes(), pts.sizes());
        EXPECT_TRUE(torch::equal(t.slice(1, 6), pts.slice(1, 6))) << "albedo/emission untouched";
        EXPECT_TRUE(torch::equal(t.select(1, 1), pts.select(1, 1))) << "heights untouched";
        // Signed permutation: every coordinate is ± an input coordinate, bit for bit.
        EXPECT_TRUE(torch::equal(std::get<0>(t.slice(1, 0, 3).abs().sort(1)), std::get<0>(pts.slice(1, 0, 3).abs().sort(1))));
        const auto pos = t.slice(1, 0, 3).contiguous();
        EXPECT_TRUE(torch::equal(farthest_point_sampling(pos, 64), centers)) << "s = " << s;
        EXPECT_TRUE(torch::equal(knn(pos.index_select(0, centers), pos, 8), groups)) << "s = " << s;
        EXPECT_TRUE(torch::allclose(distances(pos), d0, 0, 1e-5));
    }
}

}  // namespace
}  // namespace ltm
