// transport_prior.cpp: the visibility-free radiosity solve and its gather (equations in the header).
#include "ltm/transport/transport_prior.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <memory>
#include <utility>

#include "ltm/core/error.h"
#include "ltm/core/log.h"
#include "ltm/core/parallel.h"
#include "ltm/core/progress.h"
#include "ltm/core/sampling.h"
#include "ltm/transport/patch_form_factor.h"
#include "ltm/points/point_grid.h"
#include "ltm/transport/power_balance.h"

namespace ltm {

namespace {
// Structure-of-arrays copy of the nodes, so the inner loops over j vectorise.
struct Soa {
    std::vector<float> px, py, pz, nx, ny, nz;
    explicit Soa(const std::vector<Vec3f> &p, const std::vector<Vec3f> &n) {
        for (size_t j = 0; j < p.size(); ++j) {
            px.push_back(p[j].x), py.push_back(p[j].y), pz.push_back(p[j].z);
            nx.push_back(n[j].x), ny.push_back(n[j].y), nz.push_back(n[j].z);
        }
    }
};

// Σ_j a_j·b_j with 8 partial sums: vectorises without -ffast-math, and the order is fixed, so the
// result is the same at any thread count.
inline float dot8(const float *__restrict a, const float *__restrict b, size_t m) {
    float acc[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    size_t j = 0;
    for (; j + 8 <= m; j += 8)
        for (size_t l = 0; l < 8; ++l) acc[l] += a[j + l] * b[j + l];
    float s = ((acc[0] + acc[1]) + (acc[2] + acc[3])) + ((acc[4] + acc[5]) + (acc[6] + acc[7]));
    for (; j < m; ++j) s += a[j] * b[j];
    return s;
}

inline float sum8(const float *__restrict a, size_t m) {
    float acc[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    size_t j = 0;
    for (; j + 8 <= m; j += 8)
        for (size_t l = 0; l < 8; ++l) acc[l] += a[j + l];
    float s = ((acc[0] + acc[1]) + (acc[2] + acc[3])) + ((acc[4] + acc[5]) + (acc[6] + acc[7]));
    for (; j < m; ++j) s += a[j];
    return s;
}

// Ĝ's unnormalised row for a receiver (p, n) over nodes [lo, hi): G_j without the area factor a
// (it cancels in the row normalisation), see the header. The receiver's own node (r = 0) gets 0
// from the cosines. row[j] (absolute j) receives the terms.
inline void transfer_row(const Soa &s, size_t lo, size_t hi, Vec3f p, Vec3f n, float reg, float *__restrict row) {
    const float *__restrict px = s.px.data(), *__restrict py = s.py.data(), *__restrict pz = s.pz.data();
    const float *__restrict nx = s.nx.data(), *__restrict ny = s.ny.data(), *__restrict nz = s.nz.data();
    for (size_t j = lo; j < hi; ++j) {
        const float dx = px[j] - p.x, dy = py[j] - p.y, dz = pz[j] - p.z;
        const float r2 = dx * dx + dy * dy + dz * dz;
        const float cr = n.x * dx + n.y * dy + n.z * dz;               // cosines times r
        const float cs = -(nx[j] * dx + ny[j] * dy + nz[j] * dz);
        const float t = cr * cs / (r2 * (r2 + reg) + 1e-30f);
        row[j] = (cr > 0.f && cs > 0.f) ? t : 0.f;
    }
}

// The nodes in cluster order (stable): each cluster's nodes are one range [seg_c, seg_c+1) of
// places, so what a receiver sees is a few runs of consecutive places. Without occlusion, one
// cluster holds every node in its own order.
struct ClusterOrder {
    std::vector<uint32_t> order;   ///< [m] the node at each place
    std::vector<size_t> seg;       ///< [C + 1] first place of each cluster
    ClusterOrder(const ClusterVisibility &vis, size_t m) : order(m), seg(vis.empty() ? 2 : vis.size() + 1, 0) {
        for (size_t j = 0; j < m; ++j) order[j] = uint32_t(j);
        if (vis.empty()) {
            seg[1] = m;
            return;
        }
        std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return vis.node_cluster[a] < vis.node_cluster[b]; });
        for (size_t j = 0; j < m; ++j) ++seg[vis.node_cluster[j] + 1];
        for (size_t c = 0; c + 1 < seg.size(); ++c) seg[c + 1] += seg[c];
    }
    template <class T> std::vector<T> permuted(const std::vector<T> &v) const {
        std::vector<T> out(order.size());
        for (size_t j = 0; j < order.size(); ++j) out[j] = v[order[j]];
        return out;
    }
};

// A receiver's blended clusters and their weights (ClusterVisibility::receiver_clusters), for the
// dense rows (ReceiverView) and the tree (PriorTree::View) alike: a node of the solve (own) with
// blend 1 takes its own cluster. set() returns the closure; without occlusion the view is empty (K 0).
struct BlendedView {
    uint32_t ids[ClusterVisibility::k_candidates];
    float w[ClusterVisibility::k_candidates];
    PriorTree::View view;
    float set(const ClusterVisibility &vis, Vec3f p, Vec3f n, const uint32_t *own) {
        view = {};
        if (vis.empty()) return 1.f;
        LTM_CHECK(vis.pairs);   // clusters built without their pairwise visibility (rays only) have no views
        int K = 1;
        if (own && vis.blend <= 1) ids[0] = *own, w[0] = 1.f;
        else K = vis.receiver_clusters(p, n, ids, w);
        view = {ids, w, K};
        return vis.closure_of(ids, w, K);
    }
};

// What one receiver sees: the weight of each cluster, Σ_k w_k V(c_k, c) over the clusters its
// visibility blends (ClusterVisibility::receiver_clusters; weight 1 everywhere without occlusion),
// the runs [lo, hi) of places whose cluster weighs > 0, and mask[place] = that weight.
struct ReceiverView {
    std::vector<float> weight, mask;
    float closure = 1.f;   ///< what the row sums to: the blended closure of its clusters (1: closed)
    std::vector<std::pair<size_t, size_t>> runs;
    explicit ReceiverView(const ClusterOrder &co) : mask(co.order.size(), 1.f), runs{{0, co.order.size()}} {}
    void set(const ClusterVisibility &vis, const ClusterOrder &co, const uint32_t *ids, const float *w, int K) {
        const size_t C = vis.size();
        LTM_CHECK(vis.pairs);
        closure = vis.closure_of(ids, w, K);
        weight.resize(C);
        vis.blend_rows(ids, w, K, weight.data());
        runs.clear();
        for (size_t c = 0; c < C; ++c) {
            const size_t lo = co.seg[c], hi = co.seg[c + 1];
            if (!(weight[c] > 0.f) || lo == hi) continue;
            std::fill(mask.begin() + ptrdiff_t(lo), mask.begin() + ptrdiff_t(hi), weight[c]);
            if (!runs.empty() && runs.back().second == lo) runs.back().second = hi;
            else runs.emplace_back(lo, hi);
        }
    }
    /// The receiver (p, n), or the node at place i of the solve (blend 1: its own cluster).
    void set(const ClusterVisibility &vis, const ClusterOrder &co, Vec3f p, Vec3f n, const uint32_t *own = nullptr) {
        if (vis.empty()) return;
        BlendedView blended;
        blended.set(vis, p, n, own);
        set(vis, co, blended.ids, blended.w, blended.view.K);
    }
};

// Σ_j row_j · x_j over a sparse row: its values packed run after run.
inline float sparse_dot(const float *vals, const std::vector<std::pair<uint32_t, uint32_t>> &runs, const float *x) {
    float s = 0.f;
    for (const auto &[lo, hi] : runs) s += dot8(vals, x + lo, hi - lo), vals += hi - lo;
    return s;
}

// The near field (TransportPrior::patches): the nodes (places) on a grid of the reach's edge, and
// the side s = √a of their squares.
struct NearNodes {
    PointGrid grid;
    float side;
    NearNodes(const std::vector<Vec3f> &pos, float s) : grid(pos, 2.5f * s), side(s) {}
};

// Replaces the point formula by the square patch's exact form factor (transport/patch_form_factor.h)
// for the nodes near the receiver (p, n), blended over r ∈ [1.5 s, 2.5 s] so the row has no seam:
//     t_j = (1 − β) · F_j · π/a + β · t_j(point),   β = clamp((r − 1.5 s)/s, 0, 1),
// F · π/a being the point term's scale (the on-axis disc: a/(πr² + a) = (a/π) · t). Only places
// the receiver sees (seen(place)) are touched: the others are not in its runs.
template <class Seen>
void near_field(const NearNodes &near, const std::vector<Vec3f> &pos, const std::vector<Vec3f> &nrm, Vec3f p, Vec3f n,
                Seen seen, float *row) {
    const float s = near.side, scale = float(k_pi) / (s * s);
    near.grid.visit_ball(p, 2.5f * s, [&](uint32_t j) {
        const float r = length(pos[j] - p);
        if (!(r < 2.5f * s) || !seen(j)) return;
        const float beta = std::clamp((r - 1.5f * s) / s, 0.f, 1.f);
        const float patch = near_form_factor(p, n, pos[j], nrm[j], s) * scale;
        row[j] = (1.f - beta) * patch + beta * row[j];
    });
}

// The nodes in cluster order with what a row of Ĝ needs — positions and normals (and their
// structure-of-arrays copy), each place's cluster, the near-field grid — shared by the solve
// (receivers: the nodes) and the gather (receivers: the queries).
struct PlacedNodes {
    const ClusterVisibility &vis;
    ClusterOrder co;
    std::vector<Vec3f> pos, nrm;
    Soa soa;
    std::vector<uint32_t> place_cluster;   ///< [m] the cluster of each place (0 without occlusion)
    std::unique_ptr<NearNodes> near;       ///< null without patches
    float reg;                             ///< a/π
    PlacedNodes(const std::vector<Vec3f> &position, const std::vector<Vec3f> &normal, const ClusterVisibility &v,
                float node_area, bool patches)
        : vis(v), co(v, position.size()), pos(co.permuted(position)), nrm(co.permuted(normal)), soa(pos, nrm),
          place_cluster(position.size(), 0), reg(node_area / float(k_pi)) {
        if (!vis.empty())
            for (size_t j = 0; j < pos.size(); ++j) place_cluster[j] = vis.node_cluster[co.order[j]];
        if (patches) near = std::make_unique<NearNodes>(pos, std::sqrt(node_area));
    }
    /// Ĝ's unnormalised row for the receiver (p, n) over the places its view sees (row[place],
    /// the others untouched): the point formula, the near field, times its cluster's weight.
    void row(const ReceiverView &view, Vec3f p, Vec3f n, float *row) const {
        for (const auto &[lo, hi] : view.runs) transfer_row(soa, lo, hi, p, n, reg, row);
        if (near) near_field(*near, pos, nrm, p, n, [&](uint32_t j) { return vis.empty() || view.weight[place_cluster[j]] > 0.f; }, row);
        if (!vis.empty())
            for (const auto &[lo, hi] : view.runs)
                for (size_t j = lo; j < hi; ++j) row[j] *= view.mask[j];
    }
};

}  // namespace

namespace {
// Calls body(first, last) for every block of `block` consecutive groups of [0, groups), the blocks in
// parallel. The bounds are fixed, so what the walks of one block share — its Scratch, and with rays
// their answers (PriorTree::RayShare) — is the same at any thread count: each call starts its own.
void parallel_blocks(int64_t groups, int64_t block, const std::function<void(int64_t, int64_t)> &body) {
    parallel_for(0, (groups + block - 1) / block, 1, [&](int64_t b0, int64_t b1) {
        for (int64_t k = b0; k < b1; ++k) body(k * block, std::min(groups, (k + 1) * block));
    });
}

// The dense solve: every node's row of Ĝ stored (sparse by what it sees), D sparse products.
// -> Σ_{k=1..D} B_k per node (caller's order); mean_e: the area mean of E⁺ at the nodes.
std::vector<Vec3f> dense_bounces(const std::vector<Vec3f> &position, const std::vector<Vec3f> &normal,
                                 const std::vector<Vec3f> &albedo, const std::vector<Vec3f> &radiance, float node_area,
                                 int bounces, const ClusterVisibility &vis, bool patches, bool want_mean, Vec3f &mean_e) {
    const size_t m = position.size();
    // Everything in cluster order (places): a node's row is then the runs of places it sees, and
    // the transport Ĝ is stored sparse — only what each node sees (about a room's worth of a house).
    const PlacedNodes nodes(position, normal, vis, node_area, patches);
    const ClusterOrder &co = nodes.co;
    const std::vector<Vec3f> &pos = nodes.pos, &nrm = nodes.nrm;
    const std::vector<Vec3f> rho = co.permuted(albedo);
    std::vector<std::vector<float>> g(m);                                 // [m] packed row values
    std::vector<std::vector<std::pair<uint32_t, uint32_t>>> g_runs(m);   // [m] their runs of places
    parallel_for(0, int64_t(m), 16, [&](int64_t b, int64_t e) {
        ReceiverView view(co);
        std::vector<float> row(m);
        for (int64_t i = b; i < e; ++i) {
            const uint32_t node = co.order[size_t(i)];
            view.set(vis, co, pos[size_t(i)], nrm[size_t(i)], vis.empty() ? nullptr : &vis.node_cluster[node]);
            nodes.row(view, pos[size_t(i)], nrm[size_t(i)], row.data());
            float sum = 0.f;
            size_t len = 0;
            for (const auto &[lo, hi] : view.runs) sum += sum8(row.data() + lo, hi - lo), len += hi - lo;
            // The row sums to the node's closure: light sent into its open share leaves the scene.
            const float inv = sum > 0.f ? view.closure / sum : 0.f;
            std::vector<float> &vals = g[size_t(i)];
            vals.reserve(len);
            for (const auto &[lo, hi] : view.runs) {
                g_runs[size_t(i)].emplace_back(uint32_t(lo), uint32_t(hi));
                for (size_t j = lo; j < hi; ++j) vals.push_back(row[j] * inv);
            }
        }
    });
    // B_0 = π L (exitance of the emitters); B_{k+1} = ρ · Ĝ B_k, channel-major for the dot products.
    std::vector<float> bk[3], next[3], ex[3];
    for (int c = 0; c < 3; ++c) {
        bk[c].resize(m), next[c].resize(m), ex[c].assign(m, 0.f);
        for (size_t j = 0; j < m; ++j) bk[c][j] = radiance[co.order[j]][c] * float(k_pi);
    }
    for (int k = 0; k < bounces; ++k) {
        parallel_for(0, int64_t(m), 64, [&](int64_t lo, int64_t hi) {
            for (int64_t i = lo; i < hi; ++i)
                for (int c = 0; c < 3; ++c)
                    next[c][size_t(i)] = rho[size_t(i)][c] * sparse_dot(g[size_t(i)].data(), g_runs[size_t(i)], bk[c].data());
        });
        for (int c = 0; c < 3; ++c) {
            std::swap(bk[c], next[c]);
            for (size_t j = 0; j < m; ++j) ex[c][j] += bk[c][j];
        }
    }
    mean_e = Vec3f(0.f);
    if (want_mean)
        for (size_t i = 0; i < m; ++i)
            for (int c = 0; c < 3; ++c) mean_e[c] += sparse_dot(g[i].data(), g_runs[i], ex[c].data()) / float(m);
    std::vector<Vec3f> out(m);
    for (size_t j = 0; j < m; ++j)
        for (int c = 0; c < 3; ++c) out[co.order[j]][c] = ex[c][j];
    return out;
}

// The hierarchical solve (transport/prior_hierarchy.h): each bounce gathers B_k at every node
// through the tree, Ĝ never stored densely. The first pass records each node's row (its aggregates'
// and exact terms) while they fit in row_budget bytes (k_prior_row_budget), and the later bounces
// apply the recorded rows instead of walking the tree again; rows beyond the budget are walked
// again. The result is the same either way. Same outputs as dense_bounces.

// ray_closure: with visibility by rays, each node's closure measured by rays ([m]); empty: from vis.
std::vector<Vec3f> tree_bounces(const PriorTree &tree, const std::vector<Vec3f> &position, const std::vector<Vec3f> &normal,
                                const std::vector<Vec3f> &albedo, const std::vector<Vec3f> &radiance, int bounces,
                                const ClusterVisibility &vis, bool want_mean, Vec3f &mean_e, size_t row_budget,
                                const std::vector<float> &ray_closure) {
    const size_t m = position.size();
    std::vector<double> den(m, 0.0);
    std::vector<float> closure(m, 1.f);
    const bool rays = !ray_closure.empty();
    std::vector<Vec3f> bk(m), ex(m, Vec3f(0.f)), next(m), at_node(m);
    for (size_t j = 0; j < m; ++j) bk[j] = radiance[j] * float(k_pi);
    std::vector<PriorTree::Row> rows(m);
    std::vector<uint8_t> kept(m, 0);
    // With visibility by rays, a row the budget does not keep replays its first walk's decisions
    // instead of tracing them again at every bounce (PriorTree::RayLog: a byte a term, not a row's ~20).
    std::vector<PriorTree::RayLog> logs(rays ? m : 0);
    auto logs_free = [&](size_t j) {   // a kept row needs no log
        if (!logs.empty()) logs[j] = PriorTree::RayLog{};
    };
    std::atomic<size_t> kept_bytes{0};
    // One pass: every node's row against the values x; the first also keeps each row's sum and
    // closure and records the rows. Nodes walk the tree in groups of k_group consecutive places
    // (neighbours facing alike, mostly one leaf's: PriorTree::record_group), each with the row it
    // would have alone (with rays, up to the rays it shares). A block of 16 groups reuses one scratch
    // (parallel_blocks; with rays its groups share their answers).
    constexpr int G = PriorTree::k_group;
    const std::vector<uint32_t> &place = tree.place_nodes();
    auto pass = [&](const std::vector<Vec3f> &x, bool first, std::vector<Vec3f> &gathered) {
        const PriorTree::Sums sums = tree.sums(x);
        auto gather = [&](size_t j, const double num[3]) {
            for (int c = 0; c < 3; ++c) gathered[j][c] = den[j] > 0 ? float(double(closure[j]) * num[c] / den[j]) : 0.f;
        };
        parallel_blocks(int64_t((m + G - 1) / G), 16, [&](int64_t b, int64_t e) {
            PriorTree::Scratch scratch;
            BlendedView bv[G];
            PriorTree::Receiver rc[G];
            size_t walk[G];
            for (int64_t g = b; g < e; ++g) {
                const size_t lo = size_t(g) * G, hi = std::min(m, lo + G);
                int count = 0;   // the group's nodes whose rows are not kept: they walk
                for (size_t k = lo; k < hi; ++k) {
                    const size_t j = place[k];
                    double num[3];
                    if (kept[j]) {
                        tree.apply(rows[j], sums, num);
                        gather(j, num);
                        continue;
                    }
                    const float c = rays ? (bv[count].view = {}, ray_closure[j])
                                         : bv[count].set(vis, position[j], normal[j], vis.empty() ? nullptr : &vis.node_cluster[j]);
                    if (first) closure[j] = c;
                    rc[count] = {position[j], normal[j], bv[count].view};
                    walk[count++] = j;
                }
                if (count == 0) continue;
                PriorTree::RayLog *group_logs = nullptr, gl[G];
                if (rays) {   // the walkers' logs, moved in and back (their places are not consecutive)
                    for (int l = 0; l < count; ++l) gl[l] = std::move(logs[walk[l]]);
                    group_logs = gl;
                }
                tree.record_group(rc, count, scratch.rows, scratch, group_logs);
                for (int l = 0; l < count; ++l) {
                    const size_t j = walk[l];
                    if (rays) logs[j] = std::move(gl[l]);
                    const PriorTree::Row &row = scratch.rows[l];
                    double num[3];
                    tree.apply(row, sums, num);
                    if (first) {
                        den[j] = row.den;
                        const size_t bytes = row.bytes();
                        if (kept_bytes.fetch_add(bytes) + bytes <= row_budget) rows[j] = row, kept[j] = 1, logs_free(j);
                    }
                    gather(j, num);
                }
            }
        });
    };
    const auto t0 = std::chrono::steady_clock::now();
    double first_s = 0;
    for (int k = 0; k < bounces; ++k) {
        pass(bk, k == 0, next);
        for (size_t j = 0; j < m; ++j) bk[j] = albedo[j] * next[j], ex[j] += bk[j];
        if (k == 0) first_s = seconds_since(t0);
    }
    log_debug("prior tree: ", m, " nodes; first bounce (walks, rows recorded) ", first_s, " s, later bounces ", seconds_since(t0) - first_s,
              " s, ", kept_bytes.load() >> 20, " MB of rows");
    mean_e = Vec3f(0.f);
    if (want_mean) {
        pass(ex, false, at_node);
        for (size_t j = 0; j < m; ++j) mean_e += at_node[j] / float(m);
    }
    return ex;
}
}  // namespace

TransportPrior solve_transport_prior(const std::vector<Vec3f> &position, const std::vector<Vec3f> &normal,
                                     const std::vector<Vec3f> &albedo, const std::vector<Vec3f> &radiance,
                                     float node_area, int bounces, ClusterVisibility visibility, PriorBalance balance,
                                     bool patches, float theta, size_t row_budget, const PriorRays &rays) {
    const size_t m = position.size();
    if (m == 0) LTM_THROW("transport prior: no nodes");
    if (normal.size() != m || albedo.size() != m || radiance.size() != m)
        LTM_THROW("transport prior: ", m, " positions but ", normal.size(), " normals, ", albedo.size(), " albedos, ",
                  radiance.size(), " radiances");
    if (!(node_area > 0.f) || !std::isfinite(node_area)) LTM_THROW("transport prior: node area must be > 0, got ", node_area);
    if (bounces < 0) LTM_THROW("transport prior: bounces must be >= 0, got ", bounces);
    if (!(theta >= 0.f) || !(theta <= 1.f)) LTM_THROW("transport prior: theta must be in [0, 1], got ", theta);
    if (rays && !(theta > 0.f)) LTM_THROW("transport prior: visibility by rays goes through the cluster tree: needs theta > 0");
    if (rays && (rays.closure_rays < 0 || rays.closure_rays > 64))
        LTM_THROW("transport prior: closure rays per side must be in [0, 64], got ", rays.closure_rays);
    if (!visibility.empty() && visibility.node_cluster.size() != m)
        LTM_THROW("transport prior: visibility for ", visibility.node_cluster.size(), " nodes, not ", m);
    TransportPrior out;
    out.position = position, out.normal = normal, out.area = node_area, out.patches = patches;
    out.visibility = std::move(visibility);
    const ClusterVisibility &vis = out.visibility;
    if (theta > 0.f) {
        const auto t0 = std::chrono::steady_clock::now();
        auto tree = std::make_shared<PriorTree>(position, normal, vis, node_area, patches, theta);
        if (rays) {   // the emitters never aggregated (PriorTree::set_rays)
            std::vector<uint8_t> emitter(m, 0);
            size_t emitters = 0;
            for (size_t j = 0; j < m; ++j) emitters += emitter[j] = max_component(radiance[j]) > 0.f;
            // A scene mostly emitting (the furnace, a lit ceiling) would lose every aggregate: O(m²)
            // rays. Lamps are a few per cent of the nodes (at least 1/128 by the sampler).
            if (emitters * 8 > m) emitter.clear();
            tree->set_rays(rays.occlusion, emitter);
        }
        out.tree = std::move(tree);
        out.rays = rays;
        log_debug("prior tree: built over ", m, " nodes in ", seconds_since(t0), " s (", out.tree->bytes() >> 20, " MB)");
    }
    out.exitance.assign(m, Vec3f(0.f));
    if (bounces == 0) return out;
    const bool balanced = (!vis.empty() || rays) && balance != PriorBalance::none;
    Vec3f mean_e(0.f);
    std::vector<float> closure;
    if (rays) {
        closure.assign(m, 1.f);
        if (rays.closure_rays > 0)
            ray_closures(*rays.occlusion, &position[0].x, &normal[0].x, 3, m, out.tree->ray_lift(), rays.closure_rays, closure.data());
    }
    std::vector<Vec3f> ex = out.tree ? tree_bounces(*out.tree, position, normal, albedo, radiance, bounces, vis, balanced, mean_e, row_budget, closure)
                                     : dense_bounces(position, normal, albedo, radiance, node_area, bounces, vis, patches, balanced, mean_e);
    Vec3f gain(1.f);
    if (balanced) {
        // Approximate occlusion breaks the closure that keeps power balanced: a falsely blocked far
        // node drops out of a row, the near ones gain, and the lit rooms recirculate too much light
        // (validation views: level 1.19). Restore the enclosure's balance per channel: the area mean
        // of E⁺ at the nodes (equal areas) is π L̄_c Σ_{k=1..D} ρ̄_c^k, as in a closed box (exact in
        // the furnace; transport/power_balance.h).
        Vec3f mean_rho(0.f), mean_le(0.f);
        for (size_t i = 0; i < m; ++i) mean_rho += albedo[i] / float(m), mean_le += radiance[i] / float(m);
        Vec3f target(0.f);
        for (int c = 0; c < 3; ++c) {
            const double t = k_pi * double(mean_le[c]) * bounce_series(double(mean_rho[c]), bounces);
            target[c] = float(t);
            gain[c] = mean_e[c] > 0.f ? float(t / double(mean_e[c])) : 0.f;   // in double, as before v0.9
        }
        if (balance == PriorBalance::grey)   // one gain: the luminance's
            gain = Vec3f(luminance(mean_e) > 0.f ? luminance(target) / luminance(mean_e) : 0.f);
    }
    for (size_t j = 0; j < m; ++j) out.exitance[j] = ex[j] * gain;
    if (out.tree) out.tree_sums = std::make_shared<const PriorTree::Sums>(out.tree->sums(out.exitance));
    return out;
}

TransportPrior solve_transport_prior(const PointSet &sp, float node_area, int bounces, const Vec3f *emission_scale,
                                     const VisibilityOptions &vis, const PointSet *occupancy, PriorBalance balance,
                                     bool patches, float theta) {
    if (sp.columns != scene_point_columns()) LTM_THROW("transport prior: not a scene point table");
    const size_t m = sp.size();
    std::vector<Vec3f> p(m), n(m), rho(m), le(m);
    Vec3f mean(0.f);
    for (size_t i = 0; i < m; ++i) {
        p[i] = Vec3f(sp.at(i, 0), sp.at(i, 1), sp.at(i, 2)), n[i] = Vec3f(sp.at(i, 3), sp.at(i, 4), sp.at(i, 5));
        rho[i] = Vec3f(sp.at(i, 6), sp.at(i, 7), sp.at(i, 8)), le[i] = Vec3f(sp.at(i, 9), sp.at(i, 10), sp.at(i, 11));
        mean += le[i] / float(m > 0 ? m : 1);
    }
    if (emission_scale) {
        Vec3f gain(0.f);
        for (int c = 0; c < 3; ++c) gain[c] = mean[c] > 0.f ? (*emission_scale)[c] / (float(k_pi) * mean[c]) : 0.f;
        for (auto &l : le) l = l * gain;
    }
    if (vis.blend < 1) LTM_THROW("transport prior: visibility blend must be >= 1, got ", vis.blend);
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    double t_spacing = 0;
    ClusterVisibility v;
    const bool pairs = !vis.rays || vis.cluster_pairs;   // with rays, only the directional gather reads them
    const bool clusters = vis.voxel > 0.f || vis.voxel_spacings > 0.f, discs = vis.disc_spacings > 0.f;
    if (vis.open_rays > 0 && !(clusters && discs)) LTM_THROW("transport prior: open_rays needs occlusion by discs");
    if (clusters) {
        std::vector<Vec3f> op, on;
        if (occupancy) {
            if (occupancy->columns != scene_point_columns()) LTM_THROW("transport prior: occupancy is not a scene point table");
            for (size_t i = 0; i < occupancy->size(); ++i) {
                op.emplace_back(occupancy->at(i, 0), occupancy->at(i, 1), occupancy->at(i, 2));
                on.emplace_back(occupancy->at(i, 3), occupancy->at(i, 4), occupancy->at(i, 5));
            }
        } else {
            op = p, on = n;
        }
        // The points' spacing (8th-neighbour distances) only when a length is given in spacings.
        const bool in_spacings = !(vis.voxel > 0.f) || vis.splat_spacings > 0.f || vis.disc_spacings > 0.f;
        const float spacing = in_spacings ? point_spacing(op) : 0.f;
        t_spacing = seconds_since(t0);
        const float h = vis.voxel > 0.f ? vis.voxel : vis.voxel_spacings * spacing;
        // With discs, the cluster grid's edge from the points alone (point_visibility.h): n_solid ≈
        // κ·M voxels of edge h at h = s (κ = 0.71, 0.68–0.75 on 6 validation houses), so
        // g = h·√(2·n_solid/C) becomes s·√(2·κ·M/C), whatever the voxel edge. 0: from the voxels.
        constexpr double k_voxels_per_point = 0.71;
        const float cell =
            discs ? float(double(spacing) * std::sqrt(2.0 * k_voxels_per_point * double(op.size()) / double(vis.clusters))) : 0.f;
        v = cluster_visibility(p, n, VoxelOccupancy(op, on, h, vis.splat_spacings * spacing), vis.clusters,
                               discs ? DiscOccluder(op, on, vis.disc_spacings * spacing) : DiscOccluder(), cell, pairs);
        if (vis.open_rays > 0 && discs && pairs) v.closure = cluster_closure(v, DiscOccluder(op, on, k_closure_disc_spacings * spacing), vis.open_rays);
    }
    v.blend = vis.blend;
    const auto t1 = Clock::now();
    TransportPrior out = solve_transport_prior(p, n, rho, le, node_area, bounces, std::move(v), balance, patches, theta,
                                               k_prior_row_budget, vis.rays);
    log_debug("transport prior: ", m, " nodes; spacing ", t_spacing, " s, clusters and visibility ",
              std::chrono::duration<double>(t1 - t0).count() - t_spacing, " s, solve ",
              seconds_since(t1), " s");
    return out;
}

namespace {
// gather_transport_prior, and with `also` (a copy of prior with another exitance) the same rows
// summed against its exitance too, into also_out: one walk, one set of rays.
void gather_rows(const TransportPrior &prior, const TransportPrior *also, const float *position, const float *normal, size_t stride,
                 size_t n, float *out, float *far, float *also_out) {
    if (stride < 3) LTM_THROW("transport prior: row stride ", stride, " < 3");
    if (far && !prior.tree) LTM_THROW("transport prior: the far share needs the prior's tree (theta > 0)");
    const size_t m = prior.position.size();
    const ClusterVisibility &vis = prior.visibility;
    if (prior.tree) {   // through the cluster tree: far nodes as aggregates
        const auto sums_of = [](const TransportPrior &t) {
            return t.tree_sums ? t.tree_sums : std::make_shared<const PriorTree::Sums>(t.tree->sums(t.exitance));
        };
        const std::shared_ptr<const PriorTree::Sums> held = sums_of(prior), held_also = also ? sums_of(*also) : nullptr;
        const PriorTree::Sums &sums = *held;
        // Neighbours that face alike walk the tree together (PriorTree::record_group): each
        // receiver's row is what it would be alone, so the order changes no bit of the answer —
        // except with rays, where neighbours share the rays to far terms (deterministic still: the
        // order is a function of the receivers).
        constexpr int G = PriorTree::k_group;
        const std::vector<uint32_t> order = PriorTree::group_order(position, normal, stride, n);
        // Visibility by rays: each receiver's closure by rays, no cluster views (the tree tests its terms).
        const bool rays = prior.tree->has_rays();
        std::vector<float> ray_closure;
        if (rays) {
            ray_closure.assign(n, 1.f);
            if (prior.rays.closure_rays > 0)
                ray_closures(*prior.rays.occlusion, position, normal, stride, n, prior.tree->ray_lift(), prior.rays.closure_rays,
                             ray_closure.data());
        }
        // Blocks of 32 groups, each with its own scratch (parallel_blocks: with rays, the answers its
        // groups share).
        parallel_blocks(int64_t((n + G - 1) / G), 32, [&](int64_t b, int64_t e) {
            PriorTree::Scratch scratch;
            BlendedView bv[G];
            PriorTree::Receiver rc[G];
            float closure[G];
            for (int64_t g = b; g < e; ++g) {
                const size_t first = size_t(g) * G;
                const int count = int(std::min<size_t>(G, n - first));
                for (int l = 0; l < count; ++l) {
                    const size_t q = order[first + size_t(l)];
                    const float *pp = position + q * stride, *pn = normal + q * stride;
                    const Vec3f p(pp[0], pp[1], pp[2]), nq(pn[0], pn[1], pn[2]);
                    closure[l] = rays ? (bv[l].view = {}, ray_closure[q]) : bv[l].set(vis, p, nq, nullptr);
                    rc[l] = {p, nq, bv[l].view};
                }
                double den[G], num[G][3], agg[G][3], num_also[G][3];
                if (also) prior.tree->gather_group2(rc, count, sums, *held_also, den, num, num_also, scratch);
                else prior.tree->gather_group(rc, count, sums, den, num, scratch, far ? agg : nullptr);
                for (int l = 0; l < count; ++l) {
                    const size_t q = order[first + size_t(l)];
                    const auto value = [&](const double *sum, float *o) {   // closure · Σ / den, per channel
                        for (int k = 0; k < 3; ++k) o[k] = den[l] > 0 ? float(double(closure[l]) * sum[k] / den[l]) : 0.f;
                    };
                    value(num[l], out + q * 3);
                    if (far) value(agg[l], far + q * 3);
                    if (also) value(num_also[l], also_out + q * 3);
                }
            }
        });
        return;
    }
    // Nodes in cluster order: a receiver visits the runs of clusters it sees and skips the rest.
    const PlacedNodes nodes(prior.position, prior.normal, vis, prior.area, prior.patches);
    const ClusterOrder &co = nodes.co;
    std::vector<float> ex[3], ex_also[3];
    for (int c = 0; c < 3; ++c)
        for (size_t j = 0; j < m; ++j) {
            ex[c].push_back(prior.exitance[co.order[j]][c]);
            if (also) ex_also[c].push_back(also->exitance[co.order[j]][c]);
        }
    parallel_for(0, int64_t(n), 64, [&](int64_t b, int64_t e) {
        ReceiverView view(co);
        std::vector<float> row(m);
        for (int64_t q = b; q < e; ++q) {
            const float *pp = position + size_t(q) * stride, *pn = normal + size_t(q) * stride;
            const Vec3f p(pp[0], pp[1], pp[2]), nq(pn[0], pn[1], pn[2]);
            view.set(vis, co, p, nq);
            // E⁺ = Σ_j v_j t_j ex_j / Σ_j v_j t_j over the nodes it sees (v_j its cluster's weight),
            // run by run in a fixed order: the same at any thread count.
            double den = 0, num[3] = {0, 0, 0}, num_also[3] = {0, 0, 0};
            float *r = row.data();
            nodes.row(view, p, nq, r);
            for (const auto &[lo, hi] : view.runs) {
                den += sum8(r + lo, hi - lo);
                for (int k = 0; k < 3; ++k) num[k] += dot8(r + lo, ex[k].data() + lo, hi - lo);
                if (also)
                    for (int k = 0; k < 3; ++k) num_also[k] += dot8(r + lo, ex_also[k].data() + lo, hi - lo);
            }
            float *o = out + size_t(q) * 3;
            for (int k = 0; k < 3; ++k) o[k] = den > 0 ? float(double(view.closure) * num[k] / den) : 0.f;
            if (also) {
                float *oa = also_out + size_t(q) * 3;
                for (int k = 0; k < 3; ++k) oa[k] = den > 0 ? float(double(view.closure) * num_also[k] / den) : 0.f;
            }
        }
    });
}
}  // namespace

void gather_transport_prior(const TransportPrior &prior, const float *position, const float *normal, size_t stride,
                            size_t n, float *out, float *far) {
    gather_rows(prior, nullptr, position, normal, stride, n, out, far, nullptr);
}

void gather_transport_prior_pair(const TransportPrior &prior, const TransportPrior &also, const float *position, const float *normal,
                                 size_t stride, size_t n, float *out, float *also_out) {
    // The rows are prior's: `also` must be the same nodes, tree, near field and rays with another exitance.
    const auto same = [](const std::vector<Vec3f> &a, const std::vector<Vec3f> &b) {
        return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3f)) == 0);
    };
    if (also.tree != prior.tree || also.exitance.size() != prior.exitance.size() || !same(also.position, prior.position) ||
        !same(also.normal, prior.normal) || also.area != prior.area || also.patches != prior.patches ||
        also.rays.occlusion != prior.rays.occlusion || also.rays.closure_rays != prior.rays.closure_rays ||
        also.visibility.size() != prior.visibility.size())
        LTM_THROW("transport prior: a paired gather needs a copy of the prior with another exitance (the same nodes, tree and visibility)");
    gather_rows(prior, &also, position, normal, stride, n, out, nullptr, also_out);
}

