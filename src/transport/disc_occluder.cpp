// disc_occluder.cpp: oriented discs binned in a cube grid, segments walked by a 3D DDA (header).
#include "ltm/transport/disc_occluder.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ltm/core/error.h"
#include "ltm/core/lanes8.h"
#include "ltm/core/simd_clones.h"

namespace ltm {

namespace {
constexpr float k_grazing = 0.05f;   // |cos| below which a segment runs along a disc, not into it
constexpr float k_end_margin = 0.25f;   // ε = r/4: hits this close to an end belong to that end's surface
constexpr float k_ray_margin = 1e-3f;   // a ray's: only its origin's own plane (t = 0) is excluded
using namespace lanes8;   // 8 discs at once (core/lanes8.h); a cell's run is padded to a multiple
}  // namespace

DiscOccluder::DiscOccluder(const std::vector<Vec3f> &points, const std::vector<Vec3f> &normals, float radius)
    : m_r(radius), m_center(points), m_normal(normals) {
    if (points.empty()) LTM_THROW("disc occluder: no points");
    if (normals.size() != points.size()) LTM_THROW("disc occluder: ", points.size(), " points but ", normals.size(), " normals");
    if (!(radius > 0.f) || !std::isfinite(radius)) LTM_THROW("disc occluder: radius must be > 0, got ", radius);
    Vec3f lo = points.front(), hi = points.front();
    for (const Vec3f &p : points) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) LTM_THROW("disc occluder: a point is not finite");
        lo = min(lo, p), hi = max(hi, p);
    }
    const float cell = 2.f * m_r;
    m_origin = lo - Vec3f(m_r);
    // Cells per axis in double, checked before any cast to int (a tiny radius overflows int).
    double dims[3], cells = 1;
    for (int a = 0; a < 3; ++a) dims[a] = std::max(1.0, std::ceil((double(hi[a]) - double(lo[a]) + 2.0 * double(m_r)) / double(cell))), cells *= dims[a];
    if (!(cells <= double(1 << 28)))
        LTM_THROW("disc occluder: the scene is too large for the prior's discs of radius ", radius, " (", cells, " grid cells, at most 2^28)");
    for (int a = 0; a < 3; ++a) m_dim[a] = int(dims[a]);
    // Each disc into every cell its bounding box overlaps (half-extent r·√(1 − n_a²) along axis a).
    auto cell_range = [&](size_t k, int lo_c[3], int hi_c[3]) {
        for (int a = 0; a < 3; ++a) {
            // Padded by 10⁻⁴ of a cell: the walk's accumulated rounding may step past a corner cell.
            const float e = m_r * std::sqrt(std::max(0.f, 1.f - m_normal[k][a] * m_normal[k][a])) + 1e-4f * cell;
            lo_c[a] = std::clamp(int(std::floor((m_center[k][a] - e - m_origin[a]) / cell)), 0, m_dim[a] - 1);
            hi_c[a] = std::clamp(int(std::floor((m_center[k][a] + e - m_origin[a]) / cell)), 0, m_dim[a] - 1);
        }
    };
    std::vector<uint32_t> count(size_t(cells) + 1, 0);
    for (int pass = 0; pass < 2; ++pass) {
        if (pass == 1) {
            m_cell_start.assign(count.size(), 0);
            for (size_t c = 0; c + 1 < count.size(); ++c) {
                const uint64_t end = uint64_t(m_cell_start[c]) + ((uint64_t(count[c]) + k_lanes - 1) / k_lanes) * k_lanes;
                if (end > std::numeric_limits<uint32_t>::max()) LTM_THROW("disc occluder: more than 2^32 disc entries in the grid");
                m_cell_start[c + 1] = uint32_t(end);
            }
            for (auto *v : {&m_cx, &m_cy, &m_cz, &m_nx, &m_ny, &m_nz}) v->assign(m_cell_start.back(), 0.f);
            std::fill(count.begin(), count.end(), 0);
        }
        for (size_t k = 0; k < m_center.size(); ++k) {
            int lo_c[3], hi_c[3], c[3];
            cell_range(k, lo_c, hi_c);
            for (c[2] = lo_c[2]; c[2] <= hi_c[2]; ++c[2])
                for (c[1] = lo_c[1]; c[1] <= hi_c[1]; ++c[1])
                    for (c[0] = lo_c[0]; c[0] <= hi_c[0]; ++c[0]) {
                        const size_t i = size_t(cell_index(c));
                        if (pass == 1) {
                            const size_t e = m_cell_start[i] + count[i];
                            m_cx[e] = m_center[k].x, m_cy[e] = m_center[k].y, m_cz[e] = m_center[k].z;
                            m_nx[e] = m_normal[k].x, m_ny[e] = m_normal[k].y, m_nz[e] = m_normal[k].z;
                        }
                        ++count[i];
                    }
        }
    }
}

