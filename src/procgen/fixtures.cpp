// fixtures.cpp: windows, recesses, lamps, sconces, strips and curtains of generated rooms
// (procgen/fixtures.h). Plan geometry works on one side of an interior rectangle at a time: a
// "side" is the rectangle's edge, an "along" coordinate runs on it and an "out" distance leaves the
// room through it (negative: into the room).
#include "ltm/procgen/fixtures.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "ltm/core/color.h"
#include "ltm/core/error.h"
#include "ltm/procgen/palettes.h"
#include "ltm/scene/material.h"
#include "ltm/scene/mesh_builder.h"

namespace ltm {

namespace {

constexpr uint64_t k_fixtures = 9;   // the generator's stream for this file (indoor_generator.cpp: 1-8)
enum What : uint64_t { k_windows = 1, k_recess = 2, k_floor_lamp = 3, k_table_lamp = 4, k_sconce = 5, k_strip = 6, k_off = 7, k_pane = 8, k_curtain = 9, k_lamp_mat = 10 };

/// Plan coordinates are integer millimetres (procgen/floor_plan.h).
float mm_round(float v) { return std::round(v * 1000.f) / 1000.f; }

Pcg32 stream(uint64_t seed, What what, uint64_t index) { return Pcg32(hash_keys({seed, k_fixtures, uint64_t(what), index})); }

/// One side of an interior rectangle: 0 z0 (out = −z), 1 z1 (+z), 2 x0 (−x), 3 x1 (+x).
struct Side {
    Rect2f rect;
    int side = 0;
    bool along_x() const { return side < 2; }
    float sign() const { return side % 2 ? 1.f : -1.f; }
    float face() const { return side == 0 ? rect.z0 : side == 1 ? rect.z1 : side == 2 ? rect.x0 : rect.x1; }
    float along0() const { return along_x() ? rect.x0 : rect.z0; }
    float along1() const { return along_x() ? rect.x1 : rect.z1; }
    Vec3f outward() const { return along_x() ? Vec3f(0.f, 0.f, sign()) : Vec3f(sign(), 0.f, 0.f); }
    /// Plan rectangle over along [t0, t1] and out distance [d0, d1] (either order).
    Rect2f plan(float t0, float t1, float d0, float d1) const {
        const float a = face() + sign() * d0, b = face() + sign() * d1;
        const float c0 = std::min(a, b), c1 = std::max(a, b);
        return along_x() ? Rect2f{t0, c0, t1, c1} : Rect2f{c0, t0, c1, t1};
    }
    /// World point at along t, out distance d, height y.
    Vec3f point(float t, float d, float y) const {
        const float c = face() + sign() * d;
        return along_x() ? Vec3f(t, y, c) : Vec3f(c, y, t);
    }
};

bool overlaps_any(const Rect2f &r, const std::vector<Rect2f> &others) {
    for (const Rect2f &o : others)
        if (r.overlaps(o)) return true;
    return false;
}

bool boxes_overlap(const Bounds3f &a, const Bounds3f &b) {
    for (int k = 0; k < 3; ++k)
        if (!(a.lo[k] < b.hi[k] && b.lo[k] < a.hi[k])) return false;
    return true;
}

Bounds3f box_of(const Rect2f &r, float y0, float y1) {
    Bounds3f b;
    b.expand(Vec3f(r.x0, y0, r.z0));
    b.expand(Vec3f(r.x1, y1, r.z1));
    return b;
}

/// Every room's air and every door's and window's hole: what must not lie behind a wall.
std::vector<Rect2f> holes_and_air(const GeneratedScene &g) {
    std::vector<Rect2f> v;
    for (const RoomInfo &r : g.rooms) v.insert(v.end(), r.rects.begin(), r.rects.end());
    for (const DoorInfo &d : g.doors) v.push_back(d.opening);
    for (const WindowInfo &w : g.windows) v.push_back(w.hole);
    return v;
}

/// A solid wall stands behind along [t0, t1] of this side: the thin strip just beyond the face
/// meets no air (another rectangle of the same room, a door, a window).
bool wall_behind(const Side &s, float t0, float t1, const std::vector<Rect2f> &air) {
    return !overlaps_any(s.plan(t0, t1, 0.001f, 0.02f), air);
}

Vec3f radiance_for(float power, float area, float kelvin) { return quantize(blackbody_rgb(kelvin) * (power / (k_pi * area))); }

void add_emitter(GeneratedScene &g, int room, const std::string &kind, TriangleMesh mesh, float power, float area, float kelvin) {
    FixtureLightInfo li;
    li.room = room;
    li.kind = kind;
    li.radiance = radiance_for(power, area, kelvin);
    li.power = quantize(power);
    mesh.name = kind + "_light" + std::to_string(g.fixture_lights.size());
    li.mesh = add_generated_mesh(g.scene, std::move(mesh), Texture::constant(Vec3f(0.8f)), li.radiance);
    g.fixture_lights.push_back(li);
}

/// A bulb: a small box of side s centred at c, emitting Φ from its 6 faces.
void add_bulb(GeneratedScene &g, int room, const std::string &kind, Vec3f c, float s, float power, float kelvin) {
    TriangleMesh bulb;
    add_box(bulb, c - Vec3f(0.5f * s), c + Vec3f(0.5f * s));
    add_emitter(g, room, kind, std::move(bulb), power, 6.f * s * s, kelvin);
}

// ---------------------------------------------------------------------------------------------
// Stage 1: windows and recesses

constexpr float k_corner = 0.15f;   // min distance from a window to its rectangle's corner (m)

void place_windows(GeneratedScene &g, FloorPlan &plan, const GenConfig &cfg, uint64_t seed) {
    const GenConfig::Fixtures &fx = cfg.fixtures;
    const float wall = float(plan.wall_mm) / 1000.f, ceiling = float(plan.ceiling_mm) / 1000.f;
    std::vector<Rect2f> door_zones;
    for (const DoorInfo &d : g.doors) door_zones.push_back(d.opening.expanded(cfg.doors.clear_depth));
    std::vector<Rect2f> curtains;   // every panel so far: panels of two windows do not meet
    std::vector<Rect2f> air = holes_and_air(g);   // grows with each window placed
    for (size_t r = 0; r < g.rooms.size(); ++r) {
        if (g.rooms[r].kind == "hallway") continue;
        Pcg32 rng = stream(seed, k_windows, r);
        if (!rng.bernoulli(fx.p_windows)) continue;
        const int n = rng.uniform_int(fx.windows_per_room.lo, fx.windows_per_room.hi);
        for (int i = 0; i < n; ++i)
            for (int attempt = 0; attempt < 30; ++attempt) {
                const Side s{g.rooms[r].rects[pick_area_weighted(g.rooms[r].rects, rng)], int(rng.next_below(4))};
                const float span = s.along1() - s.along0() - 2.f * k_corner;
                const float width = mm_round(std::min(rng.uniform(fx.window_width.x, fx.window_width.y), span));
                const float sill = mm_round(rng.uniform(fx.window_sill.x, fx.window_sill.y));
                const float top = mm_round(std::min(rng.uniform(fx.window_top.x, fx.window_top.y), ceiling - 0.1f));
                const float depth = mm_round(rng.uniform(fx.window_depth.x, fx.window_depth.y));
                const float t0 = mm_round(rng.uniform(s.along0() + k_corner, std::max(s.along0() + k_corner, s.along1() - k_corner - width)));
                if (width < 0.3f || top - sill < 0.3f || depth < 0.01f) continue;
                // Outside: no air (any room, door, window) within the window's depth plus a wall.
                if (overlaps_any(s.plan(t0 - wall, t0 + width + wall, 0.001f, depth + wall), air)) continue;
                WindowInfo w;
                w.room = int(r);
                w.hole = s.plan(t0, t0 + width, 0.f, depth);
                w.sill = sill, w.top = top;
                w.outward = s.outward();
                // Curtains: a panel at each end, over the window's edge and the wall beside it,
                // hanging c in front of the wall; furniture keeps off their footprint.
                if (rng.bernoulli(fx.p_curtains)) {
                    const float c = rng.uniform(0.06f, 0.12f);
                    for (int end = 0; end < 2; ++end) {
                        const float over = rng.uniform(0.05f, 0.2f), beside = rng.uniform(0.1f, 0.35f);
                        float a0 = end == 0 ? t0 - beside : t0 + width - over;
                        float a1 = end == 0 ? t0 + over : t0 + width + beside;
                        a0 = std::max(a0, s.along0() + 0.02f), a1 = std::min(a1, s.along1() - 0.02f);
                        const Rect2f foot = s.plan(a0, a1, -(c + 0.06f), 0.f);
                        if (a1 - a0 < 0.15f || overlaps_any(foot, door_zones) || overlaps_any(foot, curtains)) continue;
                        w.curtains.push_back(foot);
                        curtains.push_back(foot);
                    }
                }
                PlanOpening op;
                op.kind = PlanOpening::Kind::window;
                op.room = int(r);
                const Rect2f &h = w.hole;
                op.lo[0] = int(std::lround(h.x0 * 1000.f)), op.lo[1] = int(std::lround(sill * 1000.f)), op.lo[2] = int(std::lround(h.z0 * 1000.f));
                op.hi[0] = int(std::lround(h.x1 * 1000.f)), op.hi[1] = int(std::lround(top * 1000.f)), op.hi[2] = int(std::lround(h.z1 * 1000.f));
                op.outward_axis = s.along_x() ? 2 : 0;
                op.outward_sign = s.sign() > 0.f ? 1 : -1;
                w.opening = int(plan.openings.size());
                plan.openings.push_back(op);
                air.push_back(w.hole);
                g.windows.push_back(std::move(w));
                break;
            }
    }
}

void place_recesses(GeneratedScene &g, FloorPlan &plan, const GenConfig &cfg, uint64_t seed) {
    const GenConfig::Fixtures &fx = cfg.fixtures;
    for (size_t i = 0; i < g.lights.size(); ++i) {
        Pcg32 rng = stream(seed, k_recess, i);
        if (!rng.bernoulli(fx.p_recessed)) continue;
        LightInfo &li = g.lights[i];
        const int trim = int(std::lround(1000.f * rng.uniform(fx.recess_trim.x, fx.recess_trim.y)));
        const int depth = std::max(5, int(std::lround(1000.f * rng.uniform(fx.recess_depth.x, fx.recess_depth.y))));
        PlanOpening op;
        op.kind = PlanOpening::Kind::recess;
        op.room = li.room;
        op.lo[0] = int(std::floor(li.corners[0].x * 1000.f)) - trim, op.lo[2] = int(std::floor(li.corners[0].z * 1000.f)) - trim;
        op.hi[0] = int(std::ceil(li.corners[2].x * 1000.f)) + trim, op.hi[2] = int(std::ceil(li.corners[2].z * 1000.f)) + trim;
        op.lo[1] = plan.ceiling_mm, op.hi[1] = plan.ceiling_mm + depth;
        // The recess stays inside its room's air and clear of the other recesses.
        const Rect2f foot{float(op.lo[0]) / 1000.f, float(op.lo[2]) / 1000.f, float(op.hi[0]) / 1000.f, float(op.hi[2]) / 1000.f};
        bool inside = false;
        for (const Rect2f &r : g.rooms[size_t(li.room)].rects) inside |= r.contains(foot);
        bool clear = true;
        for (const PlanOpening &o : plan.openings)
            if (o.kind == PlanOpening::Kind::recess)
                clear &= !(op.lo[0] < o.hi[0] + 20 && o.lo[0] < op.hi[0] + 20 && op.lo[2] < o.hi[2] + 20 && o.lo[2] < op.hi[2] + 20);
        if (!inside || !clear) continue;
        plan.openings.push_back(op);
        const float y = quantize(float(op.hi[1]) / 1000.f - cfg.lights.ceiling_gap);
        for (Vec3f &c : li.corners) c.y = y;
    }
}

// ---------------------------------------------------------------------------------------------
// Stage 2 pieces

/// Pleated curtain panels of one window: a zigzag sheet from the floor to above the window head.
void add_curtains(GeneratedScene &g, const WindowInfo &w, const GenConfig &cfg, uint64_t seed, size_t index) {
    if (w.curtains.empty()) return;
    Pcg32 rng = stream(seed, k_curtain, index);
    const RoomInfo &room = g.rooms[size_t(w.room)];
    const float y_top = std::min(w.top + rng.uniform(0.1f, 0.3f), room.ceiling_height - 0.03f);
    const float amp = rng.uniform(0.015f, 0.035f);
    // The side the window is on: the room rectangle whose face holds the hole.
    const bool along_x = w.outward.z != 0.f;
    const float sign = along_x ? w.outward.z : w.outward.x;
    TriangleMesh mesh;
    for (const Rect2f &foot : w.curtains) {
        // foot spans out distance [−(c + 0.06), 0]; the sheet hangs at −(c + 0.03) ± amp.
        const float face = along_x ? (sign > 0.f ? foot.z1 : foot.z0) : (sign > 0.f ? foot.x1 : foot.x0);
        const float depth = along_x ? foot.depth() : foot.width();
        const float mid = face - sign * (depth - 0.03f);
        const float a0 = along_x ? foot.x0 : foot.z0, a1 = along_x ? foot.x1 : foot.z1;
        const int pleats = std::max(2, int(std::lround((a1 - a0) / rng.uniform(0.08f, 0.14f))));
        auto at = [&](int k, float y) {
            const float t = a0 + (a1 - a0) * float(k) / float(pleats);
            const float c = mid + (k % 2 ? amp : -amp);
            return along_x ? Vec3f(t, y, c) : Vec3f(c, y, t);
        };
        for (int k = 0; k < pleats; ++k)
            add_quad_facing(mesh, at(k, 0.02f), at(k + 1, 0.02f), at(k + 1, y_top), at(k, y_top),
                            at(k, 1.f) - w.outward);   // the room side faces the room
    }
    mesh.name = "room" + std::to_string(w.room) + "_curtain" + std::to_string(index);
    add_generated_mesh(g.scene, std::move(mesh), sample_albedo(SurfaceKind::fabric, cfg.textures, rng));
}

/// The sky pane of a window (an emitter facing the room) or nothing (a hole onto the void).
void add_pane(GeneratedScene &g, WindowInfo &w, std::vector<RoomShell> &shells, const GenConfig &cfg, uint64_t seed, size_t index) {
    const GenConfig::Fixtures &fx = cfg.fixtures;
    auto it = shells[size_t(w.room)].panes.find(w.opening);
    LTM_CHECK(it != shells[size_t(w.room)].panes.end());
    Pcg32 rng = stream(seed, k_pane, index);
    w.sky = rng.bernoulli(fx.p_window_sky);
    if (!w.sky) return;
    const float area = (w.outward.z != 0.f ? w.hole.width() : w.hole.depth()) * (w.top - w.sill);
    const float density = 0.5f * (cfg.lights.power_density.x + cfg.lights.power_density.y);
    const float power = rng.uniform(fx.sky_power.x, fx.sky_power.y) * density * g.rooms[size_t(w.room)].floor_area;
    const float kelvin = std::round(rng.uniform(fx.sky_temperature.x, fx.sky_temperature.y));
    w.radiance = radiance_for(power, area, kelvin);
    w.power = quantize(power);
    w.pane_mesh = add_generated_mesh(g.scene, std::move(it->second), Texture::constant(Vec3f(0.f)), w.radiance);
}

/// A lit floor lamp: its closed shade becomes an open tube with a bulb inside, above the pole.
void light_floor_lamp(GeneratedScene &g, const FurnitureInfo &f, const GenConfig &cfg, Pcg32 &rng) {
    for (int m : f.meshes) {
        TriangleMesh &shade = g.scene.meshes[size_t(m)];
        if (shade.name.size() < 6 || shade.name.compare(shade.name.size() - 6, 6, "_shade") != 0) continue;
        Bounds3f b;
        for (const Vec3f &p : shade.positions) b.expand(p);
        const float r = 0.5f * (b.hi.x - b.lo.x), h = b.hi.y - b.lo.y;
        const Vec3f base{0.5f * (b.lo.x + b.hi.x), b.lo.y, 0.5f * (b.lo.z + b.hi.z)};
        shade.positions.clear(), shade.uvs.clear(), shade.indices.clear();
        add_cylinder(shade, base, r, h, 24, /*caps=*/false);
        for (Vec3f &p : shade.positions) p = quantize(p);
        for (Vec2f &uv : shade.uvs) uv = {quantize(uv.x), quantize(uv.y)};
        const float power = rng.uniform(cfg.fixtures.lamp_power.x, cfg.fixtures.lamp_power.y);
        const float kelvin = std::round(rng.uniform(cfg.fixtures.lamp_temperature.x, cfg.fixtures.lamp_temperature.y));
        add_bulb(g, f.room, "floor_lamp", base + Vec3f(0.f, 0.45f * h, 0.f), std::min(0.06f, 0.5f * r), power, kelvin);
        return;
    }
}

/// A table lamp on top of a piece: base, stem, open shade, bulb. Appends its bounds to `taken`.
void add_table_lamp(GeneratedScene &g, const FurnitureInfo &f, const GenConfig &cfg, Pcg32 &rng, Pcg32 &mat_rng,
                    std::vector<Bounds3f> &taken) {
    const float top = f.bounds.hi.y, ceiling = g.rooms[size_t(f.room)].ceiling_height;
    const float w = f.bounds.hi.x - f.bounds.lo.x, d = f.bounds.hi.z - f.bounds.lo.z;
    const float r = std::min(rng.uniform(0.08f, 0.18f), 0.4f * std::min(w, d));
    const float hs = rng.uniform(0.12f, 0.25f);
    float stem = std::min(rng.uniform(0.15f, 0.35f), ceiling - 0.15f - top - 0.02f - hs);
    if (r < 0.06f || stem < 0.05f) return;
    const float x = rng.uniform(f.bounds.lo.x + r + 0.02f, f.bounds.hi.x - r - 0.02f);
    const float z = rng.uniform(f.bounds.lo.z + r + 0.02f, f.bounds.hi.z - r - 0.02f);
    TriangleMesh body;
    add_cylinder(body, {x, top, z}, 0.6f * r, 0.02f, 16);
    add_cylinder(body, {x, top + 0.02f, z}, 0.01f, stem + 0.3f * hs, 8);
    body.name = f.name + "_lamp_base";
    add_generated_mesh(g.scene, std::move(body), sample_albedo(SurfaceKind::metal, cfg.textures, mat_rng));
    TriangleMesh shade;
    const float y_shade = top + 0.02f + stem;
    add_cylinder(shade, {x, y_shade, z}, r, hs, 24, /*caps=*/false);
    shade.name = f.name + "_lamp_shade";
    add_generated_mesh(g.scene, std::move(shade), sample_albedo(SurfaceKind::bedding, cfg.textures, mat_rng));
    const float power = rng.uniform(cfg.fixtures.lamp_power.x, cfg.fixtures.lamp_power.y);
    const float kelvin = std::round(rng.uniform(cfg.fixtures.lamp_temperature.x, cfg.fixtures.lamp_temperature.y));
    add_bulb(g, f.room, "table_lamp", {x, y_shade + 0.3f * hs + 0.03f, z}, 0.05f, power, kelvin);
    taken.push_back(box_of(Rect2f{x - r, z - r, x + r, z + r}, top, y_shade + hs));
}

/// Room r's wall-mounted pieces: sconces (an open cup with an up-facing emitter) and a light
/// strip under the ceiling. `air`: holes_and_air(); `taken` holds what they must not meet (furniture,
/// curtains, each other).
void add_wall_lights(GeneratedScene &g, size_t r, const std::vector<Rect2f> &air, std::vector<Bounds3f> &taken, const GenConfig &cfg,
                     uint64_t seed) {
    const GenConfig::Fixtures &fx = cfg.fixtures;
    const RoomInfo &room = g.rooms[r];
    Pcg32 rng = stream(seed, k_sconce, r);
    if (rng.bernoulli(fx.p_sconces)) {
        const int n = rng.uniform_int(fx.sconces_per_room.lo, fx.sconces_per_room.hi);
        const Texture cup_albedo = sample_albedo(rng.bernoulli(0.5f) ? SurfaceKind::metal : SurfaceKind::painted, cfg.textures, rng);
        for (int i = 0; i < n; ++i)
            for (int attempt = 0; attempt < 30; ++attempt) {
                const Side s{room.rects[pick_area_weighted(room.rects, rng)], int(rng.next_below(4))};
                const float w = rng.uniform(0.15f, 0.3f), d = 0.1f, h = 0.12f;
                const float y0 = std::max(1.0f, std::min(rng.uniform(1.5f, 2.0f), room.ceiling_height - 0.45f));
                if (s.along1() - s.along0() < w + 0.2f) continue;
                const float t0 = rng.uniform(s.along0() + 0.1f, s.along1() - 0.1f - w);
                const Bounds3f box = box_of(s.plan(t0, t0 + w, -d, 0.f), y0, y0 + h);
                bool clear = wall_behind(s, t0, t0 + w, air);
                for (const Bounds3f &o : taken) clear &= !boxes_overlap(box, o);
                if (!clear) continue;
                TriangleMesh cup;
                const Vec3f in = -s.outward();
                const Vec3f c = s.point(t0 + 0.5f * w, -0.5f * d, y0 + 0.5f * h);
                add_quad_facing(cup, s.point(t0, 0.f, y0), s.point(t0 + w, 0.f, y0), s.point(t0 + w, -d, y0), s.point(t0, -d, y0), c - Vec3f(0.f, 1.f, 0.f));
                add_quad_facing(cup, s.point(t0, -d, y0), s.point(t0 + w, -d, y0), s.point(t0 + w, -d, y0 + h), s.point(t0, -d, y0 + h), c + in);
                add_quad_facing(cup, s.point(t0, 0.f, y0), s.point(t0, -d, y0), s.point(t0, -d, y0 + h), s.point(t0, 0.f, y0 + h), s.point(t0 - 1.f, -0.5f * d, y0));
                add_quad_facing(cup, s.point(t0 + w, 0.f, y0), s.point(t0 + w, -d, y0), s.point(t0 + w, -d, y0 + h), s.point(t0 + w, 0.f, y0 + h), s.point(t0 + w + 1.f, -0.5f * d, y0));
                cup.name = "room" + std::to_string(r) + "_sconce" + std::to_string(i);
                add_generated_mesh(g.scene, std::move(cup), cup_albedo);
                TriangleMesh lamp;
                const float ye = y0 + 0.6f * h, e0 = t0 + 0.01f, e1 = t0 + w - 0.01f;
                add_quad_facing(lamp, s.point(e0, -0.005f, ye), s.point(e1, -0.005f, ye), s.point(e1, -(d - 0.01f), ye), s.point(e0, -(d - 0.01f), ye),
                                s.point(t0, -0.5f * d, ye + 1.f));
                const float power = rng.uniform(fx.sconce_power.x, fx.sconce_power.y);
                const float kelvin = std::round(rng.uniform(fx.lamp_temperature.x, fx.lamp_temperature.y));
                add_emitter(g, int(r), "sconce", std::move(lamp), power, (e1 - e0) * (d - 0.015f), kelvin);
                taken.push_back(box);
                break;
            }
    }
    Pcg32 srng = stream(seed, k_strip, r);
    if (srng.bernoulli(fx.p_strip))
        for (int attempt = 0; attempt < 30; ++attempt) {
            const Side s{room.rects[pick_area_weighted(room.rects, srng)], int(srng.next_below(4))};
            const float avail = s.along1() - s.along0() - 0.3f;
            const float len = srng.uniform(0.5f, 1.f) * avail, hs = srng.uniform(0.02f, 0.04f);
            const float y0 = room.ceiling_height - srng.uniform(0.06f, 0.25f) - hs;
            if (len < 0.4f) continue;
            const float t0 = srng.uniform(s.along0() + 0.15f, s.along1() - 0.15f - len);
            const Bounds3f box = box_of(s.plan(t0, t0 + len, -0.01f, 0.f), y0, y0 + hs);
            bool clear = wall_behind(s, t0, t0 + len, air);
            for (const Bounds3f &o : taken) clear &= !boxes_overlap(box, o);
            if (!clear) continue;
            TriangleMesh strip;
            add_quad_facing(strip, s.point(t0, -0.003f, y0), s.point(t0 + len, -0.003f, y0), s.point(t0 + len, -0.003f, y0 + hs),
                            s.point(t0, -0.003f, y0 + hs), s.point(t0, -1.f, y0));
            const float power = srng.uniform(fx.strip_power.x, fx.strip_power.y) * len;
            const float kelvin = std::round(srng.uniform(fx.lamp_temperature.x, fx.lamp_temperature.y));
            add_emitter(g, int(r), "strip", std::move(strip), power, len * hs, kelvin);
            taken.push_back(box);
            break;
        }
}

}  // namespace

int add_generated_mesh(Scene &scene, TriangleMesh mesh, const Texture &albedo, Vec3f emission) {
    Material m;
    m.name = mesh.name;
    m.albedo = albedo;
    if (max_component(emission) > 0.f) m.emission = Texture::constant(emission);
    mesh.material = scene.add_material(std::move(m));
    for (Vec3f &p : mesh.positions) p = quantize(p);
    for (Vec2f &uv : mesh.uvs) uv = {quantize(uv.x), quantize(uv.y)};
    scene.meshes.push_back(std::move(mesh));
    return int(scene.meshes.size()) - 1;
}

void place_openings(GeneratedScene &g, FloorPlan &plan, const GenConfig &cfg, uint64_t seed) {
    if (cfg.fixtures.p_windows > 0.f) place_windows(g, plan, cfg, seed);
    if (cfg.fixtures.p_recessed > 0.f) place_recesses(g, plan, cfg, seed);
}

void add_fixtures(GeneratedScene &g, std::vector<RoomShell> &shells, const GenConfig &cfg, uint64_t seed) {
    const GenConfig::Fixtures &fx = cfg.fixtures;
    for (size_t i = 0; i < g.windows.size(); ++i) {
        add_pane(g, g.windows[i], shells, cfg, seed, i);
        add_curtains(g, g.windows[i], cfg, seed, i);
    }
    // What wall pieces must not meet: furniture, lamps on it, curtains.
    std::vector<Bounds3f> taken;
    for (const FurnitureInfo &f : g.furniture) taken.push_back(f.bounds);
    for (const WindowInfo &w : g.windows)
        for (const Rect2f &c : w.curtains) taken.push_back(box_of(c, 0.f, g.rooms[size_t(w.room)].ceiling_height));
    const size_t n_furniture = g.furniture.size();
    for (size_t i = 0; i < n_furniture; ++i) {
        const FurnitureInfo &f = g.furniture[i];
        if (f.archetype == "floor_lamp" && fx.p_lamp_lit > 0.f) {
            Pcg32 rng = stream(seed, k_floor_lamp, i);
            if (rng.bernoulli(fx.p_lamp_lit)) light_floor_lamp(g, f, cfg, rng);
        }
        if ((f.archetype == "nightstand" || f.archetype == "desk" || f.archetype == "cabinet" || f.archetype == "table") &&
            fx.p_table_lamp > 0.f) {
            Pcg32 rng = stream(seed, k_table_lamp, i), mat_rng = stream(seed, k_lamp_mat, i);
            if (rng.bernoulli(fx.p_table_lamp)) add_table_lamp(g, f, cfg, rng, mat_rng, taken);
        }
    }
    if (fx.p_sconces > 0.f || fx.p_strip > 0.f) {
        const std::vector<Rect2f> air = holes_and_air(g);
        for (size_t r = 0; r < g.rooms.size(); ++r) add_wall_lights(g, r, air, taken, cfg, seed);
    }
    if (fx.p_ceiling_off > 0.f)
        for (size_t r = 0; r < g.rooms.size(); ++r) {
            // Lit otherwise: a lamp, sconce or strip, or a sky window.
            bool other = false;
            for (const FixtureLightInfo &f : g.fixture_lights) other |= f.room == int(r);
            for (const WindowInfo &w : g.windows) other |= w.room == int(r) && w.sky;
            Pcg32 rng = stream(seed, k_off, r);
            if (!other || !rng.bernoulli(fx.p_ceiling_off)) continue;
            // The panels stay as unlit diffusers; the lights list keeps the lights that are on.
            std::vector<LightInfo> on;
            for (const LightInfo &l : g.lights) {
                if (l.room == int(r)) g.scene.materials[size_t(g.scene.meshes[size_t(l.mesh)].material)].emission = Texture::constant(Vec3f(0.f));
                else on.push_back(l);
            }
            g.lights = std::move(on);
        }
}

}  // namespace ltm
