// traced_queries_test.cpp: ModelConfig::traced_queries (issue #30, session 37) — every query also
// carries ln(R / Ê), the regathered prior's ratio to the prior there, and that column reaches the
// output through the decoder's learned skip. At skip 1 with the output layer zero the model is the
// regathered prior exactly; at skip 0 it is its prior (and folds); the fused decoder and libtorch
// agree; the column keeps the exact symmetries; the trainer's cached R is the gathered one. The
// trainer's side (the widening conversion, skip_lr_scale): tests/train/trainer_test.cpp.
#include <cmath>
#include <string>

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "ltm/core/error.h"
#include "ltm/infer/prior_model.h"
#include "ltm/nn/checkpoint.h"
#include "ltm/nn/ltm_model.h"
#include "ltm/points/safetensors.h"
#include "ltm/render/embree_accel.h"
#include "ltm/scene/scene_transform.h"
#include "test_util.h"
#include "tiny_scene_fixture.h"

using namespace ltm;

namespace {
using test::random_model;
struct Fixture : test::TracedSceneFixture {
    Fixture() { cfg.traced_queries = true; }
};

void set_skip(LtmModel &m, float w) {
    torch::NoGradGuard g;
    m->decoder->skip.fill_(w);
}
}  // namespace

TEST(TracedQueries, ConfigNeedsTracedInputsAndStaysOutOfOlderJson) {
    Fixture f;
    const auto j = f.cfg.to_json();
    EXPECT_TRUE(j.at("traced_queries").get<bool>());
    EXPECT_TRUE(ModelConfig::from_json(j, "t").traced_queries);
    auto untraced = j;
    untraced.erase("traced_inputs");
    EXPECT_THROW(ModelConfig::from_json(untraced, "t"), Error);
    auto held = j;
    held["decoder"]["level_points"] = 64;
    EXPECT_EQ(ModelConfig::from_json(held, "t").decoder.level_points, 64) << "the level held is R's (LevelPointsHoldRsLevel)";
    ModelConfig plain = f.cfg;
    plain.traced_queries = false;
    EXPECT_FALSE(plain.to_json().contains("traced_queries")) << "written only when set: older weights keep their JSON";
    const LtmModel m(f.cfg);
    EXPECT_EQ(m->cfg.decoder.extra_inputs, 6) << "the prior's 3 and ln(R / Ê)";
    EXPECT_EQ(m->cfg.decoder.skip_inputs, 3);
    ASSERT_TRUE(m->decoder->skip.defined());
    EXPECT_EQ(m->decoder->named_parameters().find("skip")->sizes(), (c10::IntArrayRef{3}));
    EXPECT_FALSE(LtmModel(plain)->decoder->skip.defined());
    // Built in code, not read from JSON: the model refuses the same combinations in one line.
    ModelConfig untraced_code = f.cfg;
    untraced_code.traced_inputs = 0;
    EXPECT_THROW(LtmModel{untraced_code}, Error);
}

// decoder.level_points with traced queries holds R's level, not the prior's: a random body (not
// silent) keeps Σ E⁺ = Σ R over the level points (the body corrects R's shape only), through the
// fused decoder and libtorch; its queries elsewhere still move.
TEST(TracedQueries, LevelPointsHoldRsLevel) {
    Fixture f;
    f.cfg.decoder.level_points = 64;
    LtmModel m = random_model(f.cfg, 11);
    set_skip(m, 1.f);
    m->fold_prior = false;
    ASSERT_FALSE(m->decoder->body_silent());
    torch::NoGradGuard g;
    const EmbreeAccel accel(f.scene);
    const auto geometry = m->scene_geometry(f.sp);
    const SceneLatents lat = m->encode(f.sp, geometry, {}, nullptr, nullptr, traced_inputs_tracer(f.cfg, accel));
    ASSERT_TRUE(lat.level_regathered.defined());
    ASSERT_EQ(lat.level_regathered.sizes(), (c10::IntArrayRef{64, 3}));
    EXPECT_LT(test::relative_error(lat.level_regathered, regathered_scale(lat.level_queries, lat.norm)), 1e-5)
        << "the frame's per-point R is the gathered one";
    const auto at_level = m->predict_irradiance(lat.level_queries, lat);
    const double held = at_level.sum().item<double>(), r = lat.level_regathered.sum().item<double>();
    EXPECT_NEAR(held, r, 1e-4 * r) << "R's level over the level points";
    m->fused_inference = false;
    EXPECT_NEAR(m->predict_irradiance(lat.level_queries, lat).sum().item<double>(), r, 1e-4 * r) << "libtorch";
    // Without the hold, the same body moves the level: the test above is not vacuous.
    ModelConfig free_cfg = f.cfg;
    free_cfg.decoder.level_points = 0;
    LtmModel free = random_model(free_cfg, 11);
    set_skip(free, 1.f);
    free->fold_prior = false;
    const SceneLatents free_lat = free->encode(f.sp, free->scene_geometry(f.sp), {}, nullptr, nullptr, traced_inputs_tracer(free_cfg, accel));
    EXPECT_GT(std::abs(free->predict_irradiance(lat.level_queries, free_lat).sum().item<double>() - r), 1e-3 * r);
    // At its prior (skip 0, body silent) the model folds and traces nothing: the level, never read
    // there, must not ask for R.
    LtmModel at_prior = random_model(f.cfg, 11);
    at_prior->decoder->start_at_prior();
    set_skip(at_prior, 0.f);
    const SceneLatents folded = at_prior->encode(f.sp, geometry, {}, nullptr, nullptr, traced_inputs_tracer(f.cfg, accel));
    EXPECT_FALSE(folded.norm.regather);
    EXPECT_TRUE(torch::equal(at_prior->predict_irradiance(f.qp, folded), prior_irradiance(f.qp, folded.norm)));
}

