// eval_setup.cpp: evaluation views and per-role random streams; see eval_setup.h.
#include "ltm/eval/eval_setup.h"

#include <cmath>
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
