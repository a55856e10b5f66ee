// fixtures_test.cpp: windows, recesses, lamps, sconces, strips and curtains (procgen/fixtures.h):
// the shell stays closed with panes in, windows open only onto the outside, every emitter's
// power is π·L·A as drawn, nothing meets furniture, and turning fixtures on leaves the plan alone.
#include <map>
#include <set>
#include <tuple>

#include <gtest/gtest.h>

#include "ltm/core/color.h"
#include "ltm/core/json_util.h"
#include "ltm/procgen/indoor_generator.h"
#include "ltm/scene/scene.h"
#include "ltm/scene/scene_json.h"

using namespace ltm;

namespace {

constexpr int k_n_seeds = 40;

/// Every fixture on, every window a sky (so the shell with its panes is closed).
GenConfig all_on(float p_sky = 1.f) {
    GenConfig c;
    c.fixtures.p_windows = 1.f;
    c.fixtures.p_window_sky = p_sky;
    c.fixtures.p_curtains = 1.f;
    c.fixtures.p_recessed = 0.5f;
    c.fixtures.p_lamp_lit = 1.f;
    c.fixtures.p_table_lamp = 1.f;
    c.fixtures.p_sconces = 1.f;
    c.fixtures.p_strip = 1.f;
    c.fixtures.p_ceiling_off = 0.5f;
    c.furniture.archetypes["floor_lamp"].weight = 3.f;
    return c;
}

const std::vector<GeneratedScene> &fixture_scenes() {
    static const std::vector<GeneratedScene> v = [] {
        std::vector<GeneratedScene> s;
        for (uint64_t seed = 0; seed < uint64_t(k_n_seeds); ++seed) s.push_back(generate_indoor(all_on(), seed));
        return s;
    }();
    return v;
}

double mesh_area(const TriangleMesh &m) {
    double a = 0.0;
    for (size_t t = 0; t < m.n_triangles(); ++t) a += 0.5 * double(length(m.cross_normal(t)));
    return a;
}

/// π·lum(L)·A of an emitting mesh (W, luminance-weighted).
double emitted_power(const Scene &scene, int mesh) {
    const TriangleMesh &m = scene.meshes[size_t(mesh)];
    const Material &mat = scene.materials[size_t(m.material)];
    return double(k_pi) * double(luminance(mat.emission.color_a)) * mesh_area(m);
}

bool plan_overlap(const Rect2f &a, const Rect2f &b) { return a.overlaps(b); }

}  // namespace

TEST(Fixtures, ScenesAreValidAndEveryFeatureAppears) {
    int windows = 0, sky = 0, curtains = 0, lights_off = 0;
    std::set<std::string> kinds;
    for (int i = 0; i < k_n_seeds; ++i) {
        const GeneratedScene &g = fixture_scenes()[size_t(i)];
        const std::string where = "seed " + std::to_string(i);
        EXPECT_NO_THROW(validate_scene(g.scene, where));
        std::set<std::string> names;
        for (const TriangleMesh &m : g.scene.meshes) EXPECT_TRUE(names.insert(m.name).second) << where << ": duplicate mesh " << m.name;
        windows += int(g.windows.size());
        for (const WindowInfo &w : g.windows) sky += w.sky, curtains += int(w.curtains.size());
        for (const FixtureLightInfo &f : g.fixture_lights) kinds.insert(f.kind);
        bool any_emitter = false;
        for (const Material &m : g.scene.materials) any_emitter |= m.is_emissive();
        EXPECT_TRUE(any_emitter) << where;
        // Ceiling lights switched off keep their panel (a "light" mesh without emission).
        for (const TriangleMesh &m : g.scene.meshes)
            lights_off += m.name.rfind("light", 0) == 0 && !g.scene.materials[size_t(m.material)].is_emissive();
    }
    EXPECT_GT(windows, k_n_seeds);   // at least one per house on average
    EXPECT_EQ(sky, windows);         // p_window_sky = 1
    EXPECT_GT(curtains, windows);
    EXPECT_EQ(kinds.size(), 4u) << "floor_lamp, table_lamp, sconce and strip should all occur in " << k_n_seeds << " houses";
    EXPECT_GT(lights_off, 0);
}

