// point_visibility.cpp: voxel occupancy of the scene points and visibility between node clusters
// (definitions in the header).
#include "ltm/transport/point_visibility.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <utility>

#include "ltm/core/error.h"
#include "ltm/core/key_grid.h"
#include "ltm/core/parallel.h"
#include "ltm/core/sampling.h"

namespace ltm {

namespace {
// Facing bits of a normal: bit 2a for +axis a, 2a + 1 for −axis a, where |n_a| ≥ 0.25.
uint8_t facing_bits(Vec3f n) {
    uint8_t bits = 0;
    for (int a = 0; a < 3; ++a) {
        if (n[a] >= 0.25f) bits |= uint8_t(1u << (2 * a));
        if (n[a] <= -0.25f) bits |= uint8_t(1u << (2 * a + 1));
    }
    return bits;
}

// The facings a segment along unit d meets from the front: a surface facing −a when d_a > 0.05,
// +a when d_a < −0.05 (within 0.05 it runs along that surface; a steep crossing of a wall, as from
// a ceiling to the floor of the next room, has |d_a| well above it).
uint8_t blocking_bits(Vec3f d) {
    uint8_t bits = 0;
    for (int a = 0; a < 3; ++a) {
        if (d[a] > 0.05f) bits |= uint8_t(1u << (2 * a + 1));
        if (d[a] < -0.05f) bits |= uint8_t(1u << (2 * a));
    }
    return bits;
}
}  // namespace

VoxelOccupancy::VoxelOccupancy(const std::vector<Vec3f> &points, const std::vector<Vec3f> &normals, float voxel, float splat)
    : m_h(voxel) {
    if (!(splat >= 0.f) || !std::isfinite(splat)) LTM_THROW("voxel occupancy: splat radius must be >= 0, got ", splat);
    if (points.empty()) LTM_THROW("voxel occupancy: no points");
    if (normals.size() != points.size()) LTM_THROW("voxel occupancy: ", points.size(), " points but ", normals.size(), " normals");
    if (!(voxel > 0.f) || !std::isfinite(voxel)) LTM_THROW("voxel occupancy: voxel edge must be > 0, got ", voxel);
    Vec3f lo = points.front(), hi = points.front();
    for (const Vec3f &p : points) lo = min(lo, p), hi = max(hi, p);
    m_center = (lo + hi) * 0.5f;
    double cells = 1;
    for (int a = 0; a < 3; ++a) {
        // One spare cell per side: samples just off a surface stay inside.
        m_half[a] = int(std::ceil(double(hi[a] - lo[a]) * 0.5 / double(m_h))) + 1;
        cells *= 2.0 * m_half[a];
    }
    if (!(cells <= double(1 << 28)))
        LTM_THROW("voxel occupancy: the scene is too large for the prior's voxel grid (", cells, " voxels of edge ", voxel,
                  ", at most 2^28)");
    m_facing.assign(size_t(cells), 0);
    for (size_t i = 0; i < points.size(); ++i) {
        const uint8_t bits = facing_bits(normals[i]);
        m_facing[size_t(cell(points[i]))] |= bits;
        if (splat <= 0.f) continue;
        for (int a = 0; a < 3; ++a) {
            Vec3f d(0.f);
            d[a] = 1.f;
            d = d - normals[i] * normals[i][a];   // e_a projected onto the tangent plane
            const float len = length(d);
            if (len < 0.5f) continue;
            for (float sign : {-1.f, 1.f}) {
                const int64_t c = cell(points[i] + d * (sign * splat / len));
                if (c >= 0) m_facing[size_t(c)] |= bits;   // a splat past the spare cell is dropped
            }
        }
    }
}

int64_t VoxelOccupancy::cell(Vec3f p) const {
    int64_t index = 0;
    for (int a = 2; a >= 0; --a) {
        const float u = std::floor((p[a] - m_center[a]) / m_h);
        if (!(u >= float(-m_half[a]) && u < float(m_half[a]))) return -1;
        index = index * (2 * m_half[a]) + int64_t(u) + m_half[a];
    }
    return index;
}

uint8_t VoxelOccupancy::facing(Vec3f p) const {
    const int64_t c = m_facing.empty() ? -1 : cell(p);
    return c < 0 ? 0 : m_facing[size_t(c)];
}

bool VoxelOccupancy::blocked(Vec3f a, Vec3f na, Vec3f b, Vec3f nb) const {
    const Vec3f d = b - a;
    const float len = length(d);
    if (!(len > 0.f)) return false;
    const Vec3f dir = d / len;
    const uint8_t block = blocking_bits(dir);
    if (!block) return false;
    // Within h of an end, that end's own surface does not count (the segment arrives at its front).
    const uint8_t near_a = uint8_t(block & ~facing_bits(na)), near_b = uint8_t(block & ~facing_bits(nb));
    const float step = 0.5f * m_h;
    for (float t = step; t < len; t += step) {
        const uint8_t mask = t < m_h ? near_a : (t > len - m_h ? near_b : block);
        if (facing(a + dir * t) & mask) return true;
    }
    return false;
}

float point_spacing(const std::vector<Vec3f> &points) {
    constexpr size_t k = 8;
    const size_t m = points.size();
    if (m <= k) LTM_THROW("point spacing: ", m, " points (needs more than ", k, ")");
    for (const Vec3f &q : points)
        if (!is_finite(q)) LTM_THROW("point spacing: a point is not finite: ", q);
    // A grid of about twice the spacing the bounding box's surface suggests; the ring search
    // returns exactly the k smallest distances a scan of every point finds (point_grid.h).
    Vec3f lo = points[0], hi = points[0];
    for (const Vec3f &q : points) lo = min(lo, q), hi = max(hi, q);
    const Vec3f ext = hi - lo;
    const double box_area = 2.0 * (double(ext.x) * ext.y + double(ext.y) * ext.z + double(ext.z) * ext.x);
    const float cell = box_area > 0.0 ? float(2.0 * std::sqrt(box_area / double(m))) : std::max(max_component(ext), 1.f);
    const PointGrid grid(points, cell > 0.f ? cell : 1.f);
    std::vector<double> r2(m);
    parallel_for(0, int64_t(m), 64, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            float best[k];   // the k smallest squared distances, ascending
            for (float &v : best) v = std::numeric_limits<float>::infinity();
            const Vec3f p = points[size_t(i)];
            auto visit = [&](uint32_t j) {
                if (j == uint32_t(i)) return;
                const Vec3f d = points[j] - p;
                const float q = dot(d, d);
                if (!(q < best[k - 1])) return;
                size_t s = k - 1;
                for (; s > 0 && q < best[s - 1]; --s) best[s] = best[s - 1];
                best[s] = q;
            };
            grid.visit_nearest(p, visit, [&] { return best[k - 1]; });
            r2[size_t(i)] = double(best[k - 1]);
        }
    });
    double sum = 0;
    for (double v : r2) sum += v;   // fixed order: the same at any thread count
    return float(std::sqrt(k_pi * sum / double(m) / double(k)));
}

