// power_balance_test.cpp: the exact emission scale S = Φ/A against closed forms, its scale
// freedom, and the point-mean estimate it replaces.
#include <gtest/gtest.h>

#include "ltm/core/error.h"
#include "ltm/core/math.h"
#include "ltm/transport/power_balance.h"
#include "ltm/points/surface_sampler.h"
#include "ltm/scene/builtin_scenes.h"
#include "ltm/scene/mesh_builder.h"
#include "ltm/scene/scene_transform.h"

using namespace ltm;

namespace {
// A 1 m² grey quad and a 1 m² emitter of radiance `le` (optionally textured).
Scene two_quads(Texture le) {
    Scene s;
    Material grey;
    grey.name = "grey";
    grey.albedo = Texture::constant(Vec3f(0.5f));
    s.add_material(grey);
    Material light;
    light.name = "light";
    light.albedo = Texture::constant(Vec3f(0.f));
    light.emission = le;
    s.add_material(light);
    TriangleMesh a, b;
    a.name = "floor", a.material = 0;
    add_quad(a, {0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0});
    b.name = "lamp", b.material = 1;
    add_quad(b, {0, 2, 0}, {1, 2, 0}, {1, 2, 1}, {0, 2, 1});
    s.meshes.push_back(a);
    s.meshes.push_back(b);
    return s;
}
}  // namespace

TEST(EmissionScale, ClosedFormAndPassFraction) {
    const Scene s = two_quads(Texture::constant(Vec3f(2.f, 1.f, 0.5f)));
    // Φ = π · Le · 1 m², A = 2 m².
    const Vec3f S = scene_emission_scale(s);
    EXPECT_NEAR(S.x, k_pi * 2.f / 2.f, 1e-5);
    EXPECT_NEAR(S.y, k_pi * 1.f / 2.f, 1e-5);
    EXPECT_NEAR(S.z, k_pi * 0.5f / 2.f, 1e-5);
    // Half the area filtered away: the same flux over half the area.
    EXPECT_NEAR(scene_emission_scale(s, 0.5).x, 2.f * S.x, 1e-5);
    EXPECT_THROW(scene_emission_scale(s, 0.0), Error);
    EXPECT_THROW(scene_emission_scale(s, 1.5), Error);
    // A textured emitter is averaged over the triangle: a checker of 0 and 2 has mean ≈ 1.
    const Vec3f St = scene_emission_scale(two_quads(Texture::checker(Vec3f(0.f), Vec3f(2.f), 0.25f)));
    EXPECT_NEAR(St.x, k_pi * 1.f / 2.f, 0.1 * k_pi / 2.f);
}

TEST(EmissionScale, IndependentOfTheUnitOfLength) {
    Scene s = cornell_box();
    const Vec3f S = scene_emission_scale(s);
    scale_lengths(s, 0.1f);
    const Vec3f S01 = scene_emission_scale(s);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(S01[c], S[c], 1e-5f * S[c]) << c;
}

TEST(EmissionScale, AgreesWithThePointMeanItReplaces) {
    // 200k stratified points: the emitter's share of them is exact to a point or two.
    const Scene s = cornell_box();
    const Vec3f S = scene_emission_scale(s);
    const PointSet sp = to_scene_points(sample_surface(s, 200000, 3, SampleStream::scene_points));
    const auto pb_points = power_balance_irradiance(sp, 1);
    const auto pb_exact = power_balance_irradiance(sp, 1, &S);
    for (size_t c = 0; c < 3; ++c) EXPECT_NEAR(pb_exact[c], pb_points[c], 0.01 * pb_exact[c]) << c;
    // With D = 0 bounces the prior is 0 whatever S is.
    EXPECT_EQ(power_balance_irradiance(sp, 0, &S)[0], 0.0);
}
