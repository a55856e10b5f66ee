// embree_accel_test.cpp: Embree agrees with the brute-force intersector on every random ray.
#include <gtest/gtest.h>

#include "ltm/core/error.h"
#include "ltm/core/rng.h"
#include "ltm/core/sampling.h"
#include "ltm/procgen/indoor_generator.h"
#include "ltm/render/brute_accel.h"
#include "ltm/render/embree_accel.h"
#include "ltm/scene/builtin_scenes.h"
#include "box_scenes.h"

using namespace ltm;

namespace {
// Rays from random points inside the bounds in uniform directions; hits must match in
// triangle and distance (misses in both, or neither).
void expect_agreement(const Scene &s, int n_rays, uint64_t seed) {
    const EmbreeAccel embree(s);
    const BruteAccel brute(s);
    const Bounds3f b = s.bounds();
    Pcg32 rng(seed);
    int hits = 0, mismatches = 0;
    for (int i = 0; i < n_rays; ++i) {
        const Vec3f o = b.lo + b.extent() * Vec3f(rng.next_float(), rng.next_float(), rng.next_float());
        const float z = 1.f - 2.f * rng.next_float(), phi = 2.f * k_pi * rng.next_float();
        const float r = std::sqrt(std::max(0.f, 1.f - z * z));
        const Ray ray{o, {r * std::cos(phi), z, r * std::sin(phi)}};
        const auto e = embree.intersect(ray), f = brute.intersect(ray);
        ASSERT_EQ(e.has_value(), f.has_value()) << "ray " << i;
        EXPECT_EQ(embree.occluded(ray), e.has_value());
        if (!e) continue;
        ++hits;
        EXPECT_NEAR(e->t, f->t, 1e-4f * (1.f + f->t)) << "ray " << i;
        // Ties between coplanar/adjacent triangles may pick either; the distance must agree.
        if (e->mesh != f->mesh || e->triangle != f->triangle) ++mismatches;
        else {
            EXPECT_NEAR(e->b1, f->b1, 1e-3f);
            EXPECT_NEAR(e->b2, f->b2, 1e-3f);
        }
    }
    EXPECT_GT(hits, n_rays / 2);
    EXPECT_LE(mismatches, n_rays / 500 + 2) << "triangle ids differ beyond edge ties";
}
}  // namespace

TEST(EmbreeAccel, MatchesBruteForceOnCornellBox) { expect_agreement(cornell_box(), 3000, 1); }

TEST(EmbreeAccel, MatchesBruteForceOnGeneratedIndoorScene) {
    expect_agreement(generate_indoor(GenConfig{}, 42).scene, 2000, 2);
}

TEST(EmbreeAccel, RespectsRayInterval) {
    const Scene s = furnace_box(0.5f, 1.f);
    const EmbreeAccel accel(s);
    const Ray ray{{0.5f, 0.5f, 0.5f}, {1.f, 0.f, 0.f}, 0.f, 0.4f};
    EXPECT_FALSE(accel.intersect(ray).has_value());
    EXPECT_FALSE(accel.occluded(ray));
    const auto hit = accel.intersect({{0.5f, 0.5f, 0.5f}, {1.f, 0.f, 0.f}});
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->t, 0.5f, 1e-6f);
    EXPECT_NEAR(hit->n.x, -1.f, 1e-6f);   // the wall faces back into the box
}

TEST(EmbreeAccel, OffsetOriginDoesNotSelfIntersect) {
    const Scene s = cornell_box();
    const EmbreeAccel accel(s);
    Pcg32 rng(4);
    // From random points on the floor, cosine directions must never hit the floor itself.
    for (int i = 0; i < 2000; ++i) {
        const Vec3f p{0.05f + 0.45f * rng.next_float(), 0.f, 0.05f + 0.45f * rng.next_float()};
        const Vec3f n{0, 1, 0};
        const Vec3f d = Frame(n).to_world(sample_cosine_hemisphere({rng.next_float(), rng.next_float()}));
        const auto hit = accel.intersect({offset_ray_origin(p, n, d), d});
        if (hit) {
            EXPECT_NE(s.meshes[hit->mesh].name, "floor");
        }
    }
}

// A mesh Embree refuses after the device and scene exist (no vertices for its triangles): the
// constructor throws ltm::Error, and the handles it made are released by their owners (issue #14
// item 4; the LTM_SANITIZE build's LeakSanitizer checks the "nothing leaks" half). A second
// accelerator over a valid scene still works afterwards.
TEST(EmbreeAccel, ConstructorThatThrowsReleasesWhatItMade) {
    Scene bad = cornell_box();
    bad.meshes[1].positions.clear();
    for (int i = 0; i < 3; ++i) EXPECT_THROW(EmbreeAccel{bad}, Error);
    const Scene good = cornell_box();   // EmbreeAccel keeps a reference: not a temporary
    const EmbreeAccel ok(good);
    EXPECT_TRUE(ok.intersect(Ray{{0.f, 0.f, 0.f}, {0.f, 1.f, 0.f}}).has_value() ||
                ok.intersect(Ray{{0.f, 0.f, 0.f}, {0.f, -1.f, 0.f}}).has_value());
}

// Two boxes stacked in the unit furnace box: box A's top and box B's bottom coincide at y = 0.5.
// hits() lists every face a ray crosses, the coincident pair included, sorted by t, then mesh.
TEST(EmbreeAccel, HitsListsEveryFaceInTheIntervalCoincidentOnesToo) {
    const Scene s = test::furnace_with_boxes({{{0.25f, 0.f, 0.25f}, {0.75f, 0.5f, 0.75f}}, {{0.25f, 0.5f, 0.25f}, {0.75f, 0.75f, 0.75f}}});
    const EmbreeAccel accel(s);
    const Ray up{{0.4f, 0.3f, 0.6f}, {0.f, 1.f, 0.f}};
    const std::vector<Hit> all = accel.hits(up);
    ASSERT_EQ(all.size(), 4u);   // A's top, B's bottom, B's top, the furnace's ceiling
    const float t[4] = {0.2f, 0.2f, 0.45f, 0.7f};
    const uint32_t mesh[4] = {1, 2, 2, 0};
    const float ny[4] = {1.f, -1.f, 1.f, -1.f};
    for (size_t i = 0; i < 4; ++i) {
        EXPECT_NEAR(all[i].t, t[i], 1e-6f) << i;
        EXPECT_EQ(all[i].mesh, mesh[i]) << i;
        EXPECT_NEAR(all[i].n.y, ny[i], 1e-6f) << i;
    }
    const auto first = accel.intersect(up);
    ASSERT_TRUE(first);
    EXPECT_EQ(first->t, all[0].t);
    // The interval bounds the list, as it bounds intersect().
    EXPECT_EQ(accel.hits({up.o, up.d, 0.f, 0.3f}).size(), 2u);
    EXPECT_EQ(accel.hits({up.o, up.d, 0.3f, 0.6f}).size(), 1u);
    EXPECT_TRUE(accel.hits({up.o, up.d, 0.f, 0.1f}).empty());
    // Embree's own closest-hit queries are unaffected by the context filter's scene flag.
    EXPECT_FALSE(accel.occluded({up.o, up.d, 0.f, 0.1f}));
    EXPECT_TRUE(accel.occluded({up.o, up.d, 0.f, 0.3f}));
}
