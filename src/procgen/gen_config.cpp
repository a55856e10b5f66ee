// gen_config.cpp: strict JSON reading and writing of GenConfig, with range validation.
#include "ltm/procgen/gen_config.h"

#include <cstdio>
#include <cstdlib>

#include "ltm/core/error.h"

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

OrderedJson range_json(Vec2f r) { return OrderedJson::array({json_float(r.x), json_float(r.y)}); }
OrderedJson range_json(IntRange r) { return OrderedJson::array({r.lo, r.hi}); }

// Readers: keep the default when the key is absent, validate when present.
void read_float(JsonObject &o, const std::string &key, float &v, float lo, float hi) {
    v = o.get_float(key, v);
    if (!(v >= lo && v <= hi)) LTM_THROW(o.where(key), ": must be in [", lo, ", ", hi, "], got ", v);
}
void read_prob(JsonObject &o, const std::string &key, float &p) { read_float(o, key, p, 0.f, 1.f); }
void read_int(JsonObject &o, const std::string &key, int &v, int lo, int hi) {
    v = o.get_int(key, v);
    if (v < lo || v > hi) LTM_THROW(o.where(key), ": must be in [", lo, ", ", hi, "], got ", v);
}
void read_range(JsonObject &o, const std::string &key, Vec2f &r, float lo, float hi) {
    r = o.get_range(key, r);   // checks lo <= hi
    if (!(r.x >= lo && r.y <= hi))
        LTM_THROW(o.where(key), ": range [", r.x, ", ", r.y, "] must lie in [", lo, ", ", hi, "]");
}
void read_int_range(JsonObject &o, const std::string &key, IntRange &r, int lo, int hi) {
    if (!o.has(key)) return;
    const Json &v = o.require(key);
    if (!v.is_array() || v.size() != 2 || !v[0].is_number_integer() || !v[1].is_number_integer())
        LTM_THROW(o.where(key), ": expected an integer range [lo, hi]");
    const int64_t a = v[0].get<int64_t>(), b = v[1].get<int64_t>();
    if (a > b) LTM_THROW(o.where(key), ": range has lo > hi: [", a, ", ", b, "]");
    if (a < lo || b > hi)
        LTM_THROW(o.where(key), ": range [", a, ", ", b, "] must lie in [", lo, ", ", hi, "]");
    r = {int(a), int(b)};
}

constexpr float k_big = 1e6f;

void read_plan(JsonObject &o, GenConfig::Plan &p) {
    read_float(o, "weight_single", p.weight_single, 0.f, k_big);
    read_float(o, "weight_l_room", p.weight_l_room, 0.f, k_big);
    read_float(o, "weight_bsp", p.weight_bsp, 0.f, k_big);
    read_float(o, "weight_hallway", p.weight_hallway, 0.f, k_big);
    read_float(o, "weight_l_split", p.weight_l_split, 0.f, k_big);
    if (!(p.weight_single + p.weight_l_room + p.weight_bsp + p.weight_hallway + p.weight_l_split > 0.f))
        LTM_THROW(o.where(), ": the plan weights must not all be zero");
    read_range(o, "footprint_size", p.footprint_size, 1.f, 100.f);
    read_int_range(o, "n_rooms", p.n_rooms, 2, 64);
    read_range(o, "split_fraction", p.split_fraction, 0.05f, 0.95f);
    read_range(o, "l_cut_fraction", p.l_cut_fraction, 0.05f, 0.95f);
    read_range(o, "hallway_width", p.hallway_width, 0.5f, 10.f);
    read_int_range(o, "hallway_rooms_per_side", p.hallway_rooms_per_side, 1, 16);
    read_prob(o, "p_hallway_two_sided", p.p_hallway_two_sided);
    read_float(o, "snap", p.snap, 0.002f, 1.f);
    read_int(o, "max_attempts", p.max_attempts, 1, 10000);
    o.finish();
}

void read_rooms(JsonObject &o, GenConfig::Rooms &r) {
    read_range(o, "size", r.size, 1.f, 100.f);
    read_range(o, "l_room_size", r.l_room_size, 2.f, 100.f);
    read_float(o, "min_side", r.min_side, 0.5f, 100.f);
    read_range(o, "ceiling_height", r.ceiling_height, 1.f, 20.f);
    o.finish();
}

void read_doors(JsonObject &o, GenConfig::Doors &d) {
    read_range(o, "width", d.width, 0.3f, 5.f);
    read_range(o, "height", d.height, 0.5f, 10.f);
    read_float(o, "corner_margin", d.corner_margin, 0.f, 5.f);
    read_prob(o, "p_extra", d.p_extra);
    read_float(o, "clear_depth", d.clear_depth, 0.f, 10.f);
    read_float(o, "clear_side", d.clear_side, 0.f, 10.f);
    o.finish();
}

