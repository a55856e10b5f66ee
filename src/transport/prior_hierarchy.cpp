// prior_hierarchy.cpp: the cluster tree of the transport prior and a receiver's row through it
// (criteria and equations in the header).
#include "ltm/transport/prior_hierarchy.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <limits>

#include "ltm/core/error.h"
#include "ltm/core/lanes8.h"
#include "ltm/core/simd_clones.h"
#include "ltm/transport/patch_form_factor.h"

namespace ltm {

namespace {
constexpr uint32_t k_leaf = 8;   // nodes per leaf at most
// Aggregates only over subtrees whose normals lie within this cone of their mean: the normals'
// first-order terms (Σ_j e_j n_jᵀ) are carried, their second-order ones are not (header).
// 0.6 rad: on the staircase at 16 384 points, 822 → 719 exactly summed nodes per receiver against
// 0.3 rad, the gather's difference to the dense rows 0.17 % → 0.15 % RMS (0.8 rad: 700, 0.15 %).
constexpr float k_flat_cos = 0.8253356f;   // cos 0.6
// Visibility by rays: a group's lane reuses another lane's ray to the same term when their receivers
// lie within this share of the distance to it (RayFilter).
constexpr float k_ray_share = 0.05f;
constexpr int k_share_bits = 12;   // RayShare's slots: 4 096
// The build's key grid (KeyGrid): steps of √a / 64, far above the ~1e-5 spacings of rounding that a
// change of unit leaves, far below the points' spacing.
constexpr double k_keys_per_side = 64.0;

// Which way a normal faces most: 2a for +axis a, 2a + 1 for −axis a.
int facing_class(Vec3f n) {
    const float ax = std::abs(n.x), ay = std::abs(n.y), az = std::abs(n.z);
    const int a = ax >= ay && ax >= az ? 0 : ay >= az ? 1 : 2;
    return 2 * a + (n[a] < 0.f ? 1 : 0);
}

// Splits items[lo, hi) (≥ 2) into two non-empty halves and returns the first place of the second.
// Items facing several ways are sorted by facing (then by index) and cut at the class boundary
// nearest the middle; items facing one way at the median of their longest extent (ties by index).
// Coordinates and extents are compared on the tree's key grid (core/key_grid.h), so that the same
// points in another unit, which float rounding moves by ~1e-5 spacings, split alike.
template <class PosOf, class NrmOf>
uint32_t split(std::vector<uint32_t> &items, uint32_t lo, uint32_t hi, PosOf pos, NrmOf nrm, const KeyGrid &grid) {
    const auto first = items.begin() + lo, last = items.begin() + hi;
    const int c0 = facing_class(nrm(items[lo]));
    if (std::any_of(first, last, [&](uint32_t i) { return facing_class(nrm(i)) != c0; })) {
        std::sort(first, last, [&](uint32_t a, uint32_t b) {
            const int ca = facing_class(nrm(a)), cb = facing_class(nrm(b));
            return ca != cb ? ca < cb : a < b;
        });
        uint32_t best = lo, mid2 = lo + hi;   // compare 2·place with lo + hi: no rounding
        for (uint32_t k = lo + 1; k < hi; ++k)
            if (facing_class(nrm(items[k])) != facing_class(nrm(items[k - 1])) &&
                (best == lo || std::abs(int64_t(2 * k) - int64_t(mid2)) < std::abs(int64_t(2 * best) - int64_t(mid2))))
                best = k;
        return best;
    }
    int64_t kmin[3], kmax[3];
    for (int a = 0; a < 3; ++a) kmin[a] = std::numeric_limits<int64_t>::max(), kmax[a] = std::numeric_limits<int64_t>::min();
    for (auto it = first; it != last; ++it)
        for (int a = 0; a < 3; ++a) {
            const int64_t k = grid.key(pos(*it)[a], a);
            kmin[a] = std::min(kmin[a], k), kmax[a] = std::max(kmax[a], k);
        }
    const int64_t ext[3] = {kmax[0] - kmin[0], kmax[1] - kmin[1], kmax[2] - kmin[2]};
    const int axis = ext[0] >= ext[1] && ext[0] >= ext[2] ? 0 : ext[1] >= ext[2] ? 1 : 2;
    const uint32_t mid = lo + (hi - lo) / 2;
    std::nth_element(first, items.begin() + mid, last, [&](uint32_t a, uint32_t b) {
        const int64_t ka = grid.key(pos(a)[axis], axis), kb = grid.key(pos(b)[axis], axis);
        return ka != kb ? ka < kb : a < b;
    });
    return mid;
}
}  // namespace

PriorTree::PriorTree(const std::vector<Vec3f> &position, const std::vector<Vec3f> &normal, const ClusterVisibility &vis,
                     float node_area, bool patches, float theta) {
    const size_t m = position.size();
    if (normal.size() != m) LTM_THROW("prior tree: ", m, " positions but ", normal.size(), " normals");
    if (!(theta >= 0.f) || !std::isfinite(theta)) LTM_THROW("prior tree: theta must be >= 0, got ", theta);
    if (!(node_area > 0.f)) LTM_THROW("prior tree: node area must be > 0, got ", node_area);
    if (!vis.empty() && vis.node_cluster.size() != m) LTM_THROW("prior tree: visibility for ", vis.node_cluster.size(), " nodes, not ", m);
    m_theta = theta, m_reg = node_area / float(k_pi), m_side = std::sqrt(node_area), m_patches = patches;
    m_coplanar = 1e-3f * m_side;
    m_clusters = vis.empty() ? 1 : vis.size();
    if (m == 0) return;
    m_grid.step = double(m_side) / k_keys_per_side;
    m_grid.origin = position[0];
    for (const Vec3f &p : position) m_grid.origin = min(m_grid.origin, p);
    // Off the lowest node by an irrational share of a step, so that points on a lattice from it
    // (a grid of nodes, walls at whole spacings) do not sit on the steps' edges.
    m_grid.origin = m_grid.origin - Vec3f(float(KeyGrid::k_offset * m_grid.step));
    const KeyGrid &grid = m_grid;
    // Each cluster's nodes, in node order.
    std::vector<std::vector<uint32_t>> members(m_clusters);
    for (size_t j = 0; j < m; ++j) members[vis.empty() ? 0 : vis.node_cluster[j]].push_back(uint32_t(j));
    // The clusters' centroids and normal sums: how the level above them is split.
    std::vector<Vec3f> cpos(m_clusters, Vec3f(0.f)), cnrm(m_clusters, Vec3f(0.f));
    std::vector<uint32_t> clusters;
    for (size_t c = 0; c < m_clusters; ++c) {
        if (members[c].empty()) continue;
        for (uint32_t j : members[c]) cpos[c] += position[j] / float(members[c].size()), cnrm[c] += normal[j];
        clusters.push_back(uint32_t(c));
    }
    m_tree.reserve(2 * m / k_leaf + 2 * clusters.size() + 8);
    m_place_node.reserve(m);
    // Recursive, preorder (a node is appended before its children).
    auto node_pos = [&](uint32_t j) { return position[j]; };
    auto node_nrm = [&](uint32_t j) { return normal[j]; };
    std::function<int32_t(std::vector<uint32_t> &, uint32_t, uint32_t, int32_t)> build_nodes =
        [&](std::vector<uint32_t> &items, uint32_t lo, uint32_t hi, int32_t cluster) -> int32_t {
        const int32_t t = int32_t(m_tree.size());
        m_tree.emplace_back();
        m_tree[size_t(t)].cluster = cluster;
        if (hi - lo <= k_leaf) {
            m_tree[size_t(t)].lo = uint32_t(m_place_node.size());
            for (uint32_t k = lo; k < hi; ++k) m_place_node.push_back(items[k]);
            m_tree[size_t(t)].hi = uint32_t(m_place_node.size());
            return t;
        }
        const uint32_t mid = split(items, lo, hi, node_pos, node_nrm, grid);
        const int32_t a = build_nodes(items, lo, mid, cluster), b = build_nodes(items, mid, hi, cluster);
        m_tree[size_t(t)].child[0] = a, m_tree[size_t(t)].child[1] = b;
        m_tree[size_t(t)].lo = m_tree[size_t(a)].lo, m_tree[size_t(t)].hi = m_tree[size_t(b)].hi;
        return t;
    };
    std::function<int32_t(uint32_t, uint32_t)> build_clusters = [&](uint32_t lo, uint32_t hi) -> int32_t {
        if (hi - lo == 1) {
            const uint32_t c = clusters[lo];
            const int32_t t = build_nodes(members[c], 0, uint32_t(members[c].size()), int32_t(c));
            m_upper.push_back(uint32_t(t));
            return t;
        }
        const int32_t t = int32_t(m_tree.size());
        m_tree.emplace_back();
        m_upper.push_back(uint32_t(t));
        const uint32_t mid = split(clusters, lo, hi, [&](uint32_t c) { return cpos[c]; }, [&](uint32_t c) { return cnrm[c]; }, grid);
        const int32_t a = build_clusters(lo, mid), b = build_clusters(mid, hi);
        Node &s = m_tree[size_t(t)];
        s.child[0] = a, s.child[1] = b;
        s.lo = m_tree[size_t(a)].lo, s.hi = m_tree[size_t(b)].hi;
        return t;
    };
    build_clusters(0, uint32_t(clusters.size()));
    std::sort(m_upper.begin(), m_upper.end());
    for (size_t u = 0; u < m_upper.size(); ++u) m_tree[m_upper[u]].upper = int32_t(u);
    // Per viewing cluster, what each node at or above the clusters shows it: 0 none of its clusters,
    // 1 all of them, 2 some (children after parents, so from the back). O(C·U) bytes.
    if (!vis.empty()) {
        m_visible = vis.visible;
        const size_t C = m_clusters, U = m_upper.size();
        m_upper_state.assign(C * U, 0);
        for (size_t c = 0; c < C; ++c) {
            uint8_t *state = m_upper_state.data() + c * U;
            for (size_t u = U; u-- > 0;) {
                const Node &t = m_tree[m_upper[u]];
                if (t.cluster >= 0) {
                    state[u] = m_visible[c * C + size_t(t.cluster)];
                } else {
                    const uint8_t a = state[m_tree[size_t(t.child[0])].upper], b = state[m_tree[size_t(t.child[1])].upper];
                    state[u] = a == b ? a : 2;
                }
            }
        }
    }
    for (uint32_t j : m_place_node) {
        m_pos.push_back(position[j]), m_nrm.push_back(normal[j]);
        m_px.push_back(position[j].x), m_py.push_back(position[j].y), m_pz.push_back(position[j].z);
        m_nx.push_back(normal[j].x), m_ny.push_back(normal[j].y), m_nz.push_back(normal[j].z);
    }
    for (Node &t : m_tree) summarise(t);
}

void PriorTree::summarise(Node &t) const {
    t.box_min = Vec3f(std::numeric_limits<float>::infinity()), t.box_max = Vec3f(-std::numeric_limits<float>::infinity());
    for (uint32_t k = t.lo; k < t.hi; ++k) t.box_min = min(t.box_min, m_pos[k]), t.box_max = max(t.box_max, m_pos[k]);
    // The centroid in double: Σ_j e_j = 0 is what the expansion drops (float sums over a large
    // subtree left ~1e-3 of the furnace's value).
    double c[3] = {0, 0, 0};
    t.normal_sum = Vec3f(0.f);
    for (uint32_t k = t.lo; k < t.hi; ++k) {
        for (int a = 0; a < 3; ++a) c[a] += double(m_pos[k][a]);
        t.normal_sum += m_nrm[k];
    }
    t.centroid = Vec3f(float(c[0] / double(t.hi - t.lo)), float(c[1] / double(t.hi - t.lo)), float(c[2] / double(t.hi - t.lo)));
    t.radius = 0.f;
    // The members the rays go to, chosen by distances on the key grid (ties: the first place), so that
    // rounding does not pick another member of a symmetric patch in another unit: the representative
    // nearest the centroid, and the ends of the longest extent — the member farthest from the
    // centroid, and the one farthest from that.
    int64_t nearest = std::numeric_limits<int64_t>::max(), far = -1;
    for (uint32_t k = t.lo; k < t.hi; ++k) {
        const float r = length(m_pos[k] - t.centroid);
        t.radius = std::max(t.radius, r);
        const int64_t key = m_grid.distance_key(double(r));
        if (key < nearest) nearest = key, t.representative = k;
        if (key > far) far = key, t.probe[0] = k;
    }
    far = -1;
    for (uint32_t k = t.lo; k < t.hi; ++k)
        if (const int64_t r = m_grid.length_key(m_pos[k] - m_pos[t.probe[0]]); r > far) far = r, t.probe[1] = k;
    for (float &v : t.spread) v = 0.f;
    for (float &v : t.tilt) v = 0.f;
    for (uint32_t k = t.lo; k < t.hi; ++k) {
        const Vec3f e = m_pos[k] - t.centroid;
        t.spread[0] += e.x * e.x, t.spread[1] += e.x * e.y, t.spread[2] += e.x * e.z;
        t.spread[3] += e.y * e.y, t.spread[4] += e.y * e.z, t.spread[5] += e.z * e.z;
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) t.tilt[a * 3 + b] += e[a] * m_nrm[k][b];
    }
    const float len = length(t.normal_sum);
    t.normal_length = len;
    if (!(len > 1e-6f)) {
        t.cos_cone = -1.f, t.sin_cone = 0.f, t.normal_length = 0.f;   // normals cancel (a cone of π): never aggregated
        return;
    }
    const Vec3f axis = t.normal_sum / len;
    t.thickness = 0.f;
    float cone = 0.f;   // β
    for (uint32_t k = t.lo; k < t.hi; ++k) {
        cone = std::max(cone, std::acos(std::clamp(dot(m_nrm[k], axis), -1.f, 1.f)));
        t.thickness = std::max(t.thickness, std::abs(dot(m_pos[k] - t.centroid, axis)));
    }
    t.cos_cone = std::cos(cone), t.sin_cone = std::sin(cone), t.delta = 2.f * std::sin(0.5f * cone);
}

