// floor_plan.cpp: floor-plan generation (single, L-shaped, BSP, hallway, L-split) and doors over a
// random spanning tree of room adjacency. The meshes around it: procgen/room_shell.h.
#include "ltm/procgen/floor_plan.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "ltm/core/error.h"

namespace ltm {

size_t pick_area_weighted(const std::vector<Rect2f> &rects, Pcg32 &rng) {
    float total = 0.f;
    for (const Rect2f &r : rects) total += r.area();
    float u = rng.uniform(0.f, total);
    for (size_t k = 0; k + 1 < rects.size(); ++k) {
        if (u < rects[k].area()) return k;
        u -= rects[k].area();
    }
    return rects.size() - 1;
}

Rect2f RectMm::to_metres() const {
    return {float(x0) / 1000.f, float(z0) / 1000.f, float(x1) / 1000.f, float(z1) / 1000.f};
}

int64_t PlanRoom::floor_area_mm2() const {
    int64_t a = 0;
    for (const RectMm &r : interiors) a += r.area();
    return a;
}

namespace {

int to_mm(float m) { return int(std::lround(double(m) * 1000.0)); }
int snap_mm(double mm, int snap) { return int(std::lround(mm / snap)) * snap; }
/// Uniform in a metre range, snapped to the plan grid.
int sample_snapped(Pcg32 &rng, Vec2f range, int snap) {
    return std::max(snap, snap_mm(double(rng.uniform(range.x, range.y)) * 1000.0, snap));
}
int ceil_snap(int mm, int snap) { return (mm + snap - 1) / snap * snap; }

struct PlanContext {
    const GenConfig &cfg;
    Pcg32 &rng;
    int snap, min_side;
};

// Splits a length into k pieces of at least `min_len`, all multiples of snap; returns the k+1
// cut positions from 0 to len.
std::vector<int> split_length(PlanContext &c, int len, int k) {
    k = std::max(1, std::min(k, len / c.min_side));
    const int slack = len - k * c.min_side;
    std::vector<int> cuts;
    for (int i = 0; i + 1 < k; ++i) cuts.push_back(snap_mm(double(c.rng.uniform(0.f, float(slack))), c.snap));
    std::sort(cuts.begin(), cuts.end());
    std::vector<int> pos{0};
    for (int i = 0; i + 1 < k; ++i) pos.push_back((i + 1) * c.min_side + std::min(cuts[size_t(i)], slack));
    pos.push_back(len);
    return pos;
}

// Splits the largest splittable cell along its longer side until there are n cells.
void bsp_split(PlanContext &c, std::vector<RectMm> &cells, int n) {
    while (int(cells.size()) < n) {
        int best = -1;
        for (size_t i = 0; i < cells.size(); ++i) {
            const RectMm &r = cells[i];
            if (std::max(r.width(), r.depth()) < 2 * c.min_side) continue;
            if (best < 0 || r.area() > cells[size_t(best)].area()) best = int(i);
        }
        if (best < 0) return;
        const RectMm r = cells[size_t(best)];
        const bool along_x = r.width() > r.depth() || (r.width() == r.depth() && c.rng.bernoulli(0.5f));
        const int len = along_x ? r.width() : r.depth();
        const float f = c.rng.uniform(c.cfg.plan.split_fraction.x, c.cfg.plan.split_fraction.y);
        const int cut = std::clamp(snap_mm(double(len) * double(f), c.snap), c.min_side, len - c.min_side);
        RectMm a = r, b = r;
        if (along_x) a.x1 = b.x0 = r.x0 + cut;
        else a.z1 = b.z0 = r.z0 + cut;
        cells[size_t(best)] = a;
        cells.insert(cells.begin() + best + 1, b);
    }
}

using RoomCells = std::vector<std::vector<RectMm>>;   // per room, its cells

RoomCells plan_single(PlanContext &c) {
    const int w = std::max(c.min_side, sample_snapped(c.rng, c.cfg.rooms.size, c.snap));
    const int d = std::max(c.min_side, sample_snapped(c.rng, c.cfg.rooms.size, c.snap));
    return {{RectMm{0, 0, w, d}}};
}

// An L: a w×d box (sides drawn from `size`) less a corner a×b, as the main part [0,w]x[0,d-b] and
// the wing [0,w-a]x[d-b,d]; empty unless both parts are usable rooms and the cut is b >= min_cut deep.
std::vector<RectMm> l_shape(PlanContext &c, Vec2f size, int min_cut) {
    const int w = sample_snapped(c.rng, size, c.snap);
    const int d = sample_snapped(c.rng, size, c.snap);
    const Vec2f f = c.cfg.plan.l_cut_fraction;
    const int a = snap_mm(double(w) * double(c.rng.uniform(f.x, f.y)), c.snap);
    const int b = snap_mm(double(d) * double(c.rng.uniform(f.x, f.y)), c.snap);
    if (a <= 0 || b < min_cut || w - a < c.min_side || d - b < c.min_side) return {};
    return {RectMm{0, 0, w, d - b}, RectMm{0, d - b, w - a, d}};
}

RoomCells one_room_per_cell(const std::vector<RectMm> &cells) {
    RoomCells rooms;
    for (const RectMm &r : cells) rooms.push_back({r});
    return rooms;
}

RoomCells plan_l_room(PlanContext &c) {
    const std::vector<RectMm> l = l_shape(c, c.cfg.rooms.l_room_size, c.min_side / 2);
    if (l.empty()) return {};
    return {l};
}

RoomCells plan_bsp(PlanContext &c) {
    const int w = sample_snapped(c.rng, c.cfg.plan.footprint_size, c.snap);
    const int d = sample_snapped(c.rng, c.cfg.plan.footprint_size, c.snap);
    std::vector<RectMm> cells{RectMm{0, 0, w, d}};
    bsp_split(c, cells, c.rng.uniform_int(c.cfg.plan.n_rooms.lo, c.cfg.plan.n_rooms.hi));
    return one_room_per_cell(cells);
}

RoomCells plan_hallway(PlanContext &c, std::vector<std::string> &kinds) {
    const GenConfig &cfg = c.cfg;
    const int hw = sample_snapped(c.rng, cfg.plan.hallway_width, c.snap);
    const IntRange per_side = cfg.plan.hallway_rooms_per_side;
    const int k1 = c.rng.uniform_int(per_side.lo, per_side.hi);
    int len = 0;
    for (int i = 0; i < k1; ++i) len += std::max(c.min_side, sample_snapped(c.rng, cfg.rooms.size, c.snap));
    RoomCells rooms{{RectMm{0, 0, len, hw}}};
    kinds = {"hallway"};
    auto add_side = [&](int k, bool above) {
        const int depth = std::max(c.min_side, sample_snapped(c.rng, cfg.rooms.size, c.snap));
        const std::vector<int> pos = split_length(c, len, k);
        for (size_t i = 0; i + 1 < pos.size(); ++i) {
            rooms.push_back({above ? RectMm{pos[i], hw, pos[i + 1], hw + depth}
                                   : RectMm{pos[i], -depth, pos[i + 1], 0}});
            kinds.push_back("room");
        }
    };
    add_side(k1, /*above=*/true);
    if (c.rng.bernoulli(cfg.plan.p_hallway_two_sided))
        add_side(c.rng.uniform_int(per_side.lo, per_side.hi), /*above=*/false);
    return rooms;
}

RoomCells plan_l_split(PlanContext &c) {
    std::vector<RectMm> cells = l_shape(c, c.cfg.plan.footprint_size, c.min_side);
    if (cells.empty()) return {};
    bsp_split(c, cells, std::max(2, c.rng.uniform_int(c.cfg.plan.n_rooms.lo, c.cfg.plan.n_rooms.hi)));
    return one_room_per_cell(cells);
}

// Random axis swap and mirrors, then centre the footprint on the origin (on the snap grid).
void orient_plan(PlanContext &c, RoomCells &rooms) {
    const bool swap = c.rng.bernoulli(0.5f), flip_x = c.rng.bernoulli(0.5f), flip_z = c.rng.bernoulli(0.5f);
    int lo_x = INT32_MAX, lo_z = INT32_MAX, hi_x = INT32_MIN, hi_z = INT32_MIN;
    for (auto &cells : rooms)
        for (RectMm &r : cells) {
            if (swap) r = {r.z0, r.x0, r.z1, r.x1};
            if (flip_x) r = {-r.x1, r.z0, -r.x0, r.z1};
            if (flip_z) r = {r.x0, -r.z1, r.x1, -r.z0};
            lo_x = std::min(lo_x, r.x0), hi_x = std::max(hi_x, r.x1);
            lo_z = std::min(lo_z, r.z0), hi_z = std::max(hi_z, r.z1);
        }
    const int ox = snap_mm(0.5 * (double(lo_x) + double(hi_x)), c.snap);
    const int oz = snap_mm(0.5 * (double(lo_z) + double(hi_z)), c.snap);
    for (auto &cells : rooms)
        for (RectMm &r : cells) r = {r.x0 - ox, r.z0 - oz, r.x1 - ox, r.z1 - oz};
}

// Insets each cell by half a wall, except on sides fully backed by another cell of the same
// room, which move out by half a wall so the room's pieces meet without a wall between them.
std::vector<RectMm> room_interiors(const std::vector<RectMm> &cells, int half_wall) {
    std::vector<RectMm> out;
    for (size_t k = 0; k < cells.size(); ++k) {
        const RectMm &c = cells[k];
        bool covered[4] = {false, false, false, false};   // -x, +x, -z, +z
        for (size_t m = 0; m < cells.size(); ++m) {
            if (m == k) continue;
            const RectMm &o = cells[m];
            const bool spans_z = o.z0 <= c.z0 && o.z1 >= c.z1, spans_x = o.x0 <= c.x0 && o.x1 >= c.x1;
            covered[0] |= o.x1 == c.x0 && spans_z;
            covered[1] |= o.x0 == c.x1 && spans_z;
            covered[2] |= o.z1 == c.z0 && spans_x;
            covered[3] |= o.z0 == c.z1 && spans_x;
        }
        auto off = [&](int side) { return covered[side] ? -half_wall : half_wall; };
        out.push_back({c.x0 + off(0), c.z0 + off(2), c.x1 - off(1), c.z1 - off(3)});
    }
    return out;
}

struct Adjacency {
    int a, b;
    int axis;      // 0: wall along x at z = coord; 1: wall along z at x = coord
    int coord;
    int s0, s1;    // overlap along the wall
};

std::vector<Adjacency> find_adjacencies(const FloorPlan &plan, int min_overlap) {
    std::vector<Adjacency> out;
    for (int i = 0; i < int(plan.rooms.size()); ++i)
        for (int j = i + 1; j < int(plan.rooms.size()); ++j)
            for (const RectMm &p : plan.rooms[size_t(i)].cells)
                for (const RectMm &q : plan.rooms[size_t(j)].cells) {
                    Adjacency adj{i, j, 0, 0, 0, 0};
                    if (p.x1 == q.x0 || q.x1 == p.x0) {
                        adj.axis = 1, adj.coord = p.x1 == q.x0 ? p.x1 : p.x0;
                        adj.s0 = std::max(p.z0, q.z0), adj.s1 = std::min(p.z1, q.z1);
                    } else if (p.z1 == q.z0 || q.z1 == p.z0) {
                        adj.axis = 0, adj.coord = p.z1 == q.z0 ? p.z1 : p.z0;
                        adj.s0 = std::max(p.x0, q.x0), adj.s1 = std::min(p.x1, q.x1);
                    } else {
                        continue;
                    }
                    if (adj.s1 - adj.s0 >= min_overlap) out.push_back(adj);
                }
    return out;
}

PlanDoor make_door(PlanContext &c, const FloorPlan &plan, const Adjacency &adj) {
    const GenConfig::Doors &dc = c.cfg.doors;
    const int half_wall = plan.wall_mm / 2, margin = to_mm(dc.corner_margin);
    const int room_len = adj.s1 - adj.s0 - plan.wall_mm - 2 * margin;   // usable wall length
    const int width = std::min(to_mm(c.rng.uniform(dc.width.x, dc.width.y)), room_len);
    const int lo = adj.s0 + half_wall + margin + width / 2;
    const int center = c.rng.uniform_int(lo, std::max(lo, adj.s1 - half_wall - margin - (width - width / 2)));
    PlanDoor door;
    door.room_a = adj.a, door.room_b = adj.b, door.axis = adj.axis;
    const int w0 = center - width / 2, w1 = w0 + width;
    door.opening = adj.axis == 0 ? RectMm{w0, adj.coord - half_wall, w1, adj.coord + half_wall}
                                 : RectMm{adj.coord - half_wall, w0, adj.coord + half_wall, w1};
    door.height_mm = std::min(to_mm(c.rng.uniform(dc.height.x, dc.height.y)), plan.ceiling_mm - plan.wall_mm);
    return door;
}

// Random spanning tree (Prim with uniform edge choice; hallway edges first) plus extra doors.
bool add_doors(PlanContext &c, FloorPlan &plan) {
    const int n = int(plan.rooms.size());
    const int min_overlap = plan.wall_mm + 2 * to_mm(c.cfg.doors.corner_margin) + to_mm(c.cfg.doors.width.x);
    const std::vector<Adjacency> adj = find_adjacencies(plan, min_overlap);
    std::vector<bool> visited(size_t(n), false), used(adj.size(), false);
    visited[0] = true;
    for (int n_visited = 1; n_visited < n; ++n_visited) {
        std::vector<size_t> frontier, hall;
        for (size_t e = 0; e < adj.size(); ++e) {
            if (visited[size_t(adj[e].a)] == visited[size_t(adj[e].b)]) continue;
            frontier.push_back(e);
            if (plan.rooms[size_t(adj[e].a)].kind == "hallway" || plan.rooms[size_t(adj[e].b)].kind == "hallway")
                hall.push_back(e);
        }
        const std::vector<size_t> &pick_from = hall.empty() ? frontier : hall;
        if (pick_from.empty()) return false;   // disconnected: the caller retries
        const size_t e = pick_from[c.rng.next_below(uint32_t(pick_from.size()))];
        used[e] = true;
        visited[size_t(adj[e].a)] = visited[size_t(adj[e].b)] = true;
    }
    for (size_t e = 0; e < adj.size(); ++e)
        if (used[e] || c.rng.bernoulli(c.cfg.doors.p_extra)) plan.doors.push_back(make_door(c, plan, adj[e]));
    return true;
}

}  // namespace

FloorPlan generate_floor_plan(const GenConfig &cfg, Pcg32 &rng) {
    const GenConfig::Plan &pc = cfg.plan;
    const int snap = std::max(1, to_mm(pc.snap));
    PlanContext c{cfg, rng, snap, ceil_snap(to_mm(cfg.rooms.min_side), snap)};
    const char *names[5] = {"single", "l_room", "bsp", "hallway", "l_split"};
    const float weights[5] = {pc.weight_single, pc.weight_l_room, pc.weight_bsp, pc.weight_hallway,
                              pc.weight_l_split};
    for (int attempt = 0; attempt <= pc.max_attempts; ++attempt) {
        int type = 0;
        if (attempt < pc.max_attempts) {
            float total = 0.f;
            for (float w : weights) total += w;
            float u = rng.uniform(0.f, total);
            while (type < 4 && (u >= weights[type] || weights[type] == 0.f)) u -= weights[type++];
        }   // the last attempt is the fallback: one rectangular room
        FloorPlan plan;
        plan.type = names[type];
        plan.wall_mm = std::max(2, 2 * int(std::lround(double(cfg.walls.thickness) * 500.0)));
        plan.ceiling_mm = sample_snapped(rng, cfg.rooms.ceiling_height, 10);
        std::vector<std::string> kinds;
        RoomCells rooms;
        switch (type) {
        case 0: rooms = plan_single(c); break;
        case 1: rooms = plan_l_room(c); break;
        case 2: rooms = plan_bsp(c); break;
        case 3: rooms = plan_hallway(c, kinds); break;
        default: rooms = plan_l_split(c); break;
        }
        if (rooms.empty() || (type >= 2 && rooms.size() < 2)) continue;
        orient_plan(c, rooms);
        for (size_t r = 0; r < rooms.size(); ++r) {
            PlanRoom room;
            room.kind = kinds.empty() ? "room" : kinds[r];
            room.cells = rooms[r];
            room.interiors = room_interiors(room.cells, plan.wall_mm / 2);
            plan.rooms.push_back(room);
        }
        if (plan.rooms.size() > 1 && !add_doors(c, plan)) continue;
        return plan;
    }
    LTM_THROW("generate_floor_plan(): no plan after ", pc.max_attempts, " attempts");
}

}  // namespace ltm
