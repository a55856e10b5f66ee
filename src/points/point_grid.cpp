// point_grid.cpp: the uniform grid's construction and its ring bound (header).
#include "ltm/points/point_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ltm/core/error.h"

namespace ltm {

PointGrid::PointGrid(const std::vector<Vec3f> &points, float cell) {
    if (points.empty()) LTM_THROW("point grid: no points");
    if (!(cell > 0.f) || !std::isfinite(cell)) LTM_THROW("point grid: cell must be > 0, got ", cell);
    Vec3f lo = points[0], hi = points[0];
    for (const Vec3f &q : points) {
        if (!is_finite(q)) LTM_THROW("point grid: a point is not finite: ", q);
        lo = min(lo, q), hi = max(hi, q);
    }
    auto count = [&](float h) {
        double n = 1;
        for (int a = 0; a < 3; ++a) n *= std::floor(double(hi[a] - lo[a]) / h) + 1;
        return n;
    };
    while (count(cell) > double(1 << 22)) cell *= 2.f;
    m_cell = cell, m_lo = lo;
    for (int a = 0; a < 3; ++a) m_dims[a] = int64_t(std::floor(double(hi[a] - lo[a]) / cell)) + 1;
    m_start.assign(size_t(m_dims[0] * m_dims[1] * m_dims[2] + 1), 0);
    std::vector<size_t> cell_of(points.size());
    for (size_t j = 0; j < points.size(); ++j) {
        int64_t c[3];
        coord(points[j], c);
        cell_of[j] = size_t((c[2] * m_dims[1] + c[1]) * m_dims[0] + c[0]);
        ++m_start[cell_of[j] + 1];
    }
    for (size_t c = 0; c + 1 < m_start.size(); ++c) m_start[c + 1] += m_start[c];
    m_items.resize(points.size());
    std::vector<size_t> fill(m_start.begin(), m_start.end() - 1);
    for (size_t j = 0; j < points.size(); ++j) m_items[fill[cell_of[j]]++] = uint32_t(j);
}

// In double throughout, as guaranteed_radius places the faces (a float difference may file a point
// within an ulp of a face in the neighbouring cell); clamped before the cast (huge coordinates).
int64_t PointGrid::cell_index(float v, int a) const {
    const double c = std::floor((double(v) - double(m_lo[a])) / double(m_cell));
    return int64_t(std::clamp(c, -1.0, double(m_dims[a])));
}

void PointGrid::coord(Vec3f p, int64_t c[3]) const {
    for (int a = 0; a < 3; ++a) c[a] = std::clamp<int64_t>(cell_index(p[a], a), 0, m_dims[a] - 1);
}

float PointGrid::guaranteed_radius(Vec3f p, int64_t R) const {
    int64_t c[3];
    coord(p, c);
    double r = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        // The searched block spans cells c−R..c+R; beyond the grid's own extent there are no points.
        const double lo = double(m_lo[a]) + double(c[a] - R) * m_cell, hi = double(m_lo[a]) + double(c[a] + R + 1) * m_cell;
        if (c[a] - R > 0) r = std::min(r, double(p[a]) - lo);
        if (c[a] + R < m_dims[a] - 1) r = std::min(r, hi - double(p[a]));
    }
    return float(std::max(0.0, r));
}

}  // namespace ltm