void PriorTree::set_rays(std::shared_ptr<const SegmentOcclusion> rays, const std::vector<uint8_t> &exact) {
    if (!exact.empty() && exact.size() != nodes()) LTM_THROW("prior tree: ", exact.size(), " exact flags for ", nodes(), " nodes");
    m_rays = std::move(rays);
    static std::atomic<uint64_t> epochs{0};
    m_ray_epoch = ++epochs;   // a Scratch's shared answers belong to this tree and these rays only
    // The leaf of every place (RayFilter's whole leaves).
    m_leaf_of.assign(m_rays ? nodes() : 0, 0u);
    for (size_t t = 0; t < m_tree.size() && m_rays; ++t)
        if (m_tree[t].child[0] < 0)
            for (uint32_t k = m_tree[t].lo; k < m_tree[t].hi; ++k) m_leaf_of[k] = uint32_t(t);
    for (Node &t : m_tree) {
        t.keep_exact = t.flagged_only = false;
        if (!m_rays || exact.empty()) continue;
        uint32_t flagged = 0;
        for (uint32_t k = t.lo; k < t.hi; ++k) flagged += exact[m_place_node[k]] != 0;
        t.keep_exact = flagged > 0, t.flagged_only = flagged == t.hi - t.lo;
    }
}

size_t PriorTree::bytes() const {
    return m_tree.size() * sizeof(Node) + m_place_node.size() * (sizeof(uint32_t) + 2 * sizeof(Vec3f) + 6 * sizeof(float)) +
           m_upper.size() * sizeof(uint32_t) + m_visible.size() + m_upper_state.size() + m_leaf_of.size() * sizeof(uint32_t);
}

