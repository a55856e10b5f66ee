// gen_config.h: every range and probability of the procedural indoor generator, with its
// documented default. configs/gen/indoor.json is the default config written out in full.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "ltm/core/config_fields.h"
#include "ltm/core/json_util.h"
#include "ltm/core/math.h"

namespace ltm {

/// Size ranges of one furniture archetype, in its local frame: width along the wall it backs
/// onto (x), depth away from the wall (z), height (y). Metres.
struct ArchetypeRanges {
    float weight = 1.f;   ///< relative frequency among the archetypes a room role allows
    Vec2f width{1.f, 1.f};
    Vec2f depth{1.f, 1.f};
    Vec2f height{1.f, 1.f};
};

/// The archetypes the generator knows, with realistic default sizes (keys: furniture.h).
std::map<std::string, ArchetypeRanges> default_archetypes();

struct GenConfig {
    struct Plan {
        /// Keys, limits and docs (core/config_fields.h; the table in docs/config.md).
        static const ConfigFields<Plan> &fields();
        float weight_single = 0.25f;    ///< relative frequency: one rectangular room
        float weight_l_room = 0.15f;    ///< one L-shaped room
        float weight_bsp = 0.3f;        ///< rectangle split into rooms by binary space partition
        float weight_hallway = 0.15f;   ///< hallway strip with rooms along one or both sides
        float weight_l_split = 0.15f;   ///< L-shaped footprint split into rooms
        Vec2f footprint_size{6.f, 11.f};     ///< sides of a multi-room footprint (m)
        IntRange n_rooms{2, 5};              ///< target room count of BSP plans
        Vec2f split_fraction{0.35f, 0.65f};  ///< BSP cut position as a fraction of the side
        Vec2f l_cut_fraction{0.35f, 0.6f};   ///< fraction of each side the L's notch removes
        Vec2f hallway_width{1.1f, 1.6f};     ///< m
        IntRange hallway_rooms_per_side{1, 3};
        float p_hallway_two_sided = 0.5f;    ///< rooms on both sides of the hallway
        float snap = 0.05f;                  ///< every plan coordinate is a multiple of this (m)
        int max_attempts = 20;               ///< plan retries before falling back to one room
    } plan;

    struct Rooms {
        /// Keys, limits and docs (core/config_fields.h; the table in docs/config.md).
        static const ConfigFields<Rooms> &fields();
        Vec2f size{2.5f, 7.f};            ///< sides of single rooms and of hallway rooms (m)
        Vec2f l_room_size{4.f, 8.f};      ///< bounding sides of an L-shaped single room (m)
        float min_side = 2.2f;            ///< no partition cell gets a side shorter than this (m)
        Vec2f ceiling_height{2.5f, 3.2f}; ///< m, one height per plan
    } rooms;

    struct Walls {
        /// Keys, limits and docs (core/config_fields.h; the table in docs/config.md).
        static const ConfigFields<Walls> &fields();
        float thickness = 0.1f;   ///< interior wall thickness (m); door openings go through it
    } walls;

    struct Doors {
        /// Keys, limits and docs (core/config_fields.h; the table in docs/config.md).
        static const ConfigFields<Doors> &fields();
        Vec2f width{0.8f, 1.0f};    ///< m
        Vec2f height{2.0f, 2.2f};   ///< m, clamped below the ceiling
        float corner_margin = 0.15f;  ///< min distance from a door to a wall corner (m)
        float p_extra = 0.25f;        ///< chance of a door on each adjacency beyond the tree
        float clear_depth = 0.9f;     ///< furniture-free depth in front of a door, each side (m)
        float clear_side = 0.1f;      ///< furniture-free margin beside the door's width (m)
    } doors;

    struct Furniture {
        /// Keys, limits and docs (core/config_fields.h; the table in docs/config.md).
        static const ConfigFields<Furniture> &fields();
        Vec2f density{0.12f, 0.3f};       ///< items per m² of room floor
        IntRange items_per_room{1, 10};   ///< clamp of the density-derived count
        float hallway_density_scale = 0.3f;  ///< hallways hold fewer items
        float clearance = 0.08f;          ///< min gap between two pieces of furniture (m)
        float wall_gap = 0.01f;           ///< gap between a wall-placed piece and its wall (m)
        float p_carpet = 0.5f;            ///< chance of a carpet per room
        int max_attempts = 60;            ///< placement tries per item
        int ajar_light_room_max_items = 1;  ///< furniture allowed in the lit room of ajar scenes
        std::map<std::string, ArchetypeRanges> archetypes = default_archetypes();
    } furniture;

