// room_shell.h: the meshes around a floor plan — per room a floor, a ceiling and walls, watertight,
// normals into the air, door openings cut through.
#pragma once

#include <map>
#include <vector>

#include "ltm/procgen/floor_plan.h"
#include "ltm/scene/mesh.h"

namespace ltm {

/// Which surface a shell face belongs to.
enum class ShellSurface { floor, ceiling, walls };

/// The room shell: per room, one mesh each for floor, ceiling and walls, normals into the air.
struct RoomShell {
    TriangleMesh floor, ceiling, walls;
    /// Window panes of this room: opening index (FloorPlan::openings) -> the outer end face of
    /// the window, facing the room. Recess sides are walls, their tops ceiling.
    std::map<int, TriangleMesh> panes;
};

/// Builds the watertight shell: air = room interiors + door openings; every face between an air
/// cell and a solid cell of the rectilinear grid over all breakpoints becomes a quad facing the
/// air. Faces of door cells go to room_a (threshold to its floor, jambs and lintel to its
/// walls). Window openings (sills, jambs, heads) are walls of their room, their outer end face its
/// pane. uvs are world-space metres, so patterns continue across faces.
std::vector<RoomShell> build_room_shell(const FloorPlan &plan);

}  // namespace ltm