// Each window's hole leaves its room through one face and meets no other air: no room, door or
// window within its depth plus a wall's thickness.
TEST(Fixtures, WindowsOpenOnlyOntoTheOutside) {
    for (int i = 0; i < k_n_seeds; ++i) {
        const GeneratedScene &g = fixture_scenes()[size_t(i)];
        const float wall = GenConfig().walls.thickness;
        for (size_t k = 0; k < g.windows.size(); ++k) {
            const WindowInfo &w = g.windows[k];
            const std::string where = "seed " + std::to_string(i) + " window " + std::to_string(k);
            EXPECT_GT(w.top - w.sill, 0.29f) << where;
            EXPECT_LE(w.top, g.rooms[size_t(w.room)].ceiling_height - 0.1f + 1e-4f) << where;
            // Grown by a wall along the outward axis (minus the touching face), it meets no air.
            Rect2f beyond = w.hole;
            if (w.outward.x > 0) beyond.x0 += 0.001f, beyond.x1 += wall;
            if (w.outward.x < 0) beyond.x1 -= 0.001f, beyond.x0 -= wall;
            if (w.outward.z > 0) beyond.z0 += 0.001f, beyond.z1 += wall;
            if (w.outward.z < 0) beyond.z1 -= 0.001f, beyond.z0 -= wall;
            for (const RoomInfo &r : g.rooms)
                for (const Rect2f &q : r.rects) EXPECT_FALSE(plan_overlap(beyond, q)) << where << " opens into room " << r.id;
            for (const DoorInfo &d : g.doors) EXPECT_FALSE(plan_overlap(beyond, d.opening)) << where;
            for (size_t o = 0; o < g.windows.size(); ++o)
                if (o != k) {
                    EXPECT_FALSE(plan_overlap(w.hole, g.windows[o].hole)) << where;
                }
            // Its inner face touches its own room: the hole grown back by 1 mm enters the room.
            Rect2f inner = w.hole;
            if (w.outward.x > 0) inner.x0 -= 0.001f;
            if (w.outward.x < 0) inner.x1 += 0.001f;
            if (w.outward.z > 0) inner.z0 -= 0.001f;
            if (w.outward.z < 0) inner.z1 += 0.001f;
            bool touches = false;
            for (const Rect2f &q : g.rooms[size_t(w.room)].rects) touches |= plan_overlap(inner, q);
            EXPECT_TRUE(touches) << where;
        }
    }
}

// With every window a sky, each room's shell plus its panes is still closed and consistently
// oriented (recesses included): every directed edge once, its reverse once.
TEST(Fixtures, ShellWithPanesAndRecessesIsWatertight) {
    using Key = std::tuple<int64_t, int64_t, int64_t>;
    auto key = [](Vec3f p) { return Key{std::llround(double(p.x) * 1e4), std::llround(double(p.y) * 1e4), std::llround(double(p.z) * 1e4)}; };
    int recessed = 0;
    for (int i = 0; i < k_n_seeds; ++i) {
        const GeneratedScene &g = fixture_scenes()[size_t(i)];
        std::vector<int> meshes;
        for (const RoomInfo &room : g.rooms) meshes.insert(meshes.end(), room.shell_meshes.begin(), room.shell_meshes.end());
        for (const WindowInfo &w : g.windows) meshes.push_back(w.pane_mesh);
        std::map<std::pair<Key, Key>, int> edges;
        for (int mi : meshes) {
            ASSERT_GE(mi, 0);
            const TriangleMesh &m = g.scene.meshes[size_t(mi)];
            for (size_t t = 0; t < m.n_triangles(); ++t)
                for (int k = 0; k < 3; ++k) ++edges[{key(m.vertex(t, k)), key(m.vertex(t, (k + 1) % 3))}];
        }
        int bad = 0;
        for (const auto &[e, count] : edges) {
            const auto rev = edges.find({e.second, e.first});
            if (count != 1 || rev == edges.end() || rev->second != 1) ++bad;
        }
        EXPECT_EQ(bad, 0) << "seed " << i;
        for (const RoomInfo &room : g.rooms)
            for (const LightInfo &l : g.lights) recessed += l.room == room.id && l.corners[0].y > room.ceiling_height;
    }
    EXPECT_GT(recessed, 0);
}

