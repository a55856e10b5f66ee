// direct_light_test.cpp: the analytic unshadowed irradiance and the ratio estimator against the
// path tracer's unbiased MIS estimator of E_direct (the ground truth, tested against closed forms).
#include <gtest/gtest.h>

#include "ltm/core/error.h"
#include "ltm/render/direct_light.h"
#include "ltm/render/path_tracer.h"
#include "ltm/scene/builtin_scenes.h"
#include "ltm/scene/mesh_builder.h"

namespace ltm {
namespace {

// A 1 m × 0.5 m light at y = 2 facing down (radiance (4, 2, 1)), and a small occluder plate at
// y = 1 under part of it; nothing else, so points away from the plate see the light unshadowed.
Scene lamp_scene(bool with_plate) {
    Scene s;
    s.name = "lamp";
    Material light, plate;
    light.name = "light";
    light.albedo = Texture::constant(Vec3f(0.f));
    light.emission = Texture::constant(Vec3f(4.f, 2.f, 1.f));
    plate.name = "plate";
    plate.albedo = Texture::constant(Vec3f(0.f));   // black: no light scattered back
    s.add_material(light);
    s.add_material(plate);
    TriangleMesh lamp, occ;
    lamp.name = "light", lamp.material = 0;
    add_quad_facing(lamp, {-0.5f, 2, -0.25f}, {0.5f, 2, -0.25f}, {0.5f, 2, 0.25f}, {-0.5f, 2, 0.25f}, {0, -1, 0});
    s.meshes = {lamp};
    if (with_plate) {
        occ.name = "plate", occ.material = 1;
        add_quad_facing(occ, {0.f, 1, -0.6f}, {1.f, 1, -0.6f}, {1.f, 1, 0.6f}, {0.f, 1, 0.6f}, {0, 1, 0});
        s.meshes.push_back(occ);
    }
    return s;
}

struct Probe {
    Vec3f p, n;
};
// Below the light, tilted so that the light straddles the horizon, grazing, and above (behind) it.
const std::vector<Probe> k_probes = {
    {{0.f, 0.f, 0.f}, {0, 1, 0}},          {{0.3f, 1.5f, 0.1f}, {0, 1, 0}},
    {{-0.2f, 1.8f, 0.f}, normalize(Vec3f(1, 0.2f, 0))},   // light partly below this point's horizon
    {{0.4f, 1.9f, 0.3f}, normalize(Vec3f(-1, 0.5f, -0.3f))},
    {{2.f, 0.5f, 1.f}, normalize(Vec3f(-1, 1, -0.5f))},   {{0.f, 2.5f, 0.f}, {0, 1, 0}},
};

TEST(DirectLight, AnalyticUnshadowedEqualsThePathTracerEstimate) {
    const Scene s = lamp_scene(false);
    const EmbreeAccel accel(s);
    const PathTracer pt(accel, {});
    const RatioDirectLight light(accel, 0);
    for (size_t i = 0; i < k_probes.size(); ++i) {
        const Vec3f e = light.unoccluded(k_probes[i].p, k_probes[i].n);
        const Vec3f ref = pt.irradiance(k_probes[i].p, k_probes[i].n, i, 65536, false).direct;
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(e[c], ref[c], 0.01f * std::max(ref[c], 0.05f)) << "probe " << i << " channel " << c;
    }
    EXPECT_EQ(max_component(light.unoccluded({0.f, 2.5f, 0.f}, {0, -1, 0})), 0.f) << "behind a one-sided emitter";
}

TEST(DirectLight, TriangleIrradianceKnownValues) {
    // A huge triangle covering the whole upper hemisphere of a receiver gives π (Le = 1): the
    // furnace value; a far-away small triangle gives A·cosθ/d².
    const float big = triangle_irradiance({0, 0, 0}, {0, 1, 0}, {-1e4f, 1e-3f, 1e4f}, {0, 1e-3f, -1e4f}, {1e4f, 1e-3f, 1e4f});
    EXPECT_NEAR(big, k_pi, 0.01f);
    const float small = triangle_irradiance({0, 0, 0}, {0, 1, 0}, {0, 10, 0}, {0.01f, 10, 0}, {0.01f, 10, 0.01f});
    EXPECT_NEAR(small, 0.5f * 0.01f * 0.01f / 100.f, 2e-8f);   // facing down (winding), area 5e-5 m²
    EXPECT_EQ(triangle_irradiance({0, 0, 0}, {0, 1, 0}, {0, 10, 0}, {0.01f, 10, 0.01f}, {0.01f, 10, 0}), 0.f)
        << "the same triangle facing up emits away from the receiver";
    EXPECT_EQ(triangle_irradiance({0, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, -1, 1}, {1, -1, 0}), 0.f)
        << "facing the receiver's side but below its horizon";
}

// Unshadowed: the ratio is 1, so any sample count gives the analytic value exactly.
TEST(DirectLight, RatioEstimatorIsExactWithoutOcclusion) {
    const Scene s = lamp_scene(false);
    const EmbreeAccel accel(s);
    const RatioDirectLight light(accel, 0);
    for (size_t i = 0; i < k_probes.size(); ++i)
        for (int spp : {1, 4}) {
            const Vec3f e = light.irradiance(k_probes[i].p, k_probes[i].n, i, spp), u = light.unoccluded(k_probes[i].p, k_probes[i].n);
            for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(e[c], u[c]) << "probe " << i;
        }
}

// Shadowed and penumbra points: the ratio estimate converges to the path tracer's E_direct.
TEST(DirectLight, RatioEstimatorMatchesThePathTracerInShadow) {
    const Scene s = lamp_scene(true);
    const EmbreeAccel accel(s);
    const PathTracer pt(accel, {});
    const RatioDirectLight light(accel, 0);
    // Under the plate (umbra), at its edge (penumbra), and clear of it.
    const std::vector<Vec3f> points = {{0.5f, 0.f, 0.f}, {0.f, 0.f, 0.f}, {-0.2f, 0.3f, 0.1f}, {0.2f, 0.5f, 0.f}, {-1.f, 0.f, 0.f}};
    for (size_t i = 0; i < points.size(); ++i) {
        const Vec3f e = light.irradiance(points[i], {0, 1, 0}, i, 65536);
        const Vec3f ref = pt.irradiance(points[i], {0, 1, 0}, i, 65536, false).direct;
        // Tolerance: 3% of the value, or of a tenth of the unshadowed level in deep penumbra
        // (there both estimates carry ~1.5% noise from the few visible samples).
        const float scale = std::max(ref.x, 0.1f * light.unoccluded(points[i], {0, 1, 0}).x);
        EXPECT_NEAR(e.x, ref.x, 0.03f * scale) << "point " << i << " unoccluded " << light.unoccluded(points[i], {0, 1, 0}).x;
        EXPECT_NEAR(e.z / std::max(e.x, 1e-6f), ref.z / std::max(ref.x, 1e-6f), 0.02f) << "colour of the light";
    }
}

// A second light behind a wall (another room): analytically unoccluded, in fact hidden. Per-light
// ratios make the estimate exact at any sample count: the seen light's E_unocc, nothing else.
TEST(DirectLight, LightBehindAWallAddsNoNoise) {
    Scene s = lamp_scene(false);
    TriangleMesh lamp2, wall;
    lamp2.name = "light2", lamp2.material = 0;
    add_quad_facing(lamp2, {4.5f, 2, -0.25f}, {5.5f, 2, -0.25f}, {5.5f, 2, 0.25f}, {4.5f, 2, 0.25f}, {0, -1, 0});
    wall.name = "wall", wall.material = s.add_material([] {
        Material m;
        m.name = "wall";
        m.albedo = Texture::constant(Vec3f(0.f));
        return m;
    }());
    add_quad_facing(wall, {2.5f, -1, -5}, {2.5f, 3, -5}, {2.5f, 3, 5}, {2.5f, -1, 5}, {-1, 0, 0});
    s.meshes.push_back(lamp2);
    s.meshes.push_back(wall);
    const EmbreeAccel accel(s);
    const RatioDirectLight both(accel, 0);
    const Scene alone = lamp_scene(false);
    const EmbreeAccel accel_alone(alone);
    const RatioDirectLight one(accel_alone, 0);
    for (const Vec3f p : {Vec3f{0.f, 0.f, 0.f}, Vec3f{1.f, 0.5f, 0.5f}, Vec3f{-1.f, 0.f, -1.f}}) {
        EXPECT_GT(both.unoccluded(p, {0, 1, 0}).x, one.unoccluded(p, {0, 1, 0}).x) << "the hidden light counts analytically";
        for (int spp : {2, 4, 16}) {
            const Vec3f e = both.irradiance(p, {0, 1, 0}, 7, spp), want = one.unoccluded(p, {0, 1, 0});
            EXPECT_FLOAT_EQ(e.x, want.x) << "spp " << spp;
        }
    }
}

TEST(DirectLight, TexturedEmissionIsRejected) {
    Scene s = lamp_scene(false);
    s.materials[0].emission.kind = TextureKind::checker;
    EXPECT_FALSE(RatioDirectLight::supports(s));
    const EmbreeAccel accel(s);
    EXPECT_THROW(RatioDirectLight(accel, 0), Error);
    EXPECT_TRUE(RatioDirectLight::supports(cornell_box()));
}

}  // namespace
}  // namespace ltm
