// eval_setup.cpp: evaluation views and per-role random streams; see eval_setup.h.
#include "ltm/eval/eval_setup.h"

#include <cmath>
#include <filesystem>
#include <string>

#include "ltm/core/error.h"
#include "ltm/core/log.h"
#include "ltm/core/rng.h"
#include "ltm/render/preview.h"

namespace ltm {

PathTracerConfig eval_tracer_config(uint64_t seed, EvalRole role) {
    PathTracerConfig c;
    c.seed = hash_keys({seed, uint64_t(role)});
    return c;
}

Camera eval_view_camera(const Scene &scene, int v, int n, int width, int height) {
    // A scene without a camera (an OBJ, a glTF without one) is seen as `ltm render` sees it.
    Camera cam = scene.cameras.empty() ? automatic_camera(scene, width, height) : scene.cameras.front();
    cam.width = width, cam.height = height;
    if (v > 0) {
        const float a = 2.f * k_pi * float(v) / float(n), c = std::cos(a), s = std::sin(a);
        const Vec3f d = cam.target - cam.eye;
        cam.target = cam.eye + Vec3f{c * d.x + s * d.z, d.y, -s * d.x + c * d.z};
        cam.name += "-yaw" + std::to_string(360 * v / n);
    }
    return cam;
}

bool is_seed_range(const std::string &spec) {
    return spec.find(':') != std::string::npos && spec.find_first_not_of("0123456789:") == std::string::npos &&
           !std::filesystem::exists(spec);
}

std::vector<std::string> scene_labels(const std::vector<std::string> &specs) {
    namespace fs = std::filesystem;
    const std::string builtin = "builtin:";
    auto is_file = [&](const std::string &s) { return !is_seed_range(s) && s.rfind(builtin, 0) != 0; };
    std::vector<std::string> out;
    for (const auto &s : specs) {
        if (is_seed_range(s)) continue;
        if (!is_file(s)) {
            out.push_back("builtin-" + s.substr(builtin.size()));
            continue;
        }
        // Absolute, so that ./scene.pbrt is named by its folder, not by '.'.
        const fs::path fp = fs::absolute(s).lexically_normal();
        std::string name = fp.stem().string();
        for (const auto &other : specs)
            if (&other != &s && is_file(other) && fs::path(other).stem() == fp.stem() && !fp.parent_path().filename().empty())
                name = fp.parent_path().filename().string();
        out.push_back(name);
    }
    return out;
}

std::optional<EvalView> eval_view(const EmbreeAccel &accel, const std::string &scene_name, int v, int n, int width, int height) {
    EvalView view{eval_view_camera(accel.scene(), v, n, width, height), {}};
    view.gbuffer = render_gbuffer(accel, view.camera);
    if (view.gbuffer.n_hits() == 0) {
        log_warn("eval: ", scene_name, " view ", view.camera.name, " sees nothing; skipped");
        return std::nullopt;
    }
    return view;
}

}  // namespace ltm
