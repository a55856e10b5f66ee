// cmd_preview.cpp: `ltm preview <scene> -o preview.png`: albedo / normal / head-light view.

#include <CLI/CLI.hpp>

#include "cli.h"
#include "ltm/core/log.h"
#include "ltm/render/preview.h"
#include "ltm/scene/scene_loader.h"

namespace ltm::cli {

namespace {
struct PreviewArgs {
    std::string scene, output, camera, mode = "shaded";
    int width = 0, height = 0;
};

void declare(CLI::App &sub, PreviewArgs &a) {
    add_scene_argument(sub, a.scene);
    add_output_option(sub, a.output, "Output PNG");
    add_camera_option(sub, a.camera);
    sub.add_option("--mode", a.mode, "shaded | albedo | normal")->capture_default_str();
    sub.add_option("--width", a.width, "Width in pixels (default: the camera's)")->check(CLI::Range(1, 16384));
    sub.add_option("--height", a.height, "Height in pixels (default: the camera's)")->check(CLI::Range(1, 16384));
}

void run(const PreviewArgs &a, const CommonOptions &) {
    const PreviewMode mode = parse_preview_mode(a.mode);
    ValidateOptions vopt;
    vopt.require_emitter = false;   // looking at an unlit scene is allowed
    const Scene scene = load_scene(a.scene, vopt);
    const Camera cam = choose_camera(scene, a.camera, a.width, a.height, a.scene);
    const EmbreeAccel accel(scene);
    float hit_fraction = 0.f;
    const Image img = render_preview(accel, cam, mode, &hit_fraction);
    if (hit_fraction == 0.f) LTM_THROW(a.scene, ": camera '", cam.name, "' sees no geometry");
    write_png(a.output, img);
    log_info("preview ", cam.width, "x", cam.height, " (", a.mode, ") -> ", a.output);
}
}  // namespace

Command make_preview_command() {
    return make_command(
        "preview", "Render a quick albedo/normal preview of a scene from its camera (PNG)",
        declare, run);
}

}  // namespace ltm::cli
