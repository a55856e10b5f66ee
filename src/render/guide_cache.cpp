// guide_cache.cpp: a hashed grid of edge = radius; a lookup visits the 27 cells around p.
#include "ltm/render/guide_cache.h"

#include <cmath>

#include "ltm/core/error.h"

namespace ltm {

GuideCache::GuideCache(int resolution, std::vector<Vec3f> position, std::vector<Vec3f> normal, std::vector<Vec3f> radiance,
                       float radius)
    : m_res(resolution), m_radius(radius), m_position(std::move(position)), m_normal(std::move(normal)),
      m_radiance(std::move(radiance)) {
    const size_t nb = size_t(resolution) * size_t(resolution), c = m_position.size();
    if (resolution < 1 || m_normal.size() != c || m_radiance.size() != c * nb)
        LTM_THROW("guide cache: ", c, " points, ", m_normal.size(), " normals and ", m_radiance.size(), " radiance bins (expected ",
                  c * nb, " for ", resolution, "² bins each)");
    if (!(radius > 0.f) || !std::isfinite(radius)) LTM_THROW("guide cache: radius ", radius, " must be finite and > 0");
    std::vector<float> lum(nb);
    for (size_t i = 0; i < c; ++i) {
        for (size_t b = 0; b < nb; ++b) {
            const Vec3f l = m_radiance[i * nb + b];
            if (!(std::isfinite(l.x) && std::isfinite(l.y) && std::isfinite(l.z)) || l.x < 0.f || l.y < 0.f || l.z < 0.f)
                LTM_THROW("guide cache: point ", i, " bin ", b, " has radiance (", l.x, ", ", l.y, ", ", l.z, ")");
            lum[b] = luminance(l);
        }
        m_diffuse.emplace_back(resolution, lum);
        const Vec3f &p = m_position[i];
        m_grid[cell_key(int64_t(std::floor(p.x / radius)), int64_t(std::floor(p.y / radius)), int64_t(std::floor(p.z / radius)))]
            .push_back(int(i));
    }
}

int GuideCache::lookup(Vec3f p, Vec3f n) const {
    if (empty()) return -1;
    const int64_t cx = int64_t(std::floor(p.x / m_radius)), cy = int64_t(std::floor(p.y / m_radius)),
                  cz = int64_t(std::floor(p.z / m_radius));
    int best = -1;
    float best_d2 = m_radius * m_radius;
    for (int64_t dx = -1; dx <= 1; ++dx)
        for (int64_t dy = -1; dy <= 1; ++dy)
            for (int64_t dz = -1; dz <= 1; ++dz) {
                const auto it = m_grid.find(cell_key(cx + dx, cy + dy, cz + dz));
                if (it == m_grid.end()) continue;
                for (int i : it->second) {
                    const Vec3f d = m_position[size_t(i)] - p;
                    const float d2 = dot(d, d);
                    // Ties to the lower index: the result does not depend on the grid's order.
                    if (dot(n, m_normal[size_t(i)]) >= 0.9f && (d2 < best_d2 || (d2 == best_d2 && best >= 0 && i < best))) best = i, best_d2 = d2;
                }
            }
    return best;
}

}  // namespace ltm
