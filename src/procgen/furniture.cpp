// furniture.cpp: archetype geometry (boxes and cylinders in a local frame), placed by exact
// quarter turns (so footprints stay axis-aligned). The room layout: procgen/room_layout.h.
#include "ltm/procgen/furniture.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "ltm/core/error.h"
#include "ltm/scene/mesh_builder.h"

namespace ltm {

const std::vector<std::string> &archetype_names() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> n;
        for (const auto &kv : default_archetypes()) n.push_back(kv.first);
        return n;
    }();
    return names;
}

Placement archetype_placement(const std::string &a) {
    if (a == "carpet") return Placement::floor;
    if (a == "bed" || a == "sofa" || a == "desk" || a == "shelves" || a == "cabinet" ||
        a == "wardrobe" || a == "nightstand")
        return Placement::wall;
    return Placement::free;
}

// ---------------------------------------------------------------------------------------------
// Geometry. Each builder fills x in [-w/2, w/2], y in [0, h], z in [-d/2, d/2], front +z; parts
// of one piece may touch but never leave this box.

namespace {

FurniturePart &add_part(FurnitureModel &m, const std::string &slot, SurfaceKind kind) {
    m.parts.push_back({slot, kind, {}});
    return m.parts.back();
}
void box(FurniturePart &p, float x0, float y0, float z0, float x1, float y1, float z1) {
    add_box(p.mesh, {x0, y0, z0}, {x1, y1, z1});
}
// Four square legs of side s, inset from the corners of [-hw,hw]x[-hd,hd].
void legs4(FurniturePart &p, float hw, float hd, float inset, float s, float y0, float y1) {
    for (int sx : {-1, 1})
        for (int sz : {-1, 1}) {
            const float x = float(sx) * (hw - inset), z = float(sz) * (hd - inset);
            box(p, std::min(x, x - float(sx) * s), y0, std::min(z, z - float(sz) * s),
                std::max(x, x - float(sx) * s), y1, std::max(z, z - float(sz) * s));
        }
}
SurfaceKind wood_or_metal(Pcg32 &rng) { return rng.bernoulli(0.5f) ? SurfaceKind::wood : SurfaceKind::metal; }
SurfaceKind wood_or_paint(Pcg32 &rng) { return rng.bernoulli(0.5f) ? SurfaceKind::wood : SurfaceKind::painted; }

void build_bed(FurnitureModel &m) {
    const float hw = m.width / 2, hd = m.depth / 2, h = m.height;
    FurniturePart &frame = add_part(m, "frame", SurfaceKind::wood);
    const float base = 0.3f, top = 0.5f, head = 0.06f;
    box(frame, -hw, 0, -hd + head, hw, base, hd);
    box(frame, -hw, 0, -hd, hw, std::max(h, top + 0.15f), -hd + head);   // headboard
    FurniturePart &mattress = add_part(m, "mattress", SurfaceKind::bedding);
    box(mattress, -hw + 0.02f, base, -hd + head + 0.02f, hw - 0.02f, top, hd - 0.02f);
    box(mattress, -hw + 0.08f, top, -hd + head + 0.05f, hw - 0.08f, top + 0.12f, -hd + head + 0.4f);
    FurniturePart &blanket = add_part(m, "blanket", SurfaceKind::fabric);
    box(blanket, -hw + 0.01f, top, -hd + 0.7f, hw - 0.01f, top + 0.03f, hd - 0.01f);
}

// Sofas and armchairs: base, cushion, backrest and two arms in fabric on short legs.
void build_seat(FurnitureModel &m, Pcg32 &rng, float arm) {
    const float hw = m.width / 2, hd = m.depth / 2, h = m.height;
    const float leg = 0.1f, base = 0.34f, seat = 0.42f, back = std::min(0.22f, 0.3f * m.depth);
    FurniturePart &body = add_part(m, "fabric", SurfaceKind::fabric);
    box(body, -hw, leg, -hd, hw, base, hd);
    box(body, -hw + arm, base, -hd + back, hw - arm, seat, hd);
    box(body, -hw, base, -hd, hw, std::max(h, seat + 0.25f), -hd + back);
    box(body, -hw, base, -hd + back, -hw + arm, seat + 0.2f, hd);
    box(body, hw - arm, base, -hd + back, hw, seat + 0.2f, hd);
    FurniturePart &legs = add_part(m, "legs", wood_or_metal(rng));
    legs4(legs, hw, hd, 0.03f, 0.05f, 0.f, leg);
}

void build_table(FurnitureModel &m, Pcg32 &rng, bool shelf) {
    const float hw = m.width / 2, hd = m.depth / 2, h = m.height;
    FurniturePart &top = add_part(m, "top", SurfaceKind::wood);
    box(top, -hw, h - 0.04f, -hd, hw, h, hd);
    FurniturePart &legs = add_part(m, "legs", wood_or_metal(rng));
    legs4(legs, hw, hd, 0.04f, 0.05f, 0.f, h - 0.04f);
    if (shelf) box(legs, -hw + 0.09f, 0.08f, -hd + 0.09f, hw - 0.09f, 0.1f, hd - 0.09f);
}

void build_desk(FurnitureModel &m, Pcg32 &rng) {
    const float hw = m.width / 2, hd = m.depth / 2, h = m.height;
    FurniturePart &top = add_part(m, "top", SurfaceKind::wood);
    box(top, -hw, h - 0.03f, -hd, hw, h, hd);
    FurniturePart &frame = add_part(m, "frame", wood_or_paint(rng));
    const float drawers = std::min(0.45f, 0.4f * m.width);
    box(frame, -hw, 0, -hd, -hw + 0.03f, h - 0.03f, hd);                       // side panel
    box(frame, hw - drawers, 0, -hd, hw, h - 0.03f, hd);                       // drawer unit
    box(frame, -hw + 0.03f, 0.3f, -hd, hw - drawers, h - 0.03f, -hd + 0.02f);  // modesty panel
}

void build_chair(FurnitureModel &m, Pcg32 &rng) {
    const float hw = m.width / 2, hd = m.depth / 2, h = m.height;
    FurniturePart &seat = add_part(m, "seat", rng.bernoulli(0.5f) ? SurfaceKind::fabric : SurfaceKind::wood);
    box(seat, -hw, 0.42f, -hd, hw, 0.46f, hd);
    FurniturePart &frame = add_part(m, "frame", wood_or_metal(rng));
    legs4(frame, hw, hd, 0.f, 0.035f, 0.f, 0.42f);
    box(frame, -hw, 0.46f, -hd, hw, std::max(h, 0.7f), -hd + 0.03f);
}

void build_shelves(FurnitureModel &m, Pcg32 &rng) {
    const float hw = m.width / 2, hd = m.depth / 2, h = m.height, t = 0.02f;
    FurniturePart &frame = add_part(m, "frame", wood_or_paint(rng));
    box(frame, -hw, 0, -hd, -hw + t, h, hd);
    box(frame, hw - t, 0, -hd, hw, h, hd);
    box(frame, -hw + t, 0, -hd, hw - t, h, -hd + 0.01f);   // back panel
    const int n = std::max(2, int(h / 0.35f));
    const float spacing = (h - t) / float(n);
    for (int i = 0; i <= n; ++i)
        box(frame, -hw + t, float(i) * spacing, -hd + 0.01f, hw - t, float(i) * spacing + t, hd);
    // One block of book spines per shelf: a stripes texture draws the individual books.
    FurniturePart &books = add_part(m, "books", SurfaceKind::books);
    const float inner = m.width - 2 * t;
    for (int i = 0; i < n; ++i) {
        if (!rng.bernoulli(0.8f)) continue;
        const float len = inner * rng.uniform(0.3f, 0.9f), x0 = -hw + t + rng.uniform(0.f, inner - len);
        const float y0 = float(i) * spacing + t, bh = (spacing - t) * rng.uniform(0.55f, 0.85f);
        box(books, x0, y0, -hd + 0.01f, x0 + len, y0 + bh, -hd + 0.01f + std::min(m.depth - 0.02f, 0.22f));
    }
    if (books.mesh.positions.empty()) m.parts.pop_back();
}

// Cabinets, wardrobes, nightstands: a body on a plinth with n_cols x n_rows fronts and handles.
void build_casework(FurnitureModel &m, Pcg32 &rng, int n_cols, int n_rows) {
    const float hw = m.width / 2, hd = m.depth / 2, h = m.height;
    const float plinth = 0.08f, front = 0.02f, handle = 0.01f, gap = 0.004f;
    FurniturePart &body = add_part(m, "body", wood_or_paint(rng));
    box(body, -hw, plinth, -hd, hw, h, hd - front - handle);
    box(body, -hw + 0.03f, 0, -hd + 0.03f, hw - 0.03f, plinth, hd - front - handle - 0.03f);
    FurniturePart &fronts = add_part(m, "fronts", wood_or_paint(rng));
    FurniturePart &handles = add_part(m, "handles", SurfaceKind::metal);
    const float cw = m.width / float(n_cols), rh = (h - plinth) / float(n_rows);
    for (int c = 0; c < n_cols; ++c)
        for (int r = 0; r < n_rows; ++r) {
            const float x0 = -hw + float(c) * cw + gap, x1 = x0 + cw - 2 * gap;
            const float y0 = plinth + float(r) * rh + gap, y1 = y0 + rh - 2 * gap;
            box(fronts, x0, y0, hd - front - handle, x1, y1, hd - handle);
            const float xm = 0.5f * (x0 + x1), hl = std::min(0.05f, 0.3f * (x1 - x0));
            const float yh = n_rows > 1 ? 0.5f * (y0 + y1) : std::min(y1 - 0.05f, 1.05f);
            box(handles, xm - hl, yh - 0.008f, hd - handle, xm + hl, yh + 0.008f, hd);
        }
}

void build_floor_lamp(FurnitureModel &m, Pcg32 &rng) {
    const float r = m.width / 2, h = m.height, shade = std::min(0.3f, 0.3f * h);
    FurniturePart &stand = add_part(m, "stand", SurfaceKind::metal);
    add_cylinder(stand.mesh, {0, 0, 0}, 0.7f * r, 0.03f, 16);
    add_cylinder(stand.mesh, {0, 0.03f, 0}, 0.012f, h - shade - 0.03f, 8);
    FurniturePart &s = add_part(m, "shade", rng.bernoulli(0.6f) ? SurfaceKind::bedding : SurfaceKind::fabric);
    add_cylinder(s.mesh, {0, h - shade, 0}, r, shade, 16);
}

void build_plant(FurnitureModel &m) {
    const float r = m.width / 2, h = m.height, pot = std::min(0.4f, 0.4f * h), rest = h - pot;
    FurniturePart &p = add_part(m, "pot", SurfaceKind::ceramic);
    add_cylinder(p.mesh, {0, 0, 0}, 0.6f * r, pot, 16);
    FurniturePart &leaves = add_part(m, "leaves", SurfaceKind::foliage);
    add_cylinder(leaves.mesh, {0, pot, 0}, r, 0.6f * rest, 12);
    add_cylinder(leaves.mesh, {0, pot + 0.6f * rest, 0}, 0.6f * r, 0.4f * rest, 12);
}


}  // namespace

