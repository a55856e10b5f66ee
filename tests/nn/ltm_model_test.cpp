// ltm_model_test.cpp: the tiny model end to end: shapes, chunking, checkpoint round trips, and
// located errors for bad inputs and foreign weights.
#include <gtest/gtest.h>
#include <torch/torch.h>

#include "ltm/core/error.h"
#include "ltm/nn/checkpoint.h"
#include "ltm/nn/ltm_model.h"
#include "ltm/nn/point_tensor.h"
#include "ltm/points/surface_sampler.h"
#include "ltm/scene/builtin_scenes.h"
#include "test_util.h"
#include "tiny_scene_fixture.h"

using namespace ltm;

namespace {
struct Fixture : test::TinySceneFixture {
    Fixture() : TinySceneFixture(300) {}
};
}  // namespace

// Shapes, chunking, the fused inference path against the libtorch modules, and that the output
// depends on its inputs (a constant decoder would pass shape checks and the chunking comparison).
TEST(LtmModel, TinyForwardShapesAndChunking) {
    torch::manual_seed(0);
    Fixture f;
    LtmModel model(f.cfg);
    {
        torch::NoGradGuard g;   // non-trivial outputs: a fresh output layer may be near constant
        for (auto &p : model->parameters()) p.add_(torch::randn_like(p) * 0.2);
    }
    model->eval();
    const SceneGeometry g = model->scene_geometry(f.sp);
    EXPECT_EQ(g.centers.size(0), f.cfg.n_anchors());
    const SceneLatents lat = model->encode(f.sp, g);
    EXPECT_EQ(lat.features.size(0), f.cfg.n_anchors());
    const auto e = model->predict_irradiance(f.qp, lat, /*chunk=*/1 << 20);
    ASSERT_EQ(e.sizes(), (std::vector<int64_t>{300, 3}));
    EXPECT_TRUE((e >= 0).all().item<bool>());
    EXPECT_TRUE(torch::allclose(model->predict_irradiance(f.qp, lat, /*chunk=*/7), e, 1e-5, 1e-6));
    // Fused (the default on CPU) against the libtorch modules.
    model->fused_inference = false;
    const auto reference = model->predict_irradiance(f.qp, lat);
    model->fused_inference = true;
    EXPECT_TRUE(torch::allclose(e, reference, 1e-4, 1e-5)) << "max |Δ| " << (e - reference).abs().max().item<float>();
    // Input sensitivity: the prediction varies over the queries, and moves with the albedo of the
    // scene points (through the encoder) and with the query normal (through the decoder).
    EXPECT_GT((e - e.mean(0)).abs().mean().item<double>(), 1e-3 * e.abs().mean().item<double>());
    auto sp = f.sp.clone();
    sp.slice(1, 6, 9).mul_(0.5);
    const auto e_albedo = model->predict_irradiance(f.qp, model->encode(sp, g));
    EXPECT_GT((e_albedo - e).abs().mean().item<double>(), 1e-3 * e.abs().mean().item<double>());
    auto qp = f.qp.clone();
    qp.slice(1, 3, 6).neg_();
    const auto e_normal = model->predict_irradiance(qp, lat);
    EXPECT_GT((e_normal - e).abs().mean().item<double>(), 1e-3 * e.abs().mean().item<double>());
}

TEST(LtmModel, WeightsRoundTripIsBitExact) {
    torch::manual_seed(1);
    test::TempDir dir;
    Fixture f;
    LtmModel model(f.cfg);
    model->eval();
    save_weights(dir.path("w.safetensors"), model, {{"step", "7"}});
    std::map<std::string, std::string> meta;
    LtmModel loaded = load_weights(dir.path("w.safetensors"), &meta);
    loaded->eval();
    EXPECT_EQ(meta.at("step"), "7");
    const auto g = model->scene_geometry(f.sp);
    const auto a = model->predict_irradiance(f.qp, model->encode(f.sp, g));
    const auto b = loaded->predict_irradiance(f.qp, loaded->encode(f.sp, g));
    EXPECT_TRUE(torch::equal(a, b));
}

TEST(LtmModel, ForeignWeightsAndBadInputsAreErrors) {
    test::TempDir dir;
    Fixture f;
    LtmModel tiny(f.cfg);
    ModelConfig other = f.cfg;
    other.decoder.n_layers = 2;
    LtmModel two_layers(other);
    std::map<std::string, torch::Tensor> tensors;
    for (const auto &p : two_layers->named_parameters()) tensors[p.key()] = p.value();
    EXPECT_THROW(load_state(tiny, tensors, "other.safetensors"), Error);
    EXPECT_THROW(load_weights(dir.path("missing.safetensors")), Error);
    auto nan = f.sp.clone();
    nan[3][0] = NAN;
    EXPECT_THROW(tiny->encode(nan, tiny->scene_geometry(f.sp)), Error);   // user data: ltm::Error, one line
    EXPECT_THROW(tiny->scene_geometry(f.sp.slice(1, 0, 9)), c10::Error);
}

TEST(Loss, RelativeL2InLogSpaceMatchesTheFormula) {
    const auto z = torch::tensor({0.5f, 1.0f, 2.0f}).view({1, 3});
    const auto y = torch::tensor({1.0f, 0.0f, 3.0f}).view({1, 3});
    double expect = 0;
    for (int i = 0; i < 3; ++i) {
        const double zi = z[0][i].item<double>(), yi = std::log1p(y[0][i].item<double>());
        expect += std::pow((zi - yi) / (zi + 1e-2), 2) / 3.0;
    }
    EXPECT_NEAR(relative_l2_log_loss(z, y).item<double>(), expect, 1e-6);
    // The denominator is detached: the gradient is 2(z − log1p y)/(z + ε)² / n.
    auto zg = z.clone().requires_grad_(true);
    relative_l2_log_loss(zg, y).backward();
    EXPECT_NEAR(zg.grad()[0][0].item<double>(), 2 * (0.5 - std::log1p(1.0)) / std::pow(0.51, 2) / 3, 1e-5);
}
