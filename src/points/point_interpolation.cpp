// point_interpolation.cpp: the K nearest points on the query's surface, inverse-distance weighted (header).
#include "ltm/points/point_interpolation.h"

#include <cmath>
#include <utility>

#include "ltm/core/error.h"

namespace ltm {

PointInterpolator::PointInterpolator(std::vector<Vec3f> positions, std::vector<Vec3f> normals, float spacing)
    : m_position(std::move(positions)), m_normal(std::move(normals)), m_spacing(spacing) {
    if (m_position.empty()) LTM_THROW("point interpolation: no points");
    if (m_position.size() != m_normal.size())
        LTM_THROW("point interpolation: ", m_position.size(), " positions but ", m_normal.size(), " normals");
    if (!(spacing > 0.f) || !std::isfinite(spacing)) LTM_THROW("point interpolation: spacing must be > 0, got ", spacing);
    for (const Vec3f &n : m_normal)
        if (!is_finite(n)) LTM_THROW("point interpolation: a normal is not finite: ", n);
    m_grid = PointGrid(m_position, spacing);
}

bool PointInterpolator::interpolate(Vec3f p, Vec3f n, const Vec3f *values, Vec3f &out) const {
    const float r = k_radius_spacings * m_spacing, r2 = r * r, plane = k_plane_spacings * m_spacing;
    // The K best (d², index) ascending; a fixed array: this runs a million times a frame.
    std::pair<float, uint32_t> best[k_neighbours];
    int count = 0;
    // While fewer than K qualify, the search radius is the bound: the rings stop past r.
    auto kth = [&] { return count < k_neighbours ? r2 : best[k_neighbours - 1].first; };
    m_grid.visit_nearest(p, [&](uint32_t j) {
        // Written so that a NaN normal qualifies nothing (a query with one is a bug upstream).
        if (!(dot(m_normal[j], n) >= k_min_facing)) return;
        const Vec3f d = m_position[j] - p;
        if (!(std::abs(dot(d, n)) <= plane)) return;
        const float d2 = dot(d, d);
        if (!(d2 < r2)) return;
        const std::pair<float, uint32_t> item{d2, j};
        if (count == k_neighbours && !(item < best[k_neighbours - 1])) return;
        int at = count < k_neighbours ? count++ : k_neighbours - 1;
        while (at > 0 && item < best[at - 1]) best[at] = best[at - 1], --at;
        best[at] = item;
    }, kth);
    if (count == 0) return false;
    // Summed in ascending (d², index) order: the answer does not depend on the grid's visiting order.
    const float soft = 0.25f * m_spacing * m_spacing;
    Vec3f acc(0.f);
    float w = 0.f;
    for (int k = 0; k < count; ++k) {
        const float wk = 1.f / (best[k].first + soft);
        acc += values[best[k].second] * wk, w += wk;
    }
    out = acc / w;
    return true;
}

}  // namespace ltm
