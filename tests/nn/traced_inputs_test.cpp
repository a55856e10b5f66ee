// traced_inputs_test.cpp: ModelConfig::traced_inputs (issue #30, session 36) — every scene point
// also carries its traced E⁺ and the prior regathered from the traced light. The inputs keep the
// exact symmetries when the scene itself is scaled (path tracing is linear in emission and blind to
// the unit), they are the same at any thread count, a model at its prior does not trace, and a
// model without its scene's tracer says so. The trainer's side (draws, the widening conversion):
// tests/train/trainer_test.cpp.
#include <atomic>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "ltm/core/error.h"
#include "ltm/core/parallel.h"
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
// The tiny model with the shipped prior's physics (as prior_inputs_test.cpp), prior and traced inputs.
using Fixture = test::TracedSceneFixture;

// The traced inputs the encoder reads (log1p of traced E⁺ and regathered prior over S·Σρ̄^k), [M, 6].
torch::Tensor traced_features(const SceneLatents &lat) {
    const auto &t = lat.norm.point_traced;
    return torch::cat({prior_features(t.slice(1, 0, 3), lat.norm), prior_features(t.slice(1, 3, 6), lat.norm)}, 1);
}

double max_abs(const torch::Tensor &t) { return t.abs().max().item<double>(); }
}  // namespace

TEST(TracedInputs, ConfigNeedsPriorInputsAndStaysOutOfOlderJson) {
    Fixture f;
    const auto j = f.cfg.to_json();
    EXPECT_EQ(j.at("traced_inputs").get<int>(), 4);
    EXPECT_EQ(ModelConfig::from_json(j, "t").traced_inputs, 4);
    auto no_prior = j;
    no_prior.erase("prior_inputs");
    EXPECT_THROW(ModelConfig::from_json(no_prior, "t"), Error);
    auto too_many = j;
    too_many["traced_inputs"] = 5000;
    EXPECT_THROW(ModelConfig::from_json(too_many, "t"), Error);
    const ModelConfig pi = ModelConfig::from_file(test::source_path("configs/model/cpu-pi.json"));
    EXPECT_FALSE(pi.to_json().contains("traced_inputs")) << "written only when set: older weights keep their JSON";
    EXPECT_EQ(LtmModel(f.cfg)->cfg.embedding.extra_inputs, 9) << "the prior's 3 and the traced 6";
}

// Emission ×4 in the scene (its tracer traces 4× the light) and ×4 in the points: the traced inputs
// are the same and E⁺ is 4×. Lengths ×8 (scene, points, queries; a power of two, so positions scale
// exactly and the prior's voxel grid maps onto itself): the inputs and E⁺ unchanged. The
// counter-check: emission ×4 in the points while the tracer keeps the old scene changes the inputs.
TEST(TracedInputs, InputsKeepTheSymmetriesWhenTheSceneIsScaled) {
    Fixture f;
    LtmModel m = random_model(f.cfg, 3);
    torch::NoGradGuard g;
    const EmbreeAccel accel(f.scene);
    const auto geometry = m->scene_geometry(f.sp);
    const SceneLatents lat = m->encode(f.sp, geometry, {}, nullptr, nullptr, traced_inputs_tracer(f.cfg, accel));
    ASSERT_TRUE(lat.norm.point_traced.defined());
    ASSERT_EQ(lat.norm.point_traced.sizes(), (c10::IntArrayRef{f.sp.size(0), 6}));
    const auto base = traced_features(lat);
    EXPECT_GT(max_abs(base.slice(1, 0, 3)), 0.05) << "the room's points receive indirect light";
    EXPECT_GT(max_abs(base.slice(1, 3, 6)), 0.05);
    const auto e = m->predict_irradiance(f.qp, lat);

    Scene bright = f.scene;
    scale_emission(bright, 4.f);
    const EmbreeAccel accel4(bright);
    const auto sp4 = test::scaled(f.sp, 9, 12, 4.0);
    const SceneLatents lat4 = m->encode(sp4, geometry, {}, nullptr, nullptr, traced_inputs_tracer(f.cfg, accel4));
    EXPECT_LT(max_abs(traced_features(lat4) - base), 1e-4);
    EXPECT_LT(test::relative_error(m->predict_irradiance(f.qp, lat4), 4.0 * e), 1e-4);
    const SceneLatents stale = m->encode(sp4, geometry, {}, nullptr, nullptr, traced_inputs_tracer(f.cfg, accel));
    EXPECT_GT(max_abs(traced_features(stale) - base), 0.05) << "the inputs do read the tracer";

    Scene big = f.scene;
    scale_lengths(big, 8.f);
    const EmbreeAccel accel8(big);
    const auto sp8 = test::scaled(f.sp, 0, 3, 8.0), qp8 = test::scaled(f.qp, 0, 3, 8.0);
    const SceneLatents lat8 = m->encode(sp8, m->scene_geometry(sp8), {}, nullptr, nullptr, traced_inputs_tracer(f.cfg, accel8));
    // The tracer's ray offsets scale with the scene's extent (PathTracerConfig::offset_length): with
    // a metre's floor, 2 of the 1 024 points' paths grazed an edge and went elsewhere at ×8 (inputs
    // 10⁻³ off, the random network's output 3 %); now every path is the same path.
    EXPECT_LT(max_abs(traced_features(lat8) - base), 1e-4);
    EXPECT_LT(test::relative_error(m->predict_irradiance(qp8, lat8), e), 1e-4);
}

