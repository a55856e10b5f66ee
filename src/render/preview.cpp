// preview.cpp: primary rays only; a person's first look at what the generator produced.
#include "ltm/render/preview.h"

#include <atomic>

#include "ltm/core/error.h"
#include "ltm/core/parallel.h"

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
                const TriangleMesh &mesh = scene.meshes[hit->mesh];
                const Material &mat = scene.materials[size_t(mesh.material)];
                const float b0 = 1.f - hit->b1 - hit->b2;
                const Vec2f t0 = mesh.uv(hit->triangle, 0), t1 = mesh.uv(hit->triangle, 1), t2 = mesh.uv(hit->triangle, 2);
                const Vec2f uv{t0.x * b0 + t1.x * hit->b1 + t2.x * hit->b2, t0.y * b0 + t1.y * hit->b1 + t2.y * hit->b2};
                Vec3f c;
                if (mode == PreviewMode::normal) {
                    c = (hit->n + Vec3f(1.f)) * 0.5f;
                } else if (mat.is_emissive() && dot(hit->n, d) < 0.f) {
                    const Vec3f e = mat.emission.eval(uv);
                    c = e / std::max(max_component(e), 1e-6f);
                } else {
                    c = mat.albedo.eval(uv);
                    if (mode == PreviewMode::shaded) {
                        // Head-light; back faces darkened so inside-out geometry is visible.
                        const float cos_theta = -dot(hit->n, d);
                        c = c * (cos_theta > 0.f ? 0.2f + 0.8f * cos_theta : 0.05f);
                    }
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
