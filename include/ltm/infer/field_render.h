// field_render.h: a view rendered from an Ê⁺ field — G-buffer from primary rays, Ê⁺ decoded at its
// hits (on a lattice and interpolated, render/gi_upsample.h), E_direct by shadow rays, compose
// Le + albedo/π·(E_direct + Ê⁺), conductors by one traced bounce into the field. Torch-free: what
// the field is (the model's network, or its closed-form prior alone: infer/prior_model.h) is the
// caller's (GiSource); infer/neural_renderer.h renders a tensor model through it.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "ltm/core/json_util.h"
#include "ltm/infer/traced_bounce.h"
#include "ltm/points/point_set.h"
#include "ltm/render/gbuffer.h"
#include "ltm/render/gi_upsample.h"
#include "ltm/render/path_tracer.h"

namespace ltm {

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
    double trace = 0;         ///< of encode: the traced inputs (ModelConfig::traced_inputs), 0 without
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
/// Seconds a decoder spends, when it reports them (a tensor model: kNN among its anchors, the rest).
struct DecodeTimings {
    double knn = 0, decode = 0;
};

/// Where a render reads Ê⁺: an encoded scene.
struct GiSource {
    IrradianceDecoder irradiance;   ///< Ê⁺ at query rows, pixels and bounce hits alike
    /// Where `irradiance` adds its own seconds (the render's `knn` and `decode` timings: those of its
    /// pixels' calls); null: not reported (0).
    DecodeTimings *timings = nullptr;
    /// L̂⁺ at query rows [n, 9] along unit directions [n, 3] (world frame): a directional head;
    /// null when the source has none (GlossyShading::head then throws).
    std::function<std::vector<Vec3f>(const std::vector<float> &rows, const std::vector<float> &directions)> head;
    const PointSet *points = nullptr;   ///< [M, 12] the scene points the field was made from (raw)
    float spacing = 0;                  ///< their mean spacing √(A/M), metres
    int64_t n_scene_points = 0;
    double sample_seconds = 0, geometry_seconds = 0, encode_seconds = 0, prior_solve_seconds = 0;
    double trace_seconds = 0;   ///< of encode: the traced inputs
};

/// Query rows [n, 9] of the G-buffer hits listed in `hits` (all hits if null), in that order: p, n
/// (facing the eye), albedo, as the dataset's query_point_columns().
std::vector<float> gbuffer_query_rows(const GBuffer &gb, const std::vector<size_t> *hits);
/// Ê⁺ at the G-buffer's hits listed in `hits` (all if null), in that order.  -> one Vec3f per hit
std::vector<Vec3f> decode_gbuffer(const IrradianceDecoder &decode, const GBuffer &gb, const std::vector<size_t> *hits = nullptr);
/// The same, decoded on a pixel lattice and interpolated (render/gi_upsample.h; opt.stride 1 and
/// one level: every hit). n_decoded receives the number of queries actually decoded.
std::vector<Vec3f> decode_gbuffer_upsampled(const IrradianceDecoder &decode, const GBuffer &gb, const Camera &camera,
                                            const GiUpsampleOptions &opt, int64_t *n_decoded = nullptr);

/// The whole render of one view from `src` (opt.prior_only: the caller's source is the prior already).
NeuralRender render_with_gi(const GiSource &src, const PathTracer &pt, const Camera &camera, const NeuralRenderOptions &opt);

}  // namespace ltm
