// transport_prior.cpp: the visibility-free radiosity solve and its gather (equations in the header).
#include "ltm/points/transport_prior.h"

#include <cmath>
#include <utility>

#include "ltm/core/error.h"
#include "ltm/core/parallel.h"
#include "ltm/points/power_balance.h"

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

// Ĝ's unnormalised row for a receiver (p, n): G_j without the area factor a (it cancels in the
// row normalisation), see the header. The receiver's own node (r = 0) gets 0 from the cosines.
// mask (null: all 1) multiplies the terms: visibility. Returns the row sum; row[j] receives the terms.
inline float transfer_row(const Soa &s, size_t m, Vec3f p, Vec3f n, float reg, const float *__restrict mask,
                          float *__restrict row) {
    const float *__restrict px = s.px.data(), *__restrict py = s.py.data(), *__restrict pz = s.pz.data();
    const float *__restrict nx = s.nx.data(), *__restrict ny = s.ny.data(), *__restrict nz = s.nz.data();
    for (size_t j = 0; j < m; ++j) {
        const float dx = px[j] - p.x, dy = py[j] - p.y, dz = pz[j] - p.z;
        const float r2 = dx * dx + dy * dy + dz * dz;
        const float cr = n.x * dx + n.y * dy + n.z * dz;               // cosines times r
        const float cs = -(nx[j] * dx + ny[j] * dy + nz[j] * dz);
        const float t = cr * cs / (r2 * (r2 + reg) + 1e-30f);
        row[j] = (cr > 0.f && cs > 0.f) ? t : 0.f;
    }
    if (mask)
        for (size_t j = 0; j < m; ++j) row[j] *= mask[j];
    return sum8(row, m);
}

// The visibility mask of a receiver in cluster c: mask[j] = V(c, cluster(j)).
void visibility_mask(const ClusterVisibility &v, uint32_t c, std::vector<float> &mask) {
    const size_t C = v.size();
    mask.resize(v.node_cluster.size());
    const uint8_t *row = v.visible.data() + size_t(c) * C;
    for (size_t j = 0; j < mask.size(); ++j) mask[j] = float(row[v.node_cluster[j]]);
}
}  // namespace

TransportPrior solve_transport_prior(const std::vector<Vec3f> &position, const std::vector<Vec3f> &normal,
                                     const std::vector<Vec3f> &albedo, const std::vector<Vec3f> &radiance,
                                     float node_area, int bounces, ClusterVisibility visibility, PriorBalance balance) {
    const size_t m = position.size();
    if (m == 0) LTM_THROW("transport prior: no nodes");
    if (normal.size() != m || albedo.size() != m || radiance.size() != m)
        LTM_THROW("transport prior: ", m, " positions but ", normal.size(), " normals, ", albedo.size(), " albedos, ",
                  radiance.size(), " radiances");
    if (!(node_area > 0.f) || !std::isfinite(node_area)) LTM_THROW("transport prior: node area must be > 0, got ", node_area);
    if (bounces < 0) LTM_THROW("transport prior: bounces must be >= 0, got ", bounces);
    if (!visibility.empty() && visibility.node_cluster.size() != m)
        LTM_THROW("transport prior: visibility for ", visibility.node_cluster.size(), " nodes, not ", m);
    TransportPrior out;
    out.position = position, out.normal = normal, out.area = node_area;
    out.visibility = std::move(visibility);
    const ClusterVisibility &vis = out.visibility;
    out.exitance.assign(m, Vec3f(0.f));
    if (bounces == 0) return out;
    const Soa soa(position, normal);
    // Row-normalised transport Ĝ [m, m], rows in parallel.
    const float reg = node_area / float(k_pi);
    std::vector<float> g(m * m);
    parallel_for(0, int64_t(m), 16, [&](int64_t b, int64_t e) {
        std::vector<float> mask;
        for (int64_t i = b; i < e; ++i) {
            float *row = g.data() + size_t(i) * m;
            if (!vis.empty()) visibility_mask(vis, vis.node_cluster[size_t(i)], mask);
            const float sum = transfer_row(soa, m, position[size_t(i)], normal[size_t(i)], reg,
                                           vis.empty() ? nullptr : mask.data(), row);
            const float inv = sum > 0.f ? 1.f / sum : 0.f;
            for (size_t j = 0; j < m; ++j) row[j] *= inv;
        }
    });
    // B_0 = π L (exitance of the emitters); B_{k+1} = ρ · Ĝ B_k, channel-major for the dot products.
    std::vector<float> b[3], next[3];
    for (int c = 0; c < 3; ++c) {
        b[c].resize(m), next[c].resize(m);
        for (size_t j = 0; j < m; ++j) b[c][j] = radiance[j][c] * float(k_pi);
    }
    for (int k = 0; k < bounces; ++k) {
        parallel_for(0, int64_t(m), 64, [&](int64_t lo, int64_t hi) {
            for (int64_t i = lo; i < hi; ++i) {
                const float *row = g.data() + size_t(i) * m;
                for (int c = 0; c < 3; ++c) next[c][size_t(i)] = albedo[size_t(i)][c] * dot8(row, b[c].data(), m);
            }
        });
        for (int c = 0; c < 3; ++c) {
            std::swap(b[c], next[c]);
            for (size_t j = 0; j < m; ++j) out.exitance[j][c] += b[c][j];
        }
    }
    if (!vis.empty() && balance != PriorBalance::none) {
        // Approximate occlusion breaks the closure that keeps power balanced: a falsely blocked far
        // node drops out of a row, the near ones gain, and the lit rooms recirculate too much light
        // (validation views: level 1.19). Restore the enclosure's balance per channel: the area mean
        // of E⁺ at the nodes (equal areas) is π L̄_c Σ_{k=1..D} ρ̄_c^k, as in a closed box (exact in
        // the furnace; points/power_balance.h).
        Vec3f mean_e(0.f), mean_rho(0.f), mean_le(0.f);
        std::vector<float> ex[3];
        for (int c = 0; c < 3; ++c)
            for (size_t j = 0; j < m; ++j) ex[c].push_back(out.exitance[j][c]);
        for (size_t i = 0; i < m; ++i) {
            const float *row = g.data() + i * m;
            for (int c = 0; c < 3; ++c) mean_e[c] += dot8(row, ex[c].data(), m) / float(m);
            mean_rho += albedo[i] / float(m), mean_le += radiance[i] / float(m);
        }
        Vec3f gain(0.f), target(0.f);
        for (int c = 0; c < 3; ++c) {
            const double t = k_pi * double(mean_le[c]) * bounce_series(double(mean_rho[c]), bounces);
            target[c] = float(t);
            gain[c] = mean_e[c] > 0.f ? float(t / double(mean_e[c])) : 0.f;   // in double, as before v0.9
        }
        if (balance == PriorBalance::grey)   // one gain: the luminance's
            gain = Vec3f(luminance(mean_e) > 0.f ? luminance(target) / luminance(mean_e) : 0.f);
        for (size_t j = 0; j < m; ++j) out.exitance[j] = out.exitance[j] * gain;
    }
    return out;
}