// softplus(ln g) = ln(1 + g): with 𝓦_out zero and skip 1, E⁺ = Ê · g = R at every query, through
// the fused decoder and the libtorch modules alike; skip 0 is the prior, which then folds (no
// tracing, no network).
TEST(TracedQueries, SkipOneIsTheRegatheredPriorAndSkipZeroThePrior) {
    Fixture f;
    LtmModel m = random_model(f.cfg, 3);
    m->decoder->start_at_prior();
    EXPECT_TRUE(m->decoder->at_prior());
    set_skip(m, 1.f);
    EXPECT_FALSE(m->decoder->at_prior()) << "a skip that is not zero is a network at work";
    torch::NoGradGuard g;
    const EmbreeAccel accel(f.scene);
    const auto geometry = m->scene_geometry(f.sp);
    const SceneLatents lat = m->encode(f.sp, geometry, {}, nullptr, nullptr, traced_inputs_tracer(f.cfg, accel));
    ASSERT_TRUE(lat.norm.regather);
    const auto r = regathered_scale(f.qp, lat.norm), prior = prior_irradiance(f.qp, lat.norm);
    EXPECT_GT(test::relative_error(r, prior), 0.01) << "the traced light differs from the prior's (2 % here; the check below is to 1e-5)";
    // Through the network (not folded: the silent body's fold has its own test below).
    m->fold_prior = false;
    const SceneLatents net = m->encode(f.sp, geometry, {}, nullptr, nullptr, traced_inputs_tracer(f.cfg, accel));
    const auto fused = m->predict_irradiance(f.qp, net);
    EXPECT_LT(test::relative_error(fused, r), 1e-5);
    m->fused_inference = false;
    EXPECT_LT(test::relative_error(m->predict_irradiance(f.qp, net), r), 1e-5);
    m->fused_inference = true;
    m->fold_prior = true;
    EXPECT_LT(test::relative_error(m->predict_irradiance(f.qp, lat), r), 1e-5) << "folded";
    set_skip(m, 0.f);
    EXPECT_TRUE(m->decoder->at_prior());
    const SceneLatents folded = m->encode(f.sp, geometry, {}, nullptr, nullptr, traced_inputs_tracer(f.cfg, accel));
    EXPECT_FALSE(folded.norm.regather) << "a model at its prior does not trace";
    EXPECT_TRUE(torch::equal(m->predict_irradiance(f.qp, folded), prior_irradiance(f.qp, folded.norm)));
}

// A silent body (𝓦_out zero) with a learned skip folds: encode() traces the scene for R but runs
// neither the embedding nor PTv3 (zero features), and predict_irradiance() gives what the whole
// network gives — a random body before the zero output layer, through the fused kernel and libtorch.
TEST(TracedQueries, ASilentBodyWithASkipFoldsToTheSameNumbers) {
    Fixture f;
    LtmModel m = random_model(f.cfg, 7);
    {
        torch::NoGradGuard g;
        for (auto &t : m->decoder->output_parameters()) t.zero_();
        m->decoder->skip.copy_(torch::tensor({0.75f, 0.6f, 0.9f}));
    }
    ASSERT_TRUE(m->decoder->body_silent());
    ASSERT_FALSE(m->decoder->at_prior());
    torch::NoGradGuard g;
    const EmbreeAccel accel(f.scene);
    const auto geometry = m->scene_geometry(f.sp);
    const SceneLatents folded = m->encode(f.sp, geometry, {}, nullptr, nullptr, traced_inputs_tracer(f.cfg, accel));
    ASSERT_TRUE(folded.norm.regather) << "the skip reads the regather: the scene is traced";
    EXPECT_FALSE(folded.features.any().item<bool>()) << "the encoder did not run";
    EXPECT_FALSE(folded.norm.point_traced.defined() || folded.norm.point_prior.defined()) << "nor were its inputs gathered";
    const auto e = m->predict_irradiance(f.qp, folded);
    m->fold_prior = false;
    const SceneLatents net = m->encode(f.sp, geometry, {}, nullptr, nullptr, traced_inputs_tracer(f.cfg, accel));
    ASSERT_TRUE(net.features.any().item<bool>());
    EXPECT_LT(test::relative_error(e, m->predict_irradiance(f.qp, net)), 1e-5) << "fused";
    m->fused_inference = false;
    EXPECT_LT(test::relative_error(e, m->predict_irradiance(f.qp, net)), 1e-5) << "libtorch";
    EXPECT_GT(test::relative_error(e, prior_irradiance(f.qp, net.norm)), 1e-3) << "the skip moves the output";
    m->fold_prior = true;
    try {
        m->encode(f.sp, geometry);
        ADD_FAILURE() << "folded a traced-queries model without its tracer";
    } catch (const Error &err) {
        EXPECT_NE(std::string(err.what()).find("path tracer"), std::string::npos) << err.what();
    }
}