void gather_transport_prior_radiance(const TransportPrior &prior, const float *position, const float *normal, size_t stride,
                                     const float *direction, size_t direction_stride, size_t n, int resolution, float *out) {
    if (stride < 3 || direction_stride < 3) LTM_THROW("transport prior: row strides ", stride, ", ", direction_stride, " < 3");
    if (resolution < 1 || resolution > 64) LTM_THROW("transport prior: radiance resolution ", resolution, " outside [1, 64]");
    const size_t m = prior.position.size();
    const ClusterVisibility &vis = prior.visibility;
    const PlacedNodes nodes(prior.position, prior.normal, vis, prior.area, prior.patches);
    const ClusterOrder &co = nodes.co;
    std::vector<Vec3f> ex(m);
    for (size_t j = 0; j < m; ++j) ex[j] = prior.exitance[co.order[j]];
    // Runs of consecutive rows with one receiver: one histogram each.
    auto same = [&](size_t a, size_t b) {
        for (int c = 0; c < 3; ++c)
            if (position[a * stride + size_t(c)] != position[b * stride + size_t(c)] ||
                normal[a * stride + size_t(c)] != normal[b * stride + size_t(c)])
                return false;
        return true;
    };
    std::vector<size_t> start;
    for (size_t q = 0; q < n; ++q)
        if (q == 0 || !same(q, q - 1)) start.push_back(q);
    start.push_back(n);
    const int cells = resolution * resolution;
    const double to_radiance = double(cells) / k_pi;   // L̂ = E_cell / (π/R²)
    // A node's square (side s = √a) seen from distance r spans ~s/r radians; a cell ~1/R of the
    // hemisphere's width. Binned at its centre alone, a near node (a wall beside the receiver)
    // lands in one cell and spikes it (pooled error 0.81 against the uniform radiance's 0.29 on
    // the glossy validation houses). So a node spanning more than half a cell is split into k×k
    // sub-squares, its weight shared in proportion to their point formula, each binned at its
    // own centre: the node's total stays its weight, so Σ_cells still gives E⁺ exactly.
    const float side = std::sqrt(prior.area), cell_angle = 0.5f * float(k_pi) / float(resolution);
    parallel_for(0, int64_t(start.size()) - 1, 16, [&](int64_t b, int64_t e) {
        ReceiverView view(co);
        std::vector<float> row(m);
        std::vector<double> hist(size_t(cells) * 3);
        std::vector<std::pair<int, float>> sub;   // (cell, point formula) of a near node's sub-squares
        // World direction d -> its point of the unit square in `frame` (false for d = 0). A
        // direction just below the horizon (a patch straddling it, weighing in with its centre
        // below) maps to the horizon in that azimuth.
        auto to_square = [](const Frame &frame, Vec3f d, Vec2f &u) {
            Vec3f w = frame.to_local(d);
            if (w.z < 0.f) w.z = 0.f;
            const float len = length(w);
            if (!(len > 0.f)) return false;
            u = cosine_hemisphere_to_square(w / len);
            return true;
        };
        auto cell_of = [&](const Frame &frame, Vec3f d) {
            Vec2f u;
            if (!to_square(frame, d, u)) return -1;
            return int(u.x * float(resolution)) * resolution + int(u.y * float(resolution));
        };
        auto add = [&](int cell, double weight, Vec3f exitance) {
            for (int c = 0; c < 3; ++c) hist[size_t(cell) * 3 + size_t(c)] += weight * double(exitance[c]);
        };
        auto splat = [&](Vec3f p, const Frame &frame, Vec3f pj, Vec3f nj, float weight, Vec3f exitance) {
            const Vec3f d = pj - p;
            auto at_centre = [&] {
                const int cell = cell_of(frame, d);
                if (cell >= 0) add(cell, double(weight), exitance);
            };
            const int k = std::min(16, int(std::ceil(side / (std::max(length(d), 1e-30f) * cell_angle))));
            if (k <= 1) return at_centre();   // most nodes: far enough to fit in a cell
            const Frame node(nj);
            sub.clear();
            double total = 0;
            for (int a = 0; a < k; ++a)
                for (int bb = 0; bb < k; ++bb) {
                    const float u = ((float(a) + 0.5f) / float(k) - 0.5f) * side, v = ((float(bb) + 0.5f) / float(k) - 0.5f) * side;
                    const Vec3f dq = pj + node.s * u + node.t * v - p;
                    const float r2 = dot(dq, dq), cr = dot(frame.n, dq), cs = -dot(nj, dq);
                    const float t = cr > 0.f && cs > 0.f ? cr * cs / (r2 * r2 + 1e-30f) : 0.f;
                    const int cell = cell_of(frame, dq);
                    if (cell < 0 || !(t > 0.f)) continue;
                    sub.emplace_back(cell, t);
                    total += double(t);
                }
            if (!(total > 0)) return at_centre();   // every sub-square behind the receiver or the node
            for (const auto &[cell, t] : sub) add(cell, double(weight) * double(t) / total, exitance);
        };
        for (int64_t run = b; run < e; ++run) {
            const size_t q0 = start[size_t(run)], q1 = start[size_t(run) + 1];
            const float *pp = position + q0 * stride, *pn = normal + q0 * stride;
            const Vec3f p(pp[0], pp[1], pp[2]), nq(pn[0], pn[1], pn[2]);
            const Frame frame(nq);
            view.set(vis, co, p, nq);
            float *r = row.data();
            nodes.row(view, p, nq, r);
            // As gather_transport_prior: E⁺ = Σ_j r_j ex_j / Σ_j r_j, each term in its node's cell.
            double den = 0;
            std::fill(hist.begin(), hist.end(), 0.0);
            for (const auto &[lo, hi] : view.runs)
                for (size_t j = lo; j < hi; ++j) {
                    if (!(r[j] > 0.f)) continue;
                    den += double(r[j]);
                    splat(p, frame, nodes.pos[j], nodes.nrm[j], r[j], ex[j]);
                }
            for (size_t q = q0; q < q1; ++q) {
                const float *d = direction + q * direction_stride;
                float *o = out + q * 3;
                Vec2f u;
                if (!(den > 0) || !to_square(frame, Vec3f(d[0], d[1], d[2]), u)) {
                    o[0] = o[1] = o[2] = 0.f;
                    continue;
                }
                // Bilinear between the cells' centres on the square (continuous on the hemisphere:
                // the concentric map is), so a GGX lobe that samples it sees no cell edges; at a
                // cell's centre it is the cell's value.
                const float x = u.x * float(resolution) - 0.5f, y = u.y * float(resolution) - 0.5f;
                const int x0 = std::clamp(int(std::floor(x)), 0, resolution - 1), y0 = std::clamp(int(std::floor(y)), 0, resolution - 1);
                const int x1 = std::min(x0 + 1, resolution - 1), y1 = std::min(y0 + 1, resolution - 1);
                const float fx = std::clamp(x - float(x0), 0.f, 1.f), fy = std::clamp(y - float(y0), 0.f, 1.f);
                const int cs[4] = {x0 * resolution + y0, x1 * resolution + y0, x0 * resolution + y1, x1 * resolution + y1};
                const float ws[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
                for (int c = 0; c < 3; ++c) {
                    double v = 0;
                    for (int k = 0; k < 4; ++k) v += double(ws[k]) * hist[size_t(cs[k]) * 3 + size_t(c)];
                    o[c] = float(double(view.closure) * to_radiance * v / den);
                }
            }
        }
    });
}

}  // namespace ltm
