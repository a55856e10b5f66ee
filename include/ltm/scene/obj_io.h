// obj_io.h: Wavefront OBJ + MTL scenes (tinyobjloader).
#pragma once

#include <string>

#include "ltm/scene/scene.h"

namespace ltm {

/// OBJ + MTL via tinyobjloader: Kd / map_Kd → albedo, Ke / map_Ke → emission. Polygons are
/// triangulated; normals in the file are ignored (geometric normals follow the winding).
Scene load_obj(const std::string &path);
/// The same from text in memory (the MTL given as text; texture maps are an error here, since
/// they name files). `where` names the source in errors. Used by the fuzzer.
Scene parse_obj(const std::string &obj_text, const std::string &mtl_text, const std::string &where);

}  // namespace ltm