PriorTree::Sums PriorTree::sums(const std::vector<Vec3f> &x) const {
    if (x.size() != nodes()) LTM_THROW("prior tree: ", x.size(), " values for ", nodes(), " nodes");
    Sums s;
    s.value.resize(nodes());
    for (size_t k = 0; k < nodes(); ++k) s.value[k] = x[m_place_node[k]];
    s.dipole.assign(m_tree.size() * 3, Vec3f(0.f));
    s.moment.assign(m_tree.size() * 3, Vec3f(0.f));
    // Σ_j n_j x_j and Σ_j x_j (p_j − c) from the places, O(T log m) in all.
    for (size_t t = 0; t < m_tree.size(); ++t) {
        const Node &n = m_tree[t];
        for (uint32_t k = n.lo; k < n.hi; ++k) {
            const Vec3f e = m_pos[k] - n.centroid;
            for (int c = 0; c < 3; ++c) {
                s.dipole[t * 3 + size_t(c)] += m_nrm[k] * s.value[k][c];
                s.moment[t * 3 + size_t(c)] += e * s.value[k][c];
            }
        }
    }
    return s;
}

namespace {
// The walk's lanes: one per receiver of a group (core/lanes8.h).
using namespace lanes8;
static_assert(PriorTree::k_group == k_lanes, "a group's receivers are the walk's lanes");

// The walking receivers lane by lane (structure of arrays). Lanes past `count` repeat the last
// receiver: their arithmetic stays finite and is never used.
struct Lanes {
    f8 px, py, pz, nx, ny, nz;
    f8 plane;   ///< −n·p: the box bound's start
    Lanes(const PriorTree::Receiver *r, int count) {
        for (int l = 0; l < k_lanes; ++l) {
            const PriorTree::Receiver &q = r[std::min(l, count - 1)];
            px[l] = q.p.x, py[l] = q.p.y, pz[l] = q.p.z, nx[l] = q.n.x, ny[l] = q.n.y, nz[l] = q.n.z;
            plane[l] = -dot(q.n, q.p);
        }
    }
    Vec3f p(int l) const { return {px[l], py[l], pz[l]}; }
    Vec3f n(int l) const { return {nx[l], ny[l], nz[l]}; }
};
}  // namespace

