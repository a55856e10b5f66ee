// hemisphere_bins.cpp: bins of the concentric map and its inverse (core/sampling.h).
#include "ltm/render/hemisphere_bins.h"

#include <cmath>

#include "ltm/core/sampling.h"

namespace ltm {

Vec3f square_to_direction(Vec2f u) { return sample_cosine_hemisphere(u); }

Vec2f direction_to_square(Vec3f w) { return cosine_hemisphere_to_square(w); }

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
