// scene_transform.h: whole-scene changes whose effect on light transport physics knows exactly —
// the probes of the physics checks (eval/physics_check.h): every emitter ×k (E⁺ ×k), every length ×s
// with radiance kept (E⁺ unchanged), large surfaces recoloured (E⁺ chroma follows).
#pragma once

#include <functional>
#include <string>

#include "ltm/scene/scene.h"

namespace ltm {

/// Multiplies every material's emitted radiance by k >= 0 (constant, procedural and image
/// emission alike; image textures get a scaled copy).
void scale_emission(Scene &scene, float k);

/// The same scene in another unit of length: vertex positions and cameras × s (s > 0); uvs,
/// albedo and radiance unchanged, so every texture lands on the same surface point.
void scale_lengths(Scene &scene, float s);

/// Gives every non-emissive mesh whose name satisfies `select` one new diffuse material of
/// constant `albedo` (named `material_name`). Returns the number of meshes changed.
int recolor_meshes(Scene &scene, const std::function<bool(const std::string &)> &select, Vec3f albedo,
                   const std::string &material_name = "recolored");

/// Mesh names of a generated room's shell: "<room>_walls", "<room>_floor", "<room>_ceiling".
bool is_room_shell_mesh(const std::string &mesh_name);

}  // namespace ltm