// A silent body with a skip and a directional head (the shipped regathered model: its head reads
// the encoder): encode() defers the encoder and its per-point inputs (no prior or regather gathered
// at the scene points), the irradiance does not run them, and the head's first call makes them —
// the unfolded model's features to the bit, and its radiance.
TEST(TracedQueries, ASilentBodyWithAHeadDefersTheEncoderAndItsInputs) {
    Fixture f;
    DirectionalConfig d;
    d.dim = 16, d.groups = 4, d.n_layers = 1, d.direction_frequencies = 3, d.bin_resolution = 4, d.prior_cells = 4;
    f.cfg.directional = d;
    LtmModel m = random_model(f.cfg, 9);
    {
        torch::NoGradGuard g;
        for (auto &t : m->decoder->output_parameters()) t.zero_();
        m->decoder->skip.copy_(torch::tensor({1.f, 0.8f, 1.2f}));
    }
    torch::NoGradGuard g;
    const EmbreeAccel accel(f.scene);
    const auto geometry = m->scene_geometry(f.sp);
    const SceneLatents folded = m->encode(f.sp, geometry, {}, nullptr, nullptr, traced_inputs_tracer(f.cfg, accel));
    ASSERT_TRUE(folded.deferred);
    EXPECT_FALSE(folded.norm.point_traced.defined() || folded.norm.point_prior.defined()) << "no per-point inputs yet";
    EXPECT_TRUE(folded.norm.traced_light.defined() && folded.norm.regather) << "what makes them later";
    const auto e = m->predict_irradiance(f.qp, folded);
    EXPECT_FALSE(folded.deferred->features.defined()) << "the irradiance does not run the encoder";
    const auto n = f.qp.slice(1, 3, 6);
    const auto t = torch::tensor({0.3f, -0.5f, 0.8f}).expand_as(n);
    auto dir = n + 0.5 * (t - (t * n).sum(1, true) * n);
    dir = dir / dir.norm(2, 1, true);
    const auto lazy = m->predict_radiance(f.qp, dir, folded);
    EXPECT_TRUE(folded.deferred->features.defined());
    m->fold_prior = false;
    const SceneLatents full = m->encode(f.sp, geometry, {}, nullptr, nullptr, traced_inputs_tracer(f.cfg, accel));
    ASSERT_TRUE(full.features.defined() && full.norm.point_traced.defined());
    EXPECT_TRUE(torch::equal(m->features(folded), full.features));
    EXPECT_TRUE(torch::allclose(m->predict_radiance(f.qp, dir, full), lazy, 1e-6, 0.0));
    EXPECT_LT(test::relative_error(m->predict_irradiance(f.qp, full), e), 1e-5);
}

