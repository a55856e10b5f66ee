// scene_transform_test.cpp: the whole-scene probes of the physics checks change exactly what
// they say: emission × k, lengths × s (area × s², textures on the same points), recoloured shells.
#include <algorithm>

#include <gtest/gtest.h>

#include "ltm/core/error.h"
#include "ltm/scene/builtin_scenes.h"
#include "ltm/scene/scene_transform.h"

using namespace ltm;

TEST(SceneTransform, EmissionScalesEveryEmitterOnly) {
    Scene s = quad_light_room();
    const Scene before = s;
    scale_emission(s, 4.f);
    for (size_t i = 0; i < s.materials.size(); ++i) {
        EXPECT_EQ(s.materials[i].emission.color_a.x, 4.f * before.materials[i].emission.color_a.x);
        EXPECT_EQ(s.materials[i].albedo.color_a.y, before.materials[i].albedo.color_a.y);
    }
    EXPECT_THROW(scale_emission(s, -1.f), Error);
    EXPECT_THROW(scale_emission(s, NAN), Error);
}

TEST(SceneTransform, LengthsScaleAreaByTheSquareAndKeepUvs) {
    Scene s = quad_light_room();
    const Scene before = s;
    scale_lengths(s, 10.f);
    EXPECT_NEAR(s.total_area(), 100.0 * before.total_area(), 1e-4 * s.total_area());
    ASSERT_EQ(s.meshes[0].uvs.size(), before.meshes[0].uvs.size());
    for (size_t i = 0; i < s.meshes[0].uvs.size(); ++i)
        EXPECT_TRUE(s.meshes[0].uvs[i].x == before.meshes[0].uvs[i].x && s.meshes[0].uvs[i].y == before.meshes[0].uvs[i].y);
    EXPECT_EQ(s.cameras[0].eye.x, 10.f * before.cameras[0].eye.x);
    EXPECT_THROW(scale_lengths(s, 0.f), Error);
}

TEST(SceneTransform, TheScenesExtentIsItsLongestSideAndScalesWithTheUnit) {
    EXPECT_EQ(Scene{}.extent(), 0.f);   // no meshes: no length, not -inf
    Scene s = quad_light_room();
    const Vec3f e = s.bounds().extent();
    EXPECT_EQ(s.extent(), std::max({e.x, e.y, e.z}));
    const float before = s.extent();
    scale_lengths(s, 10.f);
    EXPECT_NEAR(s.extent(), 10.f * before, 1e-5f * s.extent());
}

TEST(SceneTransform, RecolorTouchesRoomShellsOnly) {
    EXPECT_TRUE(is_room_shell_mesh("room2_walls"));
    EXPECT_TRUE(is_room_shell_mesh("room0_ceiling"));
    EXPECT_FALSE(is_room_shell_mesh("bed1_frame"));
    EXPECT_FALSE(is_room_shell_mesh("_floor"));
    Scene s = quad_light_room();
    const size_t n_materials = s.materials.size();
    const int n = recolor_meshes(s, [](const std::string &name) { return name == "walls" || name == "light"; }, {0.1f, 0.1f, 0.7f});
    EXPECT_EQ(n, 1);   // the light is emissive: kept
    ASSERT_EQ(s.materials.size(), n_materials + 1);
    for (const auto &m : s.meshes) {
        if (m.name == "walls") {
            EXPECT_EQ(s.materials[size_t(m.material)].albedo.color_a.z, 0.7f);
        }
    }
}
