// view_samples.cpp: random primary rays → surface samples. Each draw has its own generator
// (hash of seed, stream, index), so the points do not depend on the thread count.
#include "ltm/render/view_samples.h"

#include "ltm/core/error.h"
#include "ltm/core/parallel.h"
#include "ltm/core/rng.h"
#include "ltm/render/interaction.h"

namespace ltm {

std::vector<SurfaceSample> sample_view_points(const EmbreeAccel &accel, int64_t n, uint64_t seed) {
    const Scene &scene = accel.scene();
    if (n < 0 || n > k_max_sample_count) LTM_THROW("view samples: count ", n, " out of range");
    if (n > 0 && scene.cameras.empty()) LTM_THROW(scene.name, ": view samples need a camera, the scene has none");
    constexpr int k_max_tries = 64;
    std::vector<SurfaceSample> out(static_cast<size_t>(n));
    std::vector<uint8_t> ok(static_cast<size_t>(n), 0);
    parallel_for(0, n, 256, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            const Camera &cam = scene.cameras[size_t(i) % scene.cameras.size()];
            Pcg32 rng(hash_keys({seed, uint64_t(SampleStream::view_points), uint64_t(i)}));
            for (int t = 0; t < k_max_tries; ++t) {
                const float px = rng.next_float() * float(cam.width), py = rng.next_float() * float(cam.height);
                const Ray ray{cam.eye, cam.ray_direction(px, py)};
                const std::optional<Hit> hit = accel.intersect(ray);
                if (!hit) continue;
                const SurfaceInteraction si = make_interaction(scene, ray, *hit);
                SurfaceSample &s = out[size_t(i)];
                s.p = si.p;
                s.n = si.front ? si.n : -si.n;
                s.albedo = si.albedo();
                s.emission = si.emitted();
                s.mesh = hit->mesh, s.triangle = hit->triangle;
                ok[size_t(i)] = 1;
                break;
            }
        }
    });
    for (int64_t i = 0; i < n; ++i)
        if (!ok[size_t(i)])
            LTM_THROW(scene.name, ": camera '", scene.cameras[size_t(i) % scene.cameras.size()].name, "' sees no surface in ",
                      k_max_tries, " random rays");
    return out;
}

}  // namespace ltm