int64_t VoxelOccupancy::n_solid() const {
    int64_t n = 0;
    for (uint8_t s : m_facing) n += s != 0;
    return n;
}

// Voxels: both ends lifted h/2 along their normals, so a segment along a floor runs inside the
// layer of voxels that a wall standing on that floor occupies, whatever the grid's offset
// (unlifted, it may run beneath the wall's lowest voxel). Discs need no lift (their end margin).
bool ClusterVisibility::blocked(Vec3f a, Vec3f na, Vec3f b, Vec3f nb) const {
    if (!discs.empty()) return discs.blocked(a, b);
    const float lift = 0.5f * occupancy.voxel();
    return occupancy.blocked(a + na * lift, na, b + nb * lift, nb);
}

namespace {
// The k_candidates nearest centres whose normal is within 90° of n, nearest first (insertion into
// a short sorted list), and the nearest centre of all. Returns the count. Distances are ranked on
// steps of h/1024 (h the occupancy's voxel; core/key_grid.h): a
// node as far from two centres as rounding can tell (a generated house: ~30 of 16 384 nodes)
// otherwise joined one or the other by the rounding of its unit. Ties go to the centre nearer the
// grid's centre (on the same steps), which the training symmetries and the unit keep, and only then
// to the lower index. With the centres' grid the rings stop once the k-th candidate lies within the
// searched radius (widened by a step); comparisons are on (steps, steps to the grid's centre, index),
// so the list is the scan's whatever the visiting order.
size_t facing_candidates(const ClusterVisibility &v, Vec3f p, Vec3f n, std::pair<float, uint32_t> *near,
                         uint32_t &nearest) {
    constexpr size_t k = ClusterVisibility::k_candidates;
    const double step = double(v.occupancy.voxel()) / 1024.0;
    const KeyGrid steps{Vec3f(0.f), step};
    // A ClusterVisibility put together by hand has no occupancy (step 0): its d² as they are.
    auto rank = [&](Vec3f d) {
        const double d2 = double(dot(d, d));
        return step > 0.0 ? steps.distance_key(std::sqrt(d2)) : int64_t(d2 * 0x1p40);
    };
    const Vec3f middle = v.occupancy.center();
    using Key = std::tuple<int64_t, int64_t, uint32_t>;
    size_t found = 0;
    nearest = 0;
    Key keys[k];
    Key best_all{std::numeric_limits<int64_t>::max(), 0, 0u};
    auto visit = [&](uint32_t c) {
        const Vec3f d = v.position[c] - p;
        const Key key{rank(d), rank(v.position[c] - middle), c};
        if (key < best_all) best_all = key;
        if (!(dot(v.normal[c], n) > 0.f)) return;
        if (found == k && !(key < keys[k - 1])) return;
        size_t i = found < k ? found++ : k - 1;
        for (; i > 0 && key < keys[i - 1]; --i) near[i] = near[i - 1], keys[i] = keys[i - 1];
        near[i] = {dot(d, d), c}, keys[i] = key;
    };
    if (v.centres.empty() || !is_finite(p)) {
        for (size_t c = 0; c < v.position.size(); ++c) visit(uint32_t(c));
    } else {
        v.centres.visit_nearest(p, visit, [&] {
            if (found < k) return std::numeric_limits<float>::infinity();
            const float r = std::sqrt(near[k - 1].first) + float(step);   // a farther centre of the same step can still rank first
            return r * r;
        });
    }
    nearest = std::get<2>(best_all);
    return found;
}
}  // namespace