bool DiscOccluder::blocked(Vec3f a, Vec3f b) const {
    if (empty()) return false;
    const Vec3f d = b - a;
    const float len = length(d);
    const float margin = k_end_margin * m_r;
    if (!(len > 2.f * margin) || !std::isfinite(len)) return false;
    return walk(a, d, margin / len, 1.f - margin / len, false);
}

bool DiscOccluder::ray_meets_disc(Vec3f origin, Vec3f direction) const {
    if (empty()) return false;
    const float len = length(direction);
    if (!(len > 0.f) || !std::isfinite(len) || !is_finite(origin)) return false;
    const Vec3f d = direction / len;
    // Far enough to leave the box from anywhere inside or near it (walk clips to the box).
    const Vec3f extent = Vec3f(2.f * m_r * float(m_dim[0]), 2.f * m_r * float(m_dim[1]), 2.f * m_r * float(m_dim[2]));
    const float reach = 2.f * (length(extent) + length(origin - m_origin));
    // Not the segments' r/4 margin: a point within r/4 of a concave edge would see the adjacent
    // wall's discs inside the margin and its rays escape behind them (a closed furnace read 2 %
    // open). The origin's own disc and its coplanar neighbours lie at t = 0 and stay excluded.
    return walk(origin, d * reach, k_ray_margin * m_r / reach, 1.f, true);
}

LTM_SIMD_CLONES
bool DiscOccluder::walk(Vec3f a, Vec3f d, float t0, float t1, bool either_side) const {
    // Clip [t0, t1] to the grid's box (slabs).
    const float cell = 2.f * m_r;
    float tmin = t0, tmax = t1;
    for (int ax = 0; ax < 3; ++ax) {
        const float box_lo = m_origin[ax], box_hi = m_origin[ax] + cell * float(m_dim[ax]);
        if (d[ax] == 0.f) {
            if (a[ax] < box_lo || a[ax] > box_hi) return false;
            continue;
        }
        float ta = (box_lo - a[ax]) / d[ax], tb = (box_hi - a[ax]) / d[ax];
        if (ta > tb) std::swap(ta, tb);
        tmin = std::max(tmin, ta), tmax = std::min(tmax, tb);
    }
    if (!(tmin <= tmax)) return false;
    // 3D DDA from the clipped start.
    const Vec3f start = a + d * tmin;
    int c[3], step[3];
    float t_next[3], t_delta[3];
    for (int ax = 0; ax < 3; ++ax) {
        c[ax] = std::clamp(int(std::floor((start[ax] - m_origin[ax]) / cell)), 0, m_dim[ax] - 1);
        if (d[ax] > 0.f) {
            step[ax] = 1, t_delta[ax] = cell / d[ax];
            t_next[ax] = (m_origin[ax] + cell * float(c[ax] + 1) - a[ax]) / d[ax];
        } else if (d[ax] < 0.f) {
            step[ax] = -1, t_delta[ax] = -cell / d[ax];
            t_next[ax] = (m_origin[ax] + cell * float(c[ax]) - a[ax]) / d[ax];
        } else {
            step[ax] = 0, t_delta[ax] = 0.f, t_next[ax] = std::numeric_limits<float>::infinity();
        }
    }
    const float graze = k_grazing * length(d);   // once a walk, not once a disc
    const float r2 = m_r * m_r;
    // Does one of the 8 discs from entry s block the segment a + t·d, t ∈ (t0, t1)? From its front
    // (n·d < −graze), or either side; graze: below it the segment runs along the disc. Per lane:
    // t = n·(c − a) / n·d, then |a + d·t − c| < r.
    const auto lanes_hit = [&](uint32_t s) {
        const f8 nx = load8(&m_nx[s]), ny = load8(&m_ny[s]), nz = load8(&m_nz[s]);
        const f8 denom = nx * d.x + ny * d.y + nz * d.z;
        const m8 facing = either_side ? (abs8(denom) > graze) : (denom < -graze);
        if (!any8(facing)) return false;
        const f8 cx = load8(&m_cx[s]), cy = load8(&m_cy[s]), cz = load8(&m_cz[s]);
        const f8 t = (nx * (cx - a.x) + ny * (cy - a.y) + nz * (cz - a.z)) / denom;
        const m8 inside = facing & (t > t0) & (t < t1);
        if (!any8(inside)) return false;
        const f8 qx = (a.x + d.x * t) - cx, qy = (a.y + d.y * t) - cy, qz = (a.z + d.z * t) - cz;
        return any8(inside & ((qx * qx + qy * qy + qz * qz) < r2));
    };
    for (;;) {
        const size_t i = size_t(cell_index(c));
        for (uint32_t s = m_cell_start[i]; s < m_cell_start[i + 1]; s += k_lanes)
            if (lanes_hit(s)) return true;
        int ax = 0;
        if (t_next[1] < t_next[ax]) ax = 1;
        if (t_next[2] < t_next[ax]) ax = 2;
        if (!(t_next[ax] <= tmax)) return false;
        c[ax] += step[ax];
        if (c[ax] < 0 || c[ax] >= m_dim[ax]) return false;
        t_next[ax] += t_delta[ax];
    }
}

}  // namespace ltm
