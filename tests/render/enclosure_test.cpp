// enclosure_test.cpp: the floor under a closed box is enclosed, open floor is not, the
// sampler's --exclude-enclosed path leaves no samples under the boxes, and the model's input
// sampling (scene_points.h) is unit-free.
#include <algorithm>
#include <vector>

#include <gtest/gtest.h>

#include "ltm/transport/power_balance.h"
#include "ltm/points/surface_sampler.h"
#include "ltm/procgen/indoor_generator.h"
#include "ltm/render/enclosure.h"
#include "ltm/render/scene_points.h"
#include "ltm/scene/builtin_scenes.h"
#include "ltm/scene/mesh_builder.h"
#include "ltm/scene/scene_transform.h"
#include "box_scenes.h"

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

// The model's input sampling (render/scene_points.h) on a generated house: the filter drops part
// of the surface and S = Φ/A counts only what is left; the same house in decimetres gives the same
// points (scaled) and the same S — a borderline point that flips with float rounding must not
// change the candidate count and with it the whole point set.
TEST(ScenePoints, FilteredEmissionScaleAndUnitOfLength) {
    // While the rejection's candidate count followed the pass fraction, house 900103 came out a
    // wholly different point set with sampling seeds 0, 6, 8 at ×0.1 and 5 at ×10 (4 of 36 cases;
    // its unit check was 10 % off); now every one of those 36 keeps >= 8159 of 8192 points.
    struct Case {
        int house;
        float f;
        uint64_t sampling_seed;
    };
    for (const Case &k : {Case{900100, 0.1f, 7}, Case{900103, 0.1f, 0}, Case{900103, 0.1f, 6}, Case{900103, 10.f, 5}}) {
        const int seed = k.house;
        const float f = k.f;
        SCOPED_TRACE("house " + std::to_string(seed) + " ×" + std::to_string(f) + " seed " + std::to_string(k.sampling_seed));
        GeneratedScene g = generate_indoor(GenConfig{}, uint64_t(seed));
        const EmbreeAccel accel(g.scene);
        const ScenePoints a = sample_scene_points(accel, 8192, k.sampling_seed, true);
        ASSERT_EQ(a.points.size(), 8192u);
        if (seed == 900100) {
            const ScenePoints all = sample_scene_points(accel, 8192, k.sampling_seed, false);
            EXPECT_GT(a.emission_scale.x, all.emission_scale.x);   // same flux, less area
            EXPECT_NEAR(all.emission_scale.x, scene_emission_scale(g.scene).x, 1e-6f * all.emission_scale.x);
        }
        Scene scaled = g.scene;
        scale_lengths(scaled, f);
        const EmbreeAccel accel_scaled(scaled);
        const ScenePoints b = sample_scene_points(accel_scaled, 8192, k.sampling_seed, true);
        // A handful of candidates at grazing contacts still flip with float rounding (~0.1 %).
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(b.emission_scale[c], a.emission_scale[c], 5e-3f * a.emission_scale[c]) << c;
        // Compared as sets, sorted by x, then a match within 1e-5 of the house's size.
        const float tol = 1e-5f * f * length(g.scene.bounds().extent());
        std::vector<Vec3f> pa;
        for (size_t i = 0; i < a.points.size(); ++i) pa.push_back(a.points.vec3(i, 0) * f);
        std::sort(pa.begin(), pa.end(), [](Vec3f u, Vec3f v) { return u.x < v.x; });
        int same = 0, same_emitting = 0, emitting = 0;
        for (size_t i = 0; i < b.points.size(); ++i) {
            const Vec3f q = b.points.vec3(i, 0);
            const bool emits = max_component(b.points.vec3(i, 9)) > 0.f;
            emitting += emits;
            auto it = std::lower_bound(pa.begin(), pa.end(), q.x - tol, [](Vec3f u, float x) { return u.x < x; });
            for (; it != pa.end() && it->x <= q.x + tol; ++it)
                if (length(*it - q) < tol) {
                    ++same, same_emitting += emits;
                    break;
                }
        }
        EXPECT_GE(same, int(0.99 * 8192)) << "points of the scaled scene are not the scaled points";
        EXPECT_GE(same_emitting, emitting - 1) << "an emitter's points moved";
    }
}

