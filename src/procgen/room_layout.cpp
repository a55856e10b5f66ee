// room_layout.cpp: the rejection-sampling layout of a room (roles, anchors with companions,
// carpets, further pieces), over the archetypes of procgen/furniture.h.
#include "ltm/procgen/room_layout.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "ltm/core/error.h"

namespace ltm {

namespace {

struct Role {
    const char *name;
    const char *anchor;
    std::vector<std::string> others;
};

const std::vector<Role> &room_roles() {
    static const std::vector<Role> roles = {
        {"bedroom", "bed", {"wardrobe", "desk", "chair", "shelves", "plant", "floor_lamp", "armchair", "cabinet", "nightstand"}},
        {"living", "sofa", {"armchair", "coffee_table", "shelves", "cabinet", "floor_lamp", "plant", "table", "chair"}},
        {"dining", "table", {"cabinet", "shelves", "plant", "floor_lamp", "armchair"}},
        {"office", "desk", {"shelves", "cabinet", "plant", "armchair", "floor_lamp", "wardrobe"}},
    };
    return roles;
}
const Role k_hallway_role = {"hallway", "", {"cabinet", "shelves", "plant", "wardrobe", "floor_lamp"}};

bool is_unique(const std::string &a) {
    return a == "bed" || a == "sofa" || a == "table" || a == "desk" || a == "wardrobe" || a == "carpet";
}

class Layout {
public:
    Layout(const RoomLayoutInput &room, const GenConfig &cfg, Pcg32 &rng)
        : m_room(room), m_cfg(cfg), m_rng(rng) {}

    std::vector<PlacedItem> items;
    int capacity = 0;

    bool full() const { return int(items.size()) >= capacity; }
    bool has(const std::string &a) const {
        for (const PlacedItem &it : items)
            if (it.model.archetype == a) return true;
        return false;
    }
    std::optional<FurnitureModel> build(const std::string &a) {
        const auto it = m_cfg.furniture.archetypes.find(a);
        if (it == m_cfg.furniture.archetypes.end() || it->second.weight <= 0.f) return std::nullopt;
        return build_furniture(a, it->second, m_room.ceiling_height - 0.1f, m_rng);
    }

    /// Places at (q, c) if the footprint is valid; returns the index of the new item.
    int try_place(FurnitureModel model, int q, Vec2f c) {
        c = {quantize(c.x), quantize(c.y)};
        const Rect2f f = model_footprint(model, q, c);
        if (!fits(f, model.height)) return -1;
        place_model(model, q, c);
        items.push_back({std::move(model), f, q, c});
        return int(items.size()) - 1;
    }

    int place_against_wall(const FurnitureModel &model) {
        const float g = m_cfg.furniture.wall_gap, w = model.width, d = model.depth;
        for (int attempt = 0; attempt < m_cfg.furniture.max_attempts; ++attempt) {
            const size_t k = pick_rect();
            const Rect2f &r = m_room.rects[k];
            const int side = int(m_rng.next_below(4));   // wall at z0, x0, z1, x1; q = side
            const bool along_x = side % 2 == 0;
            const float lo = (along_x ? r.x0 : r.z0) + w / 2, hi = (along_x ? r.x1 : r.z1) - w / 2;
            if (lo > hi) continue;
            const float s = m_rng.uniform(lo, hi);
            Vec2f c;
            if (side == 0) c = {s, r.z0 + g + d / 2};
            else if (side == 1) c = {r.x0 + g + d / 2, s};
            else if (side == 2) c = {s, r.z1 - g - d / 2};
            else c = {r.x1 - g - d / 2, s};
            if (!backed_by_wall(k, side, model_footprint(model, side, c))) continue;
            const int i = try_place(model, side, c);
            if (i >= 0) return i;
        }
        return -1;
    }

    int place_free(const FurnitureModel &model) {
        const float clr = m_cfg.furniture.clearance;
        for (int attempt = 0; attempt < m_cfg.furniture.max_attempts; ++attempt) {
            const Rect2f &r = m_room.rects[pick_rect()];
            const int q = int(m_rng.next_below(4));
            const Rect2f f0 = model_footprint(model, q, {0.f, 0.f});
            const float x0 = r.x0 - f0.x0 + clr, x1 = r.x1 - f0.x1 - clr;
            const float z0 = r.z0 - f0.z0 + clr, z1 = r.z1 - f0.z1 - clr;
            if (x0 > x1 || z0 > z1) continue;
            const int i = try_place(model, q, {m_rng.uniform(x0, x1), m_rng.uniform(z0, z1)});
            if (i >= 0) return i;
        }
        return -1;
    }

    int place(const FurnitureModel &model) {
        return archetype_placement(model.archetype) == Placement::wall ? place_against_wall(model)
                                                                      : place_free(model);
    }

