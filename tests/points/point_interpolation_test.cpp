// point_interpolation_test.cpp: PointInterpolator against closed forms (a linear field at the
// centre of a symmetric ring, a constant field anywhere), against a scan of every point (the K
// nearest qualifying points, weighted as the header says), the surface tests (facing, tangent
// plane, radius), and bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "ltm/core/error.h"
#include "ltm/points/point_interpolation.h"

using namespace ltm;

namespace {
constexpr float k_pi_f = 3.14159265358979f;

// A floor z = 0 facing +z with points on a jittered grid of the given spacing, and a table top at
// z = 0.7 over x, y ∈ [1, 2], facing +z as well.
struct FloorAndTable {
    std::vector<Vec3f> p, n;
    std::vector<Vec3f> v;   // the field: floor 1 + x, table 10
    FloorAndTable(float s, uint32_t seed) {
        std::mt19937 rng(seed);
        std::uniform_real_distribution<float> u(-0.3f, 0.3f);
        for (float x = 0.f; x < 3.f; x += s)
            for (float y = 0.f; y < 3.f; y += s) {
                const Vec3f q(x + u(rng) * s, y + u(rng) * s, 0.f);
                p.push_back(q), n.push_back({0, 0, 1}), v.push_back(Vec3f(1.f + q.x));
            }
        for (float x = 1.f; x < 2.f; x += s)
            for (float y = 1.f; y < 2.f; y += s) p.push_back({x, y, 0.7f}), n.push_back({0, 0, 1}), v.push_back(Vec3f(10.f));
    }
};
}  // namespace

// Eight points on a circle around the query, a linear field: equal weights, so the mean is the
// field at the centre exactly.
TEST(PointInterpolation, ALinearFieldAtTheCentreOfASymmetricRingIsExact) {
    std::vector<Vec3f> p, n, v;
    for (int k = 0; k < 8; ++k) {
        const float a = 2.f * k_pi_f * float(k) / 8.f;
        p.push_back({0.5f + 0.1f * std::cos(a), 0.2f + 0.1f * std::sin(a), 1.f}), n.push_back({0, 0, 1});
        v.push_back({3.f * p.back().x - 2.f * p.back().y + 1.f, 5.f, p.back().x});
    }
    p.push_back({0.5f, 0.2f + 0.5f, 1.f}), n.push_back({0, 0, 1}), v.push_back(Vec3f(100.f));   // beyond 2·spacing
    const PointInterpolator interp(p, n, /*spacing=*/0.15f);
    Vec3f e(-1.f);
    ASSERT_TRUE(interp.interpolate({0.5f, 0.2f, 1.f}, {0, 0, 1}, v.data(), e));
    EXPECT_NEAR(e.x, 3.f * 0.5f - 2.f * 0.2f + 1.f, 1e-5f);
    EXPECT_NEAR(e.y, 5.f, 1e-5f);
    EXPECT_NEAR(e.z, 0.5f, 1e-5f);
}

// The answer is the K nearest qualifying points of a scan of every point, weighted 1/(d² + s²/4).
TEST(PointInterpolation, IsTheWeightedMeanOfTheNearestQualifyingPointsOfAScan) {
    const float s = 0.1f;
    const FloorAndTable scene(s, 3);
    const PointInterpolator interp(scene.p, scene.n, s);
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(0.f, 3.f);
    int checked = 0, misses = 0;
    for (int t = 0; t < 300; ++t) {
        const Vec3f q(u(rng), u(rng), t % 3 == 0 ? 0.7f : 0.02f * (u(rng) - 1.5f));
        const Vec3f nq = normalize(Vec3f(0.3f * (u(rng) - 1.5f), 0.f, 1.f));
        std::vector<std::pair<float, uint32_t>> all;
        for (uint32_t j = 0; j < scene.p.size(); ++j) {
            const Vec3f d = scene.p[j] - q;
            if (dot(scene.n[j], nq) >= 0.5f && std::abs(dot(d, nq)) <= s && dot(d, d) < 4.f * s * s) all.push_back({dot(d, d), j});
        }
        std::sort(all.begin(), all.end());
        if (all.size() > 8) all.resize(8);
        Vec3f e(-7.f);
        const bool found = interp.interpolate(q, nq, scene.v.data(), e);
        ASSERT_EQ(found, !all.empty()) << "query " << t;
        if (!found) {
            EXPECT_EQ(e, Vec3f(-7.f)) << "a miss leaves out untouched";
            ++misses;
            continue;
        }
        Vec3f acc(0.f);
        float w = 0.f;
        for (const auto &[d2, j] : all) acc += scene.v[j] * (1.f / (d2 + 0.25f * s * s)), w += 1.f / (d2 + 0.25f * s * s);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(e[c], acc[c] / w, 1e-5f * std::abs(acc[c] / w)) << "query " << t;
        ++checked;
    }
    EXPECT_GT(checked, 200);
    EXPECT_GT(misses, 20) << "queries at the table's height beside it";
}

