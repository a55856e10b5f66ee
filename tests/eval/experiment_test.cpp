// experiment_test.cpp: `ltm eval` (run_evaluation) reads its references from the cache
// (eval/reference_cache.h) and really uses them.
#include <filesystem>

#include <gtest/gtest.h>

#include "ltm/eval/experiment.h"
#include "ltm/eval/reference_cache.h"
#include "ltm/scene/builtin_scenes.h"
#include "test_util.h"

namespace ltm {
namespace {

// Two evaluations with the same cache: the second reads the reference from disk. To prove it is
// used (not just written), the cached image is replaced by a scaled copy, which must change the
// PT baseline's error against it, while a run without the cache is unaffected.
TEST(ReferenceCache, EvaluationReusesTheCachedReference) {
    test::TempDir dir;
    std::vector<EvalScene> scenes{{"cornell", cornell_box()}};
    std::vector<EvalModel> no_models;
    EvalOptions opt;
    opt.width = 24, opt.height = 20;
    opt.ref_spp = 16, opt.baseline_spp = 4;
    opt.ref_cache_dir = dir.path("cache");
    const EvalReport first = run_evaluation(scenes, no_models, opt);
    ASSERT_EQ(first.views.size(), 1u);
    EXPECT_FALSE(first.views[0].reference_cached);
    const EvalReport second = run_evaluation(scenes, no_models, opt);
    EXPECT_TRUE(second.views[0].reference_cached);
    EXPECT_EQ(second.views[0].reference_seconds, first.views[0].reference_seconds);
    EXPECT_EQ(second.views[0].methods[0].metrics.mse, first.views[0].methods[0].metrics.mse);

    std::string exr;
    for (const auto &e : std::filesystem::directory_iterator(opt.ref_cache_dir))
        if (e.path().extension() == ".exr") exr = e.path().string();
    ASSERT_FALSE(exr.empty());
    const std::string key = std::filesystem::path(exr).stem().string();
    auto cached = load_cached_reference(opt.ref_cache_dir, key, opt.width, opt.height);
    ASSERT_TRUE(cached);
    for (auto &p : cached->indirect.pixels) p = p * 3.f;
    store_cached_reference(opt.ref_cache_dir, key, *cached, {});
    const EvalReport tampered = run_evaluation(scenes, no_models, opt);
    EXPECT_NE(tampered.views[0].methods[0].metrics.mse, first.views[0].methods[0].metrics.mse);
    opt.ref_cache_dir.clear();
    const EvalReport uncached = run_evaluation(scenes, no_models, opt);
    EXPECT_FALSE(uncached.views[0].reference_cached);
    EXPECT_EQ(uncached.views[0].methods[0].metrics.mse, first.views[0].methods[0].metrics.mse);
}

}  // namespace
}  // namespace ltm