    void place_companions(int anchor);

private:
    bool fits(const Rect2f &f, float height) const {
        bool inside = false;
        for (const Rect2f &r : m_room.rects) inside |= r.contains(f);
        if (!inside) return false;
        for (const Rect2f &k : m_room.keep_out)
            if (f.overlaps(k)) return false;
        if (height > m_cfg.lights.tall_height)
            for (const Rect2f &k : m_room.tall_keep_out)
                if (f.overlaps(k)) return false;
        const Rect2f grown = f.expanded(m_cfg.furniture.clearance);
        for (const PlacedItem &it : items)
            if (grown.overlaps(it.footprint)) return false;
        return true;
    }
    // In L-shaped rooms a rectangle side may open onto the room's other rectangle: no wall there.
    bool backed_by_wall(size_t k, int side, const Rect2f &f) const {
        const Rect2f &r = m_room.rects[k];
        for (size_t m = 0; m < m_room.rects.size(); ++m) {
            if (m == k) continue;
            const Rect2f &o = m_room.rects[m];
            const bool open = side == 0 ? o.z1 == r.z0 && f.x0 < o.x1 && o.x0 < f.x1
                              : side == 2 ? o.z0 == r.z1 && f.x0 < o.x1 && o.x0 < f.x1
                              : side == 1 ? o.x1 == r.x0 && f.z0 < o.z1 && o.z0 < f.z1
                                          : o.x0 == r.x1 && f.z0 < o.z1 && o.z0 < f.z1;
            if (open) return false;
        }
        return true;
    }
    size_t pick_rect() { return pick_area_weighted(m_room.rects, m_rng); }

    const RoomLayoutInput &m_room;
    const GenConfig &m_cfg;
    Pcg32 &m_rng;
};

// Nightstands beside a bed, chairs at a table or desk, a coffee table before a sofa: offsets in
// the anchor's frame, each companion validated like any other piece.
void Layout::place_companions(int anchor) {
    const PlacedItem a = items[size_t(anchor)];   // a copy: items grows below
    const float w = a.model.width, d = a.model.depth, gap = m_cfg.furniture.clearance + 0.01f;
    auto put = [&](const FurnitureModel &m, Vec2f local, int q_rel) {
        if (full()) return;
        const Vec2f o = rotate_quarter(a.quarter_turns, local);
        try_place(m, (a.quarter_turns + q_rel) & 3, {a.center.x + o.x, a.center.y + o.y});
    };
    const std::string &arch = a.model.archetype;
    if (arch == "bed") {
        for (int s : {-1, 1})
            if (auto n = build("nightstand"))
                put(*n, {float(s) * (w / 2 + gap + n->width / 2), -d / 2 + n->depth / 2}, 0);
    } else if (arch == "table") {
        const int per_side = w >= 1.4f ? 2 : 1;
        for (int side : {-1, 1})
            for (int i = 0; i < per_side; ++i)
                if (auto c = build("chair")) {
                    const float x = (float(i) + 0.5f) / float(per_side) * w - w / 2;
                    put(*c, {x, float(side) * (d / 2 + gap + c->depth / 2)}, side > 0 ? 2 : 0);
                }
    } else if (arch == "desk") {
        if (auto c = build("chair")) put(*c, {0.f, d / 2 + gap + c->depth / 2}, 2);
    } else if (arch == "sofa") {
        if (auto t = build("coffee_table")) put(*t, {0.f, d / 2 + std::max(0.35f, gap) + t->depth / 2}, 0);
    }
}

}  // namespace

RoomLayout furnish_room(const RoomLayoutInput &room, const GenConfig &cfg, Pcg32 &rng) {
    LTM_CHECK(!room.rects.empty());
    const GenConfig::Furniture &fc = cfg.furniture;
    Layout lay(room, cfg, rng);
    float area = 0.f;
    for (const Rect2f &r : room.rects) area += r.area();
    const bool hallway = room.kind == "hallway";
    const float n = area * rng.uniform(fc.density.x, fc.density.y) * (hallway ? fc.hallway_density_scale : 1.f);
    lay.capacity = std::clamp(int(std::lround(n)), fc.items_per_room.lo, fc.items_per_room.hi);
    if (room.max_items >= 0) lay.capacity = std::min(lay.capacity, room.max_items);
    const Role &role = hallway ? k_hallway_role : room_roles()[rng.next_below(uint32_t(room_roles().size()))];

    // Anchor first (it needs the most room), then a carpet while the floor is still open.
    if (!lay.full() && role.anchor[0] != '\0')
        if (auto m = lay.build(role.anchor)) {
            const int i = lay.place(*m);
            if (i >= 0) lay.place_companions(i);
        }
    if (!lay.full() && rng.bernoulli(fc.p_carpet))
        if (auto m = lay.build("carpet")) lay.place(*m);
    float total = 0.f;
    for (const std::string &a : role.others) total += fc.archetypes.at(a).weight;
    for (int tries = 0; !lay.full() && total > 0.f && tries < 3 * lay.capacity; ++tries) {
        float u = rng.uniform(0.f, total);
        size_t k = 0;
        while (k + 1 < role.others.size() && u >= fc.archetypes.at(role.others[k]).weight)
            u -= fc.archetypes.at(role.others[k++]).weight;
        const std::string &a = role.others[k];
        if (is_unique(a) && lay.has(a)) continue;
        if (auto m = lay.build(a)) lay.place(*m);
    }
    return {role.name, std::move(lay.items)};
}

}  // namespace ltm
