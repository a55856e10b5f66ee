// scene_loader.h: one entry point for every scene source — ltm JSON, OBJ, pbrt-v4, glTF, builtin.
#pragma once

#include <string>

#include "ltm/scene/scene.h"

namespace ltm {

/// Loads "file.json" / "file.scene.json" (ltm scene JSON), "file.obj" (with its MTL),
/// "file.pbrt" (pbrt-v4 subset, scene/pbrt_reader.h), "file.gltf" / "file.glb" (glTF 2.0,
/// scene/gltf_reader.h) or "builtin:<name>" (see
/// builtin_scene_names()). Validates the result (validate_scene).
Scene load_scene(const std::string &path, const ValidateOptions &opt = {});

}  // namespace ltm