namespace {
// Candidates (round 0 of the scene-point stream) whose enclosure verdict differs between house
// `seed` and the same house scaled by f.
int enclosure_flips(int seed, float f) {
    const GeneratedScene g = generate_indoor(GenConfig{}, uint64_t(seed));
    Scene scaled = g.scene;
    scale_lengths(scaled, f);
    const EmbreeAccel a(g.scene), b(scaled);
    EnclosureTest ca, cb;
    ca.offset_length = max_component(g.scene.bounds().extent());
    cb.offset_length = max_component(scaled.bounds().extent());
    const auto sa = sample_surface(g.scene, 8192, 0, SampleStream::scene_points);
    const auto sb = sample_surface(scaled, 8192, 0, SampleStream::scene_points);
    int flips = 0;
    for (size_t i = 0; i < sa.size(); ++i) flips += is_enclosed(a, sa[i].p, sa[i].n, ca) != is_enclosed(b, sb[i].p, sb[i].n, cb);
    return flips;
}
}  // namespace

TEST(Enclosure, CoincidentFacesVoteAlikeInAnyUnit) {
    // Desk tops inside their frames, boxes resting on boxes: which of two coincident faces a
    // closest-hit query returns is float rounding's choice. When only that first face voted,
    // 105/106 (house 900101 at ×10/×0.1) and 39/44 (900103) of the 8 192 candidates flipped; now 0.
    for (int seed : {900101, 900103})
        for (float f : {0.1f, 10.f}) EXPECT_LE(enclosure_flips(seed, f), 2) << "house " << seed << " ×" << f;
}

TEST(Enclosure, AFloorUnderStackedBoxesIsEnclosedInAnyUnitAndMeshOrder) {
    // Box A rests on the floor, box B on A: A's top and B's bottom coincide. Rays from the floor
    // under A first meet that pair; whichever of the two the query returns, the verdict holds.
    for (bool b_first : {false, true})
        for (float f : {0.01f, 0.1f, 1.f, 10.f, 1000.f}) {
            const test::Box a{{0.25f, 0.f, 0.25f}, {0.75f, 0.5f, 0.75f}}, b{{0.2f, 0.5f, 0.2f}, {0.8f, 0.9f, 0.8f}};
            Scene s = b_first ? test::furnace_with_boxes({b, a}) : test::furnace_with_boxes({a, b});
            scale_lengths(s, f);
            const EmbreeAccel accel(s);
            EnclosureTest cfg;
            cfg.offset_length = max_component(s.bounds().extent());
            for (float x : {0.35f, 0.5f, 0.6f})
                EXPECT_TRUE(is_enclosed(accel, Vec3f(x, 0.f, 0.45f) * f, {0.f, 1.f, 0.f}, cfg)) << "x " << x << " ×" << f << " b first " << b_first;
            EXPECT_FALSE(is_enclosed(accel, Vec3f(0.1f, 0.f, 0.1f) * f, {0.f, 1.f, 0.f}, cfg)) << "open floor ×" << f;
        }
}

// A rug 1 cm above the floor of the Cornell box: the floor beneath it and the rug's underside see
// only each other, so with a buried distance of 5 cm they count as enclosed (the model's sampler:
// 0.5 point spacings), without it they do not; the rug's top and the open floor stay.
TEST(Enclosure, PointsBuriedInAThinGapCountAsEnclosed) {
    Scene s = cornell_box();
    TriangleMesh rug;
    rug.name = "rug", rug.material = 0;
    add_box(rug, Vec3f(0.33f, 0.01f, 0.02f), Vec3f(0.52f, 0.02f, 0.2f));   // clear floor, before the tall block
    s.meshes.push_back(rug);
    const EmbreeAccel accel(s);
    EnclosureTest buried;
    buried.offset_length = max_component(s.bounds().extent());
    buried.buried_distance = 0.05f;
    EnclosureTest plain = buried;
    plain.buried_distance = 0.f;
    const Vec3f under(0.42f, 0.f, 0.11f), underside(0.42f, 0.01f, 0.11f), top(0.42f, 0.02f, 0.11f), open(0.2f, 0.f, 0.45f);
    EXPECT_TRUE(is_enclosed(accel, under, {0, 1, 0}, buried));
    EXPECT_TRUE(is_enclosed(accel, underside, {0, -1, 0}, buried));
    EXPECT_FALSE(is_enclosed(accel, under, {0, 1, 0}, plain)) << "the rug's underside is a front face";
    EXPECT_FALSE(is_enclosed(accel, top, {0, 1, 0}, buried));
    EXPECT_FALSE(is_enclosed(accel, open, {0, 1, 0}, buried));
}
