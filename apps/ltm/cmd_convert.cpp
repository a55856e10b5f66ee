// cmd_convert.cpp: `ltm convert IN -o OUT.scene.json`: any scene ltm reads (pbrt-v4, glTF, OBJ,
// JSON, builtin) → ltm scene JSON (meshes inline; image textures referenced relative to the
// output; embedded images written beside it as PNG).
#include <filesystem>

#include <CLI/CLI.hpp>

#include "cli.h"
#include "ltm/core/error.h"
#include "ltm/core/file_util.h"
#include "ltm/core/image.h"
#include "ltm/core/log.h"
#include "ltm/scene/scene_json.h"
#include "ltm/scene/scene_loader.h"

namespace ltm::cli {

namespace {
struct ConvertArgs {
    std::string scene, output;
};

void declare(CLI::App &sub, ConvertArgs &a) {
    add_scene_argument(sub, a.scene);
    add_output_option(sub, a.output, "Output scene JSON");
}

void run(const ConvertArgs &a, const CommonOptions &) {
    if (file_extension(a.output) != "json") LTM_THROW(a.output, ": output must be a .json file");
    Scene scene = load_scene(a.scene);
    // Images that exist only in memory (embedded in a .glb or a data URI) are written as PNG
    // beside the output, so the JSON can reference them.
    int written = 0;
    for (Material &m : scene.materials)
        for (Texture *t : {&m.albedo, &m.emission})
            if (t->kind == TextureKind::image && t->image && !std::filesystem::is_regular_file(t->image_path)) {
                const std::string png = detail::concat(a.output.substr(0, a.output.size() - 5), "_", m.name,
                                                       t == &m.albedo ? "_albedo" : "_emission", ".png");
                write_png(png, *t->image);
                t->image_path = png;
                ++written;
            }
    save_scene_json(scene, a.output);
    if (written) log_info("wrote ", written, " embedded image(s) as PNG beside ", a.output);
    const Vec3f e = scene.bounds().extent();
    log_info(a.scene, " -> ", a.output, ": ", scene.meshes.size(), " meshes, ", scene.n_triangles(), " triangles, ",
             scene.materials.size(), " materials, ", scene.cameras.size(), " cameras, extent ", e.x, " x ", e.y, " x ", e.z);
}
}  // namespace

Command make_convert_command() {
    return make_command(
        "convert", "Convert a scene (pbrt-v4, glTF 2.0, OBJ, JSON, builtin) to ltm scene JSON",
        declare, run);
}

}  // namespace ltm::cli
