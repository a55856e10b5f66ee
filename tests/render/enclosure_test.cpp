// enclosure_test.cpp: the floor under a closed box is enclosed, open floor is not, and the
// sampler's --exclude-enclosed path leaves no samples under the boxes.
#include <gtest/gtest.h>

#include "ltm/points/surface_sampler.h"
#include "ltm/render/enclosure.h"
#include "ltm/scene/builtin_scenes.h"

using namespace ltm;

TEST(Enclosure, FloorUnderABlockIsEnclosedOpenFloorIsNot) {
    const Scene s = cornell_box();
    const EmbreeAccel accel(s);
    // Under the tall block (footprint around (0.37, 0.35)) vs. the open front of the floor.
    EXPECT_TRUE(is_enclosed(accel, {0.368f, 0.f, 0.351f}, {0, 1, 0}));
    EXPECT_FALSE(is_enclosed(accel, {0.278f, 0.f, 0.05f}, {0, 1, 0}));
    EXPECT_FALSE(is_enclosed(accel, {0.368f, 0.33f, 0.351f}, {0, 1, 0}));   // top of the block
}

TEST(Enclosure, ExcludedSamplesAvoidBlockFootprints) {
    const Scene s = cornell_box();
    const EmbreeAccel accel(s);
    const auto all = sample_surface(s, 20000, 1, SampleStream::scene_points);
    const auto kept = sample_surface(s, 20000, 1, SampleStream::scene_points, enclosed_filter(accel));
    ASSERT_EQ(kept.size(), 20000u);
    auto under_tall = [](const SurfaceSample &x) {
        return x.p.y < 1e-4f && std::abs(x.p.x - 0.368f) < 0.05f && std::abs(x.p.z - 0.351f) < 0.05f;
    };
    int before = 0, after = 0;
    for (const auto &x : all) before += under_tall(x);
    for (const auto &x : kept) after += under_tall(x);
    EXPECT_GT(before, 20);
    EXPECT_EQ(after, 0);
}
