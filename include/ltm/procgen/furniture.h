// furniture.h: furniture archetypes built from boxes and cylinders in a local frame, and their
// placement in world space by quarter turns. Where pieces go in a room: procgen/room_layout.h.
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

/// A plan offset (x, z) turned by q·90° about +y: q = 1 takes local +z (the front) to world +x.
Vec2f rotate_quarter(int q, Vec2f p);
/// World footprint of a model turned by quarter_turns·90° about +y and centred at `center`.
Rect2f model_footprint(const FurnitureModel &model, int quarter_turns, Vec2f center);
/// Moves the parts to world space: exact quarter turns (no trigonometry), then translation.
void place_model(FurnitureModel &model, int quarter_turns, Vec2f center);

}  // namespace ltm