uint32_t ClusterVisibility::cluster_of(Vec3f p, Vec3f n) const {
    std::pair<float, uint32_t> near[k_candidates];
    uint32_t nearest = 0;
    const size_t found = facing_candidates(*this, p, n, near, nearest);
    if (found == 0) return nearest;
    for (size_t i = 0; i < found; ++i) {
        const uint32_t c = near[i].second;
        if (!blocked(p, n, position[c], normal[c])) return c;
    }
    return near[0].second;
}

int ClusterVisibility::receiver_clusters(Vec3f p, Vec3f n, uint32_t *ids, float *weights) const {
    std::pair<float, uint32_t> near[k_candidates];
    uint32_t nearest = 0;
    const size_t found = facing_candidates(*this, p, n, near, nearest);
    // The visible candidates, nearest first (their squared distances in d2).
    float d2[k_candidates];
    int seen = 0;
    // Segment tests are the cost: stop at the first visible one (blend 1) or at K + 1 (the weights
    // need v_{K+1}'s distance).
    const int wanted = blend <= 1 ? 1 : blend + 1;
    for (size_t i = 0; i < found && seen < wanted; ++i) {
        const uint32_t c = near[i].second;
        if (!blocked(p, n, position[c], normal[c])) ids[seen] = c, d2[seen] = near[i].first, ++seen;
    }
    if (blend > 1 && seen > 0) {
        const int K = std::min(blend, seen);
        const float ref = K < seen ? d2[K] : near[found - 1].first;
        float sum = 0.f;
        for (int k = 0; k < K; ++k) {
            const float t = ref > 0.f ? std::max(0.f, 1.f - d2[k] / ref) : 0.f;
            weights[k] = t * t, sum += weights[k];
        }
        if (sum > 0.f) {
            for (int k = 0; k < K; ++k) weights[k] /= sum;
            return K;
        }
    }
    // One cluster, as cluster_of chooses it.
    ids[0] = seen > 0 ? ids[0] : found > 0 ? near[0].second : nearest;
    weights[0] = 1.f;
    return 1;
}