// Every receiver makes its own decision at each node, by its own bounds (all lanes at once); what
// the lanes share is the node's fetch, its stack entry and the descent while at least one of them
// still opens it. Each lane meets its terms in the tree's preorder, as when it walks alone, so its
// row is the same bit for bit whoever walks beside it (with rays, up to the rays a lane takes from a
// neighbour: RayFilter).
template <class Visit>
void PriorTree::traverse(const Receiver *receivers, int count, std::vector<Entry> &stack, Visit &&visit) const {
    if (m_tree.empty() || count <= 0) return;
    const Lanes q(receivers, count);
    const float near_reach = m_patches ? 2.5f * m_side : 0.f;
    const size_t C = m_clusters, U = m_upper.size();
    const f8 zero = {};
    // Neighbours often blend the same clusters: a lane whose view equals an earlier lane's (`same`)
    // copies that lane's weights where both still descend.
    int same[k_group];
    for (int l = 0; l < k_group; ++l) {
        same[l] = l;
        if (l >= count) continue;   // never read
        const View &a = receivers[l].view;
        for (int j = 0; j < l && same[l] == l; ++j) {
            const View &b = receivers[j].view;
            if (a.K != b.K) continue;
            bool equal = true;
            for (int k = 0; k < a.K && equal; ++k) equal = a.ids[k] == b.ids[k] && a.w[k] == b.w[k];
            if (equal) same[l] = j;
        }
    }
    Entry root;
    root.mask = (1u << count) - 1;
    for (float &w : root.w) w = -1.f;
    stack.assign(1, root);
    while (!stack.empty()) {
        const Entry e = stack.back();
        stack.pop_back();
        visit.visited();
        const Node &s = m_tree[e.node];
        uint32_t mask = e.mask;
        float w[k_group];
        bool uniform[k_group];
        for (int l = 0; l < k_group; ++l) {
            w[l] = e.w[l], uniform[l] = true;
            if (!(mask >> l & 1u)) continue;
            const View &view = receivers[l].view;
            if (view.K == 0) {
                w[l] = 1.f;
            } else if (w[l] < 0.f && same[l] != l && (mask >> same[l] & 1u)) {
                w[l] = w[same[l]], uniform[l] = uniform[same[l]];
            } else if (w[l] < 0.f) {
                w[l] = 0.f;
                if (s.cluster >= 0) {   // a cluster's root: Σ_k w_k V(c_k, c)
                    for (int k = 0; k < view.K; ++k) w[l] += view.w[k] * float(m_visible[size_t(view.ids[k]) * C + size_t(s.cluster)]);
                } else {                // above the clusters: uniform when each blended row sees all or none of them
                    for (int k = 0; k < view.K; ++k) {
                        const uint8_t state = m_upper_state[size_t(view.ids[k]) * U + size_t(s.upper)];
                        if (state == 2) uniform[l] = false;
                        else w[l] += view.w[k] * float(state);
                    }
                    if (!uniform[l]) w[l] = 1.f;   // some of it is seen: open it
                }
            }
            if (!(w[l] > 0.f)) mask &= ~(1u << l);
        }
        if (!mask) continue;
        const f8 dx = s.centroid.x - q.px, dy = s.centroid.y - q.py, dz = s.centroid.z - q.pz;
        uint32_t open = mask;
        if (s.normal_length > 0.f && s.cos_cone > 0.f) {
            // Bounds on the members' cosines (times r) with the receiver (A_j = n·(p_j − p)) and their
            // own (B_j = −n_j·(p_j − p)): A_j from the bounding box and from the centroid, the normal's
            // tilt and the thickness (n·e_j ≤ |n·N̂| h + |n × N̂| R); B_j from −N̂·d, with n_j within
            // δ = 2 sin(β/2) of N̂ and |n_j·e_j| ≤ h + δ R.
            const Vec3f nhat = s.normal_sum / s.normal_length;
            const f8 r2 = dx * dx + dy * dy + dz * dz, dist = sqrt8(r2);
            const f8 cr = q.nx * dx + q.ny * dy + q.nz * dz;
            const f8 along = abs8(q.nx * nhat.x + q.ny * nhat.y + q.nz * nhat.z);
            const f8 one = 1.f - along * along, across = sqrt8(0.f < one ? one : zero);
            const f8 spread = along * s.thickness + across * s.radius;
            f8 box_lo = q.plane, box_hi = box_lo;
            for (int a = 0; a < 3; ++a) {
                const f8 &na = a == 0 ? q.nx : a == 1 ? q.ny : q.nz;
                const f8 u = na * s.box_min[a], v = na * s.box_max[a];
                box_lo += v < u ? v : u, box_hi += u < v ? v : u;
            }
            const f8 lo = cr - spread, hi = cr + spread;
            const f8 a_lo = box_lo < lo ? lo : box_lo, a_hi = hi < box_hi ? hi : box_hi;
            const f8 b_mid = -(nhat.x * dx + nhat.y * dy + nhat.z * dz);
            const f8 b_slack = s.delta * (dist + s.radius) + s.thickness;
            // Exactly 0: every member behind the receiver's plane (its patch too: a corner lies at most
            // s/√2 · sin∠(n, n_j) off the centre along n, ∠(n, n_j) ≤ ∠(n, N̂) + β), or the receiver
            // behind every member's plane (where the point formula and the patch both give 0).
            const float cb = s.cos_cone, sb = s.sin_cone;
            const f8 c_tilt = along * cb - across * sb;   // cos(∠(n, N̂) + β)
            const f8 corner = m_patches ? 0.7072f * m_side * (c_tilt <= 0.f ? 1.f + zero : across * cb + along * sb) : zero;
            // Both planes with m_coplanar's tolerance: a receiver on a floor and a subtree reaching down
            // to it (a_lo) or a receiver in a wall's own plane (b) sit at 0 up to rounding, which a change
            // of unit flips — and with rays the walk then traces other segments (a house: 1.5 % at × 10).
            const uint32_t skip = bits((a_hi + corner <= m_coplanar) | (b_mid + b_slack <= m_coplanar)) & open;
            uint32_t aggregate = 0;
            if (m_theta > 0.f && s.cos_cone >= k_flat_cos && !s.keep_exact)
                aggregate = bits((s.radius < m_theta * dist) & (dist - s.radius > near_reach) & (a_lo > -m_coplanar) &
                                 (b_mid - b_slack > 0.f)) & open & ~skip;
            for (int l = 0; l < k_group; ++l) {
                if (!(aggregate >> l & 1u)) continue;
                // A visit may refuse the aggregate (rays that disagree on its visibility): then it is opened.
                if (!(uniform[l] && visit.aggregate(q, l, e.node, w[l], Vec3f(dx[l], dy[l], dz[l])))) aggregate &= ~(1u << l);
            }
            open &= ~(skip | aggregate);
            if (!open) continue;
        }
        if (s.child[0] < 0) {
            visit.exact(q, open, s.lo, s.hi, w);
            continue;
        }
        // Below a cluster's root the weight is the cluster's.
        Entry child;
        child.mask = open;
        for (int l = 0; l < k_group; ++l) child.w[l] = s.cluster >= 0 ? w[l] : -1.f;
        child.node = uint32_t(s.child[1]);
        stack.push_back(child);
        child.node = uint32_t(s.child[0]);
        stack.push_back(child);
    }
}