TransportPrior solve_transport_prior(const PointSet &sp, float node_area, int bounces, const Vec3f *emission_scale,
                                     const VisibilityOptions &vis, const PointSet *occupancy, PriorBalance balance) {
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
    ClusterVisibility v;
    if (vis.voxel > 0.f || vis.voxel_spacings > 0.f) {
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
        // The points' spacing (an O(M²) search) only when a length is given in spacings.
        const bool in_spacings = !(vis.voxel > 0.f) || vis.splat_spacings > 0.f || vis.disc_spacings > 0.f;
        const float spacing = in_spacings ? point_spacing(op) : 0.f;
        const float h = vis.voxel > 0.f ? vis.voxel : vis.voxel_spacings * spacing;
        // With discs, the cluster grid's edge from the points alone (point_visibility.h): n_solid ≈
        // κ·M voxels of edge h at h = s (κ = 0.71, 0.68–0.75 on 6 validation houses), so
        // g = h·√(2·n_solid/C) becomes s·√(2·κ·M/C), whatever the voxel edge. 0: from the voxels.
        constexpr double k_voxels_per_point = 0.71;
        const bool discs = vis.disc_spacings > 0.f;
        const float cell =
            discs ? float(double(spacing) * std::sqrt(2.0 * k_voxels_per_point * double(op.size()) / double(vis.clusters))) : 0.f;
        v = cluster_visibility(p, n, VoxelOccupancy(op, on, h, vis.splat_spacings * spacing), vis.clusters,
                               discs ? DiscOccluder(op, on, vis.disc_spacings * spacing) : DiscOccluder(), cell);
    }
    return solve_transport_prior(p, n, rho, le, node_area, bounces, std::move(v), balance);
}

void gather_transport_prior(const TransportPrior &prior, const float *position, const float *normal, size_t stride,
                            size_t n, float *out) {
    if (stride < 3) LTM_THROW("transport prior: row stride ", stride, " < 3");
    const size_t m = prior.position.size();
    const Soa soa(prior.position, prior.normal);
    std::vector<float> ex[3];
    for (int c = 0; c < 3; ++c)
        for (size_t j = 0; j < m; ++j) ex[c].push_back(prior.exitance[j][c]);
    const float reg = prior.area / float(k_pi);
    const ClusterVisibility &vis = prior.visibility;
    parallel_for(0, int64_t(n), 64, [&](int64_t b, int64_t e) {
        std::vector<float> row(m), mask;
        uint32_t mask_cluster = ~0u;   // neighbouring receivers (pixels) mostly share a cluster: build its mask once
        for (int64_t q = b; q < e; ++q) {
            const float *pp = position + size_t(q) * stride, *pn = normal + size_t(q) * stride;
            const Vec3f p(pp[0], pp[1], pp[2]), nq(pn[0], pn[1], pn[2]);
            if (!vis.empty()) {
                const uint32_t c = vis.cluster_of(p, nq);
                if (c != mask_cluster) visibility_mask(vis, c, mask), mask_cluster = c;
            }
            const float w = transfer_row(soa, m, p, nq, reg, vis.empty() ? nullptr : mask.data(), row.data());
            float *o = out + size_t(q) * 3;
            for (int c = 0; c < 3; ++c) o[c] = w > 0.f ? dot8(row.data(), ex[c].data(), m) / w : 0.f;
        }
    });
}

}  // namespace ltm