TEST(TracedInputs, TheSameAtAnyThreadCount) {
    Fixture f;
    LtmModel m = random_model(f.cfg, 5);
    torch::NoGradGuard g;
    const EmbreeAccel accel(f.scene);
    const auto geometry = m->scene_geometry(f.sp);
    const int threads = num_threads();
    set_num_threads(1);
    const auto one = m->encode(f.sp, geometry, {}, nullptr, nullptr, traced_inputs_tracer(f.cfg, accel)).norm.point_traced;
    set_num_threads(2);
    const auto two = m->encode(f.sp, geometry, {}, nullptr, nullptr, traced_inputs_tracer(f.cfg, accel)).norm.point_traced;
    set_num_threads(threads);
    EXPECT_TRUE(torch::equal(one, two));
}

// The tracer keyed by the scene points' identities (ScenePoints::ids) must be given as many points as
// it has keys: the keys of other points would trace the wrong streams (an internal error: the callers
// pass the ids of the points they sampled).
TEST(TracedInputs, KeysForOtherPointsAreRefused) {
    Fixture f;
    const EmbreeAccel accel(f.scene);
    const auto sp = f.sp.contiguous();
    const size_t n = size_t(sp.size(0));
    std::vector<uint64_t> keys(n);
    for (size_t i = 0; i < n; ++i) keys[i] = 1000 + i;
    std::vector<Vec3f> direct(n), indirect(n);
    EXPECT_NO_THROW(traced_inputs_tracer(f.cfg, accel, keys)(sp.data_ptr<float>(), n, direct.data(), indirect.data()));
    keys.pop_back();
    EXPECT_THROW(traced_inputs_tracer(f.cfg, accel, keys)(sp.data_ptr<float>(), n, direct.data(), indirect.data()), std::logic_error);
}

// A model at its prior reads no input (fold_prior): it must not pay for tracing. With its network
// active it traces once per encode, and without a tracer it names what is missing.
TEST(TracedInputs, TracedOnlyWhenTheNetworkReadsThemAndNamedWhenMissing) {
    Fixture f;
    LtmModel m = random_model(f.cfg, 7);
    torch::NoGradGuard g;
    const EmbreeAccel accel(f.scene);
    const PointTracer inner = traced_inputs_tracer(f.cfg, accel);
    std::atomic<int> calls{0};
    const PointTracer counting = [&](const float *rows, size_t n, Vec3f *direct, Vec3f *indirect) {
        ++calls;
        inner(rows, n, direct, indirect);
    };
    const auto geometry = m->scene_geometry(f.sp);
    m->encode(f.sp, geometry, {}, nullptr, nullptr, counting);
    EXPECT_EQ(calls.load(), 1);
    try {
        m->encode(f.sp, geometry);
        ADD_FAILURE() << "encoded a traced-inputs model without its tracer";
    } catch (const Error &e) {
        EXPECT_NE(std::string(e.what()).find("traced inputs"), std::string::npos) << e.what();
    }
    m->decoder->start_at_prior();
    calls = 0;
    const SceneLatents folded = m->encode(f.sp, geometry, {}, nullptr, nullptr, counting);
    EXPECT_EQ(calls.load(), 0);
    EXPECT_FALSE(folded.norm.point_traced.defined());
    EXPECT_NO_THROW(m->predict_irradiance(f.qp, folded));
}

