// ltm_model.h: the light transport model (paper §4): NN embedding → PTv3 encoder → latents at
// the m FPS anchors; local query decoder → z = log1p(E⁺) at any surface point.
// Inference API: encode() once per scene, decode() any number of query chunks.
#pragma once

#include <cstdint>
#include <memory>

#include <mutex>

#include <torch/torch.h>

#include "ltm/nn/directional_decoder.h"
#include "ltm/nn/model_config.h"
#include "ltm/nn/nn_embedding.h"
#include "ltm/nn/ptv3.h"
#include "ltm/nn/query_decoder.h"
#include "ltm/nn/scene_frame.h"
#include "ltm/transport/transport_prior.h"

namespace ltm {

/// FPS centres and their kNN groups: geometry only, so computed once per scene and cached.
struct SceneGeometry {
    torch::Tensor centers;   ///< [m] int64 indices into the scene points
    torch::Tensor groups;    ///< [m, k] int64
};

/// A scene's exact normalisations (PhysicsConfig): what the network's inputs are divided by and
/// what its output is multiplied by. Every field is a pure function of the scene points (and
/// their FPS/kNN groups) and, when given, the scene's exact emission scale S = Φ/A
/// (render/scene_points.h), so the encoder and the decoder see the same frame.
struct SceneNormalization {
    torch::Tensor center;     ///< [3] bounding-box centre, subtracted from every position
    torch::Tensor length;     ///< [] ℓ: positions are divided by it (1 when length_scale is off)
    torch::Tensor emission;   ///< [3] S_c: emission is divided by it (1 when emission_scale is off; 0 for a dark channel)
    torch::Tensor output;     ///< [3] E⁺ = output · expm1(z) (S_c · Σ_{k=1..D} ρ̄_c^k with the prior; 1 when off)
    /// physics.prior_field == "transport": the solved prior among the anchors, in the normalised
    /// frame (node area in units of ℓ²; emission rescaled so that π · mean node radiance = S_c);
    /// E⁺ = prior(query) · expm1(z) instead of output · expm1(z). Null for the "flat" prior.
    std::shared_ptr<const TransportPrior> transport;
    /// [M, 3] the prior at every scene point (output_scale of the points as queries, raw units):
    /// the encoder's prior inputs (ModelConfig::prior_inputs; LtmModelImpl::scene_frame sets it with
    /// point_inputs or decoder.level_points; a deferred encoder gathers it when it runs).
    torch::Tensor point_prior;
    /// [M, 6] ModelConfig::traced_inputs: the traced E⁺ (columns 0–2) and the regathered prior (3–5)
    /// at every scene point, raw units (SceneFrame::traced, regathered); undefined without a tracer.
    torch::Tensor point_traced;
    /// [M, 3] the traced E⁺ at every scene point, raw units, when the frame was made without the
    /// per-point inputs (point_inputs false) but with a tracer: what a deferred encoder (a silent body
    /// with a directional head: SceneLatents::Deferred) makes point_traced from later, with the regather.
    torch::Tensor traced_light;
    /// ModelConfig::traced_queries: the transport re-emitting the traced light (SceneFrame::regather),
    /// gathered at the queries as their regathered prior (regathered_scale); also kept without traced
    /// queries when the per-point inputs wait for a deferred encoder. Null without a tracer.
    std::shared_ptr<const TransportPrior> regather;
    /// Seconds the traced inputs took (tracing and regather; part of the encode, not of the prior).
    double trace_seconds = 0;
    /// Seconds the transport prior's solve took (part of the encode): the model's own prior, the
    /// network silenced, costs sampling, this and its gather (`ltm eval`'s model-prior row).
    double solve_seconds = 0;
};

/// What the encoder leaves for the decoder.
struct SceneLatents {
    torch::Tensor features;  ///< [m, C]; undefined while deferred (LtmModelImpl::features runs the encoder then)
    torch::Tensor anchors;   ///< [m, 3] anchor positions in the normalised frame ((p − centre) / ℓ)
    SceneNormalization norm; ///< the frame the anchors and every query are expressed in
    /// decoder.level_points = K > 0: the K first FPS centres as raw queries [K, 9] and the prior
    /// there [K, 3], where the model holds its prior's level (LtmModelImpl::level_factor).
    torch::Tensor level_queries, level_scale;
    /// With traced_queries: the regathered prior R at the level queries [K, 3], whose level is held
    /// instead of the prior's (the body corrects R's shape, not its level).
    torch::Tensor level_regathered;
    /// The encoder's inputs when its run is deferred: a model with a silent body (at its prior, or
    /// with only the traced-queries skip) and a directional head (fold_prior), whose features only the head reads — and most frames never call it (a scene
    /// without conductors, `--glossy trace`). Shared, so copies of the latents compute them once.
    /// The per-point inputs wait too (the prior and the regather gathered at all M points: most of a
    /// traced model's encode), made when the head first asks (LtmModelImpl::encoder_inputs).
    struct Deferred {
        torch::Tensor x, rows, centers, groups;   ///< [M, 12] normalised points, [M, 9] raw ones (p, n, albedo), the FPS centres and groups
        torch::Tensor features;             ///< [m, C] once computed
        std::mutex mutex;
    };
    std::shared_ptr<Deferred> deferred;
};

/// The scene's normalisation (ARCHITECTURE.md §6, PhysicsConfig): nn/scene_frame.h's
/// solve_scene_frame, its values as tensors.
///   scene_points [M, 12] raw, geometry of the same points, emission_scale [3] or undefined -> SceneNormalization
/// S = emission_scale when defined (exact Φ/A of the meshes), else π · mean emission of the points.
/// Throws ltm::Error on non-finite points, negative emission or a scene of zero extent.
/// occlusion: the scene's meshes for physics.prior_rays (transport/segment_occlusion.h, in the
/// scene's own frame); required with prior_rays, unused without.
/// point_inputs false: no point_traced (solve_scene_frame's point_inputs).
SceneNormalization scene_normalization(const torch::Tensor &scene_points, const SceneGeometry &geometry,
                                       const PhysicsConfig &physics, const torch::Tensor &emission_scale = {},
                                       std::shared_ptr<const SegmentOcclusion> occlusion = {}, const PointTracer &tracer = {},
                                       bool point_inputs = true);
/// Model inputs in the normalised frame: (p − centre)/ℓ, n, albedo, log1p(e / S).
///   scene_points [M, 12] -> [M, 12]
torch::Tensor normalize_scene_points(const torch::Tensor &scene_points, const SceneNormalization &norm);
///   query_points [N, 9] -> [N, 9]: (p − centre)/ℓ, n, albedo
torch::Tensor normalize_query_points(const torch::Tensor &query_points, const SceneNormalization &norm);

/// Where predict_irradiance spends its time (seconds, accumulated over chunks).
struct PredictTimings {
    double knn = 0.0;      ///< anchor kNN of the queries (fused CPU path only; else inside decode)
    double decode = 0.0;   ///< normalisation + decoder + expm1
};

struct LtmModelImpl : torch::nn::Module {
    explicit LtmModelImpl(const ModelConfig &cfg);