// A random network with a random skip: the fused kernel and the libtorch modules give the same E⁺,
// decode() with R handed in (the trainer's cache) is decode() that gathers it, and the prior and R
// from one walk (prior_and_regathered) are the two separate gathers' bits.
TEST(TracedQueries, FusedEqualsLibtorchAndTheCachedRegatherIsTheGatheredOne) {
    Fixture f;
    LtmModel m = random_model(f.cfg, 5);
    {
        torch::NoGradGuard g;
        m->decoder->skip.copy_(torch::tensor({0.7f, -0.4f, 1.3f}));
    }
    torch::NoGradGuard g;
    const EmbreeAccel accel(f.scene);
    const SceneLatents lat = m->encode(f.sp, m->scene_geometry(f.sp), {}, nullptr, nullptr, traced_inputs_tracer(f.cfg, accel));
    const auto fused = m->predict_irradiance(f.qp, lat);
    m->fused_inference = false;
    EXPECT_LT(test::relative_error(fused, m->predict_irradiance(f.qp, lat)), 1e-4);
    const auto scale = output_scale(f.qp, lat.norm), r = regathered_scale(f.qp, lat.norm);
    EXPECT_TRUE(torch::equal(m->decode(f.qp, lat, scale, r), m->decode(f.qp, lat)));
    // Both from one walk (prior_and_regathered: what predict and the trainer call) are the two gathers' bits.
    const auto [pair_scale, pair_r] = prior_and_regathered(f.qp, lat.norm);
    EXPECT_TRUE(torch::equal(pair_scale, scale));
    EXPECT_TRUE(torch::equal(pair_r, r));
    // The skip reads the last three columns: they are ln(R / Ê).
    const auto q = m->query_inputs(f.qp, lat.norm);
    ASSERT_EQ(q.size(1), 15);
    EXPECT_TRUE(torch::allclose(q.slice(1, 12, 15), torch::log(r / scale), 1e-5, 1e-6));
    SceneLatents bare = lat;
    bare.norm.regather.reset();
    try {
        m->predict_irradiance(f.qp, bare);
        ADD_FAILURE() << "decoded a traced-queries model without its regathered prior";
    } catch (const Error &e) {
        EXPECT_NE(std::string(e.what()).find("traced queries"), std::string::npos) << e.what();
    }
}

// Emission ×4 (the scene traced with 4× the light, the points 4× as bright): ln(R / Ê) unchanged and
// E⁺ ×4. Lengths ×8: unchanged up to the few paths whose absolute ray offsets graze an edge.
TEST(TracedQueries, TheQueryColumnKeepsTheSymmetries) {
    Fixture f;
    LtmModel m = random_model(f.cfg, 7);
    {
        torch::NoGradGuard g;
        m->decoder->skip.fill_(0.8f);
    }
    torch::NoGradGuard g;
    const EmbreeAccel accel(f.scene);
    const auto geometry = m->scene_geometry(f.sp);
    const SceneLatents lat = m->encode(f.sp, geometry, {}, nullptr, nullptr, traced_inputs_tracer(f.cfg, accel));
    const auto column = [&](const torch::Tensor &qp, const SceneLatents &l) { return m->query_inputs(qp, l.norm).slice(1, 12, 15); };
    const auto base = column(f.qp, lat);
    EXPECT_GT(base.abs().max().item<double>(), 0.05);
    const auto e = m->predict_irradiance(f.qp, lat);

    Scene bright = f.scene;
    scale_emission(bright, 4.f);
    const EmbreeAccel accel4(bright);
    const auto sp4 = test::scaled(f.sp, 9, 12, 4.0);
    const SceneLatents lat4 = m->encode(sp4, geometry, {}, nullptr, nullptr, traced_inputs_tracer(f.cfg, accel4));
    EXPECT_LT((column(f.qp, lat4) - base).abs().max().item<double>(), 1e-4);
    EXPECT_LT(test::relative_error(m->predict_irradiance(f.qp, lat4), 4.0 * e), 1e-4);

    Scene big = f.scene;
    scale_lengths(big, 8.f);
    const EmbreeAccel accel8(big);
    const auto sp8 = test::scaled(f.sp, 0, 3, 8.0), qp8 = test::scaled(f.qp, 0, 3, 8.0);
    const SceneLatents lat8 = m->encode(sp8, m->scene_geometry(sp8), {}, nullptr, nullptr, traced_inputs_tracer(f.cfg, accel8));
    EXPECT_LT((column(qp8, lat8) - base).abs().mean().item<double>(), 1e-3);
    EXPECT_LT(test::relative_error(m->predict_irradiance(qp8, lat8), e), 3e-2);
}

// The torch-free prior path (infer/prior_model.h) takes a weights file whose network is silenced:
// with traced queries that is the output layer *and* the skip at zero. A zero layer with skip 1 is the
// regathered prior (scripts/analysis/decoder_skip.py makes one), not the prior; a traced-queries file
// without its skip is refused.
TEST(TracedQueries, OnlyAZeroSkipIsASilencedNetwork) {
    Fixture f;
    LtmModel m = random_model(f.cfg, 11);
    m->decoder->start_at_prior();
    test::TempDir dir;
    save_weights(dir.path("prior.safetensors"), m);
    EXPECT_TRUE(load_prior_model(dir.path("prior.safetensors")).silenced);
    set_skip(m, 1.f);
    save_weights(dir.path("regather.safetensors"), m);
    EXPECT_FALSE(load_prior_model(dir.path("regather.safetensors")).silenced) << "skip 1 is the regathered prior";
    SafetensorsFile without = read_safetensors(dir.path("prior.safetensors"));
    ASSERT_EQ(without.tensors.erase("decoder.skip"), 1u);
    write_safetensors(dir.path("without.safetensors"), without);
    EXPECT_THROW(load_prior_model(dir.path("without.safetensors")), Error);
}
