// point_grid_test.cpp: the ring search (visit_nearest) returns exactly what a scan of every point returns — the
// k nearest points of queries inside and outside the grid, the points' spacing, a receiver's
// nearest cluster centres — and bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>

#include "ltm/core/error.h"
#include "ltm/points/point_grid.h"
#include "ltm/transport/point_visibility.h"

using namespace ltm;

namespace {
// Points on the walls, floor and ceiling of a 6 × 2.5 × 4 box with a thin table in it: planar
// clusters and empty cells, as a house.
std::vector<Vec3f> room_points(size_t n, uint32_t seed, std::vector<Vec3f> *normals = nullptr) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    std::vector<Vec3f> p;
    for (size_t i = 0; i < n; ++i) {
        const int f = int(u(rng) * 7.f);
        const float a = u(rng), b = u(rng);
        Vec3f q, nq;
        switch (f) {
        case 0: q = Vec3f(0.f, 2.5f * a, 4.f * b), nq = Vec3f(1, 0, 0); break;
        case 1: q = Vec3f(6.f, 2.5f * a, 4.f * b), nq = Vec3f(-1, 0, 0); break;
        case 2: q = Vec3f(6.f * a, 0.f, 4.f * b), nq = Vec3f(0, 1, 0); break;
        case 3: q = Vec3f(6.f * a, 2.5f, 4.f * b), nq = Vec3f(0, -1, 0); break;
        case 4: q = Vec3f(6.f * a, 2.5f * b, 0.f), nq = Vec3f(0, 0, 1); break;
        case 5: q = Vec3f(6.f * a, 2.5f * b, 4.f), nq = Vec3f(0, 0, -1); break;
        default: q = Vec3f(2.f + a, 0.75f, 1.5f + b), nq = Vec3f(0, 1, 0); break;
        }
        p.push_back(q);
        if (normals) normals->push_back(nq);
    }
    return p;
}
}  // namespace

TEST(PointGrid, RingSearchEqualsAScan) {
    const std::vector<Vec3f> pts = room_points(3000, 1);
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> u(-1.f, 7.f);   // some queries outside the box
    for (float cell : {0.05f, 0.3f, 2.f}) {
        const PointGrid grid(pts, cell);
        for (int t = 0; t < 300; ++t) {
            const Vec3f q(u(rng), u(rng) * 0.4f, u(rng) * 0.7f);
            constexpr size_t k = 8;
            std::vector<std::pair<float, uint32_t>> scan;
            for (uint32_t j = 0; j < pts.size(); ++j) scan.emplace_back(dot(pts[j] - q, pts[j] - q), j);
            std::partial_sort(scan.begin(), scan.begin() + k, scan.end());
            std::vector<std::pair<float, uint32_t>> ring;
            grid.visit_nearest(
                q, [&](uint32_t j) { ring.emplace_back(dot(pts[j] - q, pts[j] - q), j); },
                [&] {
                    if (ring.size() < k) return std::numeric_limits<float>::infinity();
                    std::vector<std::pair<float, uint32_t>> s = ring;
                    std::nth_element(s.begin(), s.begin() + (k - 1), s.end());
                    return s[k - 1].first;
                });
            std::sort(ring.begin(), ring.end());
            ASSERT_GE(ring.size(), k);
            for (size_t i = 0; i < k; ++i) ASSERT_EQ(ring[i], scan[i]) << "cell " << cell << " query " << t << " rank " << i;
            // visit_ball: every point closer than r is visited.
            const float r = 0.4f;
            std::vector<uint32_t> ball;
            grid.visit_ball(q, r, [&](uint32_t j) { ball.push_back(j); });
            std::sort(ball.begin(), ball.end());
            for (uint32_t j = 0; j < pts.size(); ++j)
                if (length(pts[j] - q) < r) {
                    ASSERT_TRUE(std::binary_search(ball.begin(), ball.end(), j)) << j;
                }
        }
    }
}

// point_spacing by the grid equals the scan's formula √(π · mean r₈² / 8) to the last bit; a
// receiver's cluster with the centres' grid equals the one a scan of the centres finds.
TEST(PointGrid, SpacingAndClustersEqualTheScan) {
    std::vector<Vec3f> nrm;
    const std::vector<Vec3f> pts = room_points(4000, 3, &nrm);
    double sum = 0;
    for (size_t i = 0; i < pts.size(); ++i) {
        std::vector<float> d;
        for (size_t j = 0; j < pts.size(); ++j)
            if (j != i) d.push_back(dot(pts[j] - pts[i], pts[j] - pts[i]));
        std::nth_element(d.begin(), d.begin() + 7, d.end());
        sum += double(d[7]);
    }
    const float s = point_spacing(pts);
    EXPECT_EQ(s, float(std::sqrt(k_pi * sum / double(pts.size()) / 8.0)));
    const ClusterVisibility vis = cluster_visibility(pts, nrm, VoxelOccupancy(pts, nrm, s), 128, DiscOccluder(pts, nrm, s));
    ASSERT_FALSE(vis.centres.empty());
    ClusterVisibility scan = vis;
    scan.centres = PointGrid();
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    for (int t = 0; t < 2000; ++t) {
        const Vec3f p(6.f * u(rng), 2.5f * u(rng), 4.f * u(rng)), n = normalize(Vec3f(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f));
        ASSERT_EQ(vis.cluster_of(p, n), scan.cluster_of(p, n)) << t;
    }
}

TEST(PointGrid, BadInputIsAnError) {
    EXPECT_THROW(PointGrid({}, 1.f), Error);
    EXPECT_THROW(PointGrid({Vec3f(0.f)}, 0.f), Error);
    EXPECT_THROW(PointGrid({Vec3f(0.f)}, NAN), Error);
    EXPECT_THROW(PointGrid({Vec3f(0.f), Vec3f(NAN, 0.f, 0.f)}, 1.f), Error);
    std::vector<Vec3f> pts = room_points(20, 5);
    pts[3].y = INFINITY;
    EXPECT_THROW(point_spacing(pts), Error);
    const PointGrid tiny({Vec3f(0.f), Vec3f(1e6f, 0.f, 0.f)}, 1e-3f);   // would need 10^9 cells: coarsened to 2^22
    EXPECT_GE(tiny.cell(), 1e6f / float(1 << 22));
}
