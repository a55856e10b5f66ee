// exr_test.cpp: named float channels survive a write/read round trip exactly.
#include <gtest/gtest.h>

#include "ltm/core/error.h"
#include "ltm/core/exr.h"
#include "test_util.h"

using namespace ltm;

TEST(Exr, NamedChannelsRoundTrip) {
    test::TempDir dir;
    std::vector<float> rgb(4 * 3 * 3), z(4 * 3);
    for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = float(i) * 0.37f + 1e-6f;
    for (size_t i = 0; i < z.size(); ++i) z[i] = 100.f - float(i);
    write_exr(dir.path("a.exr"), 4, 3, {{"R", &rgb[0], 3}, {"G", &rgb[1], 3}, {"irradiance.B", &rgb[2], 3}, {"Z", z.data(), 1}});
    int w = 0, h = 0;
    const auto g = read_exr_channel(dir.path("a.exr"), "G", &w, &h);
    EXPECT_EQ(w, 4);
    EXPECT_EQ(h, 3);
    for (size_t i = 0; i < g.size(); ++i) EXPECT_EQ(g[i], rgb[3 * i + 1]);
    EXPECT_EQ(read_exr_channel(dir.path("a.exr"), "Z", nullptr, nullptr), z);
    EXPECT_THROW(read_exr_channel(dir.path("a.exr"), "nope", nullptr, nullptr), Error);
}

// A half channel reads back within half's 11 significant bits (relative ≤ 2⁻¹¹) next to a float
// channel that stays exact; fits_half refuses what half would overflow or flush (a peak below 2⁻⁷).
TEST(Exr, HalfChannelsKeepElevenBitsAndFitsHalfGuardsTheRange) {
    test::TempDir dir;
    std::vector<float> v(6 * 5), z(6 * 5);
    for (size_t i = 0; i < v.size(); ++i) v[i] = 0.013f * float(i * i) + 0.5f, z[i] = 1000.f + 0.001f * float(i);
    ExrChannel half{"irradiance.R", v.data(), 1};
    half.half = true;
    write_exr(dir.path("h.exr"), 6, 5, {half, {"Z", z.data(), 1}});
    const auto r = read_exr_channel(dir.path("h.exr"), "irradiance.R", nullptr, nullptr);
    bool rounded = false;
    for (size_t i = 0; i < v.size(); ++i) {
        EXPECT_NEAR(r[i], v[i], v[i] / 2048.f) << i;
        rounded |= r[i] != v[i];
    }
    EXPECT_TRUE(rounded) << "stored as half, not float";
    EXPECT_EQ(read_exr_channel(dir.path("h.exr"), "Z", nullptr, nullptr), z);

    EXPECT_TRUE(fits_half(v.data(), v.size(), 1));
    const std::vector<float> zeros(8, 0.f), tiny(8, 1e-3f), huge{1.f, 7e4f}, strided{1.f, 7e4f, 2.f, 7e4f};
    EXPECT_TRUE(fits_half(zeros.data(), zeros.size(), 1));
    EXPECT_FALSE(fits_half(tiny.data(), tiny.size(), 1));   // a scene in tiny units: half's steps near 0 are coarse
    EXPECT_FALSE(fits_half(huge.data(), huge.size(), 1));   // beyond 65 504
    EXPECT_TRUE(fits_half(strided.data(), 2, 2));           // only every 2nd value is the channel's
}
