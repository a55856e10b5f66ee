// disc_occluder_test.cpp: occlusion by the scene points as oriented discs — a wall blocks from its
// front and not from behind, a segment between two walls near their common edge is not blocked
// (the voxels' failure), the grid walk agrees with testing every disc, the answers follow the
// scene under the training symmetries and the unit, bad input.
#include <gtest/gtest.h>

#include <cmath>

#include "ltm/core/error.h"
#include "ltm/transport/disc_occluder.h"
#include "point_rooms.h"

using namespace ltm;

namespace {
using test::hash01;

// The inner faces of the box [0, 2]³ on a 12×12 grid per face (spacing s = 1/6), jittered ±0.3 s.
struct Discs {
    std::vector<Vec3f> p, n;
};
Discs box_room() {
    Discs d;
    size_t i = 0;
    const auto jitter = [&i] {
        ++i;
        return std::pair{0.6f * (hash01(i, 1) - 0.5f), 0.6f * (hash01(i, 2) - 0.5f)};
    };
    test::for_each_face_cell(Vec3f(0.f), Vec3f(2.f), 12, jitter, [&](int, Vec3f p, Vec3f n) { d.p.push_back(p), d.n.push_back(n); });
    return d;
}
constexpr float k_s = 2.f / 12.f;

// The criterion of the header, disc by disc, without the grid: the oracle for the grid walk.
bool brute_blocked(const Discs &d, float r, Vec3f a, Vec3f b) {
    const Vec3f v = b - a;
    const float len = length(v), margin = 0.25f * r;
    if (!(len > 2.f * margin)) return false;
    for (size_t k = 0; k < d.p.size(); ++k) {
        const float denom = dot(d.n[k], v);
        if (!(denom < -0.05f * len)) continue;
        const float t = dot(d.n[k], d.p[k] - a) / denom;
        if (!(t * len > margin && (1.f - t) * len > margin)) continue;
        const Vec3f q = a + v * t - d.p[k];
        if (dot(q, q) < r * r) return true;
    }
    return false;
}

Vec3f random_point(size_t i, int salt, float lo, float hi) {
    return Vec3f(lo + (hi - lo) * hash01(i, salt), lo + (hi - lo) * hash01(i, salt + 1), lo + (hi - lo) * hash01(i, salt + 2));
}
}  // namespace

TEST(DiscOccluder, AWallBlocksFromItsFrontOnly) {
    const Discs room = box_room();
    const DiscOccluder occ(room.p, room.n, k_s);
    int blocked_in = 0, blocked_out = 0;
    constexpr int n = 400;
    for (int i = 0; i < n; ++i) {
        // From inside the room to a point outside it beyond the wall x = 2 (met from the front),
        // and from outside to inside (met from behind: the wall faces the room).
        const Vec3f inside(0.3f + 1.4f * hash01(size_t(i), 3), 0.3f + 1.4f * hash01(size_t(i), 4), 0.3f + 1.4f * hash01(size_t(i), 5));
        const Vec3f outside(2.6f, 0.2f + 1.6f * hash01(size_t(i), 6), 0.2f + 1.6f * hash01(size_t(i), 7));
        blocked_in += occ.blocked(inside, outside);
        blocked_out += occ.blocked(outside, inside);
    }
    EXPECT_GE(blocked_in, n * 97 / 100) << "discs of radius s close a jittered wall of spacing s";
    EXPECT_EQ(blocked_out, 0) << "a segment meeting the wall from behind passes";
}

// The voxels' failure at edges: between a floor point and a wall point beside their common edge the
// segment runs close to both surfaces but meets neither; the same holds for points on one wall.
TEST(DiscOccluder, NoFalseOcclusionNearEdges) {
    const Discs room = box_room();
    const DiscOccluder occ(room.p, room.n, k_s);
    for (int i = 0; i < 200; ++i) {
        const float x = 0.02f + 0.3f * hash01(size_t(i), 8), y = 0.02f + 0.3f * hash01(size_t(i), 9), z = 0.1f + 1.8f * hash01(size_t(i), 10);
        const Vec3f floor(x, 0.f, z), wall(0.f, y, z + 0.2f * (hash01(size_t(i), 11) - 0.5f));
        EXPECT_FALSE(occ.blocked(floor, wall)) << i;
        EXPECT_FALSE(occ.blocked(wall, floor)) << i;
        EXPECT_FALSE(occ.blocked(Vec3f(0.f, y, z), Vec3f(0.f, 2.f - y, 2.f - z))) << "along the wall " << i;
        EXPECT_FALSE(occ.blocked(floor, Vec3f(2.f - x, 2.f, 2.f - z))) << "floor to ceiling " << i;
    }
}

TEST(DiscOccluder, GridWalkAgreesWithEveryDisc) {
    const Discs room = box_room();
    for (float r : {0.5f * k_s, k_s, 2.f * k_s}) {
        const DiscOccluder occ(room.p, room.n, r);
        int blocked = 0;
        for (size_t i = 0; i < 3000; ++i) {
            // Segments anywhere in and around the room, including ones that leave the grid.
            Vec3f a = random_point(i, 20, -0.5f, 2.5f), b = random_point(i, 30, -0.5f, 2.5f);
            if (i % 5 == 1) b[int(i / 5) % 3] = a[int(i / 5) % 3];                // parallel to a cell plane
            if (i % 5 == 2) b.x = a.x, b.z = a.z;                                 // along one axis
            if (i % 5 == 3) a.y = b.y = 2.f * k_s * float(i % 7) - 0.5f;         // level: d.y = 0
            const bool grid = occ.blocked(a, b);
            ASSERT_EQ(grid, brute_blocked(room, r, a, b)) << "r " << r << " segment " << i;
            blocked += grid;
        }
        EXPECT_GT(blocked, 300) << "the test exercises both answers";
        EXPECT_LT(blocked, 2700);
    }
}