// A walk's terms, per receiver (lane) in the order the walk meets them: each aggregate's coefficients
// and each exactly summed node's, handed to a Sink that keeps them (RowSink: record_group) or sums
// them against values at once (SumSink: gather_group). Both give den and Σ terms · x alike.
template <class Sink> struct PriorTree::Terms {
    const PriorTree &tree;
    Sink &sink;
    float side, reg, near_reach, scale;
    void visited() {}
    // The expansion of k about the centroid (header): Σ_j k(p_j) x_j ≈ k(c)·f·Σ_j x_j + ∇k(c)·Σ_j x_j e_j.
    bool aggregate(const Lanes &q, int l, uint32_t t, float w, Vec3f d) {
        const Node &s = tree.m_tree[t];
        const Vec3f n = q.n(l);
        const double u = double(dot(d, d));
        const double h = u * (u + double(reg)), h1 = 2 * u + double(reg);
        const double g = 1 / h, g1 = -h1 / (h * h), g2 = (2 * h1 * h1 - 2 * h) / (h * h * h);
        const double count = double(s.hi - s.lo);
        const Vec3f mbar = s.normal_sum / float(count);
        const double A = double(dot(n, d)), B = -double(dot(mbar, d));
        const auto quad = [&s](Vec3f a, Vec3f b) {   // aᵀ Σ b
            const float *S = s.spread;
            return double(a.x * (S[0] * b.x + S[1] * b.y + S[2] * b.z) + a.y * (S[1] * b.x + S[3] * b.y + S[4] * b.z) +
                          a.z * (S[2] * b.x + S[4] * b.y + S[5] * b.z));
        };
        const double trace = double(s.spread[0] + s.spread[3] + s.spread[5]);
        const double k = A * B * g;
        const double second = g * -quad(n, mbar) + 2 * g1 * (A * -quad(mbar, d) + B * quad(n, d)) + A * B * (g1 * trace + 2 * g2 * quad(d, d));
        // The second-order terms as a factor of the first-order sum: never flips its sign.
        const double factor = std::clamp(1 + second / (count * k), 0.5, 1.5);
        // The normals' first-order terms, M = Σ_j e_j n_jᵀ (0 when they are all equal):
        // −A g tr M − g nᵀ M d − 2 A g′ dᵀ M d, as a factor on the whole sum (a uniform x stays exact).
        const float *T = s.tilt;
        const auto mq = [T](Vec3f a, Vec3f b) {   // aᵀ M b
            return double(a.x * (T[0] * b.x + T[1] * b.y + T[2] * b.z) + a.y * (T[3] * b.x + T[4] * b.y + T[5] * b.z) +
                          a.z * (T[6] * b.x + T[7] * b.y + T[8] * b.z));
        };
        const double tilt = -A * g * double(T[0] + T[4] + T[8]) - g * mq(n, d) - 2 * A * g1 * mq(d, d);
        const double tilt_factor = std::clamp(1 + tilt / (count * k), 0.5, 1.5);
        const double weight = double(w) * factor * tilt_factor;
        const double den = weight * count * k;
        // Σ_j x_j k(p_j): A g (−d · Σ_j n_j x_j) + ∇k(c) · Σ_j x_j e_j, ∇k(c) = B g n − A g n̄ + 2 A B g′ d.
        const Vec3f along = d * float(-weight * A * g);
        const Vec3f grad = (n * float(B * g) - mbar * float(A * g) + d * float(2 * A * B * g1)) * float(double(w) * tilt_factor);
        return sink.aggregate(l, t, den, along, grad);
    }
    // The dense row's terms (transport_prior.cpp): the point formula, and within 2.5 s the square
    // patch's form factor blended in over r ∈ [1.5 s, 2.5 s]. Member by member, the point formula
    // for every lane at once.
    void exact(const Lanes &q, uint32_t mask, uint32_t lo, uint32_t hi, const float *w) {
        const f8 zero = {};
        for (uint32_t j = lo; j < hi; ++j) {
            const f8 dx = tree.m_px[j] - q.px, dy = tree.m_py[j] - q.py, dz = tree.m_pz[j] - q.pz;
            const f8 r2 = dx * dx + dy * dy + dz * dz;
            const f8 cr = q.nx * dx + q.ny * dy + q.nz * dz;
            const f8 cs = -(tree.m_nx[j] * dx + tree.m_ny[j] * dy + tree.m_nz[j] * dz);
            const f8 t = (cr > 0.f) & (cs > 0.f) ? cr * cs / (r2 * (r2 + reg) + 1e-30f) : zero;
            for (int l = 0; l < k_group; ++l) {
                if (!(mask >> l & 1u)) continue;
                float tl = t[l];
                if (tree.m_patches) {
                    const float r = std::sqrt(r2[l]);
                    if (r < near_reach) {
                        const float beta = std::clamp((r - 1.5f * side) / side, 0.f, 1.f);
                        const float patch = near_form_factor(q.p(l), q.n(l), tree.m_pos[j], tree.m_nrm[j], side) * scale;
                        tl = (1.f - beta) * patch + beta * tl;
                    }
                }
                if (!(tl > 0.f)) continue;
                const double wt = double(w[l]) * double(tl);
                sink.exact(l, j, wt);
            }
        }
    }
};

