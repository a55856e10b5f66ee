// indoor_generator.h: the procedural indoor scene generator (`ltm gen`): floor plan, watertight
// room shell, furniture, ceiling area lights and a camera, deterministic in (config, seed).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "ltm/procgen/floor_plan.h"
#include "ltm/procgen/gen_config.h"
#include "ltm/scene/scene.h"

namespace ltm {

/// Bumped whenever the same (config, seed) would produce a different scene.
inline constexpr int k_indoor_generator_version = 1;

struct RoomInfo {
    int id = -1;
    std::string kind;              ///< "room" or "hallway"
    std::string role;              ///< furnishing role: bedroom, living, dining, office, hallway
    std::vector<Rect2f> rects;     ///< interior (air) rectangles on the xz plane, metres
    float ceiling_height = 0.f;    ///< m; the floor is at y = 0
    float floor_area = 0.f;        ///< m²
    std::vector<int> shell_meshes; ///< floor, ceiling, walls: indices into scene.meshes
};

struct DoorInfo {
    int room_a = -1, room_b = -1;
    Vec2f p0, p1;          ///< door segment on the wall's centre line (xz)
    Rect2f opening;        ///< the hole through the wall (xz), wall thickness deep
    float width = 0.f, height = 0.f;
};

struct FurnitureInfo {
    std::string archetype;
    std::string name;      ///< "bed3": its meshes are "bed3_<slot>"
    int room = -1;
    Bounds3f bounds;       ///< world AABB of its vertices
    std::vector<int> meshes;
};

struct LightInfo {
    int room = -1;
    std::array<Vec3f, 4> corners;   ///< world, wound so the normal is -y
    Vec3f radiance;                 ///< W/m²/sr (linear RGB)
    float temperature_k = 0.f;
    float power = 0.f;              ///< π·L·A, luminance-weighted W
    int mesh = -1;
};

/// A window through an outside wall (GenConfig::Fixtures).
struct WindowInfo {
    int room = -1;
    int opening = -1;      ///< index into the plan's openings
    Rect2f hole;           ///< plan rectangle of the opening, from the inner wall face outward
    float sill = 0.f, top = 0.f;   ///< m
    Vec3f outward;         ///< unit axis out of the room
    bool sky = false;      ///< the pane emits (daylight); else the window opens onto nothing
    Vec3f radiance;        ///< sky radiance (W/m²/sr) when sky
    float power = 0.f;     ///< π·L·A of the pane (luminance-weighted W)
    int pane_mesh = -1;    ///< the emitting pane's mesh (sky windows)
    std::vector<Rect2f> curtains;   ///< plan footprints of its curtain panels (furniture keeps out)
};

/// An emitter the fixtures add: a lamp's bulb, a sconce or a light strip.
struct FixtureLightInfo {
    int room = -1;
    std::string kind;      ///< "floor_lamp", "table_lamp", "sconce", "strip"
    Vec3f radiance;        ///< W/m²/sr
    float power = 0.f;     ///< luminance-weighted W
    int mesh = -1;
};

struct GeneratedScene {
    Scene scene;   ///< metadata: generator, generator_version, seed, plan_type, n_rooms, ajar, ..., config
    std::string plan_type;
    std::vector<RoomInfo> rooms;
    std::vector<DoorInfo> doors;
    std::vector<FurnitureInfo> furniture;
    std::vector<LightInfo> lights;   ///< ceiling lights that are on
    std::vector<WindowInfo> windows;
    std::vector<FixtureLightInfo> fixture_lights;
    bool ajar = false;    ///< all lights in one sparsely furnished room; the rest is lit via doors
};

/// Generates one scene. Single-threaded and a pure function of (cfg, seed): every coordinate is
/// on a 1e-4 m grid and every colour on a 1e-4 grid, so the output is byte-identical anywhere.
GeneratedScene generate_indoor(const GenConfig &cfg, uint64_t seed);

}  // namespace ltm
