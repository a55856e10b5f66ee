// gen_config.cpp: GenConfig declared once per section (core/config_fields.h): keys, limits and
// docs; reading, validation, writing and the docs tables all come from it.
#include "ltm/procgen/gen_config.h"

#include <cstdio>
#include <cstdlib>

#include "ltm/core/error.h"
#include "ltm/scene/material.h"

namespace ltm {

std::map<std::string, ArchetypeRanges> default_archetypes() {
    // Sizes of common IKEA-like pieces; width along the wall, depth away from it.
    auto a = [](float w, Vec2f width, Vec2f depth, Vec2f height) {
        return ArchetypeRanges{w, width, depth, height};
    };
    return {
        {"armchair", a(0.8f, {0.7f, 0.95f}, {0.7f, 0.9f}, {0.75f, 1.0f})},
        {"bed", a(1.f, {0.9f, 1.8f}, {1.95f, 2.2f}, {0.8f, 1.2f})},
        {"cabinet", a(1.f, {0.8f, 1.8f}, {0.4f, 0.5f}, {0.6f, 0.9f})},
        {"carpet", a(1.f, {1.2f, 3.f}, {0.8f, 2.2f}, {0.01f, 0.02f})},
        {"chair", a(1.f, {0.4f, 0.5f}, {0.42f, 0.52f}, {0.8f, 1.f})},
        {"coffee_table", a(1.f, {0.8f, 1.3f}, {0.45f, 0.7f}, {0.35f, 0.48f})},
        {"desk", a(1.f, {1.f, 1.6f}, {0.55f, 0.8f}, {0.72f, 0.78f})},
        {"floor_lamp", a(0.7f, {0.3f, 0.45f}, {0.3f, 0.45f}, {1.4f, 1.8f})},
        {"nightstand", a(1.f, {0.4f, 0.55f}, {0.35f, 0.45f}, {0.45f, 0.6f})},
        {"plant", a(0.8f, {0.3f, 0.55f}, {0.3f, 0.55f}, {0.6f, 1.5f})},
        {"shelves", a(1.f, {0.6f, 1.2f}, {0.25f, 0.4f}, {1.2f, 2.f})},
        {"sofa", a(1.f, {1.6f, 2.4f}, {0.8f, 1.f}, {0.75f, 0.95f})},
        {"table", a(1.f, {1.f, 1.8f}, {0.7f, 1.f}, {0.72f, 0.78f})},
        {"wardrobe", a(1.f, {0.9f, 2.f}, {0.55f, 0.65f}, {1.8f, 2.3f})},
    };
}

namespace {
constexpr float k_big = 1e6f;   // "no practical upper bound" of relative weights
}  // namespace

const ConfigFields<GenConfig::Plan> &GenConfig::Plan::fields() {
    using C = GenConfig::Plan;
    static const ConfigFields<C> f =
        ConfigFields<C>()
            .field("weight_single", &C::weight_single, "relative frequency: one rectangular room", between(0, k_big))
            .field("weight_l_room", &C::weight_l_room, "one L-shaped room", between(0, k_big))
            .field("weight_bsp", &C::weight_bsp, "rectangle split into rooms by binary space partition", between(0, k_big))
            .field("weight_hallway", &C::weight_hallway, "hallway strip with rooms along one or both sides", between(0, k_big))
            .field("weight_l_split", &C::weight_l_split, "L-shaped footprint split into rooms", between(0, k_big))
            .field("footprint_size", &C::footprint_size, "sides of a multi-room footprint (m)", between(1.0, 100.0))
            .field("n_rooms", &C::n_rooms, "target room count of BSP plans", between(2, 64))
            .field("split_fraction", &C::split_fraction, "BSP cut position as a fraction of the side", between(0.05, 0.95))
            .field("l_cut_fraction", &C::l_cut_fraction, "fraction of each side the L's notch removes", between(0.05, 0.95))
            .field("hallway_width", &C::hallway_width, "hallway width (m)", between(0.5, 10.0))
            .field("hallway_rooms_per_side", &C::hallway_rooms_per_side, "rooms on each side of a hallway", between(1, 16))
            .field("p_hallway_two_sided", &C::p_hallway_two_sided, "rooms on both sides of the hallway", between(0, 1))
            .field("snap", &C::snap, "every plan coordinate is a multiple of this (m)", between(0.002, 1.0))
            .field("max_attempts", &C::max_attempts, "plan retries before falling back to one room", between(1, 10000));
    return f;
}

const ConfigFields<GenConfig::Rooms> &GenConfig::Rooms::fields() {
    using C = GenConfig::Rooms;
    static const ConfigFields<C> f =
        ConfigFields<C>()
            .field("size", &C::size, "sides of single rooms and of hallway rooms (m)", between(1.0, 100.0))
            .field("l_room_size", &C::l_room_size, "bounding sides of an L-shaped single room (m)", between(2.0, 100.0))
            .field("min_side", &C::min_side, "no partition cell gets a side shorter than this (m)", between(0.5, 100.0))
            .field("ceiling_height", &C::ceiling_height, "ceiling height (m), one per plan", between(1.0, 20.0));
    return f;
}

const ConfigFields<GenConfig::Walls> &GenConfig::Walls::fields() {
    using C = GenConfig::Walls;
    static const ConfigFields<C> f =
        ConfigFields<C>()
            .field("thickness", &C::thickness, "interior wall thickness (m); door openings go through it", between(0.01, 2.0));
    return f;
}

const ConfigFields<GenConfig::Doors> &GenConfig::Doors::fields() {
    using C = GenConfig::Doors;
    static const ConfigFields<C> f =
        ConfigFields<C>()
            .field("width", &C::width, "door width (m)", between(0.3, 5.0))
            .field("height", &C::height, "door height (m), clamped below the ceiling", between(0.5, 10.0))
            .field("corner_margin", &C::corner_margin, "min distance from a door to a wall corner (m)", between(0.0, 5.0))
            .field("p_extra", &C::p_extra, "chance of a door on each adjacency beyond the tree", between(0, 1))
            .field("clear_depth", &C::clear_depth, "furniture-free depth in front of a door, each side (m)", between(0.0, 10.0))
            .field("clear_side", &C::clear_side, "furniture-free margin beside the door's width (m)", between(0.0, 10.0));
    return f;
}

const ConfigFields<GenConfig::Furniture> &GenConfig::Furniture::fields() {
    using C = GenConfig::Furniture;
    static const ConfigFields<C> f =
        ConfigFields<C>()
            .field("density", &C::density, "items per m² of room floor", between(0.0, 10.0))
            .field("items_per_room", &C::items_per_room, "clamp of the density-derived count", between(0, 1000))
            .field("hallway_density_scale", &C::hallway_density_scale, "hallways hold fewer items", between(0.0, 10.0))
            .field("clearance", &C::clearance, "min gap between two pieces of furniture (m)", between(0.0, 5.0))
            .field("wall_gap", &C::wall_gap, "gap between a wall-placed piece and its wall (m)", between(0.0, 1.0))
            .field("p_carpet", &C::p_carpet, "chance of a carpet per room", between(0, 1))
            .field("max_attempts", &C::max_attempts, "placement tries per item", between(1, 100000))
            .field("ajar_light_room_max_items", &C::ajar_light_room_max_items, "furniture allowed in the lit room of ajar scenes", between(0, 1000));
    return f;
}

const ConfigFields<GenConfig::Textures> &GenConfig::Textures::fields() {
    using C = GenConfig::Textures;
    static const ConfigFields<C> f =
        ConfigFields<C>()
            .field("p_floor_wood", &C::p_floor_wood, "floor gets a wood texture", between(0, 1))
            .field("p_floor_tiles", &C::p_floor_tiles, "floor gets checker tiles (else plain)", between(0, 1))
            .field("p_wall_pattern", &C::p_wall_pattern, "striped wallpaper", between(0, 1))
            .field("p_accent_wall", &C::p_accent_wall, "saturated wall colour instead of a white/pastel", between(0, 1))
            .field("p_carpet_pattern", &C::p_carpet_pattern, "carpet stripes or noise (else plain)", between(0, 1))
            .field("p_furniture_wood", &C::p_furniture_wood, "wooden parts get a wood texture (else plain)", between(0, 1))
            .field("p_fabric_pattern", &C::p_fabric_pattern, "fabric stripes or checker (else plain)", between(0, 1))
            .field("p_saturated_fabric", &C::p_saturated_fabric, "fabric from the saturated palette", between(0, 1))
            .field("wood_scale", &C::wood_scale, "wood ring period (m)", between(0.001, 100.0))
            .field("tile_scale", &C::tile_scale, "checker cell (m)", between(0.001, 100.0))
            .field("stripe_scale", &C::stripe_scale, "stripe pair period (m)", between(0.001, 100.0))
            .field("noise_scale", &C::noise_scale, "noise feature size (m)", between(0.001, 100.0))
            .field("color_jitter", &C::color_jitter, "relative per-object jitter of palette colours", between(0.0, 0.5))
            .field("p_bright_house", &C::p_bright_house, "a house's diffuse albedos are lifted toward their hue at 0.85 (white kitchens, living rooms)", between(0, 1))
            .omit_default()
            .field("bright_lift", &C::bright_lift, "range of a bright house's lift t: albedo + t (0.85 albedo / max albedo - albedo)", between(0.0, 1.0))
            .omit_default();
    return f;
}

const ConfigFields<GenConfig::Lights> &GenConfig::Lights::fields() {
    using C = GenConfig::Lights;
    static const ConfigFields<C> f =
        ConfigFields<C>()
            .field("per_room", &C::per_room, "ceiling lights in each lit room", between(1, 64))
            .field("size", &C::size, "side of a rectangular light (m)", between(0.05, 20.0))
            .field("temperature", &C::temperature, "colour temperature (K)", between(1000.0, 40000.0))
            .field("power_density", &C::power_density, "emitted power per m² of lit floor (luminance-weighted W/m²): Φ = π·L·A_light, so a 20 m² room gets 100–400 W", between(0.0, 1e5))
            .field("wall_margin", &C::wall_margin, "min distance from a light to a wall (m)", between(0.0, 10.0))
            .field("light_gap", &C::light_gap, "min distance between two lights (m)", between(0.0, 10.0))
            .field("tall_height", &C::tall_height, "furniture taller than this keeps off the lights (m)", between(0.0, 20.0))
            .field("tall_clearance", &C::tall_clearance, "plan gap between a light and tall furniture (m)", between(0.0, 10.0))
            .field("ceiling_gap", &C::ceiling_gap, "lights hang this far below the ceiling (m)", between(0.0001, 0.1))
            .field("p_ajar", &C::p_ajar, "all lights in one sparsely furnished room (>= 2 rooms)", between(0, 1))
            .field("max_attempts", &C::max_attempts, "placement tries per light", between(1, 100000));
    return f;
}

const ConfigFields<GenConfig::Glossy> &GenConfig::Glossy::fields() {
    using C = GenConfig::Glossy;
    static const std::vector<std::string> metal_names = [] {
        std::vector<std::string> v;
        for (const auto &[name, f0] : named_metal_f0()) v.push_back(name);
        return v;
    }();
    static const ConfigFields<C> f =
        ConfigFields<C>()
            .field("p_conductor", &C::p_conductor, "chance that a piece of furniture of `archetypes` is a GGX conductor (all its parts; 0 = none)", between(0, 1))
            .field("archetypes", &C::archetypes, "furniture archetypes that may be conductors (names from `furniture.archetypes`)")
            .field("p_walls", &C::p_walls, "chance that a room's walls are a GGX conductor (0 = none)", between(0, 1))
            .field("roughness", &C::roughness, "GGX α, uniform in the range (paper: 0.1)", between(0.001, 1))
            .field("metals", &C::metals, "F0 of one of these metals, uniformly (complex IOR at ~650/550/450 nm, scene/material.h)", {}, metal_names);
    return f;
}

const ConfigFields<GenConfig::Fixtures> &GenConfig::Fixtures::fields() {
    using C = GenConfig::Fixtures;
    static const ConfigFields<C> f =
        ConfigFields<C>()
            .field("p_windows", &C::p_windows, "chance that a room (not a hallway) has windows on outside walls (0 = none)", between(0, 1))
            .field("windows_per_room", &C::windows_per_room, "windows tried in such a room", between(1, 16))
            .field("window_width", &C::window_width, "window width along the wall (m)", between(0.1, 10))
            .field("window_sill", &C::window_sill, "sill height (m)", between(0, 10))
            .field("window_top", &C::window_top, "head height (m), kept 0.1 m below the ceiling", between(0.2, 20))
            .field("window_depth", &C::window_depth, "opening depth beyond the inner wall face: the outside wall's thickness (m)", between(0.01, 2))
            .field("p_window_sky", &C::p_window_sky, "chance that a window's outer end is a sky emitter (else open onto nothing)", between(0, 1))
            .field("sky_temperature", &C::sky_temperature, "sky colour temperature (K)", between(1000, 40000))
            .field("sky_power", &C::sky_power, "a window's Φ in units of its room's mean ceiling-light power (power_density's mid-range × floor area)", between(0.001, 100))
            .field("p_curtains", &C::p_curtains, "chance that a window gets pleated curtains at its sides", between(0, 1))
            .field("p_recessed", &C::p_recessed, "chance that a ceiling light sits in a recess (0 = none)", between(0, 1))
            .field("recess_depth", &C::recess_depth, "recess depth above the ceiling (m)", between(0.005, 2))
            .field("recess_trim", &C::recess_trim, "recess margin around its light (m)", between(0, 1))
            .field("p_lamp_lit", &C::p_lamp_lit, "chance that a floor lamp is lit: open shade with a bulb inside (0 = none)", between(0, 1))
            .field("p_table_lamp", &C::p_table_lamp, "chance of a lit table lamp on each nightstand, desk, cabinet or table (0 = none)", between(0, 1))
            .field("lamp_power", &C::lamp_power, "a lamp bulb's Φ (luminance-weighted W)", between(0.01, 1e5))
            .field("lamp_temperature", &C::lamp_temperature, "lamp colour temperature (K)", between(1000, 40000))
            .field("p_sconces", &C::p_sconces, "chance that a room has wall sconces lighting up the wall (0 = none)", between(0, 1))
            .field("sconces_per_room", &C::sconces_per_room, "sconces tried in such a room", between(1, 16))
            .field("sconce_power", &C::sconce_power, "a sconce's Φ (luminance-weighted W)", between(0.01, 1e5))
            .field("p_strip", &C::p_strip, "chance that a room has a light strip along a wall under the ceiling (0 = none)", between(0, 1))
            .field("strip_power", &C::strip_power, "a strip's Φ per metre (luminance-weighted W/m)", between(0.01, 1e5))
            .field("p_ceiling_off", &C::p_ceiling_off, "chance that a room lit by lamps, sconces, strips or a sky has its ceiling lights off", between(0, 1));
    return f;
}

const ConfigFields<GenConfig::CameraCfg> &GenConfig::CameraCfg::fields() {
    using C = GenConfig::CameraCfg;
    static const ConfigFields<C> f =
        ConfigFields<C>()
            .field("width", &C::width, "image width (pixels)", between(1, 16384))
            .field("height", &C::height, "image height (pixels)", between(1, 16384))
            .field("fov_y", &C::fov_y, "vertical field of view (degrees)", between(1.0, 170.0))
            .field("eye_height", &C::eye_height, "eye height above the floor (m)", between(0.1, 20.0))
            .field("target_height", &C::target_height, "height of the point the camera looks at (m)", between(0.0, 20.0))
            .field("wall_margin", &C::wall_margin, "min distance from the eye to a wall (m)", between(0.0, 10.0))
            .field("furniture_clearance", &C::furniture_clearance, "preferred plan distance to furniture (m)", between(0.0, 10.0))
            .field("n_candidates", &C::n_candidates, "eye positions tried; the best one is kept", between(1, 100000));
    return f;
}

namespace {
void read_archetypes(JsonObject &o, std::map<std::string, ArchetypeRanges> &archetypes) {
    static const ConfigFields<ArchetypeRanges> fields = ConfigFields<ArchetypeRanges>()
                                                            .field("weight", &ArchetypeRanges::weight, "relative frequency", between(0, k_big))
                                                            .field("width", &ArchetypeRanges::width, "along the wall (m)", between(0.005, 20))
                                                            .field("depth", &ArchetypeRanges::depth, "away from the wall (m)", between(0.005, 20))
                                                            .field("height", &ArchetypeRanges::height, "m", between(0.005, 20));
    for (auto &[name, a] : archetypes)
        if (o.has(name)) a = fields.read(o.require(name), o.where(name), a);
    o.finish();   // names an unknown archetype
}

OrderedJson archetypes_json(const std::map<std::string, ArchetypeRanges> &archetypes) {
    OrderedJson arch = OrderedJson::object();
    for (const auto &[name, a] : archetypes)   // std::map: sorted, stable
        arch[name] = {{"weight", json_float(a.weight)},
                      {"width", {json_float(a.width.x), json_float(a.width.y)}},
                      {"depth", {json_float(a.depth.x), json_float(a.depth.y)}},
                      {"height", {json_float(a.height.x), json_float(a.height.y)}}};
    return arch;
}
}  // namespace

GenConfig GenConfig::from_json(const Json &j, const std::string &where) {
    GenConfig c;
    JsonObject root(j, where);
    auto section = [&](const char *key, auto &member, const auto &rest) {
        if (root.has(key)) member = std::decay_t<decltype(member)>::fields().read(root.require(key), root.where(key), member, rest);
    };
    section("plan", c.plan, [](JsonObject &o, Plan &p) {
        if (!(p.weight_single + p.weight_l_room + p.weight_bsp + p.weight_hallway + p.weight_l_split > 0.f))
            LTM_THROW(o.where(), ": the plan weights must not all be zero");
    });
    section("rooms", c.rooms, nullptr);
    section("walls", c.walls, nullptr);
    section("doors", c.doors, nullptr);
    section("furniture", c.furniture, [](JsonObject &o, Furniture &f) {
        if (o.has("archetypes")) {
            JsonObject ao = o.require_object("archetypes");
            read_archetypes(ao, f.archetypes);
        }
    });
    section("textures", c.textures, [](JsonObject &o, Textures &t) {
        if (t.p_floor_wood + t.p_floor_tiles > 1.f)
            LTM_THROW(o.where("p_floor_tiles"), ": p_floor_wood + p_floor_tiles must be <= 1");
    });
    section("lights", c.lights, nullptr);
    section("camera", c.camera, nullptr);
    section("glossy", c.glossy, nullptr);
    section("fixtures", c.fixtures, [](JsonObject &o, Fixtures &x) {
        if (x.window_sill.y >= x.window_top.x)
            LTM_THROW(o.where("window_top"), ": every sill must be below every head (window_sill max < window_top min)");
    });
    root.finish();

    // Cross-field checks: a door with its corner margins must fit on the shortest wall.
    const float door_span = c.doors.width.y + 2.f * c.doors.corner_margin + c.walls.thickness;
    if (c.rooms.min_side < door_span)
        LTM_THROW(where, ": /rooms/min_side: ", c.rooms.min_side,
                  " m is too short for a door (doors.width max + 2 corner margins + wall = ",
                  door_span, " m)");
    if (c.rooms.size.x < c.rooms.min_side)
        LTM_THROW(where, ": /rooms/size: lower bound must be >= rooms.min_side (", c.rooms.min_side, ")");
    if (c.plan.footprint_size.y < 2.f * c.rooms.min_side)
        LTM_THROW(where, ": /plan/footprint_size: upper bound must be >= 2 * rooms.min_side");
    for (size_t i = 0; i < c.glossy.archetypes.size(); ++i)
        if (!c.furniture.archetypes.count(c.glossy.archetypes[i]))
            LTM_THROW(where, ": /glossy/archetypes/", i, ": '", c.glossy.archetypes[i], "' is not a furniture archetype");
    if (c.glossy.p_conductor > 0.f && c.glossy.archetypes.empty())
        LTM_THROW(where, ": /glossy/archetypes: p_conductor > 0 needs at least one archetype");
    if ((c.glossy.p_conductor > 0.f || c.glossy.p_walls > 0.f) && c.glossy.metals.empty())
        LTM_THROW(where, ": /glossy/metals: conductors need at least one metal");
    return c;
}

OrderedJson GenConfig::to_json() const {
    OrderedJson j;
    j["plan"] = Plan::fields().write(plan);
    j["rooms"] = Rooms::fields().write(rooms);
    j["walls"] = Walls::fields().write(walls);
    j["doors"] = Doors::fields().write(doors);
    j["furniture"] = Furniture::fields().write(furniture);
    j["furniture"]["archetypes"] = archetypes_json(furniture.archetypes);
    j["textures"] = Textures::fields().write(textures);
    j["lights"] = Lights::fields().write(lights);
    j["camera"] = CameraCfg::fields().write(camera);
    j["glossy"] = Glossy::fields().write(glossy);
    j["fixtures"] = Fixtures::fields().write(fixtures);
    return j;
}

}  // namespace ltm