void read_archetypes(JsonObject &o, std::map<std::string, ArchetypeRanges> &archetypes) {
    for (auto &[name, a] : archetypes) {
        if (!o.has(name)) continue;
        JsonObject ao = o.require_object(name);
        read_float(ao, "weight", a.weight, 0.f, k_big);
        read_range(ao, "width", a.width, 0.005f, 20.f);
        read_range(ao, "depth", a.depth, 0.005f, 20.f);
        read_range(ao, "height", a.height, 0.005f, 20.f);
        ao.finish();
    }
    o.finish();   // names an unknown archetype
}

void read_furniture(JsonObject &o, GenConfig::Furniture &f) {
    read_range(o, "density", f.density, 0.f, 10.f);
    read_int_range(o, "items_per_room", f.items_per_room, 0, 1000);
    read_float(o, "hallway_density_scale", f.hallway_density_scale, 0.f, 10.f);
    read_float(o, "clearance", f.clearance, 0.f, 5.f);
    read_float(o, "wall_gap", f.wall_gap, 0.f, 1.f);
    read_prob(o, "p_carpet", f.p_carpet);
    read_int(o, "max_attempts", f.max_attempts, 1, 100000);
    read_int(o, "ajar_light_room_max_items", f.ajar_light_room_max_items, 0, 1000);
    if (o.has("archetypes")) {
        JsonObject ao = o.require_object("archetypes");
        read_archetypes(ao, f.archetypes);
    }
    o.finish();
}

void read_textures(JsonObject &o, GenConfig::Textures &t) {
    read_prob(o, "p_floor_wood", t.p_floor_wood);
    read_prob(o, "p_floor_tiles", t.p_floor_tiles);
    if (t.p_floor_wood + t.p_floor_tiles > 1.f)
        LTM_THROW(o.where("p_floor_tiles"), ": p_floor_wood + p_floor_tiles must be <= 1");
    read_prob(o, "p_wall_pattern", t.p_wall_pattern);
    read_prob(o, "p_accent_wall", t.p_accent_wall);
    read_prob(o, "p_carpet_pattern", t.p_carpet_pattern);
    read_prob(o, "p_furniture_wood", t.p_furniture_wood);
    read_prob(o, "p_fabric_pattern", t.p_fabric_pattern);
    read_prob(o, "p_saturated_fabric", t.p_saturated_fabric);
    read_range(o, "wood_scale", t.wood_scale, 0.001f, 100.f);
    read_range(o, "tile_scale", t.tile_scale, 0.001f, 100.f);
    read_range(o, "stripe_scale", t.stripe_scale, 0.001f, 100.f);
    read_range(o, "noise_scale", t.noise_scale, 0.001f, 100.f);
    read_float(o, "color_jitter", t.color_jitter, 0.f, 0.5f);
    o.finish();
}

void read_lights(JsonObject &o, GenConfig::Lights &l) {
    read_int_range(o, "per_room", l.per_room, 1, 64);
    read_range(o, "size", l.size, 0.05f, 20.f);
    read_range(o, "temperature", l.temperature, 1000.f, 40000.f);
    read_range(o, "power_density", l.power_density, 0.f, 1e5f);
    read_float(o, "wall_margin", l.wall_margin, 0.f, 10.f);
    read_float(o, "light_gap", l.light_gap, 0.f, 10.f);
    read_float(o, "tall_height", l.tall_height, 0.f, 20.f);
    read_float(o, "tall_clearance", l.tall_clearance, 0.f, 10.f);
    read_float(o, "ceiling_gap", l.ceiling_gap, 0.0001f, 0.1f);
    read_prob(o, "p_ajar", l.p_ajar);
    read_int(o, "max_attempts", l.max_attempts, 1, 100000);
    o.finish();
}

void read_camera(JsonObject &o, GenConfig::CameraCfg &c) {
    read_int(o, "width", c.width, 1, 16384);
    read_int(o, "height", c.height, 1, 16384);
    read_range(o, "fov_y", c.fov_y, 1.f, 170.f);
    read_range(o, "eye_height", c.eye_height, 0.1f, 20.f);
    read_range(o, "target_height", c.target_height, 0.f, 20.f);
    read_float(o, "wall_margin", c.wall_margin, 0.f, 10.f);
    read_float(o, "furniture_clearance", c.furniture_clearance, 0.f, 10.f);
    read_int(o, "n_candidates", c.n_candidates, 1, 100000);
    o.finish();
}

}  // namespace

GenConfig GenConfig::from_json(const Json &j, const std::string &where) {
    GenConfig c;
    JsonObject root(j, where);
    auto section = [&](const char *key, auto &&reader) {
        if (!root.has(key)) return;
        JsonObject o = root.require_object(key);
        reader(o);
    };
    section("plan", [&](JsonObject &o) { read_plan(o, c.plan); });
    section("rooms", [&](JsonObject &o) { read_rooms(o, c.rooms); });
    section("walls", [&](JsonObject &o) {
        read_float(o, "thickness", c.walls.thickness, 0.01f, 2.f);
        o.finish();
    });
    section("doors", [&](JsonObject &o) { read_doors(o, c.doors); });
    section("furniture", [&](JsonObject &o) { read_furniture(o, c.furniture); });
    section("textures", [&](JsonObject &o) { read_textures(o, c.textures); });
    section("lights", [&](JsonObject &o) { read_lights(o, c.lights); });
    section("camera", [&](JsonObject &o) { read_camera(o, c.camera); });
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
    return c;
}

