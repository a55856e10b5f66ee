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

Vec2f cosine_hemisphere_to_square(Vec3f w) {
    // Disk point = (x, y) of the direction (Malley), then invert the concentric map.
    const float x = w.x, y = w.y;
    const float r = std::sqrt(x * x + y * y);
    if (r == 0.f) return {0.5f, 0.5f};
    float phi = std::atan2(y, x);   // (-π, π]
    if (phi < -k_pi / 4.f) phi += 2.f * k_pi;
    float a, b;   // in [-1, 1]²
    if (phi < k_pi / 4.f) {             // right wedge: a = r, φ = π/4·b/a
        a = r, b = phi * 4.f / k_pi * r;
    } else if (phi < 3.f * k_pi / 4.f) { // top: b = r, φ = π/2 − π/4·a/b
        b = r, a = -(phi - k_pi / 2.f) * 4.f / k_pi * r;
    } else if (phi < 5.f * k_pi / 4.f) { // left: a = −r
        a = -r, b = -(phi - k_pi) * 4.f / k_pi * r;
    } else {                             // bottom: b = −r
        b = -r, a = (phi - 3.f * k_pi / 2.f) * 4.f / k_pi * r;
    }
    return {clamp(0.5f * (a + 1.f), 0.f, 0x1.fffffep-1f), clamp(0.5f * (b + 1.f), 0.f, 0x1.fffffep-1f)};
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

std::vector<Vec3f> cosine_grid_directions(int n) {
    std::vector<Vec3f> out;
    for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) out.push_back(sample_cosine_hemisphere({(float(a) + 0.5f) / float(n), (float(b) + 0.5f) / float(n)}));
    return out;
}

}  // namespace ltm