// A query on the floor under the table (0.7 above: within 2·spacing, beyond the tangent plane's
// spacing) reads the floor alone; one on the table reads the table alone; a face turned away reads
// nothing, as does a query far from every point; a constant field comes back exactly.
TEST(PointInterpolation, ReadsOnlyTheQuerysOwnSurface) {
    const float s = 0.5f;
    FloorAndTable scene(s, 4);
    for (Vec3f &v : scene.v) v = v.x == 10.f ? v : Vec3f(2.f);   // the floor constant
    const PointInterpolator interp(scene.p, scene.n, s);
    Vec3f e;
    ASSERT_TRUE(interp.interpolate({1.5f, 1.5f, 0.f}, {0, 0, 1}, scene.v.data(), e));
    EXPECT_NEAR(e.x, 2.f, 1e-6f) << "the floor under the table";
    ASSERT_TRUE(interp.interpolate({1.5f, 1.5f, 0.7f}, {0, 0, 1}, scene.v.data(), e));
    EXPECT_NEAR(e.x, 10.f, 1e-5f) << "the table top";
    EXPECT_FALSE(interp.interpolate({1.5f, 1.5f, 0.f}, {0, 0, -1}, scene.v.data(), e)) << "the floor's underside";
    EXPECT_FALSE(interp.interpolate({1.5f, 1.5f, 0.f}, normalize(Vec3f(1, 0, 0.5f)), scene.v.data(), e)) << "turned 63° away";
    EXPECT_FALSE(interp.interpolate({1.5f, 1.5f, 5.f}, {0, 0, 1}, scene.v.data(), e)) << "far above";
    EXPECT_FALSE(interp.interpolate({10.f, 1.5f, 0.f}, {0, 0, 1}, scene.v.data(), e)) << "far beside";
}

TEST(PointInterpolation, RejectsBadInput) {
    EXPECT_THROW(PointInterpolator({}, {}, 1.f), Error);
    EXPECT_THROW(PointInterpolator({Vec3f(0.f)}, {}, 1.f), Error);
    EXPECT_THROW(PointInterpolator({Vec3f(0.f)}, {Vec3f(0, 0, 1)}, 0.f), Error);
    EXPECT_THROW(PointInterpolator({Vec3f(0.f)}, {Vec3f(0, 0, 1)}, std::nanf("")), Error);
    EXPECT_THROW(PointInterpolator({Vec3f(std::nanf(""))}, {Vec3f(0, 0, 1)}, 1.f), Error);
    EXPECT_THROW(PointInterpolator({Vec3f(0.f)}, {Vec3f(std::nanf(""))}, 1.f), Error);
    // A query with a NaN normal or position qualifies nothing (the caller's decode then reports it).
    const PointInterpolator interp({Vec3f(0.f)}, {Vec3f(0, 0, 1)}, 1.f);
    const Vec3f v(1.f);
    Vec3f e;
    EXPECT_FALSE(interp.interpolate(Vec3f(0.1f, 0.f, 0.f), Vec3f(std::nanf("")), &v, e));
    EXPECT_FALSE(interp.interpolate(Vec3f(std::nanf("")), Vec3f(0, 0, 1), &v, e));
    EXPECT_TRUE(interp.interpolate(Vec3f(0.1f, 0.f, 0.f), Vec3f(0, 0, 1), &v, e));
}
