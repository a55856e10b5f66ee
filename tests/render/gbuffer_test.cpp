// gbuffer_test.cpp: the G-buffer is what primary rays see; irradiance images are the path
// tracer's estimator at those points; composition is Le + albedo/π·E.
#include <gtest/gtest.h>

#include "ltm/core/error.h"
#include "ltm/core/parallel.h"
#include "ltm/render/gbuffer.h"
#include "ltm/render/image_renderer.h"
#include "ltm/scene/scene_loader.h"

using namespace ltm;

namespace {
Camera test_camera() {
    Camera c;
    c.eye = {1.f, 1.5f, 3.5f}, c.target = {2.5f, 0.8f, 1.5f}, c.width = 21, c.height = 17;
    return c;
}
}  // namespace

TEST(GBuffer, MatchesPrimaryRaysAndFacesTheEye) {
    const Scene scene = load_scene("builtin:quad-light-room");
    const EmbreeAccel accel(scene);
    const Camera cam = test_camera();
    const GBuffer gb = render_gbuffer(accel, cam);
    ASSERT_GT(gb.n_hits(), 0u);
    EXPECT_TRUE(std::is_sorted(gb.hit_pixels.begin(), gb.hit_pixels.end()));
    for (size_t k = 0; k < gb.n_hits(); ++k) {
        const int64_t i = gb.hit_pixels[k];
        const Ray ray{cam.eye, cam.ray_direction(float(i % cam.width) + 0.5f, float(i / cam.width) + 0.5f)};
        const auto hit = accel.intersect(ray);
        ASSERT_TRUE(hit.has_value());
        EXPECT_FLOAT_EQ(hit->t, gb.depth[k]);
        EXPECT_LT(length(ray.o + ray.d * hit->t - gb.position[k]), 1e-4f);
        EXPECT_GT(dot(gb.normal[k], cam.eye - gb.position[k]), 0.f);   // the side the camera sees
    }
}

TEST(GBuffer, IrradianceImagesAreThePathTracersEstimatesAtAnyThreadCount) {
    const Scene scene = load_scene("builtin:quad-light-room");
    const EmbreeAccel accel(scene);
    const PathTracer pt(accel, PathTracerConfig{});
    const GBuffer gb = render_gbuffer(accel, test_camera());
    set_num_threads(1);
    const IrradianceImages one = irradiance_images(pt, gb, 8, true);
    set_num_threads(2);
    const IrradianceImages two = irradiance_images(pt, gb, 8, true);
    set_num_threads(0);
    EXPECT_EQ(one.direct.pixels, two.direct.pixels);
    EXPECT_EQ(one.indirect.pixels, two.indirect.pixels);
    const IrradianceImages direct_only = irradiance_images(pt, gb, 8, false);
    double sum_indirect = 0, sum_direct = 0, sum_direct_only = 0;
    for (size_t k = 0; k < gb.n_hits(); ++k) {
        const size_t i = size_t(gb.hit_pixels[k]);
        EXPECT_EQ(direct_only.indirect.pixels[i], Vec3f(0.f));
        sum_indirect += one.indirect.pixels[i].y, sum_direct += one.direct.pixels[i].y;
        sum_direct_only += direct_only.direct.pixels[i].y;
    }
    EXPECT_GT(sum_indirect, 0.0);
    // Same estimator of E_direct with other random numbers: the image means agree statistically.
    EXPECT_NEAR(sum_direct_only / sum_direct, 1.0, 0.05);
}

TEST(GBuffer, ComposeIsEmissionPlusAlbedoOverPiTimesIrradiance) {
    const Scene scene = load_scene("builtin:quad-light-room");
    const EmbreeAccel accel(scene);
    const GBuffer gb = render_gbuffer(accel, test_camera());
    Image direct(gb.width, gb.height), indirect(gb.width, gb.height);
    for (size_t i = 0; i < direct.pixels.size(); ++i) direct.pixels[i] = Vec3f(float(i % 7)), indirect.pixels[i] = Vec3f(0.5f);
    const RenderedImage r = compose_image(gb, direct, indirect);
    for (size_t k = 0; k < gb.n_hits(); ++k) {
        const size_t i = size_t(gb.hit_pixels[k]);
        const Vec3f want = gb.emitted[k] + gb.albedo[k] * k_inv_pi * (direct.pixels[i] + indirect.pixels[i]);
        EXPECT_EQ(r.color.pixels[i], want);
    }
    EXPECT_THROW(compose_image(gb, Image(3, 3), indirect), Error);
}

// Without jitter every path-traced sample goes through the pixel centre, the G-buffer's ray, so
// the reference of `ltm eval --radiance` compares pixel by pixel with the neural render; with
// jitter (the default) the samples spread over the pixel and edges are anti-aliased.
TEST(GBuffer, PathTracedImageWithoutJitterSeesTheGBuffersPoints) {
    const Scene scene = load_scene("builtin:quad-light-room");
    const EmbreeAccel accel(scene);
    const PathTracer pt(accel, PathTracerConfig{});
    const Camera cam = test_camera();
    const GBuffer gb = render_gbuffer(accel, cam);
    const RenderedImage centre = render_pathtraced(pt, cam, 4, /*jitter=*/false), jittered = render_pathtraced(pt, cam, 4);
    int moved = 0;
    for (size_t k = 0; k < gb.n_hits(); ++k) {
        const size_t i = size_t(gb.hit_pixels[k]);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(centre.position.pixels[i][c], gb.position[k][c], 1e-5f) << i;
        moved += length(jittered.position.pixels[i] - gb.position[k]) > 1e-4f;
    }
    EXPECT_EQ(centre.hit_fraction, float(gb.n_hits()) / float(cam.width * cam.height));
    EXPECT_GT(moved, int(gb.n_hits()) / 2);
}
