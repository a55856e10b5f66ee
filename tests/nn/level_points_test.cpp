// level_points_test.cpp: DecoderConfig::level_points (issue #30) — a network that keeps its prior's
// level and only moves light within the scene. Held: the prior's light summed over the level points
// is the model's; the held output is the free network's times one factor per scene; the symmetries
// (emission ×k, unit ×s) and the prior (a silenced decoder) are untouched; the trainer's decode and
// the fused inference path give the same numbers.
#include <cmath>

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "ltm/core/error.h"
#include "ltm/nn/ltm_model.h"
#include "test_util.h"
#include "tiny_scene_fixture.h"

using namespace ltm;

namespace {
constexpr int k_level_points = 64;

// The tiny model with the shipped prior's physics and prior inputs (as prior_inputs_test.cpp).
struct Fixture : test::TinySceneFixture {
    Fixture() : TinySceneFixture(300) {
        cfg.physics = ModelConfig::from_file(test::source_path("configs/model/cpu-pi.json")).physics;
        cfg.prior_inputs = true;
    }
    ModelConfig held(int k = k_level_points) const {
        ModelConfig c = cfg;
        c.decoder.level_points = k;
        return c;
    }
};

// Random decoder weights (N(0, 0.5²)): a gain far from 1 and far from uniform.
LtmModel random_model(const ModelConfig &cfg, uint64_t seed) { return test::model_with_random_part(cfg, seed, "decoder"); }

using test::predict;
using test::scaled;
using test::relative_error;
}  // namespace

TEST(LevelPoints, ConfigIsWrittenOnlyWhenSetAndRefusesNegatives) {
    Fixture f;
    EXPECT_EQ(f.cfg.decoder.level_points, 0) << "a free level by default";
    EXPECT_FALSE(f.cfg.to_json()["decoder"].contains("level_points")) << "older weights keep their JSON";
    Json j = f.held(512).to_json();
    EXPECT_EQ(j["decoder"]["level_points"].get<int>(), 512);
    EXPECT_EQ(ModelConfig::from_json(j, "t").decoder.level_points, 512);
    j["decoder"]["level_points"] = -1;
    EXPECT_THROW(ModelConfig::from_json(j, "bad"), Error);
}

// Σ over the level points of the model's E⁺ equals Σ of its prior's (to float rounding), while the
// same weights with a free level are far from it; elsewhere the held output is the free one times
// the same factor r at every query and channel.
TEST(LevelPoints, TheModelKeepsThePriorsLevelAndTheNetworksShape) {
    Fixture f;
    torch::NoGradGuard no_grad;
    LtmModel held = random_model(f.held(), 5);
    LtmModel free = random_model(f.cfg, 5);
    const SceneLatents lat = held->encode(f.sp, held->scene_geometry(f.sp));
    ASSERT_EQ(lat.level_queries.sizes(), (std::vector<int64_t>{k_level_points, 9}));
    ASSERT_EQ(lat.level_scale.sizes(), (std::vector<int64_t>{k_level_points, 3}));
    const double prior_sum = lat.level_scale.sum().item<double>();
    ASSERT_GT(prior_sum, 0.0);

    const auto at_level_points = held->predict_irradiance(lat.level_queries, lat);
    EXPECT_NEAR(at_level_points.sum().item<double>() / prior_sum, 1.0, 1e-5);
    const auto free_at = free->predict_irradiance(lat.level_queries, free->encode(f.sp, free->scene_geometry(f.sp)));
    EXPECT_GT(std::abs(free_at.sum().item<double>() / prior_sum - 1.0), 0.05) << "the free network moves the level";

    const auto e_held = predict(held, f.sp, f.qp), e_free = predict(free, f.sp, f.qp);
    const double r = held->level_factor(lat).item<double>();
    EXPECT_GT(std::abs(r - 1.0), 0.05);
    EXPECT_LT(relative_error(e_held, e_free * r), 1e-5);
}

