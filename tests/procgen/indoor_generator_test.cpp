// indoor_generator_test.cpp: properties every generated scene must have (validity, watertight
// shell, no interpenetration, lights on the ceiling, connectivity, camera), checked over many
// seeds, plus determinism and the statistics of the config's probabilities.
#include "ltm/procgen/indoor_generator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include "ltm/core/json_util.h"
#include "ltm/scene/material.h"
#include "ltm/scene/scene_json.h"

namespace ltm {
namespace {

constexpr float k_eps = 1e-4f;
constexpr int k_n_seeds = 100;   // all of default_scenes()

// Generated once, shared by the property tests.
const std::vector<GeneratedScene> &default_scenes() {
    static const std::vector<GeneratedScene> scenes = [] {
        std::vector<GeneratedScene> v;
        for (uint64_t seed = 0; seed < uint64_t(k_n_seeds); ++seed) v.push_back(generate_indoor(GenConfig(), seed));
        return v;
    }();
    return scenes;
}

std::string scene_text(const Scene &s) { return dump_json_compact(scene_to_json(s)); }

bool inside_some(const std::vector<Rect2f> &rects, const Rect2f &r, float inset = 0.f) {
    for (const Rect2f &q : rects)
        if (q.expanded(-inset).contains(r, k_eps)) return true;
    return false;
}
Rect2f plan_rect(const Bounds3f &b) { return {b.lo.x, b.lo.z, b.hi.x, b.hi.z}; }
bool boxes_overlap(const Bounds3f &a, const Bounds3f &b) {   // touching within 1e-4 is allowed
    for (int k = 0; k < 3; ++k)
        if (a.lo[k] >= b.hi[k] - k_eps || b.lo[k] >= a.hi[k] - k_eps) return false;
    return true;
}
bool rects_overlap(const Rect2f &a, const Rect2f &b) { return a.expanded(-k_eps).overlaps(b); }

TEST(IndoorGenerator, SameSeedGivesByteIdenticalSceneJson) {
    const GenConfig cfg;
    for (uint64_t seed : {0ull, 7ull, 123456789ull}) {
        const std::string a = scene_text(generate_indoor(cfg, seed).scene);
        const std::string b = scene_text(generate_indoor(cfg, seed).scene);
        EXPECT_EQ(a, b) << "seed " << seed;
    }
    EXPECT_NE(scene_text(generate_indoor(cfg, 1).scene), scene_text(generate_indoor(cfg, 2).scene));
}

TEST(IndoorGenerator, ScenesAreValidWithUniqueNames) {
    for (int i = 0; i < k_n_seeds; ++i) {
        const GeneratedScene &g = default_scenes()[size_t(i)];
        const std::string where = "seed " + std::to_string(i);
        EXPECT_NO_THROW(validate_scene(g.scene, where)) << where;
        std::set<std::string> meshes, materials;
        for (const TriangleMesh &m : g.scene.meshes) {
            EXPECT_TRUE(meshes.insert(m.name).second) << where << ": duplicate mesh " << m.name;
            EXPECT_GT(m.n_triangles(), 0u) << where << ": " << m.name;
        }
        for (const Material &m : g.scene.materials)
            EXPECT_TRUE(materials.insert(m.name).second) << where << ": duplicate material " << m.name;
        ASSERT_EQ(g.scene.cameras.size(), 1u);
        EXPECT_EQ(g.scene.cameras[0].name, "main");
        EXPECT_EQ(g.scene.cameras[0].width, 512);
        for (const Material &m : g.scene.materials)   // physically plausible albedo
            EXPECT_LE(max_component(m.albedo.max_value()), 0.85f + k_eps) << where << ": " << m.name;
    }
}

TEST(IndoorGenerator, RoomShellIsWatertightWithConsistentOrientation) {
    // Each directed edge (on quantised positions) must appear once and its reverse once: a
    // closed, consistently oriented 2-manifold without T-junctions.
    using Key = std::tuple<int64_t, int64_t, int64_t>;
    auto key = [](Vec3f p) {
        return Key{std::llround(double(p.x) * 1e4), std::llround(double(p.y) * 1e4), std::llround(double(p.z) * 1e4)};
    };
    for (int i = 0; i < k_n_seeds; ++i) {
        const GeneratedScene &g = default_scenes()[size_t(i)];
        std::map<std::pair<Key, Key>, int> edges;
        for (const RoomInfo &room : g.rooms) {
            ASSERT_EQ(room.shell_meshes.size(), 3u);
            for (int mi : room.shell_meshes) {
                const TriangleMesh &m = g.scene.meshes[size_t(mi)];
                for (size_t t = 0; t < m.n_triangles(); ++t)
                    for (int k = 0; k < 3; ++k) ++edges[{key(m.vertex(t, k)), key(m.vertex(t, (k + 1) % 3))}];
            }
        }
        ASSERT_FALSE(edges.empty());
        int bad = 0;
        for (const auto &[e, count] : edges) {
            const auto rev = edges.find({e.second, e.first});
            if (count != 1 || rev == edges.end() || rev->second != 1) ++bad;
        }
        EXPECT_EQ(bad, 0) << "seed " << i << " (" << g.plan_type << "): " << bad << " of " << edges.size()
                          << " directed edges are unmatched";
    }
}

TEST(IndoorGenerator, FloorsFaceUpCeilingsFaceDownAndLightsFaceDown) {
    for (int i = 0; i < k_n_seeds; ++i) {
        const GeneratedScene &g = default_scenes()[size_t(i)];
        for (const RoomInfo &room : g.rooms) {
            const TriangleMesh &floor = g.scene.meshes[size_t(room.shell_meshes[0])];
            const TriangleMesh &ceiling = g.scene.meshes[size_t(room.shell_meshes[1])];
            for (size_t t = 0; t < floor.n_triangles(); ++t)
                if (floor.vertex(t, 0).y < 1e-6f) {
                    EXPECT_GT(floor.cross_normal(t).y, 0.f);
                }
            for (size_t t = 0; t < ceiling.n_triangles(); ++t) EXPECT_LT(ceiling.cross_normal(t).y, 0.f);
        }
        for (const LightInfo &l : g.lights) {
            const TriangleMesh &m = g.scene.meshes[size_t(l.mesh)];
            for (size_t t = 0; t < m.n_triangles(); ++t) EXPECT_LT(m.cross_normal(t).y, 0.f) << m.name;
        }
    }
}

TEST(IndoorGenerator, FurnitureDoesNotInterpenetrateAndStaysInItsRoomClearOfDoors) {
    const GenConfig cfg;
    for (int i = 0; i < k_n_seeds; ++i) {
        const GeneratedScene &g = default_scenes()[size_t(i)];
        const std::string where = "seed " + std::to_string(i);
        for (size_t a = 0; a < g.furniture.size(); ++a) {
            const FurnitureInfo &fa = g.furniture[a];
            const RoomInfo &room = g.rooms[size_t(fa.room)];
            EXPECT_TRUE(inside_some(room.rects, plan_rect(fa.bounds))) << where << ": " << fa.name << " leaves its room";
            EXPECT_GE(fa.bounds.lo.y, -k_eps) << where << ": " << fa.name;
            EXPECT_LE(fa.bounds.hi.y, room.ceiling_height) << where << ": " << fa.name;
            for (size_t b = a + 1; b < g.furniture.size(); ++b)
                EXPECT_FALSE(boxes_overlap(fa.bounds, g.furniture[b].bounds))
                    << where << ": " << fa.name << " intersects " << g.furniture[b].name;
            for (const DoorInfo &d : g.doors) {
                // The opening, grown across the wall by the clear depth: nothing may stand there.
                Rect2f zone = d.opening;
                const bool along_x = d.p0.y == d.p1.y;
                (along_x ? zone.z0 : zone.x0) -= cfg.doors.clear_depth;
                (along_x ? zone.z1 : zone.x1) += cfg.doors.clear_depth;
                EXPECT_FALSE(rects_overlap(zone, plan_rect(fa.bounds))) << where << ": " << fa.name << " blocks a door";
            }
        }
    }
}

TEST(IndoorGenerator, LightsAreFlushWithTheCeilingInsideTheirRoomAndAwayFromTallFurniture) {
    const GenConfig cfg;
    for (int i = 0; i < k_n_seeds; ++i) {
        const GeneratedScene &g = default_scenes()[size_t(i)];
        const std::string where = "seed " + std::to_string(i);
        ASSERT_GE(g.lights.size(), 1u) << where;
        std::map<int, int> per_room;
        for (const LightInfo &l : g.lights) {
            const RoomInfo &room = g.rooms[size_t(l.room)];
            ++per_room[l.room];
            const Rect2f r{l.corners[0].x, l.corners[0].z, l.corners[2].x, l.corners[2].z};
            EXPECT_GT(r.area(), 0.f) << where;
            EXPECT_TRUE(inside_some(room.rects, r, cfg.lights.wall_margin)) << where << ": light too close to a wall";
            for (const Vec3f &c : l.corners) EXPECT_NEAR(c.y, room.ceiling_height - 0.001f, 1e-5f) << where;
            EXPECT_GE(l.temperature_k, cfg.lights.temperature.x) << where;
            EXPECT_LE(l.temperature_k, cfg.lights.temperature.y) << where;
            EXPECT_GT(luminance(l.radiance), 0.f) << where;
            const Material &m = g.scene.materials[size_t(g.scene.meshes[size_t(l.mesh)].material)];
            EXPECT_TRUE(m.is_emissive()) << where;
            EXPECT_EQ(m.emission.color_a, l.radiance) << where;
            for (const FurnitureInfo &f : g.furniture) {
                if (f.bounds.hi.y <= cfg.lights.tall_height + k_eps) continue;
                EXPECT_FALSE(rects_overlap(r.expanded(cfg.lights.tall_clearance), plan_rect(f.bounds)))
                    << where << ": light above tall " << f.name;
            }
        }
        for (const auto &[room, n] : per_room) EXPECT_LE(n, cfg.lights.per_room.hi) << where;
    }
}

TEST(IndoorGenerator, LitRoomPowerIsInTheConfiguredRange) {
    // Φ = π·L·A summed over a room's lights equals power_density · lit floor area.
    const GenConfig cfg;
    for (int i = 0; i < k_n_seeds; ++i) {
        const GeneratedScene &g = default_scenes()[size_t(i)];
        std::map<int, double> power;
        for (const LightInfo &l : g.lights) {
            const float area = (l.corners[2].x - l.corners[0].x) * (l.corners[2].z - l.corners[0].z);
            power[l.room] += double(k_pi) * double(luminance(l.radiance)) * double(area);
        }
        float total_area = 0.f;
        for (const RoomInfo &r : g.rooms) total_area += r.floor_area;
        for (const auto &[room, p] : power) {
            const double lit = g.ajar ? total_area : g.rooms[size_t(room)].floor_area;
            EXPECT_GE(p / lit, 0.98 * cfg.lights.power_density.x) << "seed " << i;
            EXPECT_LE(p / lit, 1.02 * cfg.lights.power_density.y) << "seed " << i;
        }
    }
}

TEST(IndoorGenerator, EveryRoomIsReachableThroughDoors) {
    const GenConfig cfg;
    for (int i = 0; i < k_n_seeds; ++i) {
        const GeneratedScene &g = default_scenes()[size_t(i)];
        std::vector<bool> seen(g.rooms.size(), false);
        std::vector<int> queue{0};
        seen[0] = true;
        while (!queue.empty()) {
            const int r = queue.back();
            queue.pop_back();
            for (const DoorInfo &d : g.doors) {
                const int other = d.room_a == r ? d.room_b : d.room_b == r ? d.room_a : -1;
                if (other >= 0 && !seen[size_t(other)]) seen[size_t(other)] = true, queue.push_back(other);
            }
        }
        for (size_t r = 0; r < seen.size(); ++r) EXPECT_TRUE(seen[r]) << "seed " << i << ": room " << r;
        for (const DoorInfo &d : g.doors) {
            EXPECT_GE(d.width, cfg.doors.width.x - k_eps);
            EXPECT_LE(d.width, cfg.doors.width.y + k_eps);
            EXPECT_LT(d.height, g.rooms[0].ceiling_height);
            EXPECT_NE(d.room_a, d.room_b);
        }
    }
}

TEST(IndoorGenerator, CameraIsInALitRoomAndNotInsideFurniture) {
    for (int i = 0; i < k_n_seeds; ++i) {
        const GeneratedScene &g = default_scenes()[size_t(i)];
        const Camera &cam = g.scene.cameras.at(0);
        const std::string where = "seed " + std::to_string(i);
        int room = -1;
        for (const RoomInfo &r : g.rooms)
            if (inside_some(r.rects, {cam.eye.x, cam.eye.z, cam.eye.x, cam.eye.z})) room = r.id;
        ASSERT_GE(room, 0) << where << ": eye " << cam.eye << " is in no room";
        EXPECT_GE(cam.eye.y, 1.4f - k_eps) << where;
        EXPECT_LE(cam.eye.y, 1.7f + k_eps) << where;
        for (const FurnitureInfo &f : g.furniture) {
            const Bounds3f &b = f.bounds;
            const bool inside = cam.eye.x > b.lo.x && cam.eye.x < b.hi.x && cam.eye.y > b.lo.y &&
                                cam.eye.y < b.hi.y && cam.eye.z > b.lo.z && cam.eye.z < b.hi.z;
            EXPECT_FALSE(inside) << where << ": eye inside " << f.name;
        }
        bool lit = false;
        for (const LightInfo &l : g.lights) lit |= l.room == room;
        if (!g.ajar) {
            EXPECT_TRUE(lit) << where << ": camera in an unlit room";
        }
    }
}

TEST(IndoorGenerator, SeedsCoverArchetypesPlanTypesTexturesAndSaturatedColours) {
    std::set<std::string> archetypes, plan_types;
    int single = 0, multi = 0, textured = 0, saturated = 0;
    for (int i = 0; i < k_n_seeds; ++i) {
        const GeneratedScene &g = default_scenes()[size_t(i)];
        for (const FurnitureInfo &f : g.furniture) archetypes.insert(f.archetype);
        plan_types.insert(g.plan_type);
        (g.rooms.size() == 1 ? single : multi)++;
        for (const Material &m : g.scene.materials) {
            textured += !m.albedo.is_constant();
            const Vec3f c = m.albedo.color_a;
            const float lo = std::min(c.x, std::min(c.y, c.z)), hi = max_component(c);
            saturated += hi > 0.3f && lo < 0.25f * hi;
        }
    }
    EXPECT_GE(archetypes.size(), 8u);
    EXPECT_GE(plan_types.size(), 4u);
    EXPECT_GT(single, 0);
    EXPECT_GT(multi, 0);
    EXPECT_GT(textured, k_n_seeds);   // more than one textured surface per scene on average
    EXPECT_GT(saturated, k_n_seeds / 2);
}

TEST(IndoorGenerator, AjarFractionMatchesTheConfiguredProbability) {
    const GenConfig cfg;
    int eligible = 0, ajar = 0;
    for (const GeneratedScene &g : default_scenes()) {
        if (g.rooms.size() < 2) {
            EXPECT_FALSE(g.ajar);
            continue;
        }
        ++eligible;
        if (!g.ajar) continue;
        ++ajar;
        std::set<int> lit;
        for (const LightInfo &l : g.lights) lit.insert(l.room);
        ASSERT_EQ(lit.size(), 1u);
        int in_lit_room = 0;
        for (const FurnitureInfo &f : g.furniture) in_lit_room += f.room == *lit.begin();
        EXPECT_LE(in_lit_room, cfg.furniture.ajar_light_room_max_items);
        EXPECT_TRUE(g.scene.metadata.at("ajar").get<bool>());
    }
    const double p = cfg.lights.p_ajar, mean = p * eligible, sd = std::sqrt(eligible * p * (1 - p));
    EXPECT_GT(eligible, 30);
    EXPECT_NEAR(double(ajar), mean, 4.0 * sd + 1.0) << ajar << " ajar of " << eligible;
}

TEST(IndoorGenerator, AjarProbabilityOneMakesEveryMultiRoomSceneAjar) {
    GenConfig cfg;
    cfg.lights.p_ajar = 1.f;
    cfg.plan.weight_single = cfg.plan.weight_l_room = 0.f;
    for (uint64_t seed = 0; seed < 10; ++seed) {
        const GeneratedScene g = generate_indoor(cfg, seed);
        ASSERT_GE(g.rooms.size(), 2u);
        EXPECT_TRUE(g.ajar);
    }
}

// Glossy scenes (paper §7): with the chances at 1, every listed archetype and every room's walls
// are GGX conductors with α in range and a named metal's F0 (also their scene-point albedo); the
// geometry, lights and cameras are the default scene's, and the default config draws no conductor.
TEST(IndoorGenerator, GlossyConductorsChangeMaterialsOnly) {
    GenConfig glossy;
    glossy.glossy.p_conductor = 1.f, glossy.glossy.p_walls = 1.f;
    glossy.glossy.roughness = {0.05f, 0.2f};
    glossy.glossy.metals = {"Au", "Cu"};
    int conductors = 0, listed = 0;
    for (uint64_t seed = 0; seed < 12; ++seed) {
        const GeneratedScene &plain = default_scenes()[seed];
        const GeneratedScene g = generate_indoor(glossy, seed);
        ASSERT_EQ(g.scene.meshes.size(), plain.scene.meshes.size());
        for (size_t m = 0; m < g.scene.meshes.size(); ++m) EXPECT_EQ(g.scene.meshes[m].positions, plain.scene.meshes[m].positions);
        EXPECT_EQ(g.scene.cameras[0].eye, plain.scene.cameras[0].eye);
        for (const Material &mat : plain.scene.materials) EXPECT_EQ(mat.bsdf, BsdfKind::diffuse);
        auto is_conductor = [&](int mesh) {
            const Material &mat = g.scene.materials[size_t(g.scene.meshes[size_t(mesh)].material)];
            if (mat.bsdf != BsdfKind::conductor) return false;
            EXPECT_GE(mat.roughness, 0.05f);
            EXPECT_LE(mat.roughness, 0.2f);
            EXPECT_TRUE(mat.specular == named_metal_f0().at("Au") || mat.specular == named_metal_f0().at("Cu"));
            EXPECT_TRUE(mat.albedo.is_constant() && mat.albedo.color_a == mat.specular);
            return true;
        };
        for (const RoomInfo &r : g.rooms) {
            EXPECT_TRUE(is_conductor(r.shell_meshes[2])) << "walls";
            EXPECT_FALSE(is_conductor(r.shell_meshes[0])) << "floor";
        }
        for (const FurnitureInfo &f : g.furniture) {
            const bool in_list = std::find(glossy.glossy.archetypes.begin(), glossy.glossy.archetypes.end(), f.archetype) !=
                                 glossy.glossy.archetypes.end();
            listed += in_list;
            for (int m : f.meshes) {
                const bool c = is_conductor(m);
                EXPECT_EQ(c, in_list) << f.name;
                conductors += c;
            }
        }
        for (const LightInfo &l : g.lights) EXPECT_FALSE(is_conductor(l.mesh));
    }
    EXPECT_GT(listed, 10);
    EXPECT_GT(conductors, listed);   // every part of a listed piece
    // A chance of 0.5: about half the listed pieces, decided per piece.
    glossy.glossy.p_conductor = 0.5f, glossy.glossy.p_walls = 0.f;
    int half = 0, pieces = 0;
    for (uint64_t seed = 0; seed < 40; ++seed) {
        const GeneratedScene g = generate_indoor(glossy, seed);
        for (const FurnitureInfo &f : g.furniture)
            if (std::find(glossy.glossy.archetypes.begin(), glossy.glossy.archetypes.end(), f.archetype) != glossy.glossy.archetypes.end()) {
                ++pieces;
                half += g.scene.materials[size_t(g.scene.meshes[size_t(f.meshes[0])].material)].bsdf == BsdfKind::conductor;
            }
    }
    EXPECT_NEAR(double(half) / pieces, 0.5, 4.0 * std::sqrt(0.25 / pieces)) << pieces << " pieces";
}

// Bright houses (GenConfig::Textures::p_bright_house) lift the diffuse albedos of the seed's own
// house toward their hue at 0.85 and change nothing else; the default config writes no new key.
TEST(IndoorGenerator, BrightHousesLiftAlbedoOnlyAndDefaultsStayAsTheyWere) {
    EXPECT_FALSE(GenConfig{}.to_json()["textures"].contains("p_bright_house")) << "default houses keep their JSON";
    GenConfig bright;
    bright.textures.p_bright_house = 1.f;
    bright.textures.bright_lift = {0.5f, 0.5f};
    const auto mean_albedo = [](const Scene &s) {
        double sum = 0;
        int n = 0;
        for (const Material &m : s.materials)
            if (m.bsdf == BsdfKind::diffuse && !m.is_emissive()) sum += (m.albedo.color_a.x + m.albedo.color_a.y + m.albedo.color_a.z) / 3.0, ++n;
        return sum / n;
    };
    for (uint64_t seed = 0; seed < 6; ++seed) {
        const GeneratedScene &plain = default_scenes()[seed];
        const GeneratedScene g = generate_indoor(bright, seed);
        EXPECT_FALSE(plain.scene.metadata.contains("bright_lift"));
        EXPECT_FLOAT_EQ(g.scene.metadata.at("bright_lift").get<float>(), 0.5f);
        ASSERT_EQ(g.scene.meshes.size(), plain.scene.meshes.size());
        ASSERT_EQ(g.scene.materials.size(), plain.scene.materials.size());
        for (size_t m = 0; m < g.scene.meshes.size(); ++m) EXPECT_EQ(g.scene.meshes[m].positions, plain.scene.meshes[m].positions);
        for (size_t i = 0; i < g.scene.materials.size(); ++i) {
            const Material &a = plain.scene.materials[i], &b = g.scene.materials[i];
            EXPECT_EQ(a.emission.color_a, b.emission.color_a);
            if (a.is_emissive()) {
                EXPECT_EQ(a.albedo.color_a, b.albedo.color_a) << "light diffusers keep their albedo";
                continue;
            }
            // Halfway to the hue at 0.85: the brightest channel is (m + 0.85) / 2, the hue unchanged.
            const Vec3f c = a.albedo.color_a, d = b.albedo.color_a;
            const float m = max_component(c);
            EXPECT_NEAR(max_component(d), 0.5f * (m + 0.85f), 2e-4f) << a.name;
            if (m > 0.05f) EXPECT_NEAR(d.x / max_component(d), c.x / m, 2e-3f) << a.name;
            EXPECT_LE(max_component(d), 0.85f + 1e-4f);
        }
        EXPECT_GT(mean_albedo(g.scene), mean_albedo(plain.scene) + 0.1) << seed;
    }
}

TEST(IndoorGenerator, MetadataRecordsGeneratorSeedAndConfig) {
    GenConfig cfg;
    cfg.camera.width = 64;
    const GeneratedScene g = generate_indoor(cfg, 42);
    const OrderedJson &md = g.scene.metadata;
    EXPECT_EQ(md.at("generator"), "ltm-indoor");
    EXPECT_EQ(md.at("generator_version"), k_indoor_generator_version);
    EXPECT_EQ(md.at("seed").get<uint64_t>(), 42u);
    EXPECT_EQ(md.at("n_rooms").get<size_t>(), g.rooms.size());
    EXPECT_EQ(md.at("config"), cfg.to_json());
    EXPECT_EQ(g.scene.cameras.at(0).width, 64);
}

}  // namespace
}  // namespace ltm
