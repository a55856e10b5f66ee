// cmd_convert.cpp: `ltm convert IN -o OUT.scene.json`: any scene ltm reads (pbrt-v4, OBJ, JSON,
// builtin) → ltm scene JSON (meshes inline; image textures referenced relative to the output).
#include <memory>

#include <CLI/CLI.hpp>

#include "cli.h"
#include "ltm/core/error.h"
#include "ltm/core/file_util.h"
#include "ltm/core/log.h"
#include "ltm/scene/scene_io.h"

namespace ltm::cli {

namespace {
struct ConvertArgs {
    std::string scene, output;
};
}  // namespace

Command make_convert_command() {
    auto a = std::make_shared<ConvertArgs>();
    Command c;
    c.name = "convert";
    c.help = "Convert a scene (pbrt-v4, OBJ, JSON, builtin) to ltm scene JSON";
    c.setup = [a](CLI::App &sub, CommonOptions &) {
        sub.add_option("scene", a->scene, "Scene (json, obj, pbrt or builtin:<name>)")->required();
        sub.add_option("-o,--output", a->output, "Output scene JSON")->required();
    };
    c.run = [a](const CommonOptions &) {
        if (file_extension(a->output) != "json") LTM_THROW(a->output, ": output must be a .json file");
        const Scene scene = load_scene(a->scene);
        save_scene_json(scene, a->output);
        const Vec3f e = scene.bounds().extent();
        log_info(a->scene, " -> ", a->output, ": ", scene.meshes.size(), " meshes, ", scene.n_triangles(), " triangles, ",
                 scene.materials.size(), " materials, ", scene.cameras.size(), " cameras, extent ", e.x, " x ", e.y, " x ", e.z);
    };
    return c;
}

}  // namespace ltm::cli