Vec2f rotate_quarter(int q, Vec2f p) {
    switch (q & 3) {
    case 1: return {p.y, -p.x};
    case 2: return {-p.x, -p.y};
    case 3: return {-p.y, p.x};
    default: return p;
    }
}

FurnitureModel build_furniture(const std::string &archetype, const ArchetypeRanges &ranges,
                               float max_height, Pcg32 &rng) {
    FurnitureModel m;
    m.archetype = archetype;
    m.width = quantize(rng.uniform(ranges.width.x, ranges.width.y));
    m.depth = quantize(rng.uniform(ranges.depth.x, ranges.depth.y));
    m.height = quantize(std::min(rng.uniform(ranges.height.x, ranges.height.y), max_height));
    if (archetype == "floor_lamp" || archetype == "plant") m.depth = m.width;   // round pieces
    m.parts.reserve(4);   // builders hold references to parts while adding the next ones
    if (archetype == "bed") build_bed(m);
    else if (archetype == "sofa") build_seat(m, rng, 0.16f);
    else if (archetype == "armchair") build_seat(m, rng, 0.12f);
    else if (archetype == "table") build_table(m, rng, false);
    else if (archetype == "coffee_table") build_table(m, rng, rng.bernoulli(0.5f));
    else if (archetype == "desk") build_desk(m, rng);
    else if (archetype == "chair") build_chair(m, rng);
    else if (archetype == "shelves") build_shelves(m, rng);
    else if (archetype == "cabinet") {
        const int n_cols = rng.uniform_int(2, 4);   // separate statements: argument order is unspecified
        build_casework(m, rng, n_cols, rng.bernoulli(0.3f) ? 3 : 1);
    }
    else if (archetype == "wardrobe") build_casework(m, rng, rng.uniform_int(2, 3), 1);
    else if (archetype == "nightstand") build_casework(m, rng, 1, rng.uniform_int(1, 3));
    else if (archetype == "floor_lamp") build_floor_lamp(m, rng);
    else if (archetype == "plant") build_plant(m);
    else if (archetype == "carpet") box(add_part(m, "carpet", SurfaceKind::carpet), -m.width / 2, 0, -m.depth / 2, m.width / 2, m.height, m.depth / 2);
    else LTM_THROW("build_furniture(): unknown archetype '", archetype, "'");
    return m;
}

Rect2f model_footprint(const FurnitureModel &model, int quarter_turns, Vec2f c) {
    const bool odd = (quarter_turns & 1) != 0;
    const float hx = (odd ? model.depth : model.width) / 2, hz = (odd ? model.width : model.depth) / 2;
    return {c.x - hx, c.y - hz, c.x + hx, c.y + hz};
}

void place_model(FurnitureModel &model, int quarter_turns, Vec2f c) {
    for (FurniturePart &part : model.parts)
        for (Vec3f &p : part.mesh.positions) {
            const Vec2f r = rotate_quarter(quarter_turns, {p.x, p.z});
            p = {r.x + c.x, p.y, r.y + c.y};   // a proper rotation: winding stays outward
        }
}

}  // namespace ltm
