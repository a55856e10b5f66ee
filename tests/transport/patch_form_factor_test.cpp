// patch_form_factor_test.cpp: the square patch's form factor against a closed form (a parallel
// square above the element), Monte Carlo integration (patches cut by the receiver's horizon), the
// concave-edge limit 1/2 that the point formula misses, and its symmetries.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "ltm/transport/patch_form_factor.h"

using namespace ltm;

namespace {
// Form factor from an element to the rectangle [0, X·d] × [0, Y·d] in the plane at height d, one
// corner above the element (Howell's catalogue, configuration B-3).
double corner_rectangle(double X, double Y) {
    const double a = X / std::sqrt(1 + X * X), b = Y / std::sqrt(1 + Y * Y);
    return (a * std::atan(Y / std::sqrt(1 + X * X)) + b * std::atan(X / std::sqrt(1 + Y * Y))) / (2 * k_pi);
}

// ∫ over the square of max(0, cosθ_r) · max(0, cosθ_s) / (π r²) dA, by stratified Monte Carlo.
double monte_carlo(Vec3f p, Vec3f n, Vec3f c, Vec3f nc, float side) {
    // The square's frame as the header defines it.
    const Vec3f y_cross = cross(Vec3f(0.f, 1.f, 0.f), nc);
    const Vec3f t1 = length(y_cross) > 1e-4f ? normalize(y_cross) : normalize(Vec3f(1.f, 0.f, 0.f) - nc * nc.x);
    const Vec3f t2 = cross(nc, t1);
    constexpr int g = 400;
    double sum = 0;
    for (int i = 0; i < g; ++i)
        for (int j = 0; j < g; ++j) {
            const float u = ((float(i) + 0.5f) / g - 0.5f) * side, v = ((float(j) + 0.5f) / g - 0.5f) * side;
            const Vec3f d = c + t1 * u + t2 * v - p;
            const double r2 = dot(d, d), r = std::sqrt(r2);
            const double cr = std::max(0.0, double(dot(n, d)) / r), cs = std::max(0.0, -double(dot(nc, d)) / r);
            sum += cr * cs / (k_pi * r2);
        }
    return sum * double(side) * double(side) / (double(g) * g);
}
}  // namespace

TEST(PatchFormFactor, ParallelSquareAboveMatchesTheClosedForm) {
    for (float d : {0.2f, 1.f, 3.f}) {
        const float side = 1.f;
        const double expect = 4 * corner_rectangle(0.5 * side / d, 0.5 * side / d);
        const float f = patch_form_factor(Vec3f(0.f), Vec3f(0.f, 1.f, 0.f), Vec3f(0.f, d, 0.f), Vec3f(0.f, -1.f, 0.f), side);
        EXPECT_NEAR(f, expect, 1e-5) << "height " << d;
    }
}

// Oblique and cut by the receiver's horizon (a patch on a wall beside a floor element, a tilted
// patch): Lambert's contour integral after clipping equals the integral over the square.
TEST(PatchFormFactor, ObliqueAndClippedPatchesMatchMonteCarlo) {
    const Vec3f up(0.f, 1.f, 0.f);
    struct Case {
        Vec3f p, n, c, nc;
        float side;
    };
    const Case cases[] = {
        {Vec3f(0.f), up, Vec3f(0.3f, 0.1f, 0.f), Vec3f(-1.f, 0.f, 0.f), 0.4f},          // wall patch crossing the floor's plane
        {Vec3f(0.f), up, Vec3f(0.5f, 0.8f, 0.2f), normalize(Vec3f(-1.f, -1.f, 0.3f)), 0.6f},   // tilted, fully above
        {Vec3f(0.f), normalize(Vec3f(0.2f, 1.f, 0.f)), Vec3f(-0.2f, 0.05f, 0.f), Vec3f(1.f, 0.f, 0.f), 0.5f},   // cut by a tilted horizon
        {Vec3f(0.02f, 0.f, 0.f), up, Vec3f(0.f, 0.2f, 0.f), Vec3f(1.f, 0.f, 0.f), 0.4f},   // next to a concave edge
    };
    for (const Case &k : cases) {
        const double mc = monte_carlo(k.p, k.n, k.c, k.nc, k.side);
        EXPECT_NEAR(patch_form_factor(k.p, k.n, k.c, k.nc, k.side), mc, 2e-3 + 5e-3 * mc) << k.c;
    }
}

// At a concave edge the adjacent wall fills half the hemisphere: the form factor of a wall patch
// reaching the edge tends to 1/2 as the element approaches the edge (the point formula at the
// patch's centre tends to 0); behind the patch, or in its plane, 0.
TEST(PatchFormFactor, ConcaveEdgeLimitAndBackFace) {
    const Vec3f up(0.f, 1.f, 0.f), wall_n(1.f, 0.f, 0.f);
    const Vec3f centre(0.f, 50.f, 0.f);   // a 100-wide wall patch standing on the floor's edge x = 0
    for (float x : {1e-2f, 1e-3f}) EXPECT_NEAR(patch_form_factor(Vec3f(x, 0.f, 0.f), up, centre, wall_n, 100.f), 0.5f, 2e-3f) << x;
    EXPECT_EQ(patch_form_factor(Vec3f(-0.1f, 0.f, 0.f), up, centre, wall_n, 100.f), 0.f) << "behind";
    EXPECT_EQ(patch_form_factor(Vec3f(0.f, 1.f, 0.f), up, centre, wall_n, 100.f), 0.f) << "in its plane";
    EXPECT_EQ(patch_form_factor(Vec3f(0.f), up, Vec3f(0.f, -1.f, 0.f), up, 1.f), 0.f) << "below the horizon";
}

