// scene_edit.h: edits on a scene JSON document (paper Figs. 7–9: move a light, move an object,
// change a material) — the model needs no retraining, so an edit is just a new scene file.
// Edits work on the JSON so that everything else in the file (textures, metadata) round-trips.
#pragma once

#include <string>

#include "ltm/core/json_util.h"
#include "ltm/core/math.h"

namespace ltm {

/// Translates every mesh named `name` or whose name starts with `name` + "_" (generated objects
/// are groups: "bed1_frame", "bed1_mattress", …) by `offset` metres, composing with an existing
/// transform (translate added last). Returns the number of meshes moved; throws if none match.
int translate_meshes(Json &scene, const std::string &name, Vec3f offset, const std::string &where);

/// Sets material `name`'s albedo to a constant colour (each component in [0, 1]).
void set_albedo(Json &scene, const std::string &name, Vec3f albedo, const std::string &where);

/// Multiplies emissive material `name`'s radiance by k >= 0 (constant radiance only).
void scale_radiance(Json &scene, const std::string &name, float k, const std::string &where);

}  // namespace ltm
