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
