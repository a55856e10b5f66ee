// neural_renderer.h: images from the light transport model (paper §5, ARCHITECTURE.md §7).
// Encode the scene once (M scene points → latents), G-buffer from primary rays, decode Ê⁺ at every
// hit in chunks, E_direct by shadow rays, compose Le + albedo/π·(E_direct + Ê⁺).
#pragma once

#include <cstdint>
#include <string>

#include "ltm/core/json_util.h"
#include "ltm/nn/ltm_model.h"
#include "ltm/points/point_set.h"
#include "ltm/render/gbuffer.h"
#include "ltm/render/gi_upsample.h"

namespace ltm {

/// A model loaded from `ltm export` weights, with its config.
struct LoadedModel {
    LtmModel model{nullptr};
    std::string path;
    std::map<std::string, std::string> metadata;
};
/// Loads weights (config from the file's metadata), eval mode; throws "path: ..." on a corrupted
/// or foreign file.
LoadedModel load_model(const std::string &path);

/// Bounds of set_scene_points(): the transport prior's dense solve holds ~4·M² bytes of transfer
/// (transport/transport_prior.h; measured peak 1.0 GB at M = 16 384), so M stops at 32 768 (~4 GiB);
/// below 256 the decoder's neighbourhoods and the prior's clusters have too few points.
/// Through the prior's cluster tree (physics.prior_theta > 0) memory is linear in M (~1 KB per scene
/// point in all, measured in docs/performance.md), so the bound is k_max_scene_points_tree.
inline constexpr int64_t k_min_scene_points = 256, k_max_scene_points = 32768, k_max_scene_points_tree = 262144;
/// Makes the model sample n scene points instead of the M it was trained with (`--scene-points`):
/// the encoder and the prior adapt to any count (they measure the points' spacing), so n only trades
/// time and memory for detail. Throws a one-line error naming the bound, before any allocation, if n is
/// outside [k_min_scene_points, k_max_scene_points].
void set_scene_points(LtmModel &model, int64_t n);
/// Makes the model's transport prior go through its cluster tree with opening bound theta (0: the
/// dense rows; `--prior-theta`, transport/prior_hierarchy.h). Call before set_scene_points (its bound
/// depends on it). Throws a one-line error for theta outside [0, 1] or a model without the transport prior.
void set_prior_theta(LtmModel &model, double theta);
/// `--scene-points auto`: set_scene_points(auto_scene_points(scene)) (render/scene_points.h) and,
/// unless the tree's θ was given (theta_given), the prior through its tree at θ 0.5 when that M is
/// above the model's (faster and ~1/3 of the memory there, measured). Logs what it chose. Call after
/// set_prior_theta. (The CLI holds "auto" as k_scene_points_auto.)
inline constexpr int64_t k_scene_points_auto = -1;
void set_auto_scene_points(LtmModel &model, const Scene &scene, bool theta_given);
/// A command's `--prior-theta` (prior_theta ≥ 0; < 0: not given) and `--scene-points` (`given`: > 0 a
/// count, k_scene_points_auto, 0 not given) on a loaded model: θ, then an explicit count (its bounds
/// fail here, before any scene loads). Returns the count the command runs with: `given` when the user
/// gave one, else k_scene_points_auto for a model whose config asks for it
/// (ModelConfig::auto_scene_points), else 0 (the model's own M). On k_scene_points_auto the caller
/// calls set_auto_scene_points once the scene is loaded (eval: EvalModel::enable_auto_scene_points).
/// prior_rays (`--prior-rays`): set_prior_rays first, so an explicit θ still overrides its 0.5; rays
/// with θ 0 (the dense rows, which have no terms to test) are a one-line error here, before the scene loads.
int apply_point_options(LtmModel &model, int given, double prior_theta, bool prior_rays = false);
/// `--prior-rays`: the transport prior's visibility and closure by rays against the scene's meshes
/// (physics.prior_rays), through its cluster tree (θ 0.5 unless the model already has a θ > 0).
/// Throws a one-line error for a model without the transport prior.
void set_prior_rays(LtmModel &model);

struct EncodedScene {
    SceneLatents latents;
    PointSet points;   ///< [M, 12] the scene points it was encoded from (scene_point_columns(), raw)
    float spacing = 0;   ///< their mean spacing √(A/M), metres
    int64_t n_scene_points = 0;
    double sample_seconds = 0, geometry_seconds = 0, encode_seconds = 0;
};
/// Samples the model's M scene points exactly as `ltm dataset build` does (render/scene_points.h:
/// same sampler, stream, enclosed-surface filter and exact emission scale) with `seed`, then
/// FPS/kNN and the encoder. Independent of any camera.
EncodedScene encode_scene(LtmModel &model, const EmbreeAccel &accel, uint64_t seed, bool exclude_enclosed = true);
/// The occlusion the model's prior traces against when physics.prior_rays is set (the scene's meshes,
/// render/mesh_occlusion.h; `accel` must outlive the latents); null otherwise.
std::shared_ptr<const SegmentOcclusion> prior_occlusion(const LtmModel &model, const EmbreeAccel &accel);

/// Ê⁺ at the G-buffer's hit points (normal on the side facing the eye).  -> one Vec3f per hit.
std::vector<Vec3f> predict_gbuffer(LtmModel &model, const EncodedScene &enc, const GBuffer &gb,
                                   PredictTimings *timings = nullptr);
/// The model's own closed-form prior at the G-buffer's hits, the network silenced: Ê⁺ as a zero
/// output layer gives it, irradiance_from_z(softplus(0), output_scale) = the prior's value (its
/// config, its scene points, its emission and length normalisation). The `model-prior` rows of
/// `ltm eval`: what the network adds is the model row against this one.  -> one Vec3f per hit.
std::vector<Vec3f> predict_gbuffer_prior(const EncodedScene &enc, const GBuffer &gb);
/// The same, decoded on a pixel lattice and interpolated (render/gi_upsample.h); opt.stride 1 is
/// predict_gbuffer. n_decoded receives the number of queries actually decoded. prior_only: the
/// model's prior at those queries instead (predict_gbuffer_prior's values).
std::vector<Vec3f> predict_gbuffer_upsampled(LtmModel &model, const EncodedScene &enc, const GBuffer &gb,
                                             const Camera &camera, const GiUpsampleOptions &opt,
                                             PredictTimings *timings = nullptr, int64_t *n_decoded = nullptr,
                                             bool prior_only = false);

enum class DirectEstimator {
    mis,     ///< the path tracer's unbiased estimator (light + cosine samples, MIS)
    ratio,   ///< analytic unshadowed E × stochastic visibility (render/direct_light.h)
    automatic,   ///< ratio when every emitter has constant radiance, else mis
};
DirectEstimator parse_direct_estimator(const std::string &name);   ///< "mis" | "ratio" | "auto"
const char *direct_estimator_name(DirectEstimator e);

/// How a neural render shades conductor pixels. Every way but `diffuse` computes
///   L = Le + L_direct + (1/K) Σ_k f cos / pdf · L⁺(p, ω_k),   ω_k ~ GGX (K = glossy_samples),
/// L_direct by the path tracer's NEE + BSDF sampling with MIS (one scattering event), and differs
/// in where L⁺ — the radiance arriving along ω_k, emitters seen directly excluded — comes from.
enum class GlossyShading {
    automatic,   ///< trace
    /// One traced bounce: L⁺(ω_k) is the radiance leaving the surface y that ω_k hits towards p,
    /// without y's emission: ρ(y)/π·(E_direct(y) + Ê⁺(y)) at a diffuse y (Ê⁺ from the irradiance
    /// head, E_direct by the render's direct estimator), path traced at a conductor y, 0 on a
    /// miss. Needs no directional head; resolves a GGX lobe as finely as the scene's geometry.
    trace,
    head,        ///< the directional head's L̂⁺(p, ω_k) (paper Fig. 11); needs a directional head
    diffuse,     ///< as if diffuse: Le + ρ/π·(E_direct + Ê⁺) (what an irradiance-only model gives)
};
GlossyShading parse_glossy_shading(const std::string &name);   ///< "auto" | "trace" | "head" | "diffuse"
const char *glossy_shading_name(GlossyShading g);

/// Where GlossyShading::trace takes Ê⁺(y) at its bounce hits y. The two agree on conductor pixels
/// within the prior's own noise (docs/results.md, session 26); `nodes` costs M decodes up front and
/// ~1/50 of a decode a hit.
enum class BounceIrradiance {
    automatic,   ///< nodes where the bounce has at least k_bounce_nodes_per_point · M rays, else decode
    /// Interpolated from Ê⁺ decoded once at the M scene points (NodeIrradiance; decoded where no
    /// point lies on y's surface nearby).
    nodes,
    decode,   ///< decoded at every hit, as the G-buffer's pixels are (the reference for `nodes`)
};
/// Rays per scene point above which `automatic` interpolates: below it the M decodes at the points
/// cost about what decoding each hit does.
constexpr int64_t k_bounce_nodes_per_point = 2;
BounceIrradiance parse_bounce_irradiance(const std::string &name);   ///< "auto" | "nodes" | "decode"
const char *bounce_irradiance_name(BounceIrradiance b);

struct NeuralTimings {
    double gbuffer = 0, sample = 0, geometry = 0, encode = 0, knn = 0, decode = 0, direct = 0, total = 0;
    double glossy = 0;   ///< conductor pixels (direct light + L⁺ by the GlossyShading used)
    double prior_solve = 0;   ///< of encode: the transport prior's solve (the rest is the encoder, when it runs)
    /// The model's own cost: everything but the G-buffer and direct light (which any renderer pays).
    double model() const { return sample + geometry + encode + knn + decode; }
    OrderedJson to_json() const;
};

struct NeuralRender {
    RenderedImage image;   ///< irradiance AOV = Ê⁺, direct = E_direct
    NeuralTimings timings;
    int64_t n_queries = 0;   ///< pixels with a surface
    int64_t n_decoded = 0;   ///< queries the decoder ran on (n_queries unless gi.stride > 1)
    int64_t n_scene_points = 0, n_conductor = 0;
    GlossyShading glossy = GlossyShading::diffuse;   ///< how conductor pixels were shaded (diffuse if none is seen)
    int glossy_samples = 0;                          ///< GGX samples per conductor pixel used (0: none)
    BounceIrradiance bounce = BounceIrradiance::decode;   ///< `trace`: how its hits' Ê⁺ was taken (nodes or decode)
    DirectEstimator direct = DirectEstimator::mis;   ///< the estimator that was used
};
struct NeuralRenderOptions {
    int direct_spp = 16;            ///< light samples per pixel for E_direct
    DirectEstimator direct = DirectEstimator::automatic;
    uint64_t seed = 0;              ///< scene-point sampling and direct-light streams
    bool exclude_enclosed = true;   ///< scene points as in the dataset
    GiUpsampleOptions gi{1};        ///< stride 1: Ê⁺ decoded at every pixel
    /// Conductor pixels (GlossyShading): direct light by the path tracer's NEE + BSDF sampling
    /// with MIS (direct_spp samples), the indirect part ∫ f L⁺ cos dω by glossy_samples GGX
    /// samples (0: 64 traced, 16 through the head). `head` without a directional head throws.
    /// With `trace`, each sample's hit gets ⌈direct_spp / glossy_samples⌉ light samples.
    GlossyShading glossy = GlossyShading::automatic;
    int glossy_samples = 0;
    BounceIrradiance bounce = BounceIrradiance::automatic;   ///< `trace`: Ê⁺ at the bounce's hits
    /// The model's own prior, the network silenced, wherever the render reads Ê⁺ (pixels and the
    /// bounce's hits): `eval --radiance`'s model-prior rows. `head` throws (the head is a network).
    bool prior_only = false;
};
/// The whole neural render of one view.
NeuralRender render_neural(LtmModel &model, const PathTracer &pt, const Camera &camera, const NeuralRenderOptions &opt);

}  // namespace ltm
