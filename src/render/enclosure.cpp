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
            const auto hit = accel.intersect({offset_ray_origin(p, n, d, cfg.offset_length), d});
            ++total;
            if (hit && dot(hit->n, d) > 0.f) ++back;
        }
    return float(back) >= cfg.back_face_fraction * float(total);
}

SampleFilter enclosed_filter(const EmbreeAccel &accel, const EnclosureTest &config) {
    EnclosureTest cfg = config;
    cfg.offset_length = std::max(max_component(accel.scene().bounds().extent()), 1e-30f);
    return [&accel, cfg](const SurfaceSample &s) { return is_enclosed(accel, s.p, s.n, cfg); };
}

}  // namespace ltm