// The prior's near-field term: a node centred behind the receiver's plane gets nothing even where its
// square reaches over the horizon (a floor node under a wall, seen from the wall's foot: the square
// alone would give it a share), and in front of it the term is the square's form factor.
TEST(PatchFormFactor, NearTermIgnoresNodesCentredBehindTheReceiver) {
    const Vec3f wall_p(0.f, 0.02f, 0.f), wall_n(1.f, 0.f, 0.f), up(0.f, 1.f, 0.f);
    const Vec3f under_wall(-0.13f, 0.f, 0.f), in_front(0.13f, 0.f, 0.f);   // floor nodes, squares of side 0.665
    EXPECT_GT(patch_form_factor(wall_p, wall_n, under_wall, up, 0.665f), 0.05f) << "the square reaches out from under the wall";
    EXPECT_EQ(near_form_factor(wall_p, wall_n, under_wall, up, 0.665f), 0.f);
    EXPECT_GT(near_form_factor(wall_p, wall_n, in_front, up, 0.665f), 0.1f);
    EXPECT_EQ(near_form_factor(wall_p, wall_n, in_front, up, 0.665f), patch_form_factor(wall_p, wall_n, in_front, up, 0.665f));
}

// Quarter turns about ŷ, a mirror in x and a change of unit map the patch's frame with the scene.
TEST(PatchFormFactor, FollowsTheTrainingSymmetriesAndTheUnit) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    auto turn = [](Vec3f v) { return Vec3f(v.z, v.y, -v.x); };
    auto mirror = [](Vec3f v) { return Vec3f(-v.x, v.y, v.z); };
    for (int i = 0; i < 200; ++i) {
        const Vec3f p(u(rng), u(rng), u(rng)), n = normalize(Vec3f(u(rng), u(rng), u(rng)));
        const Vec3f c(u(rng), u(rng), u(rng));
        // Axis-aligned patch normals, as walls and floors (the frame is exact for them).
        const int axis = i % 3;
        Vec3f nc(0.f);
        nc[axis] = u(rng) > 0.f ? 1.f : -1.f;
        const float f = patch_form_factor(p, n, c, nc, 0.3f);
        EXPECT_NEAR(patch_form_factor(turn(p), turn(n), turn(c), turn(nc), 0.3f), f, 1e-5f + 1e-4f * f) << i;
        EXPECT_NEAR(patch_form_factor(mirror(p), mirror(n), mirror(c), mirror(nc), 0.3f), f, 1e-5f + 1e-4f * f) << i;
        EXPECT_NEAR(patch_form_factor(p * 10.f, n, c * 10.f, nc, 3.f), f, 1e-5f + 1e-4f * f) << i;
    }
}

// Tilted facets: a receiver on the patch's own tilted plane (within rounding) gets 0, not a
// spurious ~1 from a square that rounding lifts in front of it; a normal near ±ŷ keeps a square
// frame in its own plane that maps with quarter turns.
TEST(PatchFormFactor, TiltedPlanesAndNearVerticalNormals) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    for (int i = 0; i < 500; ++i) {
        const Vec3f nc = normalize(Vec3f(u(rng), u(rng), u(rng)));
        const Vec3f c(u(rng), u(rng), u(rng));
        Vec3f t = cross(nc, Vec3f(0.3f, 0.5f, 0.7f));
        t = normalize(t);
        const Vec3f p = c + t * (0.05f * (1.f + u(rng)));   // in the plane, near or inside the square
        EXPECT_EQ(patch_form_factor(p, nc, c, nc, 0.2f), 0.f) << i;
    }
    auto turn = [](Vec3f v) { return Vec3f(v.z, v.y, -v.x); };
    for (int i = 0; i < 100; ++i) {
        const Vec3f nc = normalize(Vec3f(0.05f * u(rng), 1.f, 0.05f * u(rng)));   // |n.y| > 0.99
        const Vec3f c(0.f), p(0.3f * u(rng), 0.2f + 0.1f * u(rng), 0.3f * u(rng)), n = normalize(Vec3f(u(rng), -1.f, u(rng)));
        const float f = patch_form_factor(p, n, c, nc, 0.3f);
        EXPECT_NEAR(patch_form_factor(turn(p), turn(n), turn(c), turn(nc), 0.3f), f, 1e-5f + 1e-4f * f) << i;
        EXPECT_NEAR(f, monte_carlo(p, n, c, nc, 0.3f), 2e-3 + 5e-3 * f) << i;
    }
}
