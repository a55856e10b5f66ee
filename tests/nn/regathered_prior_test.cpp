// regathered_prior_test.cpp: physics.prior_regathered (issue #30, session 43) — R, the transport's
// regather of the light traced at its nodes, is the prior itself: the frame solves no bounces, a
// silenced network is R (the same R a traced-queries model gathers at skip 1), the scene points'
// prior input is their traced E⁺ and the queries' is R, the inputs keep the exact symmetries, and a
// frame without the scene's tracer is refused in one line. The trainer's side (frame cache, --init):
// tests/train/trainer_test.cpp.
#include <string>

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "ltm/core/error.h"
#include "ltm/infer/prior_model.h"
#include "ltm/nn/ltm_model.h"
#include "ltm/nn/scene_frame.h"
#include "ltm/render/embree_accel.h"
#include "ltm/scene/scene_transform.h"
#include "test_util.h"
#include "tiny_scene_fixture.h"

using namespace ltm;

namespace {
using test::random_model;
struct Fixture : test::TracedSceneFixture {
    Fixture() { cfg.physics.prior_regathered = true; }
};
}  // namespace

TEST(RegatheredPrior, ConfigNeedsTracedAndPriorInputsAndRefusesTheSkipAndTheLevel) {
    Fixture f;
    const auto j = f.cfg.to_json();
    EXPECT_TRUE(j.at("physics").at("prior_regathered").get<bool>());
    EXPECT_TRUE(ModelConfig::from_json(j, "t").physics.prior_regathered);
    for (const char *breaks : {"untraced", "skip", "level", "no-prior-inputs"}) {
        auto bad = j;
        const std::string b = breaks;
        if (b == "untraced") bad.erase("traced_inputs");
        if (b == "skip") bad["traced_queries"] = true;
        if (b == "level") bad["decoder"]["level_points"] = 16;
        if (b == "no-prior-inputs") bad.erase("prior_inputs"), bad.erase("traced_inputs");
        try {
            ModelConfig::from_json(bad, "cfg.json");
            ADD_FAILURE() << b << ": accepted";
        } catch (const Error &e) {
            EXPECT_NE(std::string(e.what()).find("cfg.json"), std::string::npos) << e.what();
        }
    }
    ModelConfig plain = f.cfg;
    plain.physics.prior_regathered = false;
    EXPECT_FALSE(plain.to_json().at("physics").contains("prior_regathered")) << "written only when set: older weights keep their JSON";
    const LtmModel m(f.cfg);
    EXPECT_EQ(m->cfg.embedding.extra_inputs, 3) << "the points' traced E⁺ is their prior input: prior_inputs' shapes";
    EXPECT_EQ(m->cfg.decoder.extra_inputs, 3);
    EXPECT_FALSE(m->decoder->skip.defined());
    ModelConfig skip_code = f.cfg;
    skip_code.traced_queries = true;
    EXPECT_THROW(LtmModel{skip_code}, Error) << "built in code: refused in one line too";
}

// At its prior (𝓦_out zero) the model is R: the regather a traced-queries model of the same points
// and tracer gathers at skip 1 — folded, through the fused decoder and through libtorch — and the
// torch-free frame's prior_irradiance; the frame's prior is its regather (no bounces solved).
TEST(RegatheredPrior, ASilencedNetworkIsR) {
    Fixture f;
    torch::NoGradGuard g;
    const EmbreeAccel accel(f.scene);
    const PointTracer tracer = traced_inputs_tracer(f.cfg, accel);
    ModelConfig tq_cfg = test::TracedSceneFixture().cfg;
    tq_cfg.traced_queries = true;
    LtmModel tq = random_model(tq_cfg, 3);
    tq->fold_prior = false;
    const SceneLatents tq_lat = tq->encode(f.sp, tq->scene_geometry(f.sp), {}, nullptr, nullptr, tracer);
    const auto r = regathered_scale(f.qp, tq_lat.norm);
    const auto solved = prior_irradiance(f.qp, tq_lat.norm);
    ASSERT_GT(test::relative_error(r, solved), 0.01) << "R and the solved prior differ (the check below is to 1e-5)";

    LtmModel m = random_model(f.cfg, 3);
    m->decoder->start_at_prior();
    ASSERT_TRUE(m->decoder->at_prior());
    const auto geometry = m->scene_geometry(f.sp);
    const SceneLatents folded = m->encode(f.sp, geometry, {}, nullptr, nullptr, tracer);
    EXPECT_EQ(folded.norm.transport.get(), folded.norm.regather.get()) << "the prior gathered is the regather";
    EXPECT_LT(test::relative_error(m->predict_irradiance(f.qp, folded), r), 1e-5) << "folded";
    m->fold_prior = false;
    const SceneLatents net = m->encode(f.sp, geometry, {}, nullptr, nullptr, tracer);
    EXPECT_LT(test::relative_error(m->predict_irradiance(f.qp, net), r), 1e-5) << "fused";
    m->fused_inference = false;
    EXPECT_LT(test::relative_error(m->predict_irradiance(f.qp, net), r), 1e-5) << "libtorch";

    // The torch-free frame (infer/prior_model.h renders from it): the same R.
    const auto pos = f.sp.slice(1, 0, 3).contiguous();
    const PointGroups groups = point_groups(pos.data_ptr<float>(), size_t(pos.size(0)), f.cfg.embedding);
    const auto spc = f.sp.contiguous();
    const SceneFrame frame = solve_scene_frame(spc.data_ptr<float>(), size_t(spc.size(0)), groups, f.cfg.physics, nullptr, nullptr, tracer,
                                               /*point_inputs=*/false);
    EXPECT_FALSE(frame.transport->exitance.empty());
    const auto qc = f.qp.contiguous();
    auto plain = torch::empty({qc.size(0), 3});
    prior_irradiance(frame, qc.data_ptr<float>(), size_t(qc.size(0)), reinterpret_cast<Vec3f *>(plain.data_ptr<float>()));
    EXPECT_LT(test::relative_error(plain, r), 1e-5) << "torch-free";

    // Without the scene's tracer there is no prior: one line naming it, at its prior too.
    m->fold_prior = true;
    try {
        m->encode(f.sp, geometry);
        ADD_FAILURE() << "encoded a regathered-prior model without its tracer";
    } catch (const Error &e) {
        EXPECT_NE(std::string(e.what()).find("path tracer"), std::string::npos) << e.what();
    }
}

