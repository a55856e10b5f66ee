// hemisphere_bins.cpp: concentric map and its inverse (Shirley & Chiu 1997).
#include "ltm/render/hemisphere_bins.h"

#include <cmath>

#include "ltm/core/sampling.h"

namespace ltm {

Vec3f square_to_direction(Vec2f u) { return sample_cosine_hemisphere(u); }

Vec2f direction_to_square(Vec3f w) {
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

int direction_to_bin(Vec3f w, int resolution) {
    const Vec2f u = direction_to_square(w);
    return int(u.x * float(resolution)) * resolution + int(u.y * float(resolution));
}

HemisphereRows hemisphere_rows(const PointSet &points, const std::vector<int64_t> &rows, int resolution) {
    HemisphereRows out;
    const int nb = resolution * resolution;
    out.query.reserve(rows.size() * size_t(nb) * 9);
    out.direction.reserve(rows.size() * size_t(nb) * 3);
    for (int64_t q : rows) {
        const Frame frame(points.vec3(size_t(q), 3));
        for (int b = 0; b < nb; ++b) {
            for (size_t c = 0; c < 9; ++c) out.query.push_back(points.at(size_t(q), c));
            const Vec3f w = normalize(frame.to_world(square_to_direction(bin_to_square(b, resolution))));
            out.direction.insert(out.direction.end(), {w.x, w.y, w.z});
        }
    }
    return out;
}

}  // namespace ltm