    struct Textures {
        /// Keys, limits and docs (core/config_fields.h; the table in docs/config.md).
        static const ConfigFields<Textures> &fields();
        float p_floor_wood = 0.45f;        ///< floor gets a wood texture
        float p_floor_tiles = 0.2f;        ///< floor gets checker tiles (else plain)
        float p_wall_pattern = 0.1f;       ///< striped wallpaper
        float p_accent_wall = 0.15f;       ///< saturated wall colour instead of a white/pastel
        float p_carpet_pattern = 0.7f;     ///< carpet stripes or noise (else plain)
        float p_furniture_wood = 0.6f;     ///< wooden parts get a wood texture (else plain)
        float p_fabric_pattern = 0.2f;     ///< fabric stripes or checker (else plain)
        float p_saturated_fabric = 0.4f;   ///< fabric from the saturated palette
        Vec2f wood_scale{0.08f, 0.25f};    ///< wood ring period (m)
        Vec2f tile_scale{0.2f, 0.6f};      ///< checker cell (m)
        Vec2f stripe_scale{0.05f, 0.4f};   ///< stripe pair period (m)
        Vec2f noise_scale{0.1f, 0.5f};     ///< noise feature size (m)
        float color_jitter = 0.08f;        ///< relative per-object jitter of palette colours
        /// A bright house (issue #29/#30, real rooms): with this probability per house every
        /// diffuse, non-emitting albedo is lifted toward its own hue at 0.85, ρ' = ρ + t·(0.85·ρ/max ρ − ρ),
        /// t ~ U(bright_lift) once per house. White kitchens and living rooms have mean albedos of
        /// 0.71–0.77; the default houses 0.38–0.62. 0 (default): the houses of every seed unchanged.
        float p_bright_house = 0.f;
        Vec2f bright_lift{0.5f, 1.0f};     ///< range of the lift t of a bright house
    } textures;

    struct Lights {
        /// Keys, limits and docs (core/config_fields.h; the table in docs/config.md).
        static const ConfigFields<Lights> &fields();
        IntRange per_room{1, 3};             ///< ceiling lights in each lit room
        Vec2f size{0.3f, 1.2f};              ///< side of a rectangular light (m)
        Vec2f temperature{2700.f, 6500.f};   ///< colour temperature (K)
        /// Emitted power per m² of lit floor (luminance-weighted W/m²): Φ = π·L·A_light, so a
        /// 20 m² room gets 100–400 W.
        Vec2f power_density{5.f, 20.f};
        float wall_margin = 0.4f;      ///< min distance from a light to a wall (m)
        float light_gap = 0.3f;        ///< min distance between two lights (m)
        float tall_height = 1.4f;      ///< furniture taller than this keeps off the lights (m)
        float tall_clearance = 0.3f;   ///< plan gap between a light and tall furniture (m)
        float ceiling_gap = 0.001f;    ///< lights hang this far below the ceiling (m)
        float p_ajar = 0.15f;          ///< all lights in one sparsely furnished room (>= 2 rooms)
        int max_attempts = 50;         ///< placement tries per light
    } lights;

    struct CameraCfg {
        /// Keys, limits and docs (core/config_fields.h; the table in docs/config.md).
        static const ConfigFields<CameraCfg> &fields();
        int width = 512, height = 512;    ///< pixels
        Vec2f fov_y{55.f, 70.f};          ///< vertical field of view (degrees)
        Vec2f eye_height{1.4f, 1.7f};     ///< m
        Vec2f target_height{0.8f, 1.3f};  ///< m
        float wall_margin = 0.5f;         ///< min distance from the eye to a wall (m)
        float furniture_clearance = 0.35f;  ///< preferred plan distance to furniture (m)
        int n_candidates = 24;            ///< eye positions tried; the best one is kept
    } camera;

