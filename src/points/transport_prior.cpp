// transport_prior.cpp: the visibility-free radiosity solve and its gather (equations in the header).
#include "ltm/points/transport_prior.h"

#include <cmath>

#include "ltm/core/error.h"
#include "ltm/core/parallel.h"

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

// Ĝ's unnormalised row for a receiver (p, n): G_j without the area factor a (it cancels in the
// row normalisation), see the header. The receiver's own node (r = 0) gets 0 from the cosines.
// Returns the row sum; row[j] receives the terms. Fixed order: deterministic.
inline float transfer_row(const Soa &s, size_t m, Vec3f p, Vec3f n, float reg, float *__restrict row) {
    float sum = 0.f;
    for (size_t j = 0; j < m; ++j) {
        const float dx = s.px[j] - p.x, dy = s.py[j] - p.y, dz = s.pz[j] - p.z;
        const float r2 = dx * dx + dy * dy + dz * dz;
        const float cr = n.x * dx + n.y * dy + n.z * dz;               // cosines times r
        const float cs = -(s.nx[j] * dx + s.ny[j] * dy + s.nz[j] * dz);
        const float t = (cr > 0.f && cs > 0.f) ? cr * cs / (r2 * (r2 + reg)) : 0.f;
        row[j] = t;
        sum += t;
    }
    return sum;
}
}  // namespace

TransportPrior solve_transport_prior(const std::vector<Vec3f> &position, const std::vector<Vec3f> &normal,
                                     const std::vector<Vec3f> &albedo, const std::vector<Vec3f> &radiance,
                                     float node_area, int bounces) {
    const size_t m = position.size();
    if (m == 0) LTM_THROW("transport prior: no nodes");
    if (normal.size() != m || albedo.size() != m || radiance.size() != m)
        LTM_THROW("transport prior: ", m, " positions but ", normal.size(), " normals, ", albedo.size(), " albedos, ",
                  radiance.size(), " radiances");
    if (!(node_area > 0.f) || !std::isfinite(node_area)) LTM_THROW("transport prior: node area must be > 0, got ", node_area);
    if (bounces < 0) LTM_THROW("transport prior: bounces must be >= 0, got ", bounces);
    TransportPrior out;
    out.position = position, out.normal = normal, out.area = node_area;
    out.exitance.assign(m, Vec3f(0.f));
    if (bounces == 0) return out;
    const Soa soa(position, normal);
    // Row-normalised transport Ĝ [m, m], rows in parallel.
    const float reg = node_area / float(k_pi);
    std::vector<float> g(m * m);
    parallel_for(0, int64_t(m), 16, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            float *row = g.data() + size_t(i) * m;
            const float sum = transfer_row(soa, m, position[size_t(i)], normal[size_t(i)], reg, row);
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
                for (int c = 0; c < 3; ++c) {
                    const float *bc = b[c].data();
                    float s = 0.f;
                    for (size_t j = 0; j < m; ++j) s += row[j] * bc[j];
                    next[c][size_t(i)] = albedo[size_t(i)][c] * s;
                }
            }
        });
        for (int c = 0; c < 3; ++c) {
            std::swap(b[c], next[c]);
            for (size_t j = 0; j < m; ++j) out.exitance[j][c] += b[c][j];
        }
    }
    return out;
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
    parallel_for(0, int64_t(n), 64, [&](int64_t b, int64_t e) {
        std::vector<float> row(m);
        for (int64_t q = b; q < e; ++q) {
            const float *pp = position + size_t(q) * stride, *pn = normal + size_t(q) * stride;
            const float w = transfer_row(soa, m, Vec3f(pp[0], pp[1], pp[2]), Vec3f(pn[0], pn[1], pn[2]), reg, row.data());
            float *o = out + size_t(q) * 3;
            for (int c = 0; c < 3; ++c) {
                float s = 0.f;
                for (size_t j = 0; j < m; ++j) s += row[j] * ex[c][j];
                o[c] = w > 0.f ? s / w : 0.f;
            }
        }
    });
}

}  // namespace ltm
