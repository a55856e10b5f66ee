// reference_cache_test.cpp: the key changes with everything a reference depends on; a stored
// reference loads back bit for bit; `ltm eval` (run_evaluation) really uses the cached image.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "ltm/core/exr.h"
#include "ltm/eval/experiment.h"
#include "ltm/eval/reference_cache.h"
#include "ltm/scene/builtin_scenes.h"
#include "test_util.h"

namespace ltm {
namespace {

Camera small_camera(const Scene &s) {
    Camera c = s.cameras.front();
    c.width = 24, c.height = 20;
    return c;
}

TEST(ReferenceCache, KeyChangesWithEverythingTheReferenceDependsOn) {
    const Scene s = cornell_box();
    const Camera cam = small_camera(s);
    const PathTracerConfig cfg;
    const std::string key = reference_cache_key(s, cam, 64, cfg);
    EXPECT_EQ(key.size(), 16u);
    EXPECT_EQ(key, reference_cache_key(s, cam, 64, cfg)) << "deterministic";
    EXPECT_NE(key, reference_cache_key(s, cam, 128, cfg)) << "spp";
    PathTracerConfig c2 = cfg;
    c2.seed = 1;
    EXPECT_NE(key, reference_cache_key(s, cam, 64, c2)) << "seed";
    c2 = cfg;
    c2.max_depth = 3;
    EXPECT_NE(key, reference_cache_key(s, cam, 64, c2)) << "depth";
    Camera cam2 = cam;
    cam2.eye.x += 1e-3f;
    EXPECT_NE(key, reference_cache_key(s, cam2, 64, cfg)) << "camera";
    cam2 = cam;
    cam2.width = 25;
    EXPECT_NE(key, reference_cache_key(s, cam2, 64, cfg)) << "size";
    Scene s2 = s;
    s2.materials[0].albedo.color_a.x *= 0.5f;
    EXPECT_NE(key, reference_cache_key(s2, cam, 64, cfg)) << "albedo";
    s2 = s;
    s2.meshes[0].positions[0].y += 1e-4f;
    EXPECT_NE(key, reference_cache_key(s2, cam, 64, cfg)) << "geometry";
    s2 = s;
    s2.metadata["note"] = "provenance only";
    s2.cameras.push_back(cam2);
    EXPECT_EQ(key, reference_cache_key(s2, cam, 64, cfg)) << "metadata and unused cameras do not matter";
}

TEST(ReferenceCache, StoreThenLoadIsExactAndBadFilesAreMisses) {
    test::TempDir dir;
    CachedReference ref;
    ref.indirect = Image(5, 3);
    for (size_t i = 0; i < ref.indirect.pixels.size(); ++i)
        ref.indirect.pixels[i] = Vec3f(0.1f * float(i), 1.f / float(i + 3), 7.25f);
    ref.seconds = 12.5;
    EXPECT_FALSE(load_cached_reference(dir.path(), "0123456789abcdef", 5, 3)) << "empty cache";
    store_cached_reference(dir.path(), "0123456789abcdef", ref, {{"scene", "x"}});
    const auto back = load_cached_reference(dir.path(), "0123456789abcdef", 5, 3);
    ASSERT_TRUE(back);
    EXPECT_EQ(back->seconds, 12.5);
    for (size_t i = 0; i < ref.indirect.pixels.size(); ++i) {
        EXPECT_EQ(back->indirect.pixels[i].x, ref.indirect.pixels[i].x);
        EXPECT_EQ(back->indirect.pixels[i].y, ref.indirect.pixels[i].y);
        EXPECT_EQ(back->indirect.pixels[i].z, ref.indirect.pixels[i].z);
    }
    EXPECT_FALSE(load_cached_reference(dir.path(), "0123456789abcdef", 5, 4)) << "another size";
    std::ofstream(dir.path("0123456789abcdef.exr"), std::ios::trunc) << "not an exr";
    EXPECT_FALSE(load_cached_reference(dir.path(), "0123456789abcdef", 5, 3)) << "corrupt image";
    store_cached_reference(dir.path(), "0123456789abcdef", ref, {{"scene", "x"}});
    std::ofstream(dir.path("0123456789abcdef.json"), std::ios::trunc) << "{\"scene\": \"x\"}";
    EXPECT_FALSE(load_cached_reference(dir.path(), "0123456789abcdef", 5, 3)) << "metadata without seconds";
    std::ofstream(dir.path("0123456789abcdef.json"), std::ios::trunc) << "{\"seconds\": ";
    EXPECT_FALSE(load_cached_reference(dir.path(), "0123456789abcdef", 5, 3)) << "truncated metadata";
}

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
