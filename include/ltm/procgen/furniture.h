// furniture.h: furniture archetypes built from boxes and cylinders, and their placement in a
// room without interpenetration, with clearance, clear of doors and (for tall pieces) lights.
#pragma once

#include <string>
#include <vector>

#include "ltm/core/rng.h"
#include "ltm/procgen/floor_plan.h"
#include "ltm/procgen/gen_config.h"
#include "ltm/procgen/palettes.h"
#include "ltm/scene/mesh.h"

namespace ltm {

/// How an archetype is placed: its back against a wall, free-standing, or flat on the floor
/// (carpets: kept free of every other footprint, since a piece standing on one would cut it).
enum class Placement { wall, free, floor };

/// One material slot of a piece ("frame", "fabric", "top"...): its geometry and surface kind.
struct FurniturePart {
    std::string slot;
    SurfaceKind kind = SurfaceKind::wood;
    TriangleMesh mesh;
};

/// A piece of furniture. Local frame: x in [-w/2, w/2], y in [0, h], z in [-d/2, d/2], front
/// toward +z (the back faces the wall). After place_model() the parts are in world space.
struct FurnitureModel {
    std::string archetype;
    float width = 0, depth = 0, height = 0;
    std::vector<FurniturePart> parts;
};

/// The archetypes, sorted by name (the keys of default_archetypes()).
const std::vector<std::string> &archetype_names();
Placement archetype_placement(const std::string &archetype);

/// Builds an archetype with dimensions drawn from its ranges (height capped at max_height).
FurnitureModel build_furniture(const std::string &archetype, const ArchetypeRanges &ranges,
                               float max_height, Pcg32 &rng);

/// World footprint of a model turned by quarter_turns·90° about +y and centred at `center`.
Rect2f model_footprint(const FurnitureModel &model, int quarter_turns, Vec2f center);
/// Moves the parts to world space: exact quarter turns (no trigonometry), then translation.
void place_model(FurnitureModel &model, int quarter_turns, Vec2f center);

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
