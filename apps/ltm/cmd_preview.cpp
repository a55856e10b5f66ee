// cmd_preview.cpp: `ltm preview <scene> -o preview.png`: albedo / normal / head-light view.
#include <memory>

#include <CLI/CLI.hpp>

#include "cli.h"
#include "ltm/core/log.h"
#include "ltm/render/preview.h"
#include "ltm/scene/scene_loader.h"

namespace ltm::cli {

Camera choose_camera(const Scene &scene, const std::string &name, int width, int height, const std::string &where) {
    Camera cam;
    if (!name.empty()) {
        bool found = false;
        for (const auto &k : scene.cameras)
            if (k.name == name) cam = k, found = true;
        if (!found) LTM_THROW(where, ": no camera named '", name, "'");
    } else if (!scene.cameras.empty()) {
        cam = scene.cameras.front();
    } else {
        cam = automatic_camera(scene, 512, 512);
        log_info("scene has no camera; using an automatic one at ", cam.eye);
    }
    if (width > 0) cam.width = width;
    if (height > 0) cam.height = height;
    return cam;
}

namespace {
struct PreviewArgs {
    std::string scene, output, camera, mode = "shaded";
    int width = 0, height = 0;
};
}  // namespace

Command make_preview_command() {
    return make_command<PreviewArgs>(
        "preview", "Render a quick albedo/normal preview of a scene from its camera (PNG)",
        [](CLI::App &sub, PreviewArgs &a, CommonOptions &) {
            sub.add_option("scene", a.scene, "Scene (json, obj, pbrt, gltf, glb or builtin:<name>)")->required();
            sub.add_option("-o,--output", a.output, "Output PNG")->required();
            sub.add_option("--camera", a.camera, "Camera name (default: the scene's first, else automatic)");
            sub.add_option("--mode", a.mode, "shaded | albedo | normal")->capture_default_str();
            sub.add_option("--width", a.width, "Width in pixels (default: the camera's)")->check(CLI::Range(1, 16384));
            sub.add_option("--height", a.height, "Height in pixels (default: the camera's)")->check(CLI::Range(1, 16384));
        },
        [](PreviewArgs &a, const CommonOptions &) {
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
        });
}

}  // namespace ltm::cli
