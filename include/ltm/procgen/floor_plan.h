// floor_plan.h: 2D floor plans (rooms as unions of axis-aligned rectangles, doors on shared
// walls) and the watertight 3D room shell built from them. Plan coordinates are integer
// millimetres on the xz plane, so walls, doors and the shell grid are exact.
#pragma once

#include <cstdint>

#include <string>
#include <vector>

#include "ltm/core/rng.h"
#include "ltm/procgen/gen_config.h"

namespace ltm {

/// Axis-aligned rectangle on the xz plane, metres.
struct Rect2f {
    float x0 = 0, z0 = 0, x1 = 0, z1 = 0;
    float width() const { return x1 - x0; }
    float depth() const { return z1 - z0; }
    float area() const { return width() * depth(); }
    Rect2f expanded(float d) const { return {x0 - d, z0 - d, x1 + d, z1 + d}; }
    bool contains(const Rect2f &r, float eps = 0.f) const {
        return r.x0 >= x0 - eps && r.z0 >= z0 - eps && r.x1 <= x1 + eps && r.z1 <= z1 + eps;
    }
    bool contains(Vec2f p) const { return p.x >= x0 && p.x <= x1 && p.y >= z0 && p.y <= z1; }
    /// Open-interior overlap: rectangles that only touch do not overlap.
    bool overlaps(const Rect2f &r) const {
        return x0 < r.x1 && r.x0 < x1 && z0 < r.z1 && r.z0 < z1;
    }
};

/// Index of one of `rects`, drawn in proportion to its area (one rng.uniform draw).
size_t pick_area_weighted(const std::vector<Rect2f> &rects, Pcg32 &rng);

/// Rectangle in integer millimetres.
struct RectMm {
    int x0 = 0, z0 = 0, x1 = 0, z1 = 0;
    int width() const { return x1 - x0; }
    int depth() const { return z1 - z0; }
    int64_t area() const { return int64_t(width()) * depth(); }
    Rect2f to_metres() const;
};

struct PlanRoom {
    std::string kind = "room";       ///< "room" or "hallway"
    std::vector<RectMm> cells;       ///< partition cells (wall centre lines), cells[0] the main one
    std::vector<RectMm> interiors;   ///< air rectangles: cells inset by half a wall thickness
    int64_t floor_area_mm2() const;
};

/// An opening through the wall between two rooms: a box over `opening` from y = 0 to height.
struct PlanDoor {
    int room_a = -1, room_b = -1;
    RectMm opening;       ///< plan rectangle of the hole through the wall (wall thickness deep)
    int axis = 0;         ///< 0: the wall runs along x (door faces ±z); 1: the wall runs along z
    int height_mm = 0;
};

/// A hole the fixtures cut into the shell (procgen/fixtures.h), a box of air in millimetres: a
/// window through an outside wall (the face at its outer end, against solid, is the window's pane)
/// or a recess above the ceiling that holds a light.
struct PlanOpening {
    enum class Kind { window, recess };
    Kind kind = Kind::window;
    int room = -1;
    int lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};   ///< (x, y, z) mm
    int outward_axis = 0;   ///< windows: 0 (x) or 2 (z), the axis pointing out of the room
    int outward_sign = 1;   ///< +1: the pane is at hi[axis]; -1: at lo[axis]
};

struct FloorPlan {
    std::string type;     ///< single, l_room, bsp, hallway, l_split
    std::vector<PlanRoom> rooms;
    std::vector<PlanDoor> doors;
    std::vector<PlanOpening> openings;   ///< empty unless fixtures are on
    int ceiling_mm = 2700;
    int wall_mm = 100;
};

/// Draws a plan type by the config weights and builds it; every room is reachable from room 0
/// through doors (spanning tree over room adjacency plus optional extra doors). Retries on
/// failure and falls back to a single rectangular room.
FloorPlan generate_floor_plan(const GenConfig &cfg, Pcg32 &rng);

}  // namespace ltm