    //   scene_points [M, 12] (raw: metres, emission radiance) -> FPS/kNN indices
    SceneGeometry scene_geometry(const torch::Tensor &scene_points) const;
    /// The scene's normalisation with all the network reads from it: scene_normalization, and with
    /// prior_inputs the prior at every scene point (point_prior).
    ///   scene_points [M, 12] raw, emission_scale [3] (optional) -> SceneNormalization
    /// With traced_inputs the scene's tracer is required (the traced inputs, point_traced).
    /// point_inputs false: what the decoder alone reads (the frame, the transport, the regather),
    /// without the encoder's per-point inputs (point_prior, point_traced): two gathers of the M
    /// points less (encode() of a silent body).
    SceneNormalization scene_frame(const torch::Tensor &scene_points, const SceneGeometry &geometry,
                                   const torch::Tensor &emission_scale = {},
                                   std::shared_ptr<const SegmentOcclusion> occlusion = {}, const PointTracer &tracer = {},
                                   bool point_inputs = true) const;
    //   scene_points [M, 12] raw, emission_scale [3] (S = Φ/A, optional) -> latents at m anchors
    /// frame: scene_frame() computed beforehand for these very points, so the prior is not solved
    /// again (the trainer's cache: it solves once per scene and moves the frame with its
    /// symmetries); null: computed here.
    /// occlusion: the scene's meshes, for physics.prior_rays (scene_normalization); tracer: the
    /// scene's path tracer, for traced_inputs (scene_frame).
    SceneLatents encode(const torch::Tensor &scene_points, const SceneGeometry &geometry,
                        const torch::Tensor &emission_scale = {}, const SceneNormalization *frame = nullptr,
                        std::shared_ptr<const SegmentOcclusion> occlusion = {}, const PointTracer &tracer = {});
    //   query_points [N, 9] raw -> z [N, 3] = log1p(E⁺ / output_scale); kNN among anchors computed here.
    /// scale: output_scale(query_points, latents.norm) when already known ([N, 3], or [3] for the
    /// flat prior); read only with prior_inputs, as the queries' prior input; undefined: gathered
    /// here when needed.
    /// With decoder.level_points > 0, z is the level-held output log1p(r · expm1(z_net)), r =
    /// level_factor(latents) (computed at each call, so under autograd r carries its gradient).
    /// regathered: regathered_scale(query_points, latents.norm) when already known ([N, 3]); read only
    /// with traced_queries; undefined: gathered here when needed.
    torch::Tensor decode(const torch::Tensor &query_points, const SceneLatents &latents, const torch::Tensor &scale = {},
                         const torch::Tensor &regathered = {});
    /// The factor that holds the prior's level (DecoderConfig::level_points): with g = expm1(z_net)
    /// at the latents' level queries and S the prior there,  r = Σ_{i,c} S_ic / Σ_{i,c} S_ic g_ic;
    /// with traced_queries R's level instead,  r = Σ_{i,c} R_ic / Σ_{i,c} S_ic g_ic.
    /// 1 (up to rounding) for a decoder at its prior. Invariant to emission and unit like S and g.
    ///   -> [] (a scalar tensor; defined only with level_points > 0)
    torch::Tensor level_factor(const SceneLatents &latents);
    /// The decoder's input rows: normalize_query_points, then with prior_inputs the prior's features
    /// (prior_features of scale, gathered when undefined), then with traced_queries
    /// traced_query_features(regathered, scale) (regathered gathered when undefined).
    ///   query_points [N, 9] raw -> [N, 9 (+3) (+3)]
    torch::Tensor query_inputs(const torch::Tensor &query_points, const SceneNormalization &norm,
                               const torch::Tensor &scale = {}, const torch::Tensor &regathered = {}) const;
    /// Inference in chunks (no autograd): E⁺ = output_scale · expm1(z).  query [N, 9] -> [N, 3].
    /// On CPU the "attention" decoder runs as a FusedDecoder, built from the current weights at every
    /// call (a few ms, so it never sees stale weights) unless fused_inference is false. The fused
    /// kernel tiles internally, so large chunks cost nothing and avoid per-chunk thread start-up;
    /// the libtorch path prefers ~1024 (its [chunk, κ, D] temporaries then stay in cache).
    torch::Tensor predict_irradiance(const torch::Tensor &query_points, const SceneLatents &latents,
                                     int64_t chunk = int64_t(k_decode_chunk), PredictTimings *timings = nullptr);
    /// The directional head (cfg.directional): z at (query, direction) pairs, kNN among the
    /// anchors computed here. Throws ltm::Error when the model has no directional head.
    ///   query_points [N, 9] raw, direction [N, 3] unit (world frame) -> z [N, 3] >= 0
    torch::Tensor decode_radiance(const torch::Tensor &query_points, const torch::Tensor &direction, const SceneLatents &latents);
    /// Inference in chunks (no autograd): L_in = output_scale / π · expm1(z).   [N, 9], [N, 3] -> [N, 3]
    /// (libtorch modules: chunks of ~2k keep the [chunk, κ, D] temporaries in cache)
    torch::Tensor predict_radiance(const torch::Tensor &query_points, const torch::Tensor &direction,
                                   const SceneLatents &latents, int64_t chunk = 2048);
    int64_t n_parameters() const;
    /// The network's own z, before level_factor.   query_points [N, 9] raw -> z [N, 3] >= 0
    torch::Tensor decode_network(const torch::Tensor &query_points, const SceneLatents &latents, const torch::Tensor &scale = {},
                                 const torch::Tensor &regathered = {});
    /// The latents' features [m, C]: latents.features, or the deferred encoder run (computed once).
    torch::Tensor features(const SceneLatents &latents);