    /// GGX conductors (paper §7's glossy scenes). Off by default: with both chances 0 the generator
    /// draws nothing for them, so every scene is byte-identical to one generated without this
    /// section. Drawn from their own random streams: turning them on changes materials only,
    /// never geometry, lights or cameras.
    struct Glossy {
        /// Keys, limits and docs (core/config_fields.h; the table in docs/config.md).
        static const ConfigFields<Glossy> &fields();
        float p_conductor = 0.f;   ///< chance that a piece of furniture of `archetypes` is a conductor
        std::vector<std::string> archetypes{"cabinet", "coffee_table", "desk", "nightstand", "shelves", "table", "wardrobe"};
        float p_walls = 0.f;       ///< chance that a room's walls are a conductor
        Vec2f roughness{0.1f, 0.1f};   ///< GGX α, uniform in the range (paper: 0.1)
        std::vector<std::string> metals{"Ag", "Al", "Au", "Cu", "CuZn"};   ///< F0 from one of these (scene/material.h)
    } glossy;

    /// What real rooms have and the default houses do not (issue #29): windows to the outside
    /// with sky light behind them or open to the void, recessed ceiling lights, lamps with open
    /// shades, wall sconces, light strips, curtains. Off by default: with every chance 0 the
    /// generator draws nothing for them, so every seed's house is byte-identical to one generated
    /// without this section (held-out sets keep their meaning). Drawn from their own streams
    /// after the furniture (procgen/fixtures.h).
    struct Fixtures {
        /// Keys, limits and docs (core/config_fields.h; the table in docs/config.md).
        static const ConfigFields<Fixtures> &fields();
        float p_windows = 0.f;            ///< chance that a room (not a hallway) has windows on outside walls
        IntRange windows_per_room{1, 3};  ///< windows tried in such a room
        Vec2f window_width{0.6f, 2.0f};   ///< m, along the wall
        Vec2f window_sill{0.3f, 1.0f};    ///< sill height above the floor (m)
        Vec2f window_top{1.9f, 2.5f};     ///< head height (m), kept 0.1 m below the ceiling
        /// Depth of the opening beyond the room's inner wall face (m): the outside wall's
        /// thickness, thin (a frame) to deep (a stone wall's reveal).
        Vec2f window_depth{0.05f, 0.35f};
        /// Chance that a window's outer end is a sky: an emitter facing the room (daylight behind
        /// the glass, as pbrt scenes light windows); otherwise it opens onto nothing and light escapes.
        float p_window_sky = 0.7f;
        Vec2f sky_temperature{5500.f, 12000.f};   ///< K
        /// Sky power Φ = π·L·A of a window, in units of its room's mean ceiling-light power
        /// (the mid-range of lights.power_density × floor area).
        Vec2f sky_power{0.3f, 3.f};
        float p_curtains = 0.5f;          ///< chance that a window gets pleated curtains at its sides
        float p_recessed = 0.f;           ///< chance that a ceiling light sits in a recess
        Vec2f recess_depth{0.04f, 0.25f}; ///< m above the ceiling
        Vec2f recess_trim{0.f, 0.1f};     ///< recess margin around the light (m)
        float p_lamp_lit = 0.f;           ///< chance that a floor lamp is lit: open shade, bulb inside
        float p_table_lamp = 0.f;         ///< chance of a lit table lamp on a nightstand, desk, cabinet or table
        Vec2f lamp_power{15.f, 80.f};     ///< Φ of a lamp's bulb (luminance-weighted W)
        Vec2f lamp_temperature{2200.f, 3300.f};   ///< K
        float p_sconces = 0.f;            ///< chance that a room has wall sconces (light spilled up the wall)
        IntRange sconces_per_room{1, 4};
        Vec2f sconce_power{10.f, 60.f};   ///< Φ per sconce
        float p_strip = 0.f;              ///< chance that a room has a light strip under its ceiling
        Vec2f strip_power{10.f, 40.f};    ///< Φ per metre of strip
        /// Chance that a room lit by lamps, sconces, strips or a sky window has its ceiling lights
        /// off (evening or daylight). Never leaves a house without an emitter.
        float p_ceiling_off = 0.f;
    } fixtures;

    /// Strict parse: unknown keys and invalid ranges throw "where: /json/pointer: problem".
    /// Missing keys keep their defaults.
    static GenConfig from_json(const Json &j, const std::string &where);
    /// Every key, in a stable order.
    OrderedJson to_json() const;
};

}  // namespace ltm