void ClusterVisibility::blend_rows(const uint32_t *ids, const float *w, int K, float *out) const {
    const size_t C = size();
    std::fill(out, out + C, 0.f);
    for (int k = 0; k < K; ++k) {
        const uint8_t *row = visible.data() + size_t(ids[k]) * C;
        for (size_t c = 0; c < C; ++c) out[c] += w[k] * float(row[c]);
    }
}

std::vector<float> cluster_closure(const ClusterVisibility &vis, const DiscOccluder &discs, int rays) {
    if (discs.empty()) LTM_THROW("cluster closure: needs the points as discs (prior_discs > 0)");
    if (rays < 1 || rays > 256) LTM_THROW("cluster closure: rays per side must be in [1, 256], got ", rays);
    // One pattern of local directions for every centre: cell centres of the square, cosine-mapped.
    const std::vector<Vec3f> local = cosine_grid_directions(rays);
    std::vector<float> closure(vis.size(), 1.f);
    parallel_for(0, int64_t(vis.size()), 4, [&](int64_t lo, int64_t hi) {
        for (int64_t c = lo; c < hi; ++c) {
            const Frame frame(vis.normal[size_t(c)]);
            int met = 0;
            for (const Vec3f &w : local) met += discs.ray_meets_disc(vis.position[size_t(c)], frame.to_world(w));
            closure[size_t(c)] = float(met) / float(local.size());
        }
    });
    return closure;
}

