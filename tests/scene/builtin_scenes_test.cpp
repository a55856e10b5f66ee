// builtin_scenes_test.cpp: the analytic scenes have the geometry their closed forms assume.
#include <gtest/gtest.h>

#include "ltm/scene/builtin_scenes.h"

using namespace ltm;

// Furnace: 6 unit faces, every normal points into the cube (towards its centre).
TEST(BuiltinScenes, FurnaceBoxIsAClosedInwardCube) {
    const Scene s = furnace_box(0.3f, 2.f);
    EXPECT_NEAR(s.total_area(), 6.0, 1e-6);
    const TriangleMesh &m = s.meshes[0];
    for (size_t t = 0; t < m.n_triangles(); ++t) {
        const Vec3f c = (m.vertex(t, 0) + m.vertex(t, 1) + m.vertex(t, 2)) / 3.f;
        EXPECT_GT(dot(m.cross_normal(t), Vec3f(0.5f) - c), 0.f);
    }
    EXPECT_TRUE(s.has_emitter());
    validate_scene(s, "furnace");
}

TEST(BuiltinScenes, CornellLightFacesDownAndBlocksFaceOut) {
    const Scene s = cornell_box();
    for (const auto &m : s.meshes) {
        for (size_t t = 0; t < m.n_triangles(); ++t) {
            const Vec3f n = normalize(m.cross_normal(t));
            if (m.name == "light") {
                EXPECT_LT(n.y, -0.99f);
            }
            if (m.name == "floor") {
                EXPECT_GT(n.y, 0.99f);
            }
            if (m.name == "tall_block") {
                const Vec3f c = (m.vertex(t, 0) + m.vertex(t, 1) + m.vertex(t, 2)) / 3.f;
                EXPECT_GT(dot(n, c - Vec3f(0.368f, 0.165f, 0.351f)), 0.f) << m.name;
            }
        }
    }
    validate_scene(s, "cornell");
}

TEST(BuiltinScenes, EveryNameLoads) {
    for (const auto &n : builtin_scene_names()) EXPECT_NO_THROW(validate_scene(builtin_scene(n), n));
}