// Every emitter's π·lum(L)·A is the power it was drawn with; a pane faces into its room.
TEST(Fixtures, EmittersCarryTheirDrawnPower) {
    const GenConfig cfg = all_on();
    for (int i = 0; i < k_n_seeds; ++i) {
        const GeneratedScene &g = fixture_scenes()[size_t(i)];
        const std::string where = "seed " + std::to_string(i);
        for (const FixtureLightInfo &f : g.fixture_lights) {
            EXPECT_NEAR(emitted_power(g.scene, f.mesh), f.power, 0.01 * f.power) << where << ": " << f.kind;
            const Vec2f range = f.kind == "sconce" ? cfg.fixtures.sconce_power : cfg.fixtures.lamp_power;
            if (f.kind != "strip") {
                EXPECT_GE(f.power, range.x * 0.999f) << where << ": " << f.kind;
                EXPECT_LE(f.power, range.y * 1.001f) << where << ": " << f.kind;
            }
        }
        for (const WindowInfo &w : g.windows) {
            EXPECT_NEAR(emitted_power(g.scene, w.pane_mesh), w.power, 0.01 * w.power) << where;
            const TriangleMesh &pane = g.scene.meshes[size_t(w.pane_mesh)];
            for (size_t t = 0; t < pane.n_triangles(); ++t) EXPECT_LT(dot(pane.cross_normal(t), w.outward), 0.f) << where;
        }
    }
}

// Curtains, lamps on tables, sconces and strips meet no furniture; wall pieces stay in their room.
TEST(Fixtures, NothingMeetsTheFurniture) {
    for (int i = 0; i < k_n_seeds; ++i) {
        const GeneratedScene &g = fixture_scenes()[size_t(i)];
        const std::string where = "seed " + std::to_string(i);
        for (const WindowInfo &w : g.windows)
            for (const Rect2f &c : w.curtains)
                for (const FurnitureInfo &f : g.furniture)
                    EXPECT_FALSE(plan_overlap(c, Rect2f{f.bounds.lo.x, f.bounds.lo.z, f.bounds.hi.x, f.bounds.hi.z}))
                        << where << ": a curtain meets " << f.name;
        for (const FixtureLightInfo &l : g.fixture_lights) {
            if (l.kind != "sconce" && l.kind != "strip") continue;
            Bounds3f b;
            for (const Vec3f &p : g.scene.meshes[size_t(l.mesh)].positions) b.expand(p);
            for (const FurnitureInfo &f : g.furniture) {
                bool overlap = true;
                for (int k = 0; k < 3; ++k) overlap &= b.lo[k] < f.bounds.hi[k] && f.bounds.lo[k] < b.hi[k];
                EXPECT_FALSE(overlap) << where << ": a " << l.kind << " meets " << f.name;
            }
            EXPECT_LT(b.hi.y, g.rooms[size_t(l.room)].ceiling_height) << where;
        }
    }
}

// Fixtures add to the seed's house: its plan (rooms, doors) is the default house's; with every
// chance 0 (whatever the other fixture settings) the scene is the default scene exactly.
TEST(Fixtures, TheSeedsPlanStaysAndZeroChancesChangeNothing) {
    GenConfig zero;
    zero.fixtures.window_width = {1.f, 1.5f}, zero.fixtures.lamp_power = {1.f, 2.f}, zero.fixtures.sky_power = {5.f, 6.f};
    auto text = [](const Scene &s) {
        OrderedJson j = scene_to_json(s);
        j.erase("metadata");   // holds the config, which differs on purpose
        return dump_json_compact(j);
    };
    for (int i = 0; i < 10; ++i) {
        const GeneratedScene base = generate_indoor(GenConfig(), uint64_t(i));
        GenConfig on = all_on();
        on.furniture.archetypes = GenConfig().furniture.archetypes;
        const GeneratedScene with = generate_indoor(on, uint64_t(i));
        ASSERT_EQ(base.rooms.size(), with.rooms.size());
        for (size_t r = 0; r < base.rooms.size(); ++r) {
            ASSERT_EQ(base.rooms[r].rects.size(), with.rooms[r].rects.size());
            for (size_t k = 0; k < base.rooms[r].rects.size(); ++k) EXPECT_EQ(base.rooms[r].rects[k].area(), with.rooms[r].rects[k].area());
        }
        EXPECT_EQ(base.doors.size(), with.doors.size());
        EXPECT_NE(text(base.scene), text(with.scene));
        EXPECT_EQ(text(base.scene), text(generate_indoor(zero, uint64_t(i)).scene)) << "seed " << i;
    }
}