// Visibility by rays (header): passes a term on to the Sink only when the segment from its lane's
// receiver to the term's node (an aggregate's representative) is clear.
// With logs (record_group's RayLog), each decision is recorded, or replayed from a complete log.
template <class Sink> struct PriorTree::RayFilter {
    const PriorTree &tree;
    Sink &sink;
    const Receiver *receivers;
    float lift;
    RayLog *logs = nullptr;
    size_t read[k_group] = {};
    // A lane whose receiver lies within k_ray_share of the distance to a term from the receiver that
    // last traced it (this walk's or an earlier one's with the same Scratch: RayShare) takes that
    // answer: the two segments differ by less than k_ray_share radians, and the receivers that share
    // a Scratch are neighbours (a leaf's patch, a tile of pixels), so a far term costs one ray per
    // neighbourhood, not per lane.
    RayShare &share;
    // A far leaf (radius < θ · distance, beyond the patches' reach) that the walk sums exactly for
    // its shape — curved, or straddling the receiver's plane — and not for its nearness is seen whole
    // or not at all when the rays to its representative and to both ends of its longest extent
    // agree, as an aggregate's are: its members (≤ 8) then take that answer without a ray each.
    // Per lane, the leaf its last member belonged to and that answer (2: its members trace alone).
    struct Whole {
        uint32_t leaf = ~0u;
        uint8_t decision = 2;
    } whole[k_group];
    bool clear(int l, uint32_t place) const {
        const Receiver &r = receivers[l];
        return !tree.m_rays->blocked(r.p + r.n * lift, tree.m_pos[place] + tree.m_nrm[place] * lift);
    }
    template <class Trace> uint8_t shared(int l, uint32_t key, Vec3f target, Trace trace) {
        if (share.epoch != tree.m_ray_epoch) share.slots.assign(size_t(1) << k_share_bits, {}), share.epoch = tree.m_ray_epoch;
        RayShare::Slot &slot = share.slots[(key * 2654435761u) >> (32 - k_share_bits)];
        const Vec3f p = receivers[l].p;
        if (slot.key == key && length(p - slot.from) < k_ray_share * length(target - slot.from)) return slot.decision;
        slot = {key, trace(), p};
        return slot.decision;
    }
    // 1 when the node's representative and both probes are clear, 0 when all three are blocked, 2
    // (partly visible) when they disagree.
    uint8_t seen(int l, const Node &s) const {
        const bool rep = clear(l, s.representative);
        if (clear(l, s.probe[0]) != rep || clear(l, s.probe[1]) != rep) return 2;
        return rep ? 1 : 0;
    }
    uint8_t whole_leaf(int l, uint32_t leaf) {
        const Node &s = tree.m_tree[leaf];
        if ((s.keep_exact && !s.flagged_only) || s.hi - s.lo <= 3) return 2;   // mixed with emitters; ≤ 3 rays anyway
        const Receiver &r = receivers[l];
        const float d = length(s.centroid - r.p), near_reach = tree.m_patches ? 2.5f * tree.m_side : 0.f;
        if (!(s.radius < tree.m_theta * d) || d - s.radius <= near_reach) return 2;
        // Its three rays speak for the members only if their ends face the receiver and lie in front of
        // it: an end facing away is hidden by its own object (the far side of a bulb), which says
        // nothing of the members that face the receiver. Clear of either plane by m_coplanar, as the
        // walk's own plane tests: an end in the receiver's floor is in front or behind by rounding
        // alone, which a change of unit flips.
        const auto facing = [&](uint32_t k) {
            const Vec3f e = tree.m_pos[k] - r.p;
            return dot(r.n, e) > tree.m_coplanar && dot(tree.m_nrm[k], e) < -tree.m_coplanar;
        };
        if (!facing(s.representative) || !facing(s.probe[0]) || !facing(s.probe[1])) return 2;
        return shared(l, leaf | 0x40000000u, s.centroid, [&] { return seen(l, s); });
    }
    uint8_t member(int l, uint32_t place) {
        Whole &w = whole[l];
        const uint32_t leaf = tree.m_leaf_of[place];
        if (w.leaf != leaf) w = {leaf, whole_leaf(l, leaf)};
        if (w.decision != 2) return w.decision;
        return shared(l, place, tree.m_pos[place], [&]() -> uint8_t { return clear(l, place) ? 1 : 0; });
    }
    template <class Decide> uint8_t decision(int l, Decide decide) {
        if (!logs) return decide();
        RayLog &log = logs[l];
        if (log.complete) {   // the walk is deterministic: a replay never outruns its log
            if (read[l] >= log.decisions.size()) LTM_THROW("prior tree: a replayed walk met more terms than it recorded");
            return log.decisions[read[l]++];
        }
        const uint8_t d = decide();
        log.decisions.push_back(d);
        return d;
    }
    // Visible from the receiver when its representative is; partly visible (refused, so the walk
    // opens it) when either end of its longest extent disagrees with the representative.
    bool aggregate(int l, uint32_t t, double den, Vec3f along, Vec3f grad) {
        const Node &s = tree.m_tree[t];
        const uint8_t d = decision(l, [&] { return shared(l, t | 0x80000000u, s.centroid, [&] { return seen(l, s); }); });
        if (d == 2) return false;
        return d == 1 ? sink.aggregate(l, t, den, along, grad) : true;
    }
    void exact(int l, uint32_t place, double wt) {
        if (decision(l, [&] { return member(l, place); }))
            sink.exact(l, place, wt);
    }
};

