// experiment_test.cpp: `ltm eval` (run_evaluation) reads its references from the cache
// (eval/reference_cache.h) and really uses them.
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "ltm/eval/experiment.h"
#include "ltm/eval/reference_cache.h"
#include "ltm/infer/neural_renderer.h"
#include "ltm/render/scene_points.h"
#include "ltm/scene/builtin_scenes.h"
#include "test_util.h"

namespace ltm {
namespace {

// Path tracing alone (no model) on the Cornell box: the reference, PT and the floors, w × h pixels,
// references cached in `cache`.
struct CornellEval {
    std::vector<EvalScene> scenes{{"cornell", cornell_box()}};
    std::vector<EvalModel> no_models;
    EvalOptions opt;
    CornellEval(int w, int h, int ref_spp, int baseline_spp, const std::string &cache) {
        opt.width = w, opt.height = h;
        opt.ref_spp = ref_spp, opt.baseline_spp = baseline_spp;
        opt.ref_cache_dir = cache;
    }
    EvalReport run() { return run_evaluation(scenes, no_models, opt); }
};

// Two evaluations with the same cache: the second reads the reference from disk. To prove it is
// used (not just written), the cached image is replaced by a scaled copy, which must change the
// PT baseline's error against it, while a run without the cache is unaffected.
TEST(ReferenceCache, EvaluationReusesTheCachedReference) {
    test::TempDir dir;
    CornellEval e(24, 20, 16, 4, dir.path("cache"));
    const EvalReport first = e.run();
    ASSERT_EQ(first.views.size(), 1u);
    EXPECT_FALSE(first.views[0].reference_cached);
    const EvalReport second = e.run();
    EXPECT_TRUE(second.views[0].reference_cached);
    EXPECT_EQ(second.views[0].reference_seconds, first.views[0].reference_seconds);
    EXPECT_EQ(second.views[0].methods[0].metrics.mse, first.views[0].methods[0].metrics.mse);

    std::string exr;
    for (const auto &entry : std::filesystem::directory_iterator(e.opt.ref_cache_dir))
        if (entry.path().extension() == ".exr") exr = entry.path().string();
    ASSERT_FALSE(exr.empty());
    const std::string key = std::filesystem::path(exr).stem().string();
    auto cached = load_cached_reference(e.opt.ref_cache_dir, key, e.opt.width, e.opt.height);
    ASSERT_TRUE(cached);
    for (auto &p : cached->indirect.pixels) p = p * 3.f;
    store_cached_reference(e.opt.ref_cache_dir, key, *cached, {});
    const EvalReport tampered = e.run();
    EXPECT_NE(tampered.views[0].methods[0].metrics.mse, first.views[0].methods[0].metrics.mse);
    e.opt.ref_cache_dir.clear();
    const EvalReport uncached = e.run();
    EXPECT_FALSE(uncached.views[0].reference_cached);
    EXPECT_EQ(uncached.views[0].methods[0].metrics.mse, first.views[0].methods[0].metrics.mse);
}

// The reference's noise floor (--ref-noise) is the variance of the reference itself: PT at the
// reference's own spp has that variance too, so its MSE against the reference is about twice the
// floor; the floor falls as the reference's spp grows; it is cached with the reference.
TEST(ReferenceNoise, IsTheReferencesOwnVariance) {
    test::TempDir dir;
    CornellEval e(96, 96, 64, 64, dir.path("cache"));
    e.opt.reference_noise = true;
    const EvalReport r = e.run();
    ASSERT_EQ(r.views.size(), 1u);
    ASSERT_EQ(r.views[0].methods[0].method, "pt64");
    const double floor64 = r.views[0].reference_noise_mse, pt64 = r.views[0].methods[0].metrics.mse;
    EXPECT_GT(floor64, 0.0);
    EXPECT_NEAR(pt64 / floor64, 2.0, 0.4) << pt64 << " " << floor64;
    e.opt.ref_spp = 256;
    EXPECT_LT(e.run().views[0].reference_noise_mse, 0.5 * floor64);
    e.opt.ref_spp = 64;
    const EvalReport again = e.run();
    EXPECT_TRUE(again.views[0].reference_cached);
    EXPECT_EQ(again.views[0].reference_noise_mse, floor64) << "the twin comes from the cache too";
    EXPECT_NE(again.table_markdown().find("Reference noise: "), std::string::npos);
    e.opt.reference_noise = false;
    EXPECT_TRUE(std::isnan(e.run().views[0].reference_noise_mse));
}

// `ltm eval --scene-points auto`: every scene sets the model's M from its own size, starting from
// the model as loaded each time — so a detailed scene between two small ones does not leave its M
// (or its tree) behind — and without auto the model keeps its own M.
TEST(EvalModel, AutoScenePointsFollowEachScene) {
    Scene small = cornell_box(), detailed = cornell_box();
    TriangleMesh strip;   // k_auto_detail_triangles slivers: detail the auto rule counts
    for (size_t t = 0; t < k_auto_detail_triangles; ++t) {
        const float x = 0.1f + 0.3f * float(t) / float(k_auto_detail_triangles);
        const uint32_t i = uint32_t(strip.positions.size());
        strip.positions.insert(strip.positions.end(), {{x, 0.2f, 0.2f}, {x + 1e-4f, 0.2f, 0.2f}, {x, 0.2f, 0.2001f}});
        strip.indices.insert(strip.indices.end(), {i, i + 1, i + 2});
    }
    strip.material = detailed.meshes.front().material;
    detailed.meshes.push_back(strip);
    ASSERT_GE(detailed.n_triangles(), k_auto_detail_triangles);

    EvalModel m{"ours", "", load_model(test::source_path("models/ltm-cpu.safetensors")).model};
    const int64_t own = m.model->cfg.scene_points;
    EXPECT_EQ(m.fit_scene_points(detailed), own) << "without auto the model keeps its M";
    m.enable_auto_scene_points(false);
    EXPECT_EQ(m.fit_scene_points(small), auto_scene_points(small));
    EXPECT_EQ(m.fit_scene_points(detailed), auto_scene_points(detailed));
    EXPECT_GT(auto_scene_points(detailed), auto_scene_points(small));
    EXPECT_EQ(m.model->cfg.physics.prior_theta, 0.5f) << "above the model's M, through the tree";
    EXPECT_EQ(m.fit_scene_points(small), auto_scene_points(small)) << "the detailed scene's M is not kept";
    // A θ given on the command line stays: auto never replaces it.
    m.model->cfg.physics.prior_theta = 0.f;
    m.enable_auto_scene_points(true);
    m.fit_scene_points(detailed);
    EXPECT_EQ(m.model->cfg.physics.prior_theta, 0.f);
}

// A silent body with the skip at 1 (the shipped model) is evaluated as `ltm render` runs it: its
// regather alone, without the prior's bounces (infer/prior_model.h). The same weights through the
// tensor model's own path (fold_prior off: the encoder, attention and skip run) give the same E⁺ to
// float rounding; its model-prior row, from a frame solved for the prior alone (untraced: the scene is
// traced once, for R), is the tensor model's prior row, not R.
TEST(EvalModel, ARegatherFoldIsEvaluatedAsTheRendererRunsIt) {
    test::TempDir dir;
    CornellEval e(24, 20, 16, 4, dir.path("cache"));
    const std::string shipped = test::source_path("models/ltm-cpu.safetensors");
    std::vector<EvalModel> models{{"folded", "", load_model(shipped).model}, {"tensor", "", load_model(shipped).model}};
    for (auto &m : models) m.model->cfg.scene_points = 2048;
    models[1].model->fold_prior = false;
    const EvalReport r = run_evaluation(e.scenes, models, e.opt);
    ASSERT_EQ(r.views.size(), 1u);
    const MethodResult *folded = nullptr, *tensor = nullptr, *prior = nullptr, *tensor_prior = nullptr;
    for (const auto &m : r.views[0].methods) {
        if (m.method == "model:folded") folded = &m;
        if (m.method == "model:tensor") tensor = &m;
        if (m.method == "model-prior:folded") prior = &m;
        if (m.method == "model-prior:tensor") tensor_prior = &m;
    }
    ASSERT_TRUE(folded && tensor && prior && tensor_prior);
    // The folded model's prior row comes from an untraced torch-free frame, the tensor model's from its encode.
    EXPECT_NEAR(prior->metrics.mse, tensor_prior->metrics.mse, 1e-3 * tensor_prior->metrics.mse);
    EXPECT_NEAR(prior->field.level_ratio, tensor_prior->field.level_ratio, 1e-4);
    ASSERT_GT(folded->metrics.mse, 0.0);
    EXPECT_NEAR(folded->metrics.mse, tensor->metrics.mse, 1e-3 * tensor->metrics.mse);
    EXPECT_NEAR(folded->field.level_ratio, tensor->field.level_ratio, 1e-4);
    // The prior and R are close on this small box (MSEs 0.3 % apart, levels 1.003 and 0.992), yet
    // farther apart than the two paths to R are from each other.
    EXPECT_GT(std::abs(prior->field.level_ratio - folded->field.level_ratio), 5e-3) << "the model-prior row is the prior, not R";
}

}  // namespace
}  // namespace ltm
