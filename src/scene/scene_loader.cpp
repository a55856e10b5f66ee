// scene_loader.cpp: load_scene() dispatches on the path's form and validates the result.
#include "ltm/scene/scene_loader.h"

#include "ltm/core/error.h"
#include "ltm/core/file_util.h"
#include "ltm/scene/builtin_scenes.h"
#include "ltm/scene/gltf_reader.h"
#include "ltm/scene/obj_io.h"
#include "ltm/scene/pbrt_reader.h"
#include "ltm/scene/scene_json.h"

namespace ltm {

Scene load_scene(const std::string &path, const ValidateOptions &opt) {
    Scene s;
    const std::string builtin_prefix = "builtin:";
    if (path.rfind(builtin_prefix, 0) == 0) {
        s = builtin_scene(path.substr(builtin_prefix.size()));
    } else {
        const std::string ext = file_extension(path);
        if (ext == "json") {
            const std::string dir = parent_dir(path);
            s = scene_from_json(parse_json_file(path), path, dir.empty() ? "." : dir);
        } else if (ext == "obj") {
            s = load_obj(path);
        } else if (ext == "pbrt") {
            s = load_pbrt(path);
        } else if (ext == "gltf" || ext == "glb") {
            s = load_gltf(path);
        } else {
            LTM_THROW(path, ": unknown scene format '.", ext, "' (expected .json, .obj, .pbrt, .gltf, .glb or builtin:<name>)");
        }
    }
    validate_scene(s, path, opt);
    return s;
}

}  // namespace ltm
