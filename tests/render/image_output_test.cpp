// image_output_test.cpp: which channels of a rendered frame's EXR are half and which float
// (write_rendered_image, render/image_renderer.h), and that --exr-float's path writes every one float.
// A half channel is seen by its rounding: 0.1 + i/7 is no half value, so it reads back changed (within
// half's relative 2⁻¹¹); a float channel reads back bit for bit.
#include <gtest/gtest.h>

#include <cmath>

#include "ltm/core/exr.h"
#include "ltm/render/image_renderer.h"
#include "test_util.h"

using namespace ltm;

namespace {
constexpr int k_w = 5, k_h = 4;

// A frame whose every channel holds values that half cannot store exactly; `scale` multiplies the
// irradiance (a scene in tiny units: its peak below half's threshold, fits_half).
RenderedImage frame(float scale) {
    RenderedImage img;
    img.width = k_w, img.height = k_h;
    for (Image *im : {&img.color, &img.irradiance, &img.direct, &img.albedo, &img.normal, &img.position}) *im = Image(k_w, k_h);
    img.depth.resize(size_t(k_w) * k_h);
    for (size_t i = 0; i < img.depth.size(); ++i) {
        const float v = 0.1f + float(i) / 7.f;
        img.color.pixels[i] = {v, 2 * v, 3 * v};
        img.irradiance.pixels[i] = Vec3f(v, v + 0.01f, v + 0.02f) * scale;
        img.direct.pixels[i] = {v + 1.f, v + 2.f, v + 3.f};
        img.albedo.pixels[i] = {v / 4.f, v / 5.f, v / 6.f};
        img.normal.pixels[i] = normalize(Vec3f(v, 1.f, 0.3f));
        img.position.pixels[i] = {v + 3.f, v + 4.f, v + 5.f};
        img.depth[i] = v + 6.f;
    }
    return img;
}

// Every value of `channel` read back bit for bit (float), or every one within half's rounding and at
// least one changed (half).
enum class Stored { float32, half16 };
Stored stored(const std::string &path, const std::string &channel, const Image &im, int c) {
    const std::vector<float> r = read_exr_channel(path, channel, nullptr, nullptr);
    EXPECT_EQ(r.size(), im.pixels.size()) << channel;
    bool changed = false;
    for (size_t i = 0; i < r.size(); ++i) {
        const float v = im.pixels[i][c];
        EXPECT_NEAR(r[i], v, std::abs(v) / 2048.f) << channel << " pixel " << i;
        changed |= r[i] != v;
    }
    return changed ? Stored::half16 : Stored::float32;
}

// The five shading groups of the frame (colour, irradiance, direct, albedo, N), each channel stored as `kind`.
void expect_shading(const std::string &exr, const RenderedImage &img, Stored kind) {
    const char *rgb[] = {"R", "G", "B"}, *xyz[] = {"X", "Y", "Z"};
    for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(stored(exr, rgb[c], img.color, c), kind) << rgb[c];
        EXPECT_EQ(stored(exr, std::string("irradiance.") + rgb[c], img.irradiance, c), kind) << rgb[c];
        EXPECT_EQ(stored(exr, std::string("direct.") + rgb[c], img.direct, c), kind) << rgb[c];
        EXPECT_EQ(stored(exr, std::string("albedo.") + rgb[c], img.albedo, c), kind) << rgb[c];
        EXPECT_EQ(stored(exr, std::string("N.") + xyz[c], img.normal, c), kind) << xyz[c];
    }
}
}  // namespace

TEST(ImageOutput, ShadingChannelsAreHalfPositionAndDepthFloat) {
    test::TempDir dir;
    const RenderedImage img = frame(1.f);
    write_rendered_image(img, dir.path("f"), 1.f);
    const std::string exr = dir.path("f.exr");
    expect_shading(exr, img, Stored::half16);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(stored(exr, std::string("P.") + "XYZ"[c], img.position, c), Stored::float32);
    EXPECT_EQ(read_exr_channel(exr, "Z", nullptr, nullptr), img.depth);
}

TEST(ImageOutput, ExrFloatWritesEveryChannelFloat) {
    test::TempDir dir;
    const RenderedImage img = frame(1.f);
    write_rendered_image(img, dir.path("f"), 1.f, /*exr_float=*/true);
    expect_shading(dir.path("f.exr"), img, Stored::float32);
}

// A channel whose peak is below 2⁻⁷ (a scene in tiny units) stays float beside half neighbours.
TEST(ImageOutput, AChannelTooSmallForHalfStaysFloat) {
    test::TempDir dir;
    const RenderedImage img = frame(1e-3f);
    write_rendered_image(img, dir.path("f"), 1.f);
    const std::string exr = dir.path("f.exr");
    for (int c = 0; c < 3; ++c) EXPECT_EQ(stored(exr, std::string("irradiance.") + "RGB"[c], img.irradiance, c), Stored::float32);
    EXPECT_EQ(stored(exr, "direct.R", img.direct, 0), Stored::half16);
}
