// reference_cache_test.cpp: the key changes with everything a reference depends on; a stored
// reference loads back bit for bit (that `ltm eval` uses it: experiment_test.cpp).
#include <fstream>

#include <gtest/gtest.h>

#include "ltm/core/exr.h"
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

}  // namespace
}  // namespace ltm