// The answer is a function of the discs alone (the grid only accelerates): a quarter turn, a mirror
// and a unit ×10 of the scene with r ×10 give the same answers, whatever the grid's cells.
TEST(DiscOccluder, FollowsTheSceneUnderSymmetriesAndTheUnit) {
    const Discs room = box_room();
    const DiscOccluder occ(room.p, room.n, k_s);
    auto check = [&](auto map, float scale, const char *what) {
        Discs m = room;
        test::map_points(m.p, m.n, map, scale);
        const DiscOccluder o(m.p, m.n, k_s * scale);
        int same = 0, differ = 0;
        for (size_t i = 0; i < 2000; ++i) {
            const Vec3f a = random_point(i, 40, -0.3f, 2.3f), b = random_point(i, 50, -0.3f, 2.3f);
            // A hit within rounding of a disc's rim or of the end margin may flip: allow two.
            if (occ.blocked(a, b) == o.blocked(map(a) * scale, map(b) * scale)) ++same;
            else ++differ;
        }
        EXPECT_LE(differ, 2) << what << ": " << same << " agree";
    };
    check([](Vec3f q) { return Vec3f(q.z, q.y, -q.x); }, 1.f, "quarter turn");
    check([](Vec3f q) { return Vec3f(-q.x, q.y, q.z); }, 1.f, "mirror");
    check([](Vec3f q) { return q; }, 10.f, "unit x10");
    check([](Vec3f q) { return q; }, 1e-3f, "unit x0.001");
}

TEST(DiscOccluder, BadInputIsAnError) {
    const Discs room = box_room();
    EXPECT_THROW(DiscOccluder({}, {}, 0.1f), Error);
    EXPECT_THROW(DiscOccluder(room.p, {}, 0.1f), Error);
    EXPECT_THROW(DiscOccluder(room.p, room.n, 0.f), Error);
    EXPECT_THROW(DiscOccluder(room.p, room.n, NAN), Error);
    EXPECT_THROW(DiscOccluder(room.p, room.n, 1e-7f), Error) << "too many cells";
    EXPECT_THROW(DiscOccluder(room.p, room.n, 1e-10f), Error) << "more cells per axis than an int holds";
    std::vector<Vec3f> bad = room.p;
    bad[3].y = INFINITY;
    EXPECT_THROW(DiscOccluder(bad, room.n, 0.1f), Error) << "a point not finite";
    EXPECT_FALSE(DiscOccluder().blocked(Vec3f(0.f), Vec3f(1.f))) << "no discs block nothing";
    const DiscOccluder occ(room.p, room.n, k_s);
    EXPECT_FALSE(occ.blocked(Vec3f(1.f), Vec3f(1.f))) << "a zero-length segment";
    EXPECT_FALSE(occ.blocked(Vec3f(NAN), Vec3f(1.f))) << "NaN is never a hit";
}

// A ray meets a disc from either side (the open share counts any surface it reaches), not one it
// runs along, and not its own surface at its origin; the grid walk agrees with testing every disc.
TEST(DiscOccluder, RaysMeetDiscsFromEitherSideUntilTheyLeave) {
    const Discs room = box_room();
    const DiscOccluder occ(room.p, room.n, k_s);
    const Vec3f floor(1.f, 0.f, 1.f), up(0, 1, 0);
    EXPECT_TRUE(occ.ray_meets_disc(floor, up)) << "the ceiling, from its front";
    EXPECT_TRUE(occ.ray_meets_disc(Vec3f(1.f, 3.f, 1.f), up * -1.f)) << "the ceiling, from behind";
    EXPECT_FALSE(occ.ray_meets_disc(Vec3f(1.f, 3.f, 1.f), up)) << "above the box: nothing";
    EXPECT_FALSE(occ.ray_meets_disc(Vec3f(1.f, 0.f, 3.f), Vec3f(0, 0, 1))) << "in the floor's plane, leaving the box";
    EXPECT_TRUE(occ.ray_meets_disc(floor, Vec3f(0.3f, 0.01f, 0.f))) << "nearly along the floor: the far wall, not the floor";
    // Against every disc (either side, beyond r/4, not grazing) along the ray to far outside.
    auto brute = [&](Vec3f a, Vec3f d) {
        d = d / length(d);
        for (size_t k = 0; k < room.p.size(); ++k) {
            const float denom = dot(room.n[k], d);
            if (!(std::abs(denom) > 0.05f)) continue;
            const float t = dot(room.n[k], room.p[k] - a) / denom;
            if (!(t > 1e-3f * k_s)) continue;
            const Vec3f q = a + d * t - room.p[k];
            if (dot(q, q) < k_s * k_s) return true;
        }
        return false;
    };
    int met = 0;
    for (size_t i = 0; i < 2000; ++i) {
        const Vec3f a = random_point(i, 40, -1.f, 3.f), d = random_point(i, 50, -1.f, 1.f);
        if (!(length(d) > 0.1f)) continue;
        const bool grid = occ.ray_meets_disc(a, d);
        ASSERT_EQ(grid, brute(a, d)) << "ray " << i;
        met += grid;
    }
    EXPECT_GT(met, 300);
    EXPECT_LT(met, 1900);
}
