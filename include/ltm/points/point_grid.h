// point_grid.h: a uniform grid over a point set for exact nearest-neighbour searches by rings —
// the points' spacing (k-th neighbour distances), the nearest cluster centres of a receiver, the
// prior's near field. Each search visits the cells at Chebyshev distance 0, 1, 2, … from the
// query's cell; after ring R every point closer than guaranteed_radius(p, R) has been visited, so
// a search that stops once its k-th best lies within that radius returns exactly what a scan of
// every point returns (ties broken by the caller, by index).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "ltm/core/math.h"

namespace ltm {

class PointGrid {
public:
    PointGrid() = default;
    /// points: finite; cell > 0 (same unit). The cell grows by powers of two while the box would
    /// need more than 2^22 cells. Throws ltm::Error on no points, a non-finite point or cell ≤ 0.
    PointGrid(const std::vector<Vec3f> &points, float cell);
    bool empty() const { return m_items.empty(); }
    float cell() const { return m_cell; }
    /// Calls f(index) for each point in the cells at Chebyshev distance exactly R from p's cell
    /// (p clamped into the grid). Returns false when that ring lies wholly outside the grid (so
    /// every point has been visited by rings 0..R−1).
    template <class F> bool visit_ring(Vec3f p, int64_t R, F f) const {
        int64_t c[3];
        coord(p, c);
        bool any = false;
        for (int64_t z = c[2] - R; z <= c[2] + R; ++z) {
            if (z < 0 || z >= m_dims[2]) continue;
            for (int64_t y = c[1] - R; y <= c[1] + R; ++y) {
                if (y < 0 || y >= m_dims[1]) continue;
                const bool zy_edge = z == c[2] - R || z == c[2] + R || y == c[1] - R || y == c[1] + R;
                for (int64_t x = c[0] - R; x <= c[0] + R; x += (zy_edge || R == 0) ? 1 : 2 * R) {
                    if (x < 0 || x >= m_dims[0]) continue;
                    any = true;
                    const size_t cell = size_t((z * m_dims[1] + y) * m_dims[0] + x);
                    for (size_t k = m_start[cell]; k < m_start[cell + 1]; ++k) f(m_items[k]);
                }
            }
        }
        return any || R == 0;
    }
    /// A k-nearest search: visit(index) for the points ring by ring around p until kth() — the
    /// caller's current k-th best squared distance, +∞ while it has fewer — lies within the
    /// searched radius (less a relative 10⁻⁵ against rounding), or every point has been visited.
    /// The caller then holds exactly what a scan of every point gives, if it ranks the same way.
    template <class Visit, class Kth> void visit_nearest(Vec3f p, Visit visit, Kth kth) const {
        for (int64_t R = 0; visit_ring(p, R, visit); ++R) {
            const float g = guaranteed_radius(p, R);
            if (kth() < g * g * (1.f - 1e-5f)) return;
        }
    }
    /// After rings 0..R around p: every point closer to p than this has been visited (a lower
    /// bound, also for p outside the grid's box).
    float guaranteed_radius(Vec3f p, int64_t R) const;
    /// Calls f(index) for every point in the cells that meet the ball (p, r): a superset of the
    /// points closer than r.
    template <class F> void visit_ball(Vec3f p, float r, F f) const {
        if (!is_finite(p)) return;
        int64_t lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::max<int64_t>(0, cell_index(p[a] - r, a));
            hi[a] = std::min<int64_t>(m_dims[a] - 1, cell_index(p[a] + r, a));
        }
        for (int64_t z = lo[2]; z <= hi[2]; ++z)
            for (int64_t y = lo[1]; y <= hi[1]; ++y)
                for (int64_t x = lo[0]; x <= hi[0]; ++x) {
                    const size_t cell = size_t((z * m_dims[1] + y) * m_dims[0] + x);
                    for (size_t k = m_start[cell]; k < m_start[cell + 1]; ++k) f(m_items[k]);
                }
    }

private:
    int64_t cell_index(float v, int a) const;   ///< clamped to [−1, dims] (outside on either side)
    void coord(Vec3f p, int64_t c[3]) const;    ///< clamped into the grid
    float m_cell = 0.f;
    Vec3f m_lo{0.f};
    int64_t m_dims[3] = {0, 0, 0};
    std::vector<size_t> m_start;     ///< [cells + 1]
    std::vector<uint32_t> m_items;   ///< point indices, cell by cell, ascending within a cell
};

}  // namespace ltm
