// fixtures.h: what real rooms have and the default houses do not (issue #29, GenConfig::Fixtures):
// windows through outside walls (a sky behind them, or nothing), recessed ceiling lights, lit floor
// and table lamps with open shades, wall sconces, light strips, pleated curtains, ceiling lights
// switched off in rooms lit otherwise. Two stages of generate_indoor(): openings before the
// furniture (they change the shell and keep furniture off the curtains), the rest once the meshes
// exist. Each draws from its own stream hash(seed, k_fixtures, what, index), and draws nothing at
// all when its chance is 0: with the default config every house is the seed's house, byte for byte.
#pragma once

#include <cstdint>
#include <vector>

#include "ltm/procgen/floor_plan.h"
#include "ltm/procgen/gen_config.h"
#include "ltm/procgen/indoor_generator.h"
#include "ltm/procgen/room_shell.h"
#include "ltm/scene/scene.h"
#include "ltm/scene/texture.h"

namespace ltm {

/// Appends a generated mesh with its own material (named like it): positions and uvs on the
/// generator's 1e-4 grid, so the output is byte-stable. Returns its index in scene.meshes.
int add_generated_mesh(Scene &scene, TriangleMesh mesh, const Texture &albedo, Vec3f emission = Vec3f(0.f));

/// Stage 1, after the ceiling lights and before the furniture: windows on outside walls (a wall
/// whose far side is solid for the window's depth plus a wall's thickness) into plan.openings and
/// g.windows, with their curtains' footprints; recesses above ceiling lights (the light moves up
/// into its recess, its power unchanged).
void place_openings(GeneratedScene &g, FloorPlan &plan, const GenConfig &cfg, uint64_t seed);

/// Stage 2, after the shell, furniture and ceiling-light meshes: window panes (a sky emitter, or
/// none: a hole), curtains, lit floor lamps (open shade, bulb), table lamps, sconces, light strips,
/// and ceiling lights off in rooms lit by these or by a sky (never the last emitter).
void add_fixtures(GeneratedScene &g, std::vector<RoomShell> &shells, const GenConfig &cfg, uint64_t seed);

}  // namespace ltm