OrderedJson GenConfig::to_json() const {
    OrderedJson j;
    OrderedJson &p = j["plan"];
    p["weight_single"] = json_float(plan.weight_single);
    p["weight_l_room"] = json_float(plan.weight_l_room);
    p["weight_bsp"] = json_float(plan.weight_bsp);
    p["weight_hallway"] = json_float(plan.weight_hallway);
    p["weight_l_split"] = json_float(plan.weight_l_split);
    p["footprint_size"] = range_json(plan.footprint_size);
    p["n_rooms"] = range_json(plan.n_rooms);
    p["split_fraction"] = range_json(plan.split_fraction);
    p["l_cut_fraction"] = range_json(plan.l_cut_fraction);
    p["hallway_width"] = range_json(plan.hallway_width);
    p["hallway_rooms_per_side"] = range_json(plan.hallway_rooms_per_side);
    p["p_hallway_two_sided"] = json_float(plan.p_hallway_two_sided);
    p["snap"] = json_float(plan.snap);
    p["max_attempts"] = plan.max_attempts;

    OrderedJson &r = j["rooms"];
    r["size"] = range_json(rooms.size);
    r["l_room_size"] = range_json(rooms.l_room_size);
    r["min_side"] = json_float(rooms.min_side);
    r["ceiling_height"] = range_json(rooms.ceiling_height);

    j["walls"]["thickness"] = json_float(walls.thickness);

    OrderedJson &d = j["doors"];
    d["width"] = range_json(doors.width);
    d["height"] = range_json(doors.height);
    d["corner_margin"] = json_float(doors.corner_margin);
    d["p_extra"] = json_float(doors.p_extra);
    d["clear_depth"] = json_float(doors.clear_depth);
    d["clear_side"] = json_float(doors.clear_side);

    OrderedJson &f = j["furniture"];
    f["density"] = range_json(furniture.density);
    f["items_per_room"] = range_json(furniture.items_per_room);
    f["hallway_density_scale"] = json_float(furniture.hallway_density_scale);
    f["clearance"] = json_float(furniture.clearance);
    f["wall_gap"] = json_float(furniture.wall_gap);
    f["p_carpet"] = json_float(furniture.p_carpet);
    f["max_attempts"] = furniture.max_attempts;
    f["ajar_light_room_max_items"] = furniture.ajar_light_room_max_items;
    OrderedJson &arch = f["archetypes"];
    arch = OrderedJson::object();
    for (const auto &[name, a] : furniture.archetypes) {   // std::map: sorted, stable
        OrderedJson &aj = arch[name];
        aj["weight"] = json_float(a.weight);
        aj["width"] = range_json(a.width);
        aj["depth"] = range_json(a.depth);
        aj["height"] = range_json(a.height);
    }

    OrderedJson &t = j["textures"];
    t["p_floor_wood"] = json_float(textures.p_floor_wood);
    t["p_floor_tiles"] = json_float(textures.p_floor_tiles);
    t["p_wall_pattern"] = json_float(textures.p_wall_pattern);
    t["p_accent_wall"] = json_float(textures.p_accent_wall);
    t["p_carpet_pattern"] = json_float(textures.p_carpet_pattern);
    t["p_furniture_wood"] = json_float(textures.p_furniture_wood);
    t["p_fabric_pattern"] = json_float(textures.p_fabric_pattern);
    t["p_saturated_fabric"] = json_float(textures.p_saturated_fabric);
    t["wood_scale"] = range_json(textures.wood_scale);
    t["tile_scale"] = range_json(textures.tile_scale);
    t["stripe_scale"] = range_json(textures.stripe_scale);
    t["noise_scale"] = range_json(textures.noise_scale);
    t["color_jitter"] = json_float(textures.color_jitter);

    OrderedJson &l = j["lights"];
    l["per_room"] = range_json(lights.per_room);
    l["size"] = range_json(lights.size);
    l["temperature"] = range_json(lights.temperature);
    l["power_density"] = range_json(lights.power_density);
    l["wall_margin"] = json_float(lights.wall_margin);
    l["light_gap"] = json_float(lights.light_gap);
    l["tall_height"] = json_float(lights.tall_height);
    l["tall_clearance"] = json_float(lights.tall_clearance);
    l["ceiling_gap"] = json_float(lights.ceiling_gap);
    l["p_ajar"] = json_float(lights.p_ajar);
    l["max_attempts"] = lights.max_attempts;

    OrderedJson &c = j["camera"];
    c["width"] = camera.width;
    c["height"] = camera.height;
    c["fov_y"] = range_json(camera.fov_y);
    c["eye_height"] = range_json(camera.eye_height);
    c["target_height"] = range_json(camera.target_height);
    c["wall_margin"] = json_float(camera.wall_margin);
    c["furniture_clearance"] = json_float(camera.furniture_clearance);
    c["n_candidates"] = camera.n_candidates;
    return j;
}

}  // namespace ltm
