// sampling.cpp: square-to-domain warps (pbrt-v4 §A.5 conventions).
#include "ltm/core/sampling.h"

namespace ltm {

Vec2f sample_concentric_disk(Vec2f u) {
    const float ox = 2.f * u.x - 1.f, oy = 2.f * u.y - 1.f;
    if (ox == 0.f && oy == 0.f) return {0.f, 0.f};
    float r, theta;
    if (std::abs(ox) > std::abs(oy)) {
        r = ox;
        theta = (k_pi / 4.f) * (oy / ox);
    } else {
        r = oy;
        theta = (k_pi / 2.f) - (k_pi / 4.f) * (ox / oy);
    }
    return {r * std::cos(theta), r * std::sin(theta)};
}

Vec3f sample_cosine_hemisphere(Vec2f u) {
    const Vec2f d = sample_concentric_disk(u);
    const float z = std::sqrt(std::max(0.f, 1.f - d.x * d.x - d.y * d.y));
    return {d.x, d.y, z};
}

Vec2f sample_uniform_triangle(Vec2f u) {
    float b0, b1;
    if (u.x < u.y) {
        b0 = u.x / 2.f;
        b1 = u.y - b0;
    } else {
        b1 = u.y / 2.f;
        b0 = u.x - b1;
    }
    return {b0, b1};
}

}  // namespace ltm
