// auto_scene_points_test.cpp: `--scene-points auto`'s rule (render/scene_points.h): generated houses
// get 16 384 points, scenes with real rooms' modelled detail (k_auto_detail_triangles and more) 32 768.
#include <gtest/gtest.h>

#include "ltm/procgen/indoor_generator.h"
#include "ltm/render/scene_points.h"
#include "ltm/scene/builtin_scenes.h"

using namespace ltm;

TEST(AutoScenePoints, HousesGetSixteenThousandDetailedRoomsThirtyTwo) {
    EXPECT_EQ(auto_scene_points(generate_indoor(GenConfig{}, 900012).scene), 16384);
    EXPECT_EQ(auto_scene_points(builtin_scene("cornell-box")), 16384);
    // The Cornell box with one wall split into a fine grid: the same room, real-scan detail.
    Scene fine = builtin_scene("cornell-box");
    TriangleMesh grid = fine.meshes.front();
    grid.positions.clear(), grid.uvs.clear(), grid.indices.clear();
    const int n = 224;   // 2·224² = 100 352 triangles
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x) grid.positions.push_back({float(x) / float(n), float(y) / float(n), 0.f});
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const uint32_t i = uint32_t(y * (n + 1) + x);
            grid.indices.insert(grid.indices.end(), {i, i + 1, i + uint32_t(n) + 1, i + 1, i + uint32_t(n) + 2, i + uint32_t(n) + 1});
        }
    fine.meshes.push_back(grid);
    ASSERT_GE(fine.n_triangles(), k_auto_detail_triangles);
    EXPECT_EQ(auto_scene_points(fine), 32768);
}
