// indoor_generator.cpp: assembles a generated scene: plan → lights → furniture → camera →
// materials and meshes. Each stage draws from its own PCG stream, hash(seed, stage[, index]),
// so a change in one stage does not reshuffle the others.
#include "ltm/procgen/indoor_generator.h"

#include <algorithm>
#include <cmath>

#include "ltm/core/color.h"
#include "ltm/core/error.h"
#include "ltm/procgen/fixtures.h"
#include "ltm/procgen/furniture.h"
#include "ltm/procgen/room_layout.h"
#include "ltm/procgen/room_shell.h"
#include "ltm/procgen/palettes.h"
#include "ltm/scene/material.h"
#include "ltm/scene/mesh_builder.h"

namespace ltm {

namespace {

enum Stream : uint64_t { k_plan = 1, k_lights = 2, k_furniture = 3, k_camera = 4, k_shell_mat = 5, k_item_mat = 6, k_glossy = 7, k_bright = 8 };

// ---------------------------------------------------------------------------------------------
// Lights: rectangles on the ceiling, inside a room rectangle shrunk by the wall margin, apart
// from each other. Placed before the furniture, which then keeps tall pieces away from them.

std::vector<Rect2f> place_room_lights(const std::vector<Rect2f> &rects, const GenConfig &cfg, Pcg32 &rng) {
    const GenConfig::Lights &lc = cfg.lights;
    const int n = rng.uniform_int(lc.per_room.lo, lc.per_room.hi);
    std::vector<Rect2f> out;
    for (int i = 0; i < n; ++i) {
        for (int attempt = 0; attempt < lc.max_attempts; ++attempt) {
            const Rect2f in = rects[pick_area_weighted(rects, rng)].expanded(-lc.wall_margin);
            if (in.width() <= 0.f || in.depth() <= 0.f) continue;
            const float sx = quantize(std::min(rng.uniform(lc.size.x, lc.size.y), in.width()));
            const float sz = quantize(std::min(rng.uniform(lc.size.x, lc.size.y), in.depth()));
            if (sx < 0.05f || sz < 0.05f) continue;
            const float x0 = quantize(rng.uniform(in.x0, std::max(in.x0, in.x1 - sx)));
            const float z0 = quantize(rng.uniform(in.z0, std::max(in.z0, in.z1 - sz)));
            const Rect2f light{x0, z0, quantize(x0 + sx), quantize(z0 + sz)};
            bool ok = true;
            for (const Rect2f &o : out) ok &= !light.expanded(lc.light_gap).overlaps(o);
            if (!ok) continue;
            out.push_back(light);
            break;
        }
    }
    return out;
}

// A room can hold a light if some rectangle is wider than twice the margin plus 5 cm.
bool can_hold_light(const std::vector<Rect2f> &rects, const GenConfig &cfg) {
    for (const Rect2f &r : rects)
        if (std::min(r.width(), r.depth()) - 2.f * cfg.lights.wall_margin >= 0.05f) return true;
    return false;
}

// ---------------------------------------------------------------------------------------------
// Camera

float distance_to_rect(Vec2f p, const Rect2f &r) {
    const float dx = std::max({r.x0 - p.x, 0.f, p.x - r.x1}), dz = std::max({r.z0 - p.y, 0.f, p.y - r.z1});
    return std::sqrt(dx * dx + dz * dz);
}

Camera make_camera(const GeneratedScene &g, const std::vector<std::vector<Rect2f>> &room_items, int room,
                   const DoorInfo *door, const GenConfig &cfg, Pcg32 &rng) {
    const GenConfig::CameraCfg &cc = cfg.camera;
    const RoomInfo &info = g.rooms[size_t(room)];
    // Keep the best of n candidate eyes: the first one clear of furniture by the preferred
    // distance, else the clearest (a corner of free floor always exists beside a door zone).
    Vec2f best{};
    float best_score = -1.f;
    for (int i = 0; i < cc.n_candidates; ++i) {
        const Rect2f &r = info.rects[pick_area_weighted(info.rects, rng)];
        Rect2f in = r.expanded(-cc.wall_margin);
        if (in.width() < 0.f) in.x0 = in.x1 = 0.5f * (r.x0 + r.x1);
        if (in.depth() < 0.f) in.z0 = in.z1 = 0.5f * (r.z0 + r.z1);
        const Vec2f p{rng.uniform(in.x0, in.x1), rng.uniform(in.z0, in.z1)};
        float score = 1e9f;
        for (const Rect2f &f : room_items[size_t(room)]) score = std::min(score, distance_to_rect(p, f));
        if (score > best_score) best = p, best_score = score;
        if (score >= cc.furniture_clearance) break;
    }
    Camera cam;
    cam.name = "main";
    cam.width = cc.width, cam.height = cc.height;
    cam.fov_y_deg = quantize(rng.uniform(cc.fov_y.x, cc.fov_y.y));
    const float eye_y = std::min(rng.uniform(cc.eye_height.x, cc.eye_height.y), info.ceiling_height - 0.2f);
    cam.eye = quantize(Vec3f(best.x, eye_y, best.y));
    Vec3f target;
    if (door) {   // look through the door toward the lit room
        const float ty = std::min(rng.uniform(cc.target_height.x, cc.target_height.y), door->height - 0.2f);
        target = {0.5f * (door->p0.x + door->p1.x), ty, 0.5f * (door->p0.y + door->p1.y)};
    } else {      // look across the room, toward its farthest corner
        Vec2f far = best;
        float far_d = -1.f;
        for (const Rect2f &r : info.rects)
            for (Vec2f c : {Vec2f{r.x0, r.z0}, Vec2f{r.x1, r.z0}, Vec2f{r.x0, r.z1}, Vec2f{r.x1, r.z1}}) {
                const float d = (c.x - best.x) * (c.x - best.x) + (c.y - best.y) * (c.y - best.y);
                if (d > far_d) far = c, far_d = d;
            }
        const float ty = rng.uniform(cc.target_height.x, cc.target_height.y);
        target = {best.x + 0.8f * (far.x - best.x), ty, best.y + 0.8f * (far.y - best.y)};
    }
    cam.target = quantize(target);
    const float dx = cam.target.x - cam.eye.x, dz = cam.target.z - cam.eye.z;
    if (dx * dx + dz * dz < 0.01f)   // degenerate view (eye at the far corner)
        cam.target = quantize(cam.eye + Vec3f(1.f, -0.3f, 0.f));
    return cam;
}

// ---------------------------------------------------------------------------------------------
// Assembly

void build_rooms_and_doors(GeneratedScene &g, const FloorPlan &plan) {
    const float ceiling = float(plan.ceiling_mm) / 1000.f;
    for (size_t r = 0; r < plan.rooms.size(); ++r) {
        RoomInfo info;
        info.id = int(r);
        info.kind = plan.rooms[r].kind;
        for (const RectMm &q : plan.rooms[r].interiors) info.rects.push_back(q.to_metres());
        info.ceiling_height = ceiling;
        info.floor_area = float(double(plan.rooms[r].floor_area_mm2()) * 1e-6);
        g.rooms.push_back(info);
    }
    for (const PlanDoor &d : plan.doors) {
        DoorInfo info;
        info.room_a = d.room_a, info.room_b = d.room_b;
        info.opening = d.opening.to_metres();
        const Rect2f &o = info.opening;
        if (d.axis == 0) info.p0 = {o.x0, 0.5f * (o.z0 + o.z1)}, info.p1 = {o.x1, info.p0.y};
        else info.p0 = {0.5f * (o.x0 + o.x1), o.z0}, info.p1 = {info.p0.x, o.z1};
        info.width = d.axis == 0 ? o.width() : o.depth();
        info.height = float(d.height_mm) / 1000.f;
        g.doors.push_back(info);
    }
}

// The furniture-free zone of a door: its opening grown along the wall by clear_side and across
// it by clear_depth, into both rooms.
Rect2f door_clear_zone(const DoorInfo &d, const GenConfig &cfg) {
    const float side = cfg.doors.clear_side, depth = cfg.doors.clear_depth;
    Rect2f z = d.opening;
    const bool along_x = d.p0.y == d.p1.y;
    z.x0 -= along_x ? side : depth, z.x1 += along_x ? side : depth;
    z.z0 -= along_x ? depth : side, z.z1 += along_x ? depth : side;
    return z;
}

// What the stages hand to each other.
struct Stages {
    std::vector<std::vector<Rect2f>> room_lights;   // per room, light rectangles
    int light_room = -1;                            // ajar scenes: the only lit room
    std::vector<RoomLayout> layouts;                // per room
    std::vector<std::vector<Rect2f>> room_items;    // per room, furniture footprints
};

// Lights: every room that can hold one, or (ajar) a single random room.
void place_lights(GeneratedScene &g, Stages &st, const GenConfig &cfg, uint64_t seed) {
    const int n_rooms = int(g.rooms.size());
    Pcg32 rng(hash_keys({seed, k_lights}));
    std::vector<int> candidates;
    for (int r = 0; r < n_rooms; ++r)
        if (can_hold_light(g.rooms[size_t(r)].rects, cfg)) candidates.push_back(r);
    if (candidates.empty())
        LTM_THROW("generate_indoor(): seed ", seed, ": no room is large enough for a light with lights.wall_margin = ",
                  cfg.lights.wall_margin);
    g.ajar = n_rooms >= 2 && rng.bernoulli(cfg.lights.p_ajar);
    st.light_room = g.ajar ? candidates[rng.next_below(uint32_t(candidates.size()))] : -1;
    st.room_lights.assign(size_t(n_rooms), {});
    float total_area = 0.f;
    for (const RoomInfo &r : g.rooms) total_area += r.floor_area;
    for (int r : candidates) {
        if (g.ajar && r != st.light_room) continue;
        const std::vector<Rect2f> &lights = st.room_lights[size_t(r)] = place_room_lights(g.rooms[size_t(r)].rects, cfg, rng);
        // Φ = density · lit floor area, shared by the room's lights in proportion to their area
        // (one radiance per room); an ajar light room lights the whole plan.
        const float power = rng.uniform(cfg.lights.power_density.x, cfg.lights.power_density.y) *
                            (g.ajar ? total_area : g.rooms[size_t(r)].floor_area);
        float light_area = 0.f;
        for (const Rect2f &l : lights) light_area += l.area();
        for (const Rect2f &l : lights) {
            LightInfo li;
            li.room = r;
            li.temperature_k = std::round(rng.uniform(cfg.lights.temperature.x, cfg.lights.temperature.y));
            li.radiance = quantize(blackbody_rgb(li.temperature_k) * (power / (k_pi * light_area)));
            li.power = quantize(power * l.area() / light_area);
            const float y = quantize(g.rooms[size_t(r)].ceiling_height - cfg.lights.ceiling_gap);
            li.corners = {Vec3f(l.x0, y, l.z0), Vec3f(l.x1, y, l.z0), Vec3f(l.x1, y, l.z1), Vec3f(l.x0, y, l.z1)};
            g.lights.push_back(li);
        }
    }
    if (g.lights.empty()) LTM_THROW("generate_indoor(): seed ", seed, ": no light could be placed");
}

// Furniture, room by room, each room from its own stream.
void place_furniture(GeneratedScene &g, Stages &st, const GenConfig &cfg, uint64_t seed) {
    std::vector<Rect2f> door_zones;
    for (const DoorInfo &d : g.doors) door_zones.push_back(door_clear_zone(d, cfg));
    st.room_items.assign(g.rooms.size(), {});
    for (size_t r = 0; r < g.rooms.size(); ++r) {
        RoomLayoutInput in;
        in.kind = g.rooms[r].kind;
        in.rects = g.rooms[r].rects;
        in.ceiling_height = g.rooms[r].ceiling_height;
        in.keep_out = door_zones;
        for (const WindowInfo &w : g.windows)   // curtains (GenConfig::Fixtures)
            if (w.room == int(r)) in.keep_out.insert(in.keep_out.end(), w.curtains.begin(), w.curtains.end());
        for (const Rect2f &l : st.room_lights[r]) in.tall_keep_out.push_back(l.expanded(cfg.lights.tall_clearance));
        if (g.ajar && int(r) == st.light_room) in.max_items = cfg.furniture.ajar_light_room_max_items;
        Pcg32 rng(hash_keys({seed, k_furniture, uint64_t(r)}));
        st.layouts.push_back(furnish_room(in, cfg, rng));
        g.rooms[r].role = st.layouts.back().role;
        for (const PlacedItem &it : st.layouts.back().items) st.room_items[r].push_back(it.footprint);
    }
}

// Camera: in the largest lit room; in ajar scenes, in the most furnished room next to the lit
// one, looking through their door.
void place_camera(GeneratedScene &g, const Stages &st, const GenConfig &cfg, uint64_t seed) {
    int cam_room = -1;
    const DoorInfo *cam_door = nullptr;
    if (g.ajar) {
        for (const DoorInfo &d : g.doors) {
            if (d.room_a != st.light_room && d.room_b != st.light_room) continue;
            const int other = d.room_a == st.light_room ? d.room_b : d.room_a;
            if (cam_room < 0 || st.room_items[size_t(other)].size() > st.room_items[size_t(cam_room)].size())
                cam_room = other, cam_door = &d;
        }
    } else {
        float best = -1.f;   // hallways only when no other room is lit
        for (size_t r = 0; r < g.rooms.size(); ++r) {
            if (st.room_lights[r].empty()) continue;
            const float score = g.rooms[r].floor_area + (g.rooms[r].kind == "hallway" ? 0.f : 1e4f);
            if (score > best) best = score, cam_room = int(r);
        }
    }
    LTM_CHECK_GE(cam_room, 0);
    Pcg32 rng(hash_keys({seed, k_camera}));
    g.scene.cameras.push_back(make_camera(g, st.room_items, cam_room, cam_door, cfg, rng));
}

// With probability p (one draw from rng), the materials of `meshes` become one GGX conductor:
// α uniform in cfg.roughness, F0 of a uniformly chosen metal; the albedo the scene points carry
// is F0 (as scene_json does: the conductor's reflectance). p = 0 draws nothing.
void maybe_conductor(Scene &scene, const std::vector<int> &meshes, float p, const GenConfig::Glossy &cfg, Pcg32 &rng) {
    if (!(p > 0.f) || rng.next_float() >= p) return;
    // GenConfig::from_json checks these; a config built in code may not have been read.
    if (cfg.metals.empty()) LTM_THROW("generator: glossy conductors need at least one metal (glossy.metals)");
    const float alpha = quantize(rng.uniform(cfg.roughness.x, cfg.roughness.y));
    const std::string &metal = cfg.metals[std::min(size_t(rng.next_float() * float(cfg.metals.size())), cfg.metals.size() - 1)];
    const auto f0_it = named_metal_f0().find(metal);
    if (f0_it == named_metal_f0().end()) LTM_THROW("generator: glossy.metals: unknown metal '", metal, "'");
    const Vec3f f0 = f0_it->second;
    for (int m : meshes) {
        Material &mat = scene.materials[size_t(scene.meshes[size_t(m)].material)];
        mat.bsdf = BsdfKind::conductor;
        mat.roughness = std::max(alpha, 1e-3f);
        mat.specular = f0;
        mat.albedo = Texture::constant(f0);
    }
}

// Meshes and materials: shell, furniture, lights (one material per mesh, named like it). The
// shells keep their window panes for the fixtures.
void add_meshes(GeneratedScene &g, Stages &st, std::vector<RoomShell> &shells, const GenConfig &cfg, uint64_t seed) {
    Scene &scene = g.scene;
    Pcg32 rng_shell(hash_keys({seed, k_shell_mat}));
    for (size_t r = 0; r < g.rooms.size(); ++r) {
        RoomShell &s = shells[r];
        const Texture floor = sample_albedo(SurfaceKind::floor, cfg.textures, rng_shell);
        const Texture ceiling = sample_albedo(SurfaceKind::ceiling, cfg.textures, rng_shell);
        const Texture walls = sample_albedo(SurfaceKind::wall, cfg.textures, rng_shell);
        g.rooms[r].shell_meshes = {add_generated_mesh(scene, std::move(s.floor), floor),
                                   add_generated_mesh(scene, std::move(s.ceiling), ceiling),
                                   add_generated_mesh(scene, std::move(s.walls), walls)};
        Pcg32 rng_glossy(hash_keys({seed, k_glossy, 0, uint64_t(r)}));
        maybe_conductor(scene, {g.rooms[r].shell_meshes[2]}, cfg.glossy.p_walls, cfg.glossy, rng_glossy);
    }
    for (size_t r = 0; r < g.rooms.size(); ++r)
        for (PlacedItem &it : st.layouts[r].items) {
            FurnitureInfo info;
            info.archetype = it.model.archetype;
            info.name = it.model.archetype + std::to_string(g.furniture.size());
            info.room = int(r);
            Pcg32 rng(hash_keys({seed, k_item_mat, uint64_t(g.furniture.size())}));
            for (FurniturePart &part : it.model.parts) {
                part.mesh.name = info.name + "_" + part.slot;
                const int m = add_generated_mesh(scene, std::move(part.mesh), sample_albedo(part.kind, cfg.textures, rng));
                info.meshes.push_back(m);
                for (const Vec3f &p : scene.meshes[size_t(m)].positions) info.bounds.expand(p);
            }
            const auto &glossy = cfg.glossy.archetypes;
            if (std::find(glossy.begin(), glossy.end(), info.archetype) != glossy.end()) {
                Pcg32 rng_glossy(hash_keys({seed, k_glossy, 1, uint64_t(g.furniture.size())}));
                maybe_conductor(scene, info.meshes, cfg.glossy.p_conductor, cfg.glossy, rng_glossy);
            }
            g.furniture.push_back(info);
        }
    for (size_t i = 0; i < g.lights.size(); ++i) {
        LightInfo &li = g.lights[i];
        TriangleMesh mesh;
        mesh.name = "light" + std::to_string(i);
        add_quad(mesh, li.corners[0], li.corners[1], li.corners[2], li.corners[3]);   // normal -y
        li.mesh = add_generated_mesh(scene, std::move(mesh), Texture::constant(Vec3f(0.8f)), li.radiance);   // the diffuser also reflects
    }
}

// A bright house (GenConfig::Textures::p_bright_house): every diffuse, non-emitting albedo lifted
// by t toward its own hue at 0.85. Its own stream, so the rest of the house is the seed's house.
// Returns t, or 0 when the house stays as drawn.
float maybe_brighten(Scene &scene, const GenConfig::Textures &cfg, uint64_t seed) {
    if (!(cfg.p_bright_house > 0.f)) return 0.f;
    Pcg32 rng(hash_keys({seed, k_bright}));
    if (!rng.bernoulli(cfg.p_bright_house)) return 0.f;
    const float t = quantize(rng.uniform(cfg.bright_lift.x, cfg.bright_lift.y));
    const auto lift = [t](Vec3f c) {
        const float m = max_component(c);
        return m > 0.f ? quantize(c + t * (c * (0.85f / m) - c)) : quantize(Vec3f(t * 0.85f));
    };
    for (Material &mat : scene.materials) {
        if (mat.bsdf != BsdfKind::diffuse || mat.is_emissive()) continue;
        mat.albedo.color_a = lift(mat.albedo.color_a);
        mat.albedo.color_b = lift(mat.albedo.color_b);
    }
    return t;
}

}  // namespace

GeneratedScene generate_indoor(const GenConfig &cfg, uint64_t seed) {
    GeneratedScene g;
    Pcg32 rng_plan(hash_keys({seed, k_plan}));
    FloorPlan plan = generate_floor_plan(cfg, rng_plan);
    g.plan_type = plan.type;
    build_rooms_and_doors(g, plan);
    // Lights come before furniture so that tall pieces can keep clear of them; windows and
    // recesses (fixtures, off by default) before furniture so that it keeps off the curtains.
    Stages st;
    place_lights(g, st, cfg, seed);
    place_openings(g, plan, cfg, seed);
    place_furniture(g, st, cfg, seed);
    place_camera(g, st, cfg, seed);
    g.scene.name = "indoor_" + std::to_string(seed);
    std::vector<RoomShell> shells = build_room_shell(plan);
    add_meshes(g, st, shells, cfg, seed);
    add_fixtures(g, shells, cfg, seed);
    const float bright = maybe_brighten(g.scene, cfg.textures, seed);

    OrderedJson &md = g.scene.metadata;
    md["generator"] = "ltm-indoor";
    md["generator_version"] = k_indoor_generator_version;
    md["seed"] = seed;
    md["plan_type"] = g.plan_type;
    md["n_rooms"] = g.rooms.size();
    md["ajar"] = g.ajar;
    md["light_room"] = st.light_room;
    md["n_lights"] = g.lights.size();
    md["n_furniture"] = g.furniture.size();
    if (!g.windows.empty()) md["n_windows"] = g.windows.size();
    if (!g.fixture_lights.empty()) md["n_fixture_lights"] = g.fixture_lights.size();
    if (bright > 0.f) md["bright_lift"] = bright;
    md["config"] = cfg.to_json();
    return g;
}

}  // namespace ltm
