// traced_bounce.cpp: trace in parallel, then decode Ê⁺ at the diffuse hits in one batch.
#include "ltm/infer/traced_bounce.h"

#include <algorithm>
#include <chrono>

#include "ltm/core/error.h"
#include "ltm/core/log.h"
#include "ltm/core/progress.h"
#include "ltm/core/parallel.h"
#include "ltm/core/rng.h"
#include "ltm/points/point_set.h"
#include "ltm/render/interaction.h"
#include "ltm/transport/prior_hierarchy.h"

namespace ltm {

DirectIrradianceFn direct_irradiance_fn(const PathTracer &pt, const RatioDirectLight *ratio, int spp) {
    if (spp < 1) LTM_THROW("traced bounce: light samples must be >= 1, got ", spp);
    if (ratio) return [ratio, spp](Vec3f p, Vec3f n, uint64_t key) { return ratio->irradiance(p, n, key, spp); };
    return [&pt, spp](Vec3f p, Vec3f n, uint64_t key) { return pt.irradiance(p, n, key, spp, /*with_indirect=*/false).direct; };
}

NodeIrradiance decode_node_irradiance(const IrradianceDecoder &decode, const PointSet &points, float spacing) {
    const auto t = std::chrono::steady_clock::now();
    const size_t m = points.size();
    if (m == 0 || points.n_columns() < 9) LTM_THROW("node irradiance: needs scene points with p, n, albedo columns, got ", m, " × ", points.n_columns());
    std::vector<Vec3f> position(m), normal(m);
    for (size_t j = 0; j < m; ++j) position[j] = points.vec3(j, 0), normal[j] = points.vec3(j, 3);
    // The points' query rows in group_order, as every gather here: neighbours share their tree walks.
    const std::vector<uint32_t> order = PriorTree::group_order(&position[0].x, &normal[0].x, 3, m);
    std::vector<float> ordered(m * 9);
    for (size_t k = 0; k < m; ++k) write_query_row(&ordered[k * 9], position[order[k]], normal[order[k]], points.vec3(order[k], 6));
    NodeIrradiance nodes;
    nodes.interpolator = PointInterpolator(std::move(position), std::move(normal), spacing);
    const std::vector<Vec3f> e = decode(ordered);
    if (e.size() != m) LTM_THROW("node irradiance: the decoder returned ", e.size(), " values for ", m, " points");
    const Vec3f *ep = e.data();
    nodes.irradiance.assign(m, Vec3f(0.f));
    for (size_t k = 0; k < m; ++k) nodes.irradiance[order[k]] = ep[k];
    nodes.seconds = seconds_since(t);
    return nodes;
}

std::vector<Vec3f> traced_bounce_radiance(const IrradianceDecoder &decode, const PathTracer &pt,
                                          const std::vector<Ray> &rays, const std::vector<uint64_t> &keys,
                                          const DirectIrradianceFn &direct, bool with_emission, const NodeIrradiance *nodes) {
    LTM_CHECK_EQ(rays.size(), keys.size());
    const Scene &scene = pt.accel().scene();
    const size_t n = rays.size();
    std::vector<Vec3f> radiance(n, Vec3f(0.f));
    std::vector<float> query(n * 9);   // a diffuse hit's (p, n facing the ray, ρ): query_point_columns()
    std::vector<uint8_t> diffuse_hit(n, 0);   // 1: Ê⁺ to decode, 2: interpolated from `nodes`
    parallel_for(0, int64_t(n), 64, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            const Ray &ray = rays[size_t(i)];
            if (ray.d == Vec3f(0.f)) continue;
            const auto hit = pt.accel().intersect(ray);
            if (!hit) continue;
            const SurfaceInteraction y = make_interaction(scene, ray, *hit);
            if (with_emission) radiance[size_t(i)] += y.emitted();
            if (y.material->bsdf == BsdfKind::diffuse) {
                const Vec3f ny = y.front ? y.n : -y.n, rho = y.albedo();
                radiance[size_t(i)] += rho * k_inv_pi * direct(y.p, ny, keys[size_t(i)]);
                Vec3f e_node;
                if (nodes && nodes->interpolator.interpolate(y.p, ny, nodes->irradiance.data(), e_node)) {
                    radiance[size_t(i)] += rho * k_inv_pi * e_node;
                    diffuse_hit[size_t(i)] = 2;
                } else {
                    write_query_row(&query[size_t(i) * 9], y.p, ny, rho);
                    diffuse_hit[size_t(i)] = 1;
                }
            } else {
                // y scatters first, then up to max_depth more events, as a camera path at a conductor.
                Pcg32 rng(pt.stream_key(keys[size_t(i)], 0));
                radiance[size_t(i)] += pt.reflected_radiance(y, -ray.d, pt.config().max_depth, rng);
            }
        }
    });
    std::vector<size_t> hits;
    std::vector<float> rows;
    if (nodes) {
        const auto interpolated = std::count(diffuse_hit.begin(), diffuse_hit.end(), uint8_t(2));
        const auto decoded = std::count(diffuse_hit.begin(), diffuse_hit.end(), uint8_t(1));
        log_debug("traced bounce: Ê⁺ at ", interpolated, " diffuse hits interpolated from the scene points, ", decoded, " decoded");
    }
    for (size_t i = 0; i < n; ++i)
        if (diffuse_hit[i] == 1) hits.push_back(i), rows.insert(rows.end(), query.begin() + std::ptrdiff_t(i * 9), query.begin() + std::ptrdiff_t(i * 9 + 9));
    if (hits.empty()) return radiance;
    // The hits in an order where neighbours facing alike follow each other (PriorTree::group_order):
    // the decode goes in chunks, and the prior's gather walks its tree for neighbours together, so
    // ordered hits share their walks (each hit's answer does not depend on its company).
    const std::vector<uint32_t> order = PriorTree::group_order(rows.data(), rows.data() + 3, 9, hits.size());
    std::vector<size_t> at;
    std::vector<float> q;
    for (uint32_t k : order)
        at.push_back(hits[k]), q.insert(q.end(), rows.begin() + std::ptrdiff_t(size_t(k) * 9), rows.begin() + std::ptrdiff_t(size_t(k) * 9 + 9));
    const std::vector<Vec3f> e = decode(q);
    if (e.size() != at.size()) LTM_THROW("traced bounce: the decoder returned ", e.size(), " values for ", at.size(), " hits");
    const Vec3f *ep = e.data();
    for (size_t k = 0; k < at.size(); ++k) {
        const float *row = &q[k * 9];
        radiance[at[k]] += Vec3f(row[6], row[7], row[8]) * k_inv_pi * ep[k];
    }
    return radiance;
}

}  // namespace ltm
