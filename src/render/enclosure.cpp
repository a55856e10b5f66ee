// enclosure.cpp: back-face voting over a fixed stratified set of hemisphere directions.
#include "ltm/render/enclosure.h"

#include <algorithm>
#include <cmath>

#include "ltm/core/sampling.h"

namespace ltm {

bool is_enclosed(const EmbreeAccel &accel, Vec3f p, Vec3f n, const EnclosureTest &cfg) {
    const Frame frame(n);
    const int nu = std::max(1, int(std::sqrt(float(cfg.n_rays) / 2.f)));
    const int nv = std::max(1, cfg.n_rays / nu);
    int back = 0, total = 0;
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            const Vec2f u{(float(i) + 0.5f) / float(nu), (float(j) + 0.5f) / float(nv)};
            const Vec3f d = frame.to_world(sample_cosine_hemisphere(u));
            const Vec3f o = offset_ray_origin(p, n, d, cfg.offset_length);
            const auto hit = accel.intersect({o, d});
            ++total;
            if (!hit) continue;
            if (dot(hit->n, d) > 0.f || hit->t < cfg.buried_distance) {
                ++back;
                continue;
            }
            // A front face counts as a back face when a back face coincides with it (within the
            // origin's offset): a desk top inside its frame, a box resting on another. Which of
            // two coincident faces the closest-hit query returns is decided by float rounding, so
            // the same house in another unit voted otherwise: ~100 of house 900101's 8 192
            // candidates flipped at ×0.1 and ×10, and the unit check moved 0.6 % on that alone.
            const float window = length(o - p);
            for (const Hit &h : accel.hits({o, d, 0.f, hit->t + window}))
                if (dot(h.n, d) > 0.f) {
                    ++back;
                    break;
                }
        }
    return float(back) >= cfg.back_face_fraction * float(total);
}

SampleFilter enclosed_filter(const EmbreeAccel &accel, const EnclosureTest &config) {
    EnclosureTest cfg = config;
    cfg.offset_length = std::max(max_component(accel.scene().bounds().extent()), 1e-30f);
    return [&accel, cfg](const SurfaceSample &s) { return is_enclosed(accel, s.p, s.n, cfg); };
}

}  // namespace ltm
