// reachable_air_test.cpp: the air light and cameras are in, whatever the faces' winding; and the
// scene points (and the transport prior on them) of a room whose shell is wound outward — as real
// pbrt files often are — equal those of the same room wound inward.
#include <cmath>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "ltm/render/enclosure.h"
#include "ltm/render/gbuffer.h"
#include "ltm/render/reachable_air.h"
#include "ltm/render/scene_points.h"
#include "ltm/scene/builtin_scenes.h"
#include "ltm/scene/mesh_builder.h"
#include "ltm/transport/transport_prior.h"

using namespace ltm;

namespace {
void flip_winding(TriangleMesh &m) {
    for (size_t t = 0; t < m.n_triangles(); ++t) std::swap(m.indices[3 * t + 1], m.indices[3 * t + 2]);
}

// quad_light_room() (5 × 2.7 × 4 m, inward walls and floor, a ceiling light facing down, a closed
// box on the floor over x 3.2–4.0, z 0.8–1.6, height 0.9) with its walls and floor wound outward.
Scene outward_room() {
    Scene s = quad_light_room();
    for (TriangleMesh &m : s.meshes)
        if (m.name == "walls" || m.name == "floor") flip_winding(m);
    return s;
}

bool on_shell(Vec3f p) {
    const float e = 1e-4f;
    return std::abs(p.x) < e || std::abs(p.x - 5.f) < e || std::abs(p.y) < e || std::abs(p.y - 2.7f) < e || std::abs(p.z) < e ||
           std::abs(p.z - 4.f) < e;
}

bool under_box(Vec3f p) { return p.y < 1e-4f && p.x > 3.2f && p.x < 4.0f && p.z > 0.8f && p.z < 1.6f; }

double mean_luminance(const std::vector<Vec3f> &v) {
    double s = 0;
    for (const Vec3f &c : v) s += double(luminance(c));
    return s / double(v.size());
}
}  // namespace

TEST(ReachableAir, FloodsTheLitRoomNotTheSolidsNorTheOutside) {
    for (bool outward : {false, true}) {
        SCOPED_TRACE(outward ? "shell wound outward" : "shell wound inward");
        const Scene s = outward ? outward_room() : quad_light_room();
        const ReachableAir air(s);
        ASSERT_TRUE(air.has_seeds());
        EXPECT_TRUE(air.reaches({1.f, 0.f, 3.f}, {0, 1, 0}));          // the floor, from the room
        EXPECT_FALSE(air.reaches({1.f, 0.f, 3.f}, {0, -1, 0}));        // the floor's outside
        EXPECT_TRUE(air.reaches({0.f, 1.f, 2.f}, {1, 0, 0}));          // a wall, from the room
        EXPECT_FALSE(air.reaches({0.f, 1.f, 2.f}, {-1, 0, 0}));
        EXPECT_TRUE(air.reaches({3.6f, 0.9f, 1.2f}, {0, 1, 0}));       // the box's top
        EXPECT_FALSE(air.reaches({3.6f, 0.9f, 1.2f}, {0, -1, 0}));     // the box's inside
        EXPECT_FALSE(air.reaches({3.6f, 0.f, 1.2f}, {0, 1, 0}));       // the floor under the box
    }
}

TEST(ReachableAir, CamerasSeedTheirAirAndNoSeedsMeansNoVerdict) {
    Scene s = quad_light_room();
    Scene dark = s;
    dark.meshes.erase(dark.meshes.begin() + 2);   // the lamp
    ASSERT_EQ(dark.meshes.size(), 3u);
    const ReachableAir by_camera(dark);
    EXPECT_TRUE(by_camera.has_seeds());
    EXPECT_TRUE(by_camera.reaches({1.f, 0.f, 3.f}, {0, 1, 0}));
    EXPECT_FALSE(by_camera.reaches({3.6f, 0.9f, 1.2f}, {0, -1, 0}));
    dark.cameras.clear();
    const ReachableAir none(dark);
    EXPECT_FALSE(none.has_seeds());
    EXPECT_TRUE(none.reaches({3.6f, 0.9f, 1.2f}, {0, -1, 0}));
}

// The sampler keeps the room's side of an outward-wound shell (flipping the points' normals), drops
// the floor under the box and the shell's outside, and keeps the same share of the surface.
TEST(Enclosure, AnOutwardWoundRoomSamplesLikeAnInwardOne) {
    const Scene in = quad_light_room(), out = outward_room();
    const EmbreeAccel ain(in), aout(out);
    const ScenePoints pin = sample_scene_points(ain, 4096, 0, true), pout = sample_scene_points(aout, 4096, 0, true);
    ASSERT_EQ(pout.points.size(), 4096u);
    int shell_in = 0, shell_out = 0;
    const Vec3f centre(2.5f, 1.35f, 2.f);
    for (const auto *ps : {&pin.points, &pout.points})
        for (size_t i = 0; i < ps->size(); ++i) {
            const Vec3f p = ps->vec3(i, 0), n = ps->vec3(i, 3);
            EXPECT_FALSE(under_box(p)) << "a point under the box at " << p.x << " " << p.z;
            if (!on_shell(p)) continue;
            (ps == &pin.points ? shell_in : shell_out) += 1;
            EXPECT_GT(dot(n, centre - p), 0.f) << "a shell point faces out of the room";
        }
    // Same area kept (the emission scale is Φ over it) and the same share on the shell (binomial
    // σ ≈ 28 points of 4 096).
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(pout.emission_scale[c], pin.emission_scale[c], 0.02f * pin.emission_scale[c]);
    EXPECT_NEAR(shell_out, shell_in, 120);
}

// The prior's E⁺ on the room's view from either winding agrees; with the points of the outward
// shell facing out (the sampler before reachable air) the lamp's light had nothing to land on but the
// box, and living-room-3's first bounce came out 2× too bright.
TEST(Enclosure, ThePriorDoesNotDependOnTheShellsWinding) {
    double level[2];
    for (int w = 0; w < 2; ++w) {
        const Scene s = w ? outward_room() : quad_light_room();
        const EmbreeAccel accel(s);
        const ScenePoints sp = sample_scene_points(accel, 4096, 0, true);
        const float spacing = float(std::sqrt(s.total_area() / double(sp.points.size())));
        VisibilityOptions vis;
        vis.voxel_spacings = 1.f;
        vis.clusters = 512;
        vis.disc_spacings = 1.f;
        vis.blend = 4;
        vis.open_rays = 8;
        const TransportPrior prior = solve_transport_prior(sp.points, spacing * spacing, 5, &sp.emission_scale, vis, nullptr,
                                                           PriorBalance::none, true);
        Camera cam = s.cameras.at(0);
        cam.width = cam.height = 48;
        const GBuffer gb = render_gbuffer(accel, cam);
        ASSERT_GT(gb.n_hits(), 1000u);
        std::vector<Vec3f> e(gb.n_hits());
        gather_transport_prior(prior, &gb.position[0].x, &gb.normal[0].x, 3, gb.n_hits(), &e[0].x);
        level[w] = mean_luminance(e);
    }
    EXPECT_GT(level[0], 0.0);
    EXPECT_NEAR(level[1] / level[0], 1.0, 0.03);
}