// The inputs: each scene point's prior column is its traced E⁺, each query's is R. Emission ×4 (the
// scene traced with 4× the light): the inputs unchanged, E⁺ ×4. Lengths ×8: unchanged up to the few
// paths whose absolute ray offsets graze an edge.
TEST(RegatheredPrior, TheInputsAreTheTracedLightAndRAndKeepTheSymmetries) {
    Fixture f;
    LtmModel m = random_model(f.cfg, 7);
    m->fold_prior = false;
    ASSERT_FALSE(m->decoder->body_silent());
    torch::NoGradGuard g;
    const EmbreeAccel accel(f.scene);
    const auto geometry = m->scene_geometry(f.sp);
    const SceneLatents lat = m->encode(f.sp, geometry, {}, nullptr, nullptr, traced_inputs_tracer(f.cfg, accel));
    ASSERT_TRUE(lat.norm.point_prior.defined() && lat.norm.traced_light.defined());
    EXPECT_TRUE(torch::equal(lat.norm.point_prior, lat.norm.traced_light)) << "the points' prior input is their traced E⁺";
    EXPECT_FALSE(lat.norm.point_traced.defined()) << "R is not gathered at the M points";
    const auto inputs = [&](const SceneLatents &l, const torch::Tensor &sp, const torch::Tensor &qp) {
        const auto x = m->encoder_inputs(normalize_scene_points(sp, l.norm), sp.slice(1, 0, 9), l.norm);
        return std::pair{x.slice(1, 9, 15), m->query_inputs(qp, l.norm).slice(1, 9, 12)};   // emission and light columns
    };
    const auto [points, queries] = inputs(lat, f.sp, f.qp);
    ASSERT_EQ(queries.size(1), 3);
    EXPECT_LT(test::relative_error(queries, prior_features(regathered_scale(f.qp, lat.norm), lat.norm)), 1e-6) << "the queries read R";
    const auto e = m->predict_irradiance(f.qp, lat);
    EXPECT_GT(test::relative_error(e, regathered_scale(f.qp, lat.norm)), 1e-3) << "a random body moves the output";

    Scene bright = f.scene;
    scale_emission(bright, 4.f);
    const EmbreeAccel accel4(bright);
    const auto sp4 = test::scaled(f.sp, 9, 12, 4.0);
    const SceneLatents lat4 = m->encode(sp4, geometry, {}, nullptr, nullptr, traced_inputs_tracer(f.cfg, accel4));
    const auto [points4, queries4] = inputs(lat4, sp4, f.qp);
    EXPECT_LT((points4 - points).abs().max().item<double>(), 1e-4);
    EXPECT_LT((queries4 - queries).abs().max().item<double>(), 1e-4);
    EXPECT_LT(test::relative_error(m->predict_irradiance(f.qp, lat4), 4.0 * e), 1e-4);

    Scene big = f.scene;
    scale_lengths(big, 8.f);
    const EmbreeAccel accel8(big);
    const auto sp8 = test::scaled(f.sp, 0, 3, 8.0), qp8 = test::scaled(f.qp, 0, 3, 8.0);
    const SceneLatents lat8 = m->encode(sp8, m->scene_geometry(sp8), {}, nullptr, nullptr, traced_inputs_tracer(f.cfg, accel8));
    const auto [points8, queries8] = inputs(lat8, sp8, qp8);
    EXPECT_LT((queries8 - queries).abs().mean().item<double>(), 1e-3);
    EXPECT_LT((points8 - points).abs().mean().item<double>(), 1e-3);
    EXPECT_LT(test::relative_error(m->predict_irradiance(qp8, lat8), e), 3e-2);
}
