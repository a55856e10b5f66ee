// scene_json.h: ltm scene JSON (strict; docs/formats.md): parse, serialise, save.
#pragma once

#include <string>

#include "ltm/core/json_util.h"
#include "ltm/scene/scene.h"

namespace ltm {

inline constexpr int k_scene_format_version = 1;

/// Parses scene JSON. `where` names the file for errors, `base_dir` resolves relative paths.
Scene scene_from_json(const Json &j, const std::string &where, const std::string &base_dir);

/// Serialises a scene (all meshes inline). Texture paths are written relative to `base_dir`.
OrderedJson scene_to_json(const Scene &scene, const std::string &base_dir = "");

/// Writes scene JSON atomically (byte-stable formatting, see dump_json_compact).
void save_scene_json(const Scene &scene, const std::string &path);

}  // namespace ltm
