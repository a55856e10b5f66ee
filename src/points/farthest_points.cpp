// farthest_points.cpp: exact FPS (definition in the header).
#include "ltm/points/farthest_points.h"

#include <algorithm>
#include <limits>

namespace ltm {

std::vector<int64_t> farthest_points(const float *x, size_t n, size_t m) {
    std::vector<float> dist(n, std::numeric_limits<float>::infinity());
    std::vector<int64_t> out(m);
    int64_t last = 0;
    if (m > 0) out[0] = 0;
    for (size_t i = 1; i < m; ++i) {
        const float lx = x[3 * last], ly = x[3 * last + 1], lz = x[3 * last + 2];
        float best = -1.f;
        int64_t best_j = 0;
        for (size_t j = 0; j < n; ++j) {
            const float dx = x[3 * j] - lx, dy = x[3 * j + 1] - ly, dz = x[3 * j + 2] - lz;
            const float d = std::min(dist[j], dx * dx + dy * dy + dz * dz);
            dist[j] = d;
            if (d > best) best = d, best_j = int64_t(j);   // strict: ties keep the lower index
        }
        out[i] = last = best_j;
    }
    return out;
}

}  // namespace ltm