// The regather's bookkeeping: a tracer that hands every node exactly the irradiance whose ρ-fold is
// the prior's own exitance there (E = exitance / ρ, nodes found by their positions, not by the
// code's node order) must give back the prior at every scene point. Nodes as every point and as
// the FPS centres, dense rows and the cluster tree (whose sums the regather recomputes).
TEST(TracedInputs, RegatheringThePriorsOwnLightIsThePrior) {
    Fixture f;
    const auto sp = f.sp.contiguous();
    const size_t n = size_t(sp.size(0));
    const float *rows = sp.data_ptr<float>();
    std::vector<float> xyz(n * 3);
    for (size_t j = 0; j < n; ++j)
        for (size_t a = 0; a < 3; ++a) xyz[j * 3 + a] = rows[j * 12 + a];
    // sample_ratio 1: the FPS centres are every point, in FPS order — as many nodes as points, yet
    // node i is not point i.
    EmbeddingConfig every = f.cfg.embedding;
    every.sample_ratio = 1.f;
    const PointGroups half = point_groups(xyz.data(), n, f.cfg.embedding), all = point_groups(xyz.data(), n, every);
    for (const char *nodes : {"points", "anchors", "all anchors"})
        for (float theta : {0.f, 0.5f}) {
            const PointGroups &groups = std::string(nodes) == "all anchors" ? all : half;
            PhysicsConfig ph = f.cfg.physics;
            ph.prior_nodes = std::string(nodes) == "points" ? "points" : "anchors", ph.prior_theta = theta;
            const SceneFrame base = solve_scene_frame(rows, n, groups, ph);
            const TransportPrior &prior = *base.transport;
            std::vector<Vec3f> given(n, Vec3f(0.f));
            size_t matched = 0;
            for (size_t i = 0; i < prior.position.size(); ++i)
                for (size_t j = 0; j < n; ++j) {
                    const float *r = rows + j * 12;
                    const Vec3f x((r[0] - base.center.x) / base.length, (r[1] - base.center.y) / base.length, (r[2] - base.center.z) / base.length);
                    if (!(x == prior.position[i])) continue;
                    for (int c = 0; c < 3; ++c) given[j][c] = r[6 + c] > 0.f ? prior.exitance[i][c] / r[6 + c] : 0.f;   // ρ = 0 re-emits nothing
                    ++matched;
                    break;
                }
            ASSERT_EQ(matched, prior.position.size()) << nodes;
            ASSERT_EQ(matched, std::string(nodes) == "points" ? n : groups.centers.size());
            const PointTracer tracer = [&](const float *, size_t count, Vec3f *direct, Vec3f *indirect) {
                ASSERT_EQ(count, n);
                for (size_t j = 0; j < n; ++j) direct[j] = given[j], indirect[j] = Vec3f(0.f);
            };
            const SceneFrame traced = solve_scene_frame(rows, n, groups, ph, nullptr, nullptr, tracer);
            ASSERT_EQ(traced.regathered.size(), n);
            std::vector<float> q(n * 9);
            for (size_t j = 0; j < n; ++j) {
                for (int a = 0; a < 3; ++a) q[j * 9 + size_t(a)] = (rows[j * 12 + size_t(a)] - base.center[a]) / base.length;
                for (int a = 3; a < 9; ++a) q[j * 9 + size_t(a)] = rows[j * 12 + size_t(a)];
            }
            std::vector<Vec3f> expected(n);
            prior_scale_normalized(base.transport.get(), base.output, q.data(), 9, n, expected.data());
            double worst = 0, level = 0;
            for (size_t j = 0; j < n; ++j)
                for (int c = 0; c < 3; ++c) {
                    worst = std::max(worst, double(std::abs(traced.regathered[j][c] - expected[j][c])));
                    level += double(expected[j][c]) / double(3 * n);
                }
            EXPECT_LT(worst, 1e-4 * level) << "nodes " << nodes << ", theta " << theta;
        }
}
