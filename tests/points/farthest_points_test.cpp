// farthest_points_test.cpp: the k-d tree FPS picks exactly the plain loop's samples, in order, on
// clouds built to stress its pruning and its tie-breaking.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "ltm/points/farthest_points.h"

namespace ltm {
namespace {

void expect_same(const std::vector<float> &xyz, size_t m, const char *what) {
    const size_t n = xyz.size() / 3;
    EXPECT_EQ(farthest_points(xyz.data(), n, m), farthest_points_reference(xyz.data(), n, m)) << what << ": n " << n << ", m " << m;
}

TEST(FarthestPoints, EqualsThePlainLoopOnUniformCloudsToTheLastSample) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-3.f, 5.f);
    for (size_t n : {1u, 2u, 31u, 32u, 33u, 1000u, 4097u}) {
        std::vector<float> xyz(3 * n);
        for (float &v : xyz) v = u(rng);
        expect_same(xyz, n, "uniform");   // every point: the last samples are the closest near-ties
        expect_same(xyz, 1, "uniform, one sample");
    }
}

// Walls, floors and duplicates: boxes of zero thickness, distances equal to the last bit, and exact
// ties that must go to the lower index.
TEST(FarthestPoints, EqualsThePlainLoopOnPlanesGridsAndDuplicates) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.f, 4.f);
    std::vector<float> planes;
    for (int i = 0; i < 6000; ++i) {
        const float a = u(rng), b = u(rng);
        switch (i % 3) {
            case 0: planes.insert(planes.end(), {a, b, 0.f}); break;
            case 1: planes.insert(planes.end(), {a, 0.f, b}); break;
            default: planes.insert(planes.end(), {4.f, a, b}); break;
        }
    }
    expect_same(planes, 3000, "three planes");
    std::vector<float> grid;   // a lattice: every distance repeats, ties everywhere
    for (int x = 0; x < 16; ++x)
        for (int y = 0; y < 16; ++y)
            for (int z = 0; z < 8; ++z) grid.insert(grid.end(), {0.25f * float(x), 0.25f * float(y), 0.25f * float(z)});
    expect_same(grid, grid.size() / 3, "lattice");
    std::vector<float> dup;   // each point four times, far apart clusters
    for (int i = 0; i < 500; ++i) {
        const float a = u(rng), b = u(rng), c = 1000.f * float(i % 2) + u(rng);
        for (int k = 0; k < 4; ++k) dup.insert(dup.end(), {a, b, c});
    }
    expect_same(dup, dup.size() / 3, "duplicates");
}

}  // namespace
}  // namespace ltm
