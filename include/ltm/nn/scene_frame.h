// scene_frame.h: the model's frame of a scene and its closed-form prior, without libtorch.
//
// The model divides a scene's lengths by ℓ and its emission by S_c, and multiplies its output by the
// prior (PhysicsConfig): these are pure functions of the scene points, their FPS centres and groups,
// and the config. A model whose decoder's output layer is zero (at its prior, as the shipped model)
// predicts Ê⁺ = prior(query) · expm1(softplus(0)) wherever it is asked, so rendering it needs only
// this file: the tensor model (nn/ltm_model.h) builds its SceneNormalization from the same
// SceneFrame, and the two paths give the same numbers by construction.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "ltm/core/math.h"
#include "ltm/nn/model_config.h"
#include "ltm/transport/segment_occlusion.h"
#include "ltm/transport/transport_prior.h"

namespace ltm {

/// FPS centres of the scene points and the kNN group of each (EmbeddingConfig: m = M · sample_ratio
/// centres, k neighbours): geometry only.
struct PointGroups {
    std::vector<int64_t> centers;   ///< [m] indices into the scene points
    std::vector<int64_t> groups;    ///< [m, k] row-major
    int64_t k = 0;
};
/// positions: [M, 3] row-major. FPS from point 0 (points/farthest_points.h), then the k = min(cfg.k,
/// M) nearest points of each centre (points/knn_points.h).
PointGroups point_groups(const float *positions, size_t n_points, const EmbeddingConfig &cfg);

/// Traced irradiance at scene points (ModelConfig::traced_inputs): rows [n, 12] raw scene points
/// (p, n, …) -> direct [n], indirect [n] (E_dir and E⁺, W/m²), deterministic at any thread count.
/// The scene's path tracer behind it (render/path_tracer.h trace_irradiance), its own random streams.
using PointTracer = std::function<void(const float *rows, size_t n, Vec3f *direct, Vec3f *indirect)>;

/// What the model's inputs are divided by and its output multiplied by (nn/ltm_model.h's
/// SceneNormalization holds the same values as tensors).
struct SceneFrame {
    Vec3f center{0.f};       ///< bounding-box centre, subtracted from every position
    float length = 1.f;      ///< ℓ: mean |p_j − p_c| over the groups' (centre, member) pairs; 1 without length_scale
    Vec3f emission{1.f};     ///< S_c (exact Φ/A when given, else π · mean point emission); 1 without emission_scale
    Vec3f output{1.f};       ///< S_c · Σ_{k=1..D} ρ̄_c^k; the "flat" prior's level
    /// physics.prior_field "transport": the prior solved among the nodes, in the normalised frame.
    std::shared_ptr<const TransportPrior> transport;
    double solve_seconds = 0;   ///< the transport solve's share of the frame's time
    /// With a PointTracer: [M] the traced E⁺ at every scene point and [M] the prior regathered from
    /// the traced light there (the transport's nodes re-emitting ρ ⊙ (E_dir + E⁺) traced at each
    /// node, gathered once more: the last bounce the prior's, the rest traced), raw units. Empty
    /// without a tracer.
    std::vector<Vec3f> traced, regathered;
    /// With a PointTracer: the transport with the traced exitance at its nodes, whose gather is the
    /// regathered prior anywhere (prior_scale_normalized; ModelConfig::traced_queries reads it at
    /// the queries). Null without a tracer.
    std::shared_ptr<const TransportPrior> regather;
    double trace_seconds = 0;   ///< the tracing's and regather's share of the frame's time
    /// false: solved for the regather alone (solve_scene_frame's regather_only): `transport` holds
    /// the nodes, tree, rays and near field the regather gathers through, but not the prior's
    /// bounces (its exitance is 0) nor its clusters' pairwise visibility, so only the regather may be
    /// gathered (folded_irradiance at w = 1).
    bool prior_solved = true;
};

/// The frame of scene points [M, 12] (scene_point_columns(): p, n, albedo, emission; raw units) with
/// their groups. emission_scale: S = Φ/A from the meshes (null: π · mean point emission). occlusion:
/// the scene's meshes for physics.prior_rays (required then). Throws ltm::Error on non-finite points,
/// negative emission, a bad emission scale or a scene of zero extent. tracer (optional): also the
/// traced and regathered irradiance at every scene point (needs physics.prior_field "transport").
/// point_inputs false: the regather (for the queries) without its value at every scene point —
/// `regathered` stays empty: a model whose encoder does not run reads only the queries' (one gather of
/// the M points less). regather_only (needs a tracer, the transport prior and point_inputs false):
/// what a skip of w = 1 reads — Ê · expm1(softplus(ln(R/Ê))) = R, the prior cancels — so the prior's
/// bounces are not solved (SceneFrame::prior_solved false; the walks from every node are most of a
/// frame's time), nor, with the prior's rays, its clusters' pairwise visibility (read by a directional
/// head's gather only: VisibilityOptions::cluster_pairs), and R is the same as with them.
/// physics.prior_regathered: solved as regather_only, and `transport` is the regather (R is the
/// prior every gather reads); needs the tracer.
SceneFrame solve_scene_frame(const float *scene_points, size_t n_points, const PointGroups &groups, const PhysicsConfig &physics,
                             const Vec3f *emission_scale = nullptr, std::shared_ptr<const SegmentOcclusion> occlusion = {},
                             const PointTracer &tracer = {}, bool point_inputs = true, bool regather_only = false);

/// Queries per gather call when a model decodes (LtmModelImpl::predict_irradiance's chunk, and the
/// torch-free prior_irradiance and folded_irradiance): with the prior's visibility by rays,
/// neighbouring receivers of one call share ray answers, so the two paths chunk alike to give the
/// same numbers.
inline constexpr size_t k_decode_chunk = 16384;

/// The prior that the model's output multiplies, at query rows already in the normalised frame
/// ((p − centre)/ℓ, n, albedo: `stride` floats a row): the transport prior's gather floored at
/// 10⁻³ · output (a query that faces no node keeps a finite frame), or `output` for the flat prior
/// (transport null). out [n] (raw units: W/m²). Deterministic at any thread count.
void prior_scale_normalized(const TransportPrior *transport, Vec3f output, const float *rows, size_t stride, size_t n, Vec3f *out);

/// prior_scale_normalized for the transport and for its regather (SceneFrame::regather) at the same
/// rows in one pass (gather_transport_prior_pair: one walk, one set of rays): out and out_regather
/// [n] bit for bit what two prior_scale_normalized calls give, both floored at 10⁻³ · output.
void prior_scale_pair_normalized(const TransportPrior &transport, const TransportPrior &regather, Vec3f output, const float *rows,
                                 size_t stride, size_t n, Vec3f *out, Vec3f *out_regather);

/// Σ_{k=1..D} ρ^k per channel, ρ clamped to [0, 1], term by term in float: exact at ρ = 1 (= D),
/// where the geometric formula divides by 0. The enclosure power balance's gain.
Vec3f power_balance_factor(Vec3f rho, int bounces);

/// The value a zeroed output layer gives the decoder's z: softplus(0) = log 2, and E⁺ = scale ·
/// expm1(z), so Ê⁺ = scale · prior_gain(). (expm1(log 2) rounds to 1 or next to it in float.)
float prior_gain();

/// The model at its prior: Ê⁺ at raw query rows (p, n on the side the light is wanted, albedo; 9
/// floats a row) = prior_scale · prior_gain().   rows [n, 9] -> out [n]
void prior_irradiance(const SceneFrame &frame, const float *rows, size_t n, Vec3f *out);
/// A skip of 1 in every channel: the fold Ê · expm1(softplus(ln(R/Ê))) is R itself, so the prior
/// cancels and need not be solved (solve_scene_frame's regather_only).
inline bool skip_reads_regather_alone(Vec3f skip) { return skip == Vec3f(1.f); }
/// A silent body with a skip w (weights_file.h silent_body_skip), folded (LtmModelImpl::fold_prior):
/// Ê⁺ = Ê · expm1(softplus(w ⊙ ln(R / Ê))) at query rows (raw, 9 floats a row), Ê and R the frame's
/// prior and regather gathered in one walk (prior_scale_pair_normalized). The tensor model's
/// arithmetic in float: equal to its output up to libm's and libtorch's last bits (tested to 1e-5).
/// w = 0 is prior_irradiance; w = 1 in every channel gathers R alone (floored as Ê), which equals the
/// formula up to rounding, and is all a frame solved regather_only can give (other w throw there).
/// Both gather k_decode_chunk rows a call. Throws without the frame's regather.   rows [n, 9] -> out [n]
void folded_irradiance(const SceneFrame &frame, Vec3f skip, const float *rows, size_t n, Vec3f *out);

}  // namespace ltm
