// view_samples_test.cpp: view samples are what primary rays at random raster positions see: each
// lies where a ray from its camera first meets the scene, faces that camera, and the samples
// spread over the meshes as the G-buffer's pixels do; deterministic at any thread count.
#include <gtest/gtest.h>

#include <map>

#include "ltm/core/error.h"
#include "ltm/core/parallel.h"
#include "ltm/render/gbuffer.h"
#include "ltm/render/view_samples.h"
#include "ltm/scene/scene_loader.h"

using namespace ltm;

namespace {
Camera camera(Vec3f eye, Vec3f target, int w, int h) {
    Camera c;
    c.eye = eye, c.target = target, c.width = w, c.height = h;
    return c;
}
}  // namespace

TEST(ViewSamples, FirstHitsFacingTheirCameraAtAnyThreadCount) {
    Scene scene = load_scene("builtin:quad-light-room");
    scene.cameras = {camera({1.f, 1.5f, 3.5f}, {2.5f, 0.8f, 1.5f}, 21, 17), camera({3.f, 1.f, 1.f}, {0.5f, 1.2f, 3.f}, 8, 8)};
    const EmbreeAccel accel(scene);
    set_num_threads(1);
    const std::vector<SurfaceSample> one = sample_view_points(accel, 500, 7);
    set_num_threads(2);
    const std::vector<SurfaceSample> two = sample_view_points(accel, 500, 7);
    set_num_threads(0);
    ASSERT_EQ(one.size(), 500u);
    for (size_t i = 0; i < one.size(); ++i) {
        const SurfaceSample &s = one[i];
        EXPECT_EQ(s.p, two[i].p);
        EXPECT_EQ(s.n, two[i].n);
        const Vec3f eye = scene.cameras[i % 2].eye;
        const Ray ray{eye, normalize(s.p - eye)};
        const auto hit = accel.intersect(ray);
        ASSERT_TRUE(hit.has_value());
        EXPECT_NEAR(hit->t, length(s.p - eye), 1e-4f * length(s.p - eye));   // nothing in front of it
        EXPECT_EQ(hit->mesh, s.mesh);
        EXPECT_GT(dot(s.n, eye - s.p), 0.f);                                   // the side the camera sees
        EXPECT_NEAR(length(s.n), 1.f, 1e-5f);
    }
    EXPECT_NE(sample_view_points(accel, 500, 8)[0].p, one[0].p);   // the seed matters
}

TEST(ViewSamples, SpreadOverMeshesAsTheGBufferPixels) {
    Scene scene = load_scene("builtin:quad-light-room");
    scene.cameras = {camera({1.f, 1.5f, 3.5f}, {2.5f, 0.8f, 1.5f}, 200, 160)};
    const EmbreeAccel accel(scene);
    const GBuffer gb = render_gbuffer(accel, scene.cameras[0]);
    std::map<uint32_t, double> pixel_share, sample_share;
    // The G-buffer has no mesh ids: find each hit's mesh with the same primary ray.
    for (size_t k = 0; k < gb.n_hits(); ++k) {
        const int64_t i = gb.hit_pixels[k];
        const Camera &c = scene.cameras[0];
        const auto hit = accel.intersect(Ray{c.eye, c.ray_direction(float(i % c.width) + 0.5f, float(i / c.width) + 0.5f)});
        pixel_share[hit->mesh] += 1.0 / double(gb.n_hits());
    }
    const int n = 40000;
    for (const SurfaceSample &s : sample_view_points(accel, n, 3)) sample_share[s.mesh] += 1.0 / n;
    ASSERT_GE(pixel_share.size(), 3u);
    for (const auto &[mesh, share] : pixel_share) EXPECT_NEAR(sample_share[mesh], share, 0.01) << "mesh " << mesh;
}

TEST(ViewSamples, ASceneWithoutCameraIsAnError) {
    Scene scene = load_scene("builtin:quad-light-room");
    scene.cameras.clear();
    const EmbreeAccel accel(scene);
    EXPECT_TRUE(sample_view_points(accel, 0, 1).empty());
    EXPECT_THROW(sample_view_points(accel, 10, 1), Error);
}
