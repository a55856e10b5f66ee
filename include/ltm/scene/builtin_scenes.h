// builtin_scenes.h: small analytic scenes for tests, docs and demos ("builtin:<name>").
#pragma once

#include <string>
#include <vector>

#include "ltm/scene/scene.h"

namespace ltm {

/// The Cornell box with the measured geometry (Cornell PCG data, in metres) and the usual RGB
/// reflectances; the light sits 0.1 mm below the ceiling, facing down.
Scene cornell_box();

/// Closed unit cube [0,1]³ whose inward-facing walls all have albedo ρ and emit Le:
/// L = Le/(1−ρ) everywhere (infinite depth), E = π·Le/(1−ρ).
Scene furnace_box(float albedo, float emission);

/// A 5 m × 4 m × 2.7 m room (inward walls) with one 1 m × 1 m ceiling quad light and a box.
Scene quad_light_room();

/// Names accepted by "builtin:<name>": cornell-box, furnace, quad-light-room.
std::vector<std::string> builtin_scene_names();
/// Throws for an unknown name, listing the known ones.
Scene builtin_scene(const std::string &name);

}  // namespace ltm