ClusterVisibility cluster_visibility(const std::vector<Vec3f> &pos, const std::vector<Vec3f> &nrm, VoxelOccupancy occupancy,
                                     int clusters, DiscOccluder discs, float cell, bool pairs) {
    const size_t m = pos.size();
    if (m == 0) LTM_THROW("cluster visibility: no nodes");
    if (nrm.size() != m) LTM_THROW("cluster visibility: ", m, " positions but ", nrm.size(), " normals");
    if (clusters < 1) LTM_THROW("cluster visibility: clusters must be >= 1, got ", clusters);
    if (!(cell >= 0.f) || !std::isfinite(cell)) LTM_THROW("cluster visibility: cluster cell must be >= 0, got ", cell);
    if (!(occupancy.voxel() > 0.f)) LTM_THROW("cluster visibility: no occupancy grid");
    ClusterVisibility out;
    out.occupancy = std::move(occupancy);
    out.discs = std::move(discs);
    // Cluster centres from a coarse grid (header; FPS centres made the unit check 1.27 % mean /
    // 3.3 % max on 8 test houses, the prior without occlusion 0.29 % / 0.70 %). The edge holds
    // ~2·n_solid/C fine voxels of a surface, i.e. ~C (cell, facing) groups: a cell often holds two
    // facings (a wall's two sides, furniture).
    const float h = out.occupancy.voxel();
    const double g = cell > 0.f ? double(cell)
                                : double(h) * std::sqrt(2.0 * double(std::max<int64_t>(out.occupancy.n_solid(), 1)) / double(clusters));
    const Vec3f c0 = out.occupancy.center();
    struct Member {
        int64_t cell[3];
        int facing;
        uint32_t node;
    };
    std::vector<Member> members(m);
    for (size_t j = 0; j < m; ++j) {
        Member &e = members[j];
        for (int a = 0; a < 3; ++a) e.cell[a] = int64_t(std::floor(double(pos[j][a] - c0[a]) / g));
        int axis = 0;
        for (int a = 1; a < 3; ++a)
            if (std::abs(nrm[j][a]) > std::abs(nrm[j][axis])) axis = a;
        e.facing = 2 * axis + (nrm[j][axis] < 0.f ? 1 : 0);
        e.node = uint32_t(j);
    }
    auto group_key = [](const Member &e) { return std::make_tuple(e.cell[0], e.cell[1], e.cell[2], e.facing); };
    auto less_pos = [](Vec3f a, Vec3f b) { return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z); };
    std::sort(members.begin(), members.end(), [&](const Member &a, const Member &b) {
        const auto ka = group_key(a), kb = group_key(b);
        return ka < kb || (ka == kb && less_pos(pos[a.node], pos[b.node]));   // node order plays no part
    });
    auto dist2 = [](Vec3f p, const double *q) {
        double d = 0;
        for (int a = 0; a < 3; ++a) d += (double(p[a]) - q[a]) * (double(p[a]) - q[a]);
        return d;
    };
    const double centre[3] = {double(c0.x), double(c0.y), double(c0.z)};
    const double tie = 1e-9 * g * g;   // distances equal within rounding (first_end)
    const KeyGrid steps{Vec3f(0.f), g / 1024.0};   // the centres' ranking of distances
    for (size_t b = 0; b < m;) {
        size_t e = b;
        double mean[3] = {0, 0, 0};
        for (; e < m && group_key(members[e]) == group_key(members[b]); ++e)
            for (int a = 0; a < 3; ++a) mean[a] += double(pos[members[e].node][a]);
        for (double &x : mean) x /= double(e - b);
        // Nearest to the mean. A group of two is an exact tie (both at half their distance), and a
        // tie broken by position order is not mirror-equivariant; the distance to the grid's
        // centre is (the maps keep the centre), so ties go to the node nearer the centre, and only
        // then to the smaller position. Distances are compared on steps of g/1024 (core/key_grid.h):
        // ties within rounding include the rounding of another unit, a few ulps of each coordinate,
        // which a tolerance on d² (1e-9 g²) did not.
        auto rank = [&](Vec3f p, const double *q) { return steps.distance_key(std::sqrt(dist2(p, q))); };
        size_t best = b;
        auto best_key = std::make_pair(rank(pos[members[b].node], mean), rank(pos[members[b].node], centre));
        for (size_t k = b + 1; k < e; ++k) {   // in position order
            const Vec3f pk = pos[members[k].node];
            const auto key = std::make_pair(rank(pk, mean), rank(pk, centre));
            if (key < best_key) best = k, best_key = key;
        }
        out.position.push_back(pos[members[best].node]), out.normal.push_back(nrm[members[best].node]);
        b = e;
    }
    const size_t C = out.position.size();
    out.centres = PointGrid(out.position, float(g));
    out.node_cluster.resize(m);
    parallel_for(0, int64_t(m), 256, [&](int64_t b, int64_t e) {
        for (int64_t j = b; j < e; ++j) out.node_cluster[size_t(j)] = out.cluster_of(pos[size_t(j)], nrm[size_t(j)]);
    });
    // The segment test depends on its direction (samples every h/2 from the first end; surfaces
    // met from the front), so each pair is tested from the end nearer the grid's centre (then the
    // lower one): an order the training symmetries and the unit keep, unlike the groups' key order.
    // -1: i first, 1: j first, 0: a tie no symmetry-kept order breaks (both directions tested).
    auto first_end = [&](size_t i, size_t j) {
        const double di = dist2(out.position[i], centre), dj = dist2(out.position[j], centre);
        if (std::abs(di - dj) > tie) return di < dj ? -1 : 1;
        if (out.position[i].y != out.position[j].y) return out.position[i].y < out.position[j].y ? -1 : 1;
        return 0;
    };
    if (!pairs) {
        out.visible.assign(C * C, 1);
        out.pairs = false;
        return out;
    }
    out.visible.assign(C * C, 0);
    parallel_for(0, int64_t(C), 4, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            out.visible[size_t(i) * C + size_t(i)] = 1;
            for (size_t j = size_t(i) + 1; j < C; ++j) {
                const size_t a = size_t(i);
                const int order = first_end(a, j);
                auto blocked_from = [&](size_t s, size_t t) {
                    return out.blocked(out.position[s], out.normal[s], out.position[t], out.normal[t]);
                };
                const bool blocked = order < 0 ? blocked_from(a, j) : order > 0 ? blocked_from(j, a)
                                                                                : blocked_from(a, j) || blocked_from(j, a);
                out.visible[a * C + j] = !blocked;
            }
        }
    });
    for (size_t i = 0; i < C; ++i)
        for (size_t j = i + 1; j < C; ++j) out.visible[j * C + i] = out.visible[i * C + j];
    return out;
}

}  // namespace ltm
