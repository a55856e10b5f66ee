// scene_io.h: reading and writing scenes: ltm scene JSON (strict), OBJ+MTL, built-in names.
#pragma once

#include <string>

#include "ltm/core/json_util.h"
#include "ltm/scene/scene.h"

namespace ltm {

inline constexpr int k_scene_format_version = 1;

/// Loads "file.json" / "file.scene.json" (ltm scene JSON), "file.obj" (with its MTL),
/// "file.pbrt" (pbrt-v4 subset, scene/pbrt_reader.h), "file.gltf" / "file.glb" (glTF 2.0,
/// scene/gltf_reader.h) or "builtin:<name>" (see
/// builtin_scene_names()). Validates the result (validate_scene).
Scene load_scene(const std::string &path, const ValidateOptions &opt = {});

/// Parses scene JSON. `where` names the file for errors, `base_dir` resolves relative paths.
Scene scene_from_json(const Json &j, const std::string &where, const std::string &base_dir);

/// Serialises a scene (all meshes inline). Texture paths are written relative to `base_dir`.
OrderedJson scene_to_json(const Scene &scene, const std::string &base_dir = "");

/// Writes scene JSON atomically (byte-stable formatting, see dump_json_compact).
void save_scene_json(const Scene &scene, const std::string &path);

/// OBJ + MTL via tinyobjloader: Kd / map_Kd → albedo, Ke / map_Ke → emission. Polygons are
/// triangulated; normals in the file are ignored (geometric normals follow the winding).
Scene load_obj(const std::string &path);
/// The same from text in memory (the MTL given as text; texture maps are an error here, since
/// they name files). `where` names the source in errors. Used by the fuzzer.
Scene parse_obj(const std::string &obj_text, const std::string &mtl_text, const std::string &where);

}  // namespace ltm