// The trainer reads z from decode(); inference multiplies predict_irradiance's chunks by r. Both, on
// the fused and the module path, are the same numbers; and under autograd r carries a gradient to the
// decoder (the loss at a query feels the level points).
TEST(LevelPoints, DecodeAndBothInferencePathsAgreeAndTheFactorHasAGradient) {
    Fixture f;
    LtmModel m = random_model(f.held(), 6);
    const SceneLatents lat = m->encode(f.sp, m->scene_geometry(f.sp));
    torch::Tensor via_decode;
    {
        torch::NoGradGuard no_grad;
        via_decode = irradiance_from_z(m->decode(f.qp, lat), output_scale(f.qp, lat.norm));
    }
    const auto fused = m->predict_irradiance(f.qp, lat, /*chunk=*/128);
    m->fused_inference = false;
    const auto modules = m->predict_irradiance(f.qp, lat, /*chunk=*/100);
    EXPECT_LT(relative_error(fused, via_decode), 1e-5);
    EXPECT_LT(relative_error(modules, via_decode), 1e-5);

    const auto r = m->level_factor(lat);
    ASSERT_TRUE(r.requires_grad());
    r.backward();
    double g = 0.0;
    for (const auto &p : m->decoder->parameters())
        if (p.grad().defined()) g += p.grad().abs().sum().item<double>();
    EXPECT_GT(g, 0.0);
}

// The level factor is a ratio of two sums that both scale like S: emission ×k scales E⁺ by k, and a
// power-of-two unit leaves it to the bit, as for the free model (physics_test.cpp).
TEST(LevelPoints, EmissionAndUnitSymmetriesHold) {
    Fixture f;
    torch::NoGradGuard no_grad;
    LtmModel m = random_model(f.held(), 7);
    const auto e = predict(m, f.sp, f.qp);
    ASSERT_GT(e.abs().mean().item<double>(), 0.0);
    EXPECT_LT(relative_error(predict(m, scaled(f.sp, 9, 12, 4.0), f.qp), e * 4.0), 1e-6);
    EXPECT_LT(relative_error(predict(m, scaled(f.sp, 9, 12, 3.7), f.qp), e * 3.7), 1e-5);
    for (double s : {0.5, 1024.0}) EXPECT_TRUE(torch::equal(predict(m, scaled(f.sp, 0, 3, s), scaled(f.qp, 0, 3, s)), e)) << s;
}

// A silenced decoder (start_at_prior) is its prior with or without the level held, folded or not.
TEST(LevelPoints, ASilencedDecoderIsItsPrior) {
    Fixture f;
    torch::NoGradGuard no_grad;
    LtmModel m = random_model(f.held(), 8);
    m->decoder->start_at_prior();
    const SceneLatents lat = m->encode(f.sp, m->scene_geometry(f.sp));
    const auto prior = prior_irradiance(f.qp, lat.norm);
    EXPECT_TRUE(torch::equal(m->predict_irradiance(f.qp, lat), prior)) << "folded";
    m->fold_prior = false;
    const SceneLatents run = m->encode(f.sp, m->scene_geometry(f.sp));
    EXPECT_NEAR(m->level_factor(run).item<double>(), 1.0, 1e-6);
    EXPECT_LT(relative_error(m->predict_irradiance(f.qp, run), prior), 1e-6);
}

// Without prior inputs the level points still weigh r by the transport prior there (scene_frame keeps
// it for them), so a frame without its solve — the trainer's cache — gives inference's numbers; a
// frame with neither the solve nor the points' prior is refused rather than weighed by the flat scale.
TEST(LevelPoints, WithoutPriorInputsTheLevelPointsReadTheTransportPrior) {
    Fixture f;
    ModelConfig c = f.held();
    c.prior_inputs = false;
    torch::NoGradGuard no_grad;
    LtmModel m = random_model(c, 9);
    const SceneGeometry g = m->scene_geometry(f.sp);
    const SceneLatents lat = m->encode(f.sp, g);
    ASSERT_TRUE(lat.norm.transport);
    EXPECT_TRUE(torch::allclose(lat.level_scale, output_scale(lat.level_queries, lat.norm)));
    SceneNormalization cached = m->scene_frame(f.sp, g);
    const auto scale = output_scale(f.qp, cached);
    cached.transport.reset();
    const SceneLatents from_cache = m->encode(f.sp, g, {}, &cached);
    EXPECT_TRUE(torch::equal(from_cache.level_scale, lat.level_scale));
    EXPECT_TRUE(torch::allclose(irradiance_from_z(m->decode(f.qp, from_cache, scale), scale), m->predict_irradiance(f.qp, lat), 1e-5, 1e-6));
    cached.point_prior = torch::Tensor();
    EXPECT_THROW(m->encode(f.sp, g, {}, &cached), Error);
}
