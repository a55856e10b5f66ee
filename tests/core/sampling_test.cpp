// sampling_test.cpp: warps match their pdfs (closed-form moments, chi-square), sequences stay in range.
#include <gtest/gtest.h>

#include "ltm/core/rng.h"
#include "ltm/core/sampling.h"

using namespace ltm;

// For pdf cosθ/π: E[cosθ] = 2/3 and E[cos²θ] = 1/2 exactly.
TEST(Sampling, CosineHemisphereMomentsMatchClosedForm) {
    Pcg32 rng(1);
    double m1 = 0, m2 = 0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        const Vec3f d = sample_cosine_hemisphere({rng.next_float(), rng.next_float()});
        EXPECT_NEAR(length(d), 1.f, 1e-5f);
        ASSERT_GE(d.z, 0.f);
        m1 += d.z, m2 += double(d.z) * d.z;
    }
    EXPECT_NEAR(m1 / n, 2.0 / 3.0, 0.003);
    EXPECT_NEAR(m2 / n, 0.5, 0.003);
}

// Barycentrics uniform over the triangle: the 4 midpoint sub-triangles get equal counts (chi², 3 dof).
TEST(Sampling, UniformTriangleIsUniform) {
    Pcg32 rng(2);
    int count[4] = {0, 0, 0, 0};
    const int n = 40000;
    for (int i = 0; i < n; ++i) {
        const Vec2f b = sample_uniform_triangle({rng.next_float(), rng.next_float()});
        const float b2 = 1.f - b.x - b.y;
        ASSERT_GE(b.x, 0.f);
        ASSERT_GE(b.y, 0.f);
        ASSERT_GE(b2, -1e-6f);
        const int k = b.x > 0.5f ? 0 : (b.y > 0.5f ? 1 : (b2 > 0.5f ? 2 : 3));
        ++count[k];
    }
    double chi2 = 0;
    for (int c : count) chi2 += (c - n / 4.0) * (c - n / 4.0) / (n / 4.0);
    EXPECT_LT(chi2, 16.27);   // p = 0.001 for 3 degrees of freedom
}

TEST(Sampling, R2SequenceStaysInUnitSquareAndFillsIt) {
    int cells[16] = {};
    for (uint64_t i = 0; i < 1600; ++i) {
        const Vec2f u = r2_sequence(i, {0.3f, 0.9f});
        ASSERT_GE(u.x, 0.f);
        ASSERT_LT(u.x, 1.f);
        ASSERT_GE(u.y, 0.f);
        ASSERT_LT(u.y, 1.f);
        ++cells[int(u.x * 4) * 4 + int(u.y * 4)];
    }
    for (int c : cells) EXPECT_NEAR(c, 100, 6);   // low discrepancy: far tighter than random (±30)
}

TEST(Rng, SameSeedSameStreamDifferentSeedDifferent) {
    Pcg32 a(hash_keys({7, 1})), b(hash_keys({7, 1})), c(hash_keys({7, 2}));
    bool any_diff = false;
    for (int i = 0; i < 100; ++i) {
        const uint32_t x = a.next_u32();
        EXPECT_EQ(x, b.next_u32());
        any_diff |= x != c.next_u32();
    }
    EXPECT_TRUE(any_diff);
}

TEST(Rng, NextBelowIsUnbiased) {
    Pcg32 rng(3);
    int count[3] = {};
    for (int i = 0; i < 30000; ++i) ++count[rng.next_below(3)];
    for (int c : count) EXPECT_NEAR(c, 10000, 400);
}
