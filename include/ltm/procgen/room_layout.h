// room_layout.h: the furniture of one room — a role, its anchor piece with companions, an
// optional carpet and further pieces, placed without interpenetration, with clearance, clear of
// doors and (for tall pieces) lights.
#pragma once

#include <string>
#include <vector>

#include "ltm/core/rng.h"
#include "ltm/procgen/floor_plan.h"
#include "ltm/procgen/furniture.h"
#include "ltm/procgen/gen_config.h"

namespace ltm {

/// A placed piece in world space.
struct PlacedItem {
    FurnitureModel model;
    Rect2f footprint;
    int quarter_turns = 0;
    Vec2f center;
};

/// The furniture of one room and the role that chose it.
struct RoomLayout {
    std::string role;   ///< bedroom, living, dining, office, hallway
    std::vector<PlacedItem> items;
};

/// What furnish_room() needs to know about a room.
struct RoomLayoutInput {
    std::string kind = "room";          ///< "room" or "hallway"
    std::vector<Rect2f> rects;          ///< interior rectangles (air), metres
    float ceiling_height = 2.7f;
    std::vector<Rect2f> keep_out;       ///< door clear zones: no furniture at all
    std::vector<Rect2f> tall_keep_out;  ///< lights grown by the clearance: no tall furniture
    int max_items = -1;                 ///< cap (ajar light room); -1: from the config density
};

/// Picks a role (bedroom, living, dining, office; hallways get their own list), places its
/// anchor piece with companions (nightstands, chairs, coffee table), an optional carpet and
/// further pieces by rejection sampling. Guarantees: every footprint lies inside one interior
/// rectangle, footprints are at least `clearance` apart, none meets a keep-out zone, and no
/// piece taller than lights.tall_height meets a tall keep-out zone.
RoomLayout furnish_room(const RoomLayoutInput &room, const GenConfig &cfg, Pcg32 &rng);

}  // namespace ltm
