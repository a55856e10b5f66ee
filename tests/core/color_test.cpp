// color_test.cpp: black-body colours: unit luminance, warm below 5000 K, near-white at 6500 K.
#include <gtest/gtest.h>

#include "ltm/core/color.h"

using namespace ltm;

TEST(Color, BlackbodyHasUnitLuminanceAndTheRightHue) {
    for (float k : {2700.f, 4000.f, 5000.f, 6500.f}) {
        const Vec3f c = blackbody_rgb(k);
        EXPECT_NEAR(luminance(c), 1.f, 1e-4f) << k;
    }
    const Vec3f warm = blackbody_rgb(2700.f), d65ish = blackbody_rgb(6500.f);
    EXPECT_GT(warm.x, 1.3f * warm.z);                 // incandescent: red ≫ blue
    EXPECT_NEAR(d65ish.x / d65ish.z, 1.0f, 0.15f);    // 6500 K black body is close to D65 white
}

TEST(Color, SrgbRoundTrip) {
    for (float v : {0.f, 0.001f, 0.2f, 0.5f, 1.f}) EXPECT_NEAR(srgb_to_linear(linear_to_srgb(v)), v, 1e-5f);
}
