// segment_occlusion.cpp: the frame adapter and the closure by rays (transport/segment_occlusion.h).
#include "ltm/transport/segment_occlusion.h"

#include <cmath>

#include "ltm/core/error.h"
#include "ltm/core/parallel.h"
#include "ltm/core/sampling.h"

namespace ltm {

FramedOcclusion::FramedOcclusion(std::shared_ptr<const SegmentOcclusion> world, Vec3f centre, float length)
    : m_world(std::move(world)), m_centre(centre), m_length(length) {
    if (!m_world) LTM_THROW("framed occlusion: no occlusion to frame");
    if (!(length > 0.f) || !std::isfinite(length)) LTM_THROW("framed occlusion: length must be finite and > 0, got ", length);
}

bool FramedOcclusion::blocked(Vec3f a, Vec3f b) const {
    return m_world->blocked(m_centre + a * m_length, m_centre + b * m_length);
}

bool FramedOcclusion::meets(Vec3f origin, Vec3f direction) const { return m_world->meets(m_centre + origin * m_length, direction); }

namespace {
std::vector<Vec3f> closure_pattern(int rays) {
    if (rays < 1 || rays > 64) LTM_THROW("ray closure: rays per side must be in [1, 64], got ", rays);
    return cosine_grid_directions(rays);
}

float closure_of(const SegmentOcclusion &occ, const std::vector<Vec3f> &local, Vec3f p, Vec3f n, float lift) {
    const Frame frame(n);
    const Vec3f o = p + n * lift;
    int met = 0;
    for (const Vec3f &w : local) met += occ.meets(o, frame.to_world(w));
    return float(met) / float(local.size());
}
}  // namespace

float ray_closure(const SegmentOcclusion &occlusion, Vec3f p, Vec3f n, float lift, int rays) {
    return closure_of(occlusion, closure_pattern(rays), p, n, lift);
}

void ray_closures(const SegmentOcclusion &occlusion, const float *position, const float *normal, size_t stride, size_t n,
                  float lift, int rays, float *out) {
    if (stride < 3) LTM_THROW("ray closure: row stride ", stride, " < 3");
    const std::vector<Vec3f> local = closure_pattern(rays);
    parallel_for(0, int64_t(n), 64, [&](int64_t lo, int64_t hi) {
        for (int64_t q = lo; q < hi; ++q) {
            const float *pp = position + size_t(q) * stride, *pn = normal + size_t(q) * stride;
            out[q] = closure_of(occlusion, local, Vec3f(pp[0], pp[1], pp[2]), Vec3f(pn[0], pn[1], pn[2]), lift);
        }
    });
}

}  // namespace ltm
