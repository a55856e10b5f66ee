// field_metrics_test.cpp: level, chroma, correlation and the flat-oracle floor on fields whose
// answers are known in closed form.
#include <gtest/gtest.h>

#include <cmath>

#include "ltm/core/error.h"
#include "ltm/eval/field_metrics.h"

using namespace ltm;

TEST(FieldMetrics, ChromaErrorIgnoresLevelAndSeesColour) {
    EXPECT_NEAR(chroma_error({1, 2, 3}, {10, 20, 30}), 0.0, 1e-12);
    // a = (e, 1, 1)·c vs grey: centred logs (2/3, −1/3, −1/3) → RMS sqrt((4/9 + 1/9 + 1/9)/3) = sqrt(2)/3.
    EXPECT_NEAR(chroma_error({std::exp(1.0), 1, 1}, {5, 5, 5}), std::sqrt(2.0) / 3.0, 1e-12);
    EXPECT_TRUE(std::isfinite(chroma_error({1, 0, 0}, {1, 1, 1})));
    EXPECT_NEAR(blue_share({1, 1, 2}), 0.5, 1e-12);
    EXPECT_EQ(blue_share({0, 0, 0}), 0.0);
}

TEST(FieldMetrics, FlatOracleAndAScaledCopy) {
    std::vector<Vec3f> ref, twice, flat;
    for (int i = 0; i < 100; ++i) ref.push_back({float(i % 10), float(i % 7) + 1.f, 0.5f * float(i % 3)});
    const Color3d m = mean_color(ref);
    for (const Vec3f &r : ref) twice.push_back(r * 2.f), flat.push_back({float(m[0]), float(m[1]), float(m[2])});
    const FieldMetrics t = compare_fields(twice, ref);
    EXPECT_NEAR(t.level_ratio, 2.0, 1e-6);
    EXPECT_NEAR(t.chroma_error, 0.0, 1e-6);
    EXPECT_NEAR(t.luminance_correlation, 1.0, 1e-9);
    EXPECT_FALSE(t.level_in_band());
    // The flat oracle scores exactly its own floor: it cannot beat itself.
    const FieldMetrics f = compare_fields(flat, ref);
    EXPECT_NEAR(f.mse, f.flat_mse, 1e-9 * f.flat_mse);
    EXPECT_FALSE(f.beats_flat());
    EXPECT_NEAR(f.level_ratio, 1.0, 1e-6);
    EXPECT_EQ(f.luminance_correlation, 0.0);   // constant field
    // The reference itself beats it.
    const FieldMetrics self = compare_fields(ref, ref);
    EXPECT_EQ(self.mse, 0.0);
    EXPECT_TRUE(self.beats_flat());
    EXPECT_TRUE(self.level_in_band());
}

TEST(FieldMetrics, BadInputIsAnError) {
    std::vector<Vec3f> a{{1, 1, 1}}, b{{1, NAN, 1}}, none;
    EXPECT_THROW(compare_fields(a, b), Error);
    EXPECT_THROW(compare_fields(none, none), Error);
    EXPECT_THROW(compare_fields(a, none), Error);
}