namespace {
// Keeps the terms as rows (record, record_group).
struct RowSink {
    PriorTree::Row *rows;
    bool aggregate(int l, uint32_t t, double den, Vec3f along, Vec3f grad) {
        rows[l].den += den;
        rows[l].aggregates.push_back({t, along, grad});
        return true;
    }
    void exact(int l, uint32_t place, double wt) {
        rows[l].den += wt;
        rows[l].exact.push_back({place, float(wt)});
    }
};
// Sums the terms against values as they come (gather_group): the aggregates' and the exact nodes'
// shares apart and then added, as apply() adds them, so the answer is apply()'s to the bit. N value
// sets at once (gather_group2: the prior's exitance and its regather's): each set's sums are the
// same operations in the same order as it alone would get.
template <int N> struct SumSink {
    const PriorTree::Sums *x[N];
    double den[PriorTree::k_group] = {}, agg[N][PriorTree::k_group][3] = {}, ex[N][PriorTree::k_group][3] = {};
    bool aggregate(int l, uint32_t t, double d, Vec3f along, Vec3f grad) {
        den[l] += d;
        for (int v = 0; v < N; ++v) {
            const Vec3f *dipole = &x[v]->dipole[size_t(t) * 3], *moment = &x[v]->moment[size_t(t) * 3];
            for (int c = 0; c < 3; ++c) agg[v][l][c] += double(dot(along, dipole[c])) + double(dot(grad, moment[c]));
        }
        return true;
    }
    void exact(int l, uint32_t place, double wt) {
        den[l] += wt;
        const double coef = double(float(wt));
        for (int v = 0; v < N; ++v)
            for (int c = 0; c < 3; ++c) ex[v][l][c] += coef * double(x[v]->value[place][c]);
    }
};
}  // namespace

void PriorTree::record(Vec3f p, Vec3f n, const View &view, Row &row, Scratch &scratch) const {
    const Receiver r{p, n, view};
    record_group(&r, 1, &row, scratch);
}

void PriorTree::record_group(const Receiver *receivers, int count, Row *rows, Scratch &scratch) const {
    record_group(receivers, count, rows, scratch, nullptr);
}

// The walks run as AVX2 code where the CPU has it (core/simd_clones.h): the lanes' 8-wide vectors
// are one register instead of two, the solve's walks ~25 % faster and the gather's ~40 % (session 34,
// docs/performance.md); the rows are the same bits in either clone (-ffp-contract=off, src/CMakeLists.txt).
LTM_SIMD_CLONES
void PriorTree::record_group(const Receiver *receivers, int count, Row *rows, Scratch &scratch, RayLog *logs) const {
    if (count < 0 || count > k_group) LTM_THROW("prior tree: a group of ", count, " receivers (0 to ", k_group, ")");
    if (count == 0) return;
    for (int l = 0; l < count; ++l) rows[l].clear();
    RowSink sink{rows};
    const float near_reach = 2.5f * m_side, scale = float(k_pi) / (m_side * m_side);
    if (m_rays) {
        RayFilter<RowSink> filter{*this, sink, receivers, ray_lift(), logs, {}, scratch.shared};
        Terms<RayFilter<RowSink>> terms{*this, filter, m_side, m_reg, near_reach, scale};
        traverse(receivers, count, scratch.stack, terms);
        if (logs)
            for (int l = 0; l < count; ++l) logs[l].complete = true;
        return;
    }
    Terms<RowSink> terms{*this, sink, m_side, m_reg, near_reach, scale};
    traverse(receivers, count, scratch.stack, terms);
}

