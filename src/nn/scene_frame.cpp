// scene_frame.cpp: the model's normalisation and its transport prior from plain arrays.
#include "ltm/nn/scene_frame.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "ltm/core/error.h"
#include "ltm/core/parallel.h"
#include "ltm/core/progress.h"
#include "ltm/points/farthest_points.h"
#include "ltm/points/knn_points.h"
#include "ltm/points/point_set.h"

namespace ltm {

PointGroups point_groups(const float *positions, size_t n_points, const EmbeddingConfig &cfg) {
    if (n_points == 0) LTM_THROW("scene points: none to group");
    const int64_t m = std::max<int64_t>(1, int64_t(float(n_points) * cfg.sample_ratio));
    PointGroups g;
    g.centers = farthest_points(positions, n_points, size_t(std::min<int64_t>(m, int64_t(n_points))));
    std::vector<float> c(g.centers.size() * 3);
    for (size_t i = 0; i < g.centers.size(); ++i)
        for (size_t a = 0; a < 3; ++a) c[i * 3 + a] = positions[size_t(g.centers[i]) * 3 + a];
    g.k = std::min<int64_t>(cfg.k, int64_t(n_points));
    g.groups = knn_points(c.data(), g.centers.size(), positions, n_points, g.k);
    return g;
}

namespace {
// Mean of `cols` columns from column `first` over the rows of a [n, 12] table, summed in row order in
// double (the same last bit at any thread count: the prior's grids take ⌊x/h⌋ of lengths built on ℓ
// and S, and one ulp there moved Ê⁺ by ~1e-3), returned in float.
Vec3f column_mean(const float *rows, size_t n, size_t first) {
    double s[3] = {0.0, 0.0, 0.0};
    for (size_t i = 0; i < n; ++i)
        for (size_t a = 0; a < 3; ++a) s[a] += double(rows[i * 12 + first + a]);
    return Vec3f(float(s[0] / double(n)), float(s[1] / double(n)), float(s[2] / double(n)));
}

}  // namespace

Vec3f power_balance_factor(Vec3f rho, int bounces) {
    Vec3f out(0.f);
    for (int a = 0; a < 3; ++a) {
        const float r = std::clamp(rho[a], 0.f, 1.f);
        float term = 1.f, sum = 0.f;
        for (int k = 0; k < bounces; ++k) term = term * r, sum = sum + term;
        out[a] = sum;
    }
    return out;
}

namespace {

// The transport prior (transport/transport_prior.h) in the normalised frame, among the FPS anchors
// (prior_nodes "anchors") or every scene point ("points"). Each of n nodes stands for M/n scene
// points; a scene point for π (3ℓ/2)² / k of area — the k group members of an FPS centre lie
// within ~3ℓ/2 (mean distance 2/3 of a disc's radius), and ℓ = 1 in this frame. Emitters are few
// (20–130 of 8 192 points), so the solver rescales the nodes' emission per channel to
// π · mean = S_c exactly; a channel with S_c > 0 but no emitting anchor (a tiny lamp that FPS
// missed) uses every scene point as a node instead. With prior_visibility, occlusion from the
// voxels of every scene point (transport/point_visibility.h), edge prior_visibility × the points' own
// spacing (measured from them, so the grid does not move with ℓ); with prior_discs, segments are
// tested against every scene point as a disc of that many spacings instead.
// The scene points [M, 12] in the frame's normalised coordinates ((p − centre)/ℓ; the rest as is):
// the prior's nodes and the rows it is gathered at.
std::vector<float> normalized_points(const float *sp, size_t n_points, const SceneFrame &f) {
    std::vector<float> out(n_points * 12);
    for (size_t i = 0; i < n_points; ++i) {
        for (size_t a = 0; a < 3; ++a) out[i * 12 + a] = (sp[i * 12 + a] - f.center[int(a)]) / f.length;
        for (size_t c = 3; c < 12; ++c) out[i * 12 + c] = sp[i * 12 + c];
    }
    return out;
}

std::shared_ptr<const TransportPrior> solve_transport(const float *sp, size_t n_points, const PointGroups &groups, const SceneFrame &f,
                                                      const PhysicsConfig &physics, std::shared_ptr<const SegmentOcclusion> occlusion,
                                                      int bounces, bool cluster_pairs, bool &every_point) {
    PointSet all;
    all.columns = scene_point_columns();
    all.values = normalized_points(sp, n_points, f);
    PointSet anchors;
    const PointSet *nodes = &all;
    if (physics.prior_nodes != "points") {
        anchors.columns = all.columns;
        for (const int64_t c : groups.centers)
            anchors.values.insert(anchors.values.end(), all.values.begin() + c * 12, all.values.begin() + c * 12 + 12);
        // A channel with S_c > 0 but no emitting anchor: every scene point a node.
        bool missing = false;
        for (int a = 0; a < 3; ++a) {
            float most = 0.f;
            for (size_t j = 0; j < anchors.size(); ++j) most = std::max(most, anchors.values[j * 12 + 9 + size_t(a)]);
            missing |= most <= 0.f && f.emission[a] > 0.f;
        }
        if (!missing) nodes = &anchors;
    }
    every_point = nodes == &all;   // else node i is the FPS centre groups.centers[i]
    const double point_area = k_pi * 2.25 / double(groups.k);
    const double area = point_area * double(n_points) / double(nodes->size());
    VisibilityOptions vis;
    vis.voxel_spacings = physics.prior_visibility;   // in units of the points' own spacing: free of ℓ's FPS ties
    vis.clusters = physics.prior_clusters;
    vis.disc_spacings = physics.prior_discs;
    vis.blend = physics.prior_blend;
    vis.open_rays = physics.prior_open_rays;
    if (physics.prior_rays) {
        if (!occlusion)
            LTM_THROW("physics.prior_rays: the transport prior's visibility by rays needs the scene's meshes (render, eval, bake-gi); "
                      "scene points alone (a training record) have none");
        // The prior works in the normalised frame: its points map back by centre + ℓ·x.
        vis.rays.occlusion = std::make_shared<FramedOcclusion>(std::move(occlusion), f.center, f.length);
        vis.rays.closure_rays = physics.prior_open_rays;
        vis.cluster_pairs = cluster_pairs;
    }
    const Vec3f s = f.emission;
    return std::make_shared<const TransportPrior>(
        solve_transport_prior(*nodes, float(area), bounces, &s, vis, &all,
                              physics.prior_balance == "none"   ? PriorBalance::none
                              : physics.prior_balance == "grey" ? PriorBalance::grey
                                                                : PriorBalance::per_channel,
                              physics.prior_patches, physics.prior_theta));
}

// ModelConfig::traced_inputs: trace every scene point, then regather. The transport's nodes are the
// scene points in order (prior_nodes "points", or the anchors' fallback that takes every point) or
// the FPS centres; node i's exitance becomes ρ_i ⊙ (E_dir + E⁺)_i as traced, and the prior's own
// gather (its visibility, tree and near field) carries it to every scene point once more.
void trace_and_regather(const float *sp, size_t n_points, const PointGroups &groups, bool every_point, const PointTracer &tracer,
                        bool point_inputs, SceneFrame &f) {
    std::vector<Vec3f> direct(n_points), indirect(n_points);
    tracer(sp, n_points, direct.data(), indirect.data());
    for (size_t i = 0; i < n_points; ++i)
        if (!(std::isfinite(direct[i].x + direct[i].y + direct[i].z) && std::isfinite(indirect[i].x + indirect[i].y + indirect[i].z)))
            LTM_THROW("traced irradiance at scene point ", i, " is not finite");
    auto regather = std::make_shared<TransportPrior>(*f.transport);
    const size_t m = regather->position.size();
    if (m != (every_point ? n_points : groups.centers.size()))
        LTM_THROW("traced inputs: the prior has ", m, " nodes, not its ", every_point ? n_points : groups.centers.size(), (every_point ? " points" : " centres"));
    for (size_t i = 0; i < m; ++i) {
        const size_t j = every_point ? i : size_t(groups.centers[i]);
        const float *row = sp + j * 12;
        regather->exitance[i] = Vec3f(row[6], row[7], row[8]) * (direct[j] + indirect[j]);
    }
    if (regather->tree) regather->tree_sums = std::make_shared<const PriorTree::Sums>(regather->tree->sums(regather->exitance));
    // Floored as the prior's own inputs are (prior_scale_normalized): 10⁻³ of the flat level.
    if (point_inputs) {
        const std::vector<float> rows = normalized_points(sp, n_points, f);
        f.regathered.resize(n_points);
        prior_scale_normalized(regather.get(), f.output, rows.data(), 12, n_points, f.regathered.data());
    }
    f.traced = std::move(indirect);
    f.regather = std::move(regather);
}
}  // namespace

SceneFrame solve_scene_frame(const float *sp, size_t n_points, const PointGroups &groups, const PhysicsConfig &physics,
                             const Vec3f *emission_scale, std::shared_ptr<const SegmentOcclusion> occlusion, const PointTracer &tracer,
                             bool point_inputs, bool regather_only) {
    if (n_points == 0) LTM_THROW("scene points: none");
    if (physics.prior_regathered && !tracer)
        LTM_THROW("physics.prior_regathered: the prior is the regather of light traced through the scene, and this frame has no path tracer "
                  "(render, eval, bake-gi and training pass it; scene points alone have none)");
    if (regather_only && (!tracer || point_inputs || physics.prior_field != "transport"))
        LTM_THROW("scene frame: regather_only needs a tracer and the transport prior, and no per-point inputs (they read the prior)");
    for (size_t i = 0; i < n_points * 12; ++i)
        if (!std::isfinite(sp[i])) LTM_THROW("scene points contain NaN or Inf");
    for (size_t i = 0; i < n_points; ++i)
        for (size_t c = 9; c < 12; ++c)
            if (!(sp[i * 12 + c] >= 0.f)) LTM_THROW("scene point emission must be >= 0");
    SceneFrame f;
    bool nodes_are_points = true;
    Vec3f lo(sp[0], sp[1], sp[2]), hi = lo;
    for (size_t i = 1; i < n_points; ++i) {
        const Vec3f p(sp[i * 12], sp[i * 12 + 1], sp[i * 12 + 2]);
        lo = min(lo, p), hi = max(hi, p);
    }
    f.center = 0.5f * (lo + hi);
    if (physics.length_scale) {
        // ℓ = mean |p_j − p_c| over every (FPS centre, group member) pair: equivariant with the unit.
        const size_t m = groups.centers.size(), k = size_t(groups.k);
        if (m == 0 || k == 0 || groups.groups.size() != m * k) LTM_THROW("scene frame: ", m, " groups of ", k, " do not match their indices");
        double sum = 0.0;
        for (size_t i = 0; i < m; ++i) {
            const float *c = sp + size_t(groups.centers[i]) * 12;
            for (size_t j = 0; j < k; ++j) {
                const float *p = sp + size_t(groups.groups[i * k + j]) * 12;
                const float dx = p[0] - c[0], dy = p[1] - c[1], dz = p[2] - c[2];
                sum += double(std::sqrt(dx * dx + dy * dy + dz * dz));
            }
        }
        f.length = float(sum / double(m * k));
        if (!(f.length > 0.f) || !std::isfinite(f.length))
            LTM_THROW("scene points have zero extent (mean neighbour distance ", f.length, "): no length scale");
    }
    if (physics.emission_scale) {
        // S_c = Φ_c / A: exact from the meshes when given, else π · mean_j e_jc (the scene points
        // are area-uniform, so this estimates Φ_c / A, with the noise of the few emitter points).
        if (emission_scale) {
            for (int a = 0; a < 3; ++a)
                if (!(std::isfinite((*emission_scale)[a]) && (*emission_scale)[a] >= 0.f)) LTM_THROW("emission scale must be finite and >= 0");
            f.emission = *emission_scale;
        } else {
            f.emission = k_pi * column_mean(sp, n_points, 9);
        }
        // No emission among the scene points: S = 0, so E⁺ = 0 (no light, no indirect light).
        f.output = f.emission;
        if (physics.prior_bounces > 0) f.output = f.emission * power_balance_factor(column_mean(sp, n_points, 6), physics.prior_bounces);
        if (physics.prior_field == "transport") {
            const auto t = std::chrono::steady_clock::now();
            // Regather only: the nodes, tree, rays and near field the regather gathers through, without
            // the prior's bounces (its first walks from every node are most of the solve's time).
            // Nor the clusters' pairwise visibility: with rays only a directional head's gather reads it.
            // physics.prior_regathered reads the regather alone as its prior: the same structure.
            const bool no_bounces = regather_only || physics.prior_regathered;
            f.transport = solve_transport(sp, n_points, groups, f, physics, std::move(occlusion), no_bounces ? 0 : physics.prior_bounces,
                                          /*cluster_pairs=*/!no_bounces, nodes_are_points);
            f.prior_solved = !no_bounces;
            f.solve_seconds = seconds_since(t);
        }
    }
    if (tracer) {
        if (!f.transport) LTM_THROW("traced inputs need physics.prior_field \"transport\" (the prior they regather)");
        const auto t = std::chrono::steady_clock::now();
        trace_and_regather(sp, n_points, groups, nodes_are_points, tracer, point_inputs, f);
        f.trace_seconds = seconds_since(t);
    }
    if (physics.prior_regathered) {
        // R is the prior: every gather of "the prior" (prior_scale_normalized, output_scale) reads
        // the regather, whose transport shares the nodes, tree, rays and near field.
        f.transport = f.regather;
        f.prior_solved = true;
    }
    return f;
}

void prior_scale_normalized(const TransportPrior *transport, Vec3f output, const float *rows, size_t stride, size_t n, Vec3f *out) {
    if (!transport) {
        std::fill(out, out + n, output);
        return;
    }
    gather_transport_prior(*transport, rows, rows + 3, stride, n, &out[0].x);
    const Vec3f floor = 1e-3f * output;
    for (size_t i = 0; i < n; ++i) out[i] = max(out[i], floor);
}

void prior_scale_pair_normalized(const TransportPrior &transport, const TransportPrior &regather, Vec3f output, const float *rows,
                                 size_t stride, size_t n, Vec3f *out, Vec3f *out_regather) {
    gather_transport_prior_pair(transport, regather, rows, rows + 3, stride, n, &out[0].x, &out_regather[0].x);
    const Vec3f floor = 1e-3f * output;
    for (size_t i = 0; i < n; ++i) out[i] = max(out[i], floor), out_regather[i] = max(out_regather[i], floor);
}

float prior_gain() {
    static const float gain = std::expm1(std::log1p(std::exp(0.f)));   // expm1(softplus(0)), in float
    return gain;
}

namespace {
// Query rows [n, 9] raw -> the normalised frame: (p − centre)/ℓ, n, albedo (normalize_query_points).
std::vector<float> normalized_queries(const SceneFrame &f, const float *rows, size_t n) {
    std::vector<float> q(n * 9);
    for (size_t i = 0; i < n; ++i) {
        for (size_t a = 0; a < 3; ++a) q[i * 9 + a] = (rows[i * 9 + a] - f.center[int(a)]) / f.length;
        for (size_t c = 3; c < 9; ++c) q[i * 9 + c] = rows[i * 9 + c];
    }
    return q;
}
}  // namespace

void prior_irradiance(const SceneFrame &f, const float *rows, size_t n, Vec3f *out) {
    if (n > k_decode_chunk) {   // as the tensor model's chunks (k_decode_chunk)
        for (size_t s = 0; s < n; s += k_decode_chunk) prior_irradiance(f, rows + s * 9, std::min(k_decode_chunk, n - s), out + s);
        return;
    }
    if (!f.prior_solved) LTM_THROW("the prior at queries: this frame was solved for its regather alone (no prior bounces)");
    const std::vector<float> q = normalized_queries(f, rows, n);
    prior_scale_normalized(f.transport.get(), f.output, q.data(), 9, n, out);
    const float g = prior_gain();
    for (size_t i = 0; i < n; ++i) out[i] = out[i] * g;
}

void folded_irradiance(const SceneFrame &f, Vec3f skip, const float *rows, size_t n, Vec3f *out) {
    if (skip == Vec3f(0.f)) return prior_irradiance(f, rows, n, out);
    if (!f.transport || !f.regather) LTM_THROW("a folded skip needs the frame's transport prior and its regather (a tracer)");
    if (n > k_decode_chunk) {
        for (size_t s = 0; s < n; s += k_decode_chunk) folded_irradiance(f, skip, rows + s * 9, std::min(k_decode_chunk, n - s), out + s);
        return;
    }
    const std::vector<float> q = normalized_queries(f, rows, n);
    if (skip_reads_regather_alone(skip)) {
        // Ê · expm1(softplus(ln(R/Ê))) = R (both floored): the prior cancels, so it is not gathered.
        prior_scale_normalized(f.regather.get(), f.output, q.data(), 9, n, out);
        return;
    }
    if (!f.prior_solved) LTM_THROW("a folded skip w != 1 reads the prior, and this frame was solved for its regather alone");
    std::vector<Vec3f> r(n);
    prior_scale_pair_normalized(*f.transport, *f.regather, f.output, q.data(), 9, n, out, r.data());
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            // traced_query_features, then softplus (threshold 20, as torch's) and irradiance_from_z.
            const float s = out[i][c], x = (r[i][c] > 0.f && s > 0.f) ? std::log(std::max(r[i][c], 1e-30f) / std::max(s, 1e-30f)) : 0.f;
            const float y = skip[c] * x;
            const float z = y > 20.f ? y : std::log1p(std::exp(y));
            out[i][c] = s * std::expm1(z);
        }
}

}  // namespace ltm
