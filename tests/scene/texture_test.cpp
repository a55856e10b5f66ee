// texture_test.cpp: procedural and image lookups return the analytic values.
#include <gtest/gtest.h>

#include "ltm/scene/texture.h"

using namespace ltm;

TEST(Texture, CheckerAlternatesEveryScaleUnits) {
    Texture t = Texture::checker({1, 0, 0}, {0, 0, 1}, 0.5f);
    EXPECT_EQ(t.eval({0.1f, 0.1f}), t.color_a);
    EXPECT_EQ(t.eval({0.6f, 0.1f}), t.color_b);
    EXPECT_EQ(t.eval({0.6f, 0.6f}), t.color_a);
    EXPECT_EQ(t.eval({-0.1f, 0.1f}), t.color_b);
    t.angle_deg = 90.f;   // rotating by 90° swaps the roles of u and v, and flips one sign
    EXPECT_EQ(t.eval({0.1f, 0.6f}), t.color_a);
}

TEST(Texture, ImageIsBilinearWithRepeat) {
    auto img = std::make_shared<Image>(2, 1);
    img->at(0, 0) = Vec3f(0.f);
    img->at(1, 0) = Vec3f(1.f);
    Texture t;
    t.kind = TextureKind::image;
    t.image = img;
    EXPECT_NEAR(t.eval({0.25f, 0.5f}).x, 0.f, 1e-6f);    // texel centre 0
    EXPECT_NEAR(t.eval({0.75f, 0.5f}).x, 1.f, 1e-6f);    // texel centre 1
    EXPECT_NEAR(t.eval({0.5f, 0.5f}).x, 0.5f, 1e-6f);    // halfway
    EXPECT_NEAR(t.eval({1.0f, 0.5f}).x, 0.5f, 1e-6f);    // wraps back to texel 0
}

TEST(Texture, NoiseAndWoodStayBetweenTheirColours) {
    for (TextureKind k : {TextureKind::noise, TextureKind::wood}) {
        Texture t;
        t.kind = k;
        t.color_a = {0.2f, 0.2f, 0.2f};
        t.color_b = {0.6f, 0.6f, 0.6f};
        for (int i = 0; i < 500; ++i) {
            const Vec3f c = t.eval({float(i) * 0.037f, float(i) * 0.011f});
            EXPECT_GE(c.x, 0.2f * 0.85f - 1e-6f);
            EXPECT_LE(c.x, 0.6f + 1e-6f);
        }
    }
}
