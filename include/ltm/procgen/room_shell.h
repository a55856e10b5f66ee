// room_shell.h: the meshes around a floor plan — per room a floor, a ceiling and walls, watertight,
// normals into the air, door openings cut through.
#pragma once

#include <vector>

#include "ltm/procgen/floor_plan.h"
#include "ltm/scene/mesh.h"

namespace ltm {

/// Which surface a shell face belongs to.
enum class ShellSurface { floor, ceiling, walls };

/// The room shell: per room, one mesh each for floor, ceiling and walls, normals into the air.
struct RoomShell {
    TriangleMesh floor, ceiling, walls;
};

/// Builds the watertight shell: air = room interiors + door openings; every face between an air
/// cell and a solid cell of the rectilinear grid over all breakpoints becomes a quad facing the
/// air. Faces of door cells go to room_a (threshold to its floor, jambs and lintel to its
/// walls). uvs are world-space metres, so patterns continue across faces.
std::vector<RoomShell> build_room_shell(const FloorPlan &plan);

}  // namespace ltm
