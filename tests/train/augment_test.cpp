// augment_test.cpp: the 8 horizontal symmetries are distinct, exact, keep "up" and leave the
// cached FPS centres and kNN groups valid (the property that lets the trainer augment for free).
#include <gtest/gtest.h>

#include "ltm/nn/knn.h"
#include "ltm/train/augment.h"
#include "nn/tiny_scene_fixture.h"

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

namespace ltm {

// The trainer solves a scene's prior once and moves the frame with each of the 8 symmetries
// (apply_symmetry of a SceneNormalization): the decoder's z and the output scale it then uses
// match a frame solved for the transformed points (the occlusion grid and clusters are
// axis-aligned, so the solve differs only by rounding and cluster ties).
TEST(PriorInputs, CachedFrameUnderASymmetryMatchesTheSolvedFrame) {
    test::TinySceneFixture f(300);
    f.cfg.physics = ModelConfig::from_file(test::source_path("configs/model/cpu-pi.json")).physics;
    f.cfg.prior_inputs = true;
    LtmModel m = test::model_with_random_part(f.cfg, 6, "decoder");
    torch::NoGradGuard no_grad;
    const SceneGeometry g = m->scene_geometry(f.sp);
    const SceneNormalization frame = m->scene_frame(f.sp, g);
    const auto q_scale = output_scale(f.qp, frame);
    for (int s : {1, 6}) {
        const auto sp = apply_symmetry(f.sp, s), qp = apply_symmetry(f.qp, s);
        const SceneLatents solved = m->encode(sp, g);
        const SceneNormalization moved = apply_symmetry(frame, s);
        EXPECT_FALSE(moved.transport) << "the solve's nodes are in the old frame";
        const SceneLatents cached = m->encode(sp, g, {}, &moved);
        const auto scale = output_scale(qp, solved.norm);
        const double level = scale.mean().item<double>();
        const double scale_err = (scale - q_scale).abs().mean().item<double>() / level;
        const auto z_solved = m->decode(qp, solved), z_cached = m->decode(qp, cached, q_scale);
        const double z_err = (z_solved - z_cached).abs().mean().item<double>() / z_solved.abs().mean().item<double>();
        ::testing::Test::RecordProperty("symmetry_" + std::to_string(s), std::to_string(scale_err) + " " + std::to_string(z_err));
        EXPECT_LT(scale_err, 0.02) << "symmetry " << s;
        EXPECT_LT(z_err, 0.02) << "symmetry " << s;
        EXPECT_TRUE(torch::allclose(cached.anchors, solved.anchors, 0.0, 1e-5)) << "the centre moved like the points";
    }
}

}  // namespace ltm
