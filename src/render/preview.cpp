// preview.cpp: primary rays only; a person's first look at what the generator produced.
#include "ltm/render/preview.h"

#include <atomic>

#include "ltm/core/error.h"
#include "ltm/core/parallel.h"
#include "ltm/render/interaction.h"

namespace ltm {

PreviewMode parse_preview_mode(const std::string &s) {
    if (s == "shaded") return PreviewMode::shaded;
    if (s == "albedo") return PreviewMode::albedo;
    if (s == "normal") return PreviewMode::normal;
    LTM_THROW("--mode ", s, ": unknown preview mode (shaded, albedo, normal)");
}

Image render_preview(const EmbreeAccel &accel, const Camera &camera, PreviewMode mode, float *hit_fraction) {
    const Scene &scene = accel.scene();
    Image img(camera.width, camera.height);
    std::atomic<int64_t> hits{0};
    parallel_for(0, camera.height, 8, [&](int64_t y0, int64_t y1) {
        int64_t local_hits = 0;
        for (int64_t y = y0; y < y1; ++y)
            for (int x = 0; x < camera.width; ++x) {
                const Vec3f d = camera.ray_direction(float(x) + 0.5f, float(y) + 0.5f);
                const auto hit = accel.intersect({camera.eye, d});
                if (!hit) continue;
                ++local_hits;
                const Ray ray{camera.eye, d};
                const SurfaceInteraction si = make_interaction(scene, ray, *hit);
                Vec3f c;
                if (mode == PreviewMode::normal) {
                    c = (si.n + Vec3f(1.f)) * 0.5f;
                } else if (max_component(si.emitted()) > 0.f) {
                    const Vec3f e = si.emitted();
                    c = e / max_component(e);
                } else {
                    c = si.albedo();
                    if (mode == PreviewMode::shaded)   // head-light; back faces dark so inside-out geometry shows
                        c = c * (si.front ? 0.2f + 0.8f * -dot(si.n, d) : 0.05f);
                }
                img.at(x, int(y)) = c;
            }
        hits += local_hits;
    });
    if (hit_fraction) *hit_fraction = float(hits.load()) / float(int64_t(camera.width) * camera.height);
    return img;
}

Camera automatic_camera(const Scene &scene, int width, int height) {
    const Bounds3f b = scene.bounds();
    const Vec3f c = b.center(), e = b.extent();
    Camera cam;
    cam.name = "auto";
    cam.width = width, cam.height = height;
    cam.fov_y_deg = 60.f;
    // Outside the bounds, on the +z side, raised, looking at the centre: frames any object.
    const float dist = 0.5f * e.y / std::tan(0.5f * cam.fov_y_deg * k_pi / 180.f) + 0.5f * e.z;
    cam.eye = c + Vec3f(0.35f * e.x, 0.25f * e.y, std::max(dist, 0.6f * max_component(e)) * 1.1f);
    cam.target = c;
    return cam;
}

}  // namespace ltm