    ModelConfig cfg;
    NNEmbedding embedding{nullptr};
    PTv3 encoder{nullptr};
    QueryDecoder decoder{nullptr};
    DirectionalDecoder directional{nullptr};   ///< null unless cfg.directional
    bool fused_inference = true;   ///< predict_irradiance on CPU uses FusedDecoder (false: libtorch modules)
    /// The encoder's input rows: x [M, 12] (normalised points) with the prior's columns
    /// (prior_inputs) and the traced ones (traced_inputs) from norm.point_prior and norm.point_traced;
    /// where the frame was made without them (a deferred encoder), they are gathered now at the raw
    /// points `rows` [M, 9] — the same receivers in the same order, so the same bits as scene_frame's.
    ///   x [M, 12], rows [M, 9] -> [M, 12 + embedding.extra_inputs]
    torch::Tensor encoder_inputs(torch::Tensor x, const torch::Tensor &rows, const SceneNormalization &norm) const;
    /// Constant folding of a silent body (decoder->body_silent(): 𝓦_out's last Linear exactly zero,
    /// as --start-at-prior leaves it): without autograd, encode() skips the embedding and encoder
    /// (features = zeros without a directional head; with one, deferred until the head asks:
    /// SceneLatents::Deferred) and predict_irradiance() skips kNN and the decoder, whose output is
    /// then softplus(skip ⊙ ln(R / Ê)) whatever the latents. At the prior (no skip, or a zero one:
    /// decoder->at_prior()) that is softplus(0), and nothing is traced unless a directional head's
    /// encoder may need the traced inputs; with a skip (the regathered prior through its weights: the
    /// shipped v0.14) the scene is traced for R, and PTv3, the encoder's per-point inputs (until a head
    /// asks) and the attention are saved. Same numbers as the network path; ~1.5 s less per 512² frame
    /// at the prior, 2 s with a skip (docs/performance.md, sessions 38–39). The trainer's draws (a
    /// given frame) carry R at their queries instead of the regather. false: always run the network.
    bool fold_prior = true;
};
TORCH_MODULE(LtmModel);

/// What the decoder's output is relative to: norm.output [3] for the "flat" prior; for the
/// "transport" prior its value at each query, floored at 10⁻³ · norm.output (a query that faces
/// no anchor keeps a finite frame).   query_points [N, 9] raw -> [3] or [N, 3]
torch::Tensor output_scale(const torch::Tensor &query_points, const SceneNormalization &norm);
/// The regathered prior at queries (ModelConfig::traced_queries): norm.regather's gather, floored at
/// 10⁻³ · norm.output like output_scale. Throws ltm::Error when the frame has no regather (it was
/// made without the scene's tracer).   query_points [N, 9] raw -> [N, 3]
torch::Tensor regathered_scale(const torch::Tensor &query_points, const SceneNormalization &norm);
/// output_scale and regathered_scale at once, for a frame with a transport prior and its regather:
/// one walk of the prior's rows (and, with rays, one set of rays) for both, the same bits as the two
/// calls. Throws ltm::Error without either.   query_points [N, 9] raw -> ([N, 3], [N, 3])
std::pair<torch::Tensor, torch::Tensor> prior_and_regathered(const torch::Tensor &query_points, const SceneNormalization &norm);
/// The traced queries' input: ln(R_c / Ê_c) per channel, the regathered prior's ratio to the prior
/// at each query (0 in a dark channel). A ratio of two irradiances, both linear in emission and
/// free of the unit: invariant to both. Its value is the log gain that turns the prior into R, so
/// the decoder's skip (DecoderConfig::skip_inputs) at weight 1 predicts R exactly.
///   regathered [N, 3], scale [N, 3] -> [N, 3]
torch::Tensor traced_query_features(const torch::Tensor &regathered, const torch::Tensor &scale);
/// What the directional head's output is relative to at (query, direction) rows: with cells = 0
/// the uniform radiance output_scale / π; with cells = R > 0 (and a transport prior) the prior's
/// radiance in the direction's cell (gather_transport_prior_radiance), floored at
/// 10⁻³ · norm.output / π like output_scale.   query_points [N, 9] raw, direction [N, 3] -> [3] or [N, 3]
torch::Tensor radiance_scale(const torch::Tensor &query_points, const torch::Tensor &direction, const SceneNormalization &norm,
                             int cells);
/// The model's prior alone, the network silenced: irradiance_from_z(softplus(0), output_scale) —
/// the value of a decoder whose output layer is zero (start_at_prior), bit for bit, so the folded
/// path and the `model-prior` rows of `ltm eval` give the network's numbers at its prior.
///   query_points [N, 9] raw -> [N, 3]
torch::Tensor prior_irradiance(const torch::Tensor &query_points, const SceneNormalization &norm);
/// The prior as a network input: log1p(Ê⁺ / norm.output) per channel (0 in a dark channel).
/// Ê⁺ and norm.output = S_c·Σρ̄^k both scale with emission and neither depends on the unit, so the
/// feature is invariant to both; log1p keeps the range of bright and shadowed points moderate.
///   prior [N, 3] (E⁺, raw units) -> [N, 3]
torch::Tensor prior_features(const torch::Tensor &prior, const SceneNormalization &norm);
/// L_in from the directional head's output: scale · expm1(z), scale = radiance_scale().
///   z [N, 3], scale [3] or [N, 3] -> [N, 3]
torch::Tensor radiance_from_z(const torch::Tensor &z, const torch::Tensor &scale);
/// E⁺ from the decoder's output: scale · expm1(z).   z [N, 3], scale [3] or [N, 3] -> [N, 3]
torch::Tensor irradiance_from_z(const torch::Tensor &z, const torch::Tensor &scale);
/// Targets in the decoder's output frame: y / scale (0 where the scale is 0).
///   target [N, 3], scale [3] or [N, 3] -> [N, 3]
torch::Tensor normalized_target(const torch::Tensor &target, const torch::Tensor &scale);

/// Relative L2 in log space (paper §5, v0.3's loss): mean(((z − log1p(y)) / (stopgrad(z) + ε))²).
/// Its minimiser is not the mean of noisy targets (log of a noisy mean is biased).
///   z [N, 3] >= 0, target [N, 3] (E⁺ >= 0) -> scalar
torch::Tensor relative_l2_log_loss(const torch::Tensor &z, const torch::Tensor &target, double eps = 1e-2);
/// Relative L2 in linear space with a detached denominator (neural radiance caching):
///   mean((ŷ − y)² / (stopgrad(ŷ) + ε · mean(stopgrad(ŷ)))²).
/// The denominator does not depend on y, so the minimiser is E[y | x]: noisy (low-spp) targets
/// train an unbiased model. ε is relative to the batch mean, so the loss is invariant to a common
/// scale of ŷ and y (emission, and the per-scene output scale).
///   pred [N, 3] >= 0, target [N, 3] -> scalar
torch::Tensor relative_l2_loss(const torch::Tensor &pred, const torch::Tensor &target, double eps = 1.0);

}  // namespace ltm
