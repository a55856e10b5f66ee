// scene_edit_test.cpp: JSON-level edits move exactly the named geometry, change exactly the named
// material, and reject what they cannot do.
#include <gtest/gtest.h>

#include "ltm/core/error.h"
#include "ltm/scene/scene_edit.h"
#include "ltm/scene/scene_json.h"

using namespace ltm;

namespace {
Json two_box_scene() {
    return parse_json(R"({
      "materials": [{"name": "grey", "type": "diffuse", "albedo": [0.5, 0.5, 0.5]},
                    {"name": "lamp", "type": "emissive", "radiance": [10, 10, 10]}],
      "meshes": [
        {"name": "bed1_frame", "material": "grey", "positions": [0,0,0, 1,0,0, 1,0,1], "indices": [0,1,2]},
        {"name": "bed1_mattress", "material": "grey", "positions": [0,1,0, 1,1,0, 1,1,1], "indices": [0,1,2],
         "transform": {"translate": [0, 0.5, 0]}},
        {"name": "bed10_frame", "material": "grey", "positions": [5,0,0, 6,0,0, 6,0,1], "indices": [0,1,2]},
        {"name": "light0", "material": "lamp", "positions": [0,3,0, 0,3,1, 1,3,0], "indices": [0,1,2],
         "transform": {"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0]}}]
    })", "test");
}
Bounds3f mesh_bounds(const Scene &s, const std::string &name) {
    for (const auto &m : s.meshes)
        if (m.name == name) {
            Bounds3f b;
            for (const Vec3f &p : m.positions) b.expand(p);
            return b;
        }
    ADD_FAILURE() << "no mesh " << name;
    return {};
}
}  // namespace

TEST(SceneEdit, TranslateMovesTheObjectGroupOnly) {
    Json j = two_box_scene();
    const Scene before = scene_from_json(j, "before", ".");
    EXPECT_EQ(translate_meshes(j, "bed1", {0.5f, 0.f, -1.f}, "t"), 2);   // bed1_*, not bed10_*
    EXPECT_EQ(translate_meshes(j, "light0", {1.f, -0.25f, 0.f}, "t"), 1); // matrix transform
    const Scene after = scene_from_json(j, "after", ".");
    for (const char *name : {"bed1_frame", "bed1_mattress"}) {
        const Bounds3f a = mesh_bounds(before, name), b = mesh_bounds(after, name);
        EXPECT_EQ(b.lo, a.lo + Vec3f(0.5f, 0.f, -1.f)) << name;
    }
    EXPECT_EQ(mesh_bounds(after, "bed10_frame").lo, mesh_bounds(before, "bed10_frame").lo);
    EXPECT_EQ(mesh_bounds(after, "light0").lo, mesh_bounds(before, "light0").lo + Vec3f(1.f, -0.25f, 0.f));
}

TEST(SceneEdit, AlbedoAndRadianceChangeOnlyTheirMaterial) {
    Json j = two_box_scene();
    set_albedo(j, "grey", {0.8f, 0.2f, 0.1f}, "t");
    scale_radiance(j, "lamp", 2.5f, "t");
    const Scene s = scene_from_json(j, "t", ".");
    for (const auto &m : s.materials) {
        if (m.name == "grey") {
            EXPECT_EQ(m.albedo.eval({0.3f, 0.3f}), Vec3f(0.8f, 0.2f, 0.1f));
        }
        if (m.name == "lamp") {
            EXPECT_EQ(m.emission.eval({0.f, 0.f}), Vec3f(25.f));
        }
    }
}

TEST(SceneEdit, RejectsUnknownNamesAndBadValues) {
    Json j = two_box_scene();
    EXPECT_THROW(translate_meshes(j, "sofa", {1.f, 0.f, 0.f}, "t"), Error);
    EXPECT_THROW(translate_meshes(j, "bed1", {NAN, 0.f, 0.f}, "t"), Error);
    EXPECT_THROW(set_albedo(j, "grey", {1.2f, 0.f, 0.f}, "t"), Error);
    EXPECT_THROW(set_albedo(j, "lamp", {0.5f, 0.5f, 0.5f}, "t"), Error);
    EXPECT_THROW(set_albedo(j, "nope", {0.5f, 0.5f, 0.5f}, "t"), Error);
    EXPECT_THROW(scale_radiance(j, "grey", 2.f, "t"), Error);
    EXPECT_THROW(scale_radiance(j, "lamp", -1.f, "t"), Error);
}