template <class Sink> void PriorTree::walk_sums(const Receiver *receivers, int count, Sink &sink, Scratch &scratch) const {
    if (count < 0 || count > k_group) LTM_THROW("prior tree: a group of ", count, " receivers (0 to ", k_group, ")");
    if (count == 0) return;
    const float near_reach = 2.5f * m_side, scale = float(k_pi) / (m_side * m_side);
    if (m_rays) {
        RayFilter<Sink> filter{*this, sink, receivers, ray_lift(), nullptr, {}, scratch.shared};
        Terms<RayFilter<Sink>> terms{*this, filter, m_side, m_reg, near_reach, scale};
        traverse(receivers, count, scratch.stack, terms);
    } else {
        Terms<Sink> terms{*this, sink, m_side, m_reg, near_reach, scale};
        traverse(receivers, count, scratch.stack, terms);
    }
}

LTM_SIMD_CLONES
void PriorTree::gather_group(const Receiver *receivers, int count, const Sums &x, double *den, double (*num)[3],
                             Scratch &scratch, double (*far)[3]) const {
    SumSink<1> sink{{&x}};
    walk_sums(receivers, count, sink, scratch);
    for (int l = 0; l < count; ++l) {
        den[l] = sink.den[l];
        for (int c = 0; c < 3; ++c) num[l][c] = sink.agg[0][l][c] + sink.ex[0][l][c];
        if (far)
            for (int c = 0; c < 3; ++c) far[l][c] = sink.agg[0][l][c];
    }
}

LTM_SIMD_CLONES
void PriorTree::gather_group2(const Receiver *receivers, int count, const Sums &x, const Sums &x2, double *den, double (*num)[3],
                              double (*num2)[3], Scratch &scratch) const {
    SumSink<2> sink{{&x, &x2}};
    walk_sums(receivers, count, sink, scratch);
    for (int l = 0; l < count; ++l) {
        den[l] = sink.den[l];
        for (int c = 0; c < 3; ++c) num[l][c] = sink.agg[0][l][c] + sink.ex[0][l][c];
        for (int c = 0; c < 3; ++c) num2[l][c] = sink.agg[1][l][c] + sink.ex[1][l][c];
    }
}

void PriorTree::apply(const Row &row, const Sums &x, double num[3]) const {
    // The aggregates' share and the exact nodes' apart, then added (as gather_group sums them).
    double agg[3] = {0, 0, 0}, ex[3] = {0, 0, 0};
    for (const Row::Aggregate &a : row.aggregates) {
        const Vec3f *dipole = &x.dipole[size_t(a.node) * 3], *moment = &x.moment[size_t(a.node) * 3];
        for (int c = 0; c < 3; ++c) agg[c] += double(dot(a.along, dipole[c])) + double(dot(a.grad, moment[c]));
    }
    for (const Row::Exact &e : row.exact)
        for (int c = 0; c < 3; ++c) ex[c] += double(e.coef) * double(x.value[e.place][c]);
    for (int c = 0; c < 3; ++c) num[c] = agg[c] + ex[c];
}

size_t PriorTree::Row::bytes() const {
    return sizeof(Row) + aggregates.capacity() * sizeof(Aggregate) + exact.capacity() * sizeof(Exact);
}

std::vector<uint32_t> PriorTree::group_order(const float *position, const float *normal, size_t stride, size_t n) {
    Vec3f lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
    auto finite = [](Vec3f v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
    for (size_t i = 0; i < n; ++i) {
        const float *p = position + i * stride;
        const Vec3f v(p[0], p[1], p[2]);
        if (finite(v)) lo = min(lo, v), hi = max(hi, v);
    }
    // Spreads 10 bits so that two zeros follow each (the Morton interleave of three axes).
    auto spread = [](uint64_t x) {
        x &= 0x3ffu;
        x = (x | (x << 16)) & 0x30000ffu;
        x = (x | (x << 8)) & 0x300f00fu;
        x = (x | (x << 4)) & 0x30c30c3u;
        return (x | (x << 2)) & 0x9249249u;
    };
    std::vector<uint64_t> key(n);
    for (size_t i = 0; i < n; ++i) {
        const float *p = position + i * stride, *nn = normal + i * stride;
        const Vec3f v(p[0], p[1], p[2]);
        if (!finite(v)) {
            key[i] = ~uint64_t(0);
            continue;
        }
        uint64_t cell[3];
        for (int a = 0; a < 3; ++a) {
            const float ext = hi[a] - lo[a];
            cell[a] = ext > 0.f ? uint64_t(std::min(1023.f, (v[a] - lo[a]) / ext * 1024.f)) : 0u;
        }
        key[i] = uint64_t(facing_class(Vec3f(nn[0], nn[1], nn[2]))) << 32 | spread(cell[0]) << 2 | spread(cell[1]) << 1 | spread(cell[2]);
    }
    std::vector<uint32_t> order(n);
    for (size_t i = 0; i < n; ++i) order[i] = uint32_t(i);
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return key[a] != key[b] ? key[a] < key[b] : a < b; });
    return order;
}

PriorTree::Work PriorTree::count(Vec3f p, Vec3f n, const View &view, Scratch &scratch) const {
    struct Visit {
        Work w;
        void visited() { ++w.visited; }
        bool aggregate(const Lanes &, int, uint32_t, float, Vec3f) { return ++w.aggregates, true; }
        void exact(const Lanes &, uint32_t, uint32_t lo, uint32_t hi, const float *) { w.exact += hi - lo; }
    } visit;
    const Receiver r{p, n, view};
    traverse(&r, 1, scratch.stack, visit);
    return visit.w;
}

}  // namespace ltm
