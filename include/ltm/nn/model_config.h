// model_config.h: the whole model's hyper-parameters (ARCHITECTURE.md §6 presets), JSON-backed.
// configs/model/{tiny,cpu,paper}.json and the two ablations are instances of this struct.
#pragma once

#include <algorithm>
#include <optional>
#include <string>

#include "ltm/core/config_fields.h"
#include "ltm/core/json_util.h"
#include "ltm/nn/ptv3_config.h"

namespace ltm {

/// Nearest-neighbour embedding (paper eqs. 5–7).
struct EmbeddingConfig {
    int dim = 64;                   ///< D: width of 𝓕 and 𝓖 and of the encoder's input
    int k = 16;                     ///< neighbours grouped around each FPS centre (paper: open)
    float sample_ratio = 0.5f;      ///< m = M·ratio FPS centres (paper: M → M/2)
    bool relative_position = true;  ///< also feed p_j − p̃_l to 𝓖 (PointNet++ style; eq. 6 omits it)
    /// Feed the absolute position p_j to 𝓕 (eq. 5). Not a JSON key: LtmModel sets it from
    /// PhysicsConfig::translation_invariant (off: 𝓕 sees normal, albedo, emission only).
    bool absolute_position = true;
    /// Columns after the scene point's 12 (p, n, albedo, emission). Not a JSON key: LtmModel sets
    /// it to 3 when ModelConfig::prior_inputs (the prior's Ê⁺ at the point), 9 with traced_inputs
    /// (also the traced E⁺ and the regathered prior), else 0.
    int extra_inputs = 0;
    /// The JSON keys (core/config_fields.h).
    static const ConfigFields<EmbeddingConfig> &fields();
};

/// Local query decoder (paper eqs. 9–14) or the knn-mean ablation.
struct DecoderConfig {
    std::string type = "attention";  ///< "attention" (vector cross-attention) | "knn-mean" (Fig. 14 ablation)
    int dim = 64;                    ///< D of query features and attention values
    int n_neighbors = 32;            ///< κ nearest anchors per query (paper Tab. 2: 32)
    int n_layers = 2;                ///< stacked cross-attention blocks ("iteratively aggregate")
    int groups = 8;                  ///< G weight groups of grouped vector attention (PTv2)
    int ffn_ratio = 4;               ///< hidden width of each block's FFN = ffn_ratio · dim (transformer convention)
    /// K > 0: the network keeps its prior's level and only redistributes light within the scene.
    /// Its gain g = expm1(z) is rescaled by one factor per scene, r = Σ S / Σ S·g over the K
    /// first FPS anchors taken as queries (S: the prior there, summed over the channels), so the
    /// prior's light summed over those points is the model's (LtmModelImpl::level_factor). Why: a
    /// free level is what the network learned first from every training set and carried to scenes
    /// whose level its prior already had right (docs/results.md, sessions 31–32). 0: free level.
    int level_points = 0;
    /// Feed the query's absolute position to 𝓗 (eq. 9); positions still enter as Δp (eq. 10). Not
    /// a JSON key: LtmModel sets it from PhysicsConfig::translation_invariant.
    bool absolute_position = true;
    /// Columns after the query's 9 (p, n, albedo). Not a JSON key: LtmModel sets it to 3 when
    /// ModelConfig::prior_inputs (the prior's Ê⁺ at the query), 6 with traced_queries, else 0.
    int extra_inputs = 0;
    /// The last skip_inputs (3 or 0) query columns also reach 𝓦_out's pre-activation directly, each
    /// channel times a learned weight (the parameter "skip", [3], zero at the prior): u_c += w_c·x_c.
    /// Not a JSON key: LtmModel sets it to 3 with ModelConfig::traced_queries, whose column
    /// x_c = ln(R_c / Ê_c) makes w = 1 the regathered prior exactly (softplus(ln g) = ln(1 + g)).
    int skip_inputs = 0;
    /// The JSON keys (core/config_fields.h).
    static const ConfigFields<DecoderConfig> &fields();
};

/// The directional radiance head (paper §7, issue #11): the same κ anchors' latents and a
/// direction ω in the query's hemisphere -> incident radiance L_in(p, ω) ≥ 0, RGB, in the frame of
/// the irradiance head: L_in = (scale / π) · expm1(z), scale the irradiance head's output scale at
/// the query (its prior), so a zeroed output layer predicts the uniform radiance whose cosine
/// integral is that prior. Trained with the encoder frozen (`ltm train --head directional`).
struct DirectionalConfig {
    int dim = 64;                    ///< D of query features and attention values
    int n_layers = 2;                ///< stacked cross-attention blocks
    int groups = 8;                  ///< G weight groups of grouped vector attention; divides dim
    int ffn_ratio = 4;               ///< hidden width of each block's FFN = ffn_ratio · dim
    /// F octaves of the direction's Fourier features sin/cos(2^k π ω), k < F (plus ω and n·ω):
    /// a 32×32-bin lobe is ~1/32 of the hemisphere wide, so F ≈ 5 resolves it.
    int direction_frequencies = 5;
    /// R of the R×R hemisphere bins the head is trained on and renders/guides with (paper: 32);
    /// records of another R are refused.
    int bin_resolution = 32;
    /// What it predicts: "indirect" L_in⁺ (light scattered at least once; direct light is exact
    /// in the renderer, as for diffuse surfaces; ∫ L_in⁺ cos dω = E⁺) or "incident" L_in (the
    /// paper's, emitters included). Training records must hold the same (data preset bin_radiance).
    std::string radiance = "indirect";
    /// What the head's output is relative to: 0, the uniform radiance Ê_prior/π of the irradiance
    /// prior; R > 0, the directional transport prior (physics.prior_field "transport" only): the
    /// prior's gather split over R×R cells of equal projected solid angle
    /// (gather_transport_prior_radiance), so a fresh head already knows where bright surfaces lie.
    int prior_cells = 0;
    /// The JSON keys (core/config_fields.h).
    static const ConfigFields<DirectionalConfig> &fields();
    /// Width of the head's input: the query's 9 columns (position zeroed when translation
    /// invariant) + ω, n·ω and the 6F Fourier features.
    int input_width() const { return 9 + 4 + 6 * direction_frequencies; }
};

/// Exact physical normalisations (docs/config.md, the `physics.*` keys). Light transport is
/// linear in emission and irradiance from fixed radiance does not depend on the unit of length, so
/// the network only ever sees a scene with its emission and lengths divided out, and its output is
/// multiplied back. A config without a "physics" object is a v0.3 model: legacy(), all off.
struct PhysicsConfig {
    /// Emission enters as e_c / S_c and the output is multiplied by S_c, with
    /// S_c = π · mean over scene points of e_c (≈ Φ_c / A: emitted power per unit scene area).
    /// E⁺ is then exactly linear in a common scale of all emission, per colour channel in level.
    bool emission_scale = true;
    /// Positions enter as (p − centre) / ℓ with ℓ the mean distance of the embedding groups'
    /// members to their FPS centre (∝ the point spacing √(A/M)); PTv3's grid_size is then in
    /// units of ℓ. E⁺ is invariant to the unit of length (up to kNN ties under rounding).
    bool length_scale = true;
    /// The output is a ratio to the enclosure power balance: area-mean E⁺ ≈ S_c · Σ_{k=1..D} ρ̄_c^k
    /// (ρ̄_c the mean albedo of the scene points), D = prior_bounces; 0 = no prior (needs emission_scale).
    int prior_bounces = 5;
    /// E⁺ moves with the scene: no layer sees an absolute position, only differences (embedding
    /// groups, PTv3's grid relative to the scene's minimum corner, the decoder's Δp). Without it,
    /// positions relative to the bounding-box centre reach 𝓕 and 𝓗, a shortcut by which a network
    /// can fit a field per position (the dataset's average house) instead of reading the scene.
    bool translation_invariant = false;
    /// Where the prior's level lives: "flat" (one power-balance level per scene, above) or
    /// "transport" (transport/transport_prior.h: a visibility-free radiosity solve among the anchors,
    /// gathered at every query point, D = prior_bounces — one level per point, exact in the
    /// furnace). Needs prior_bounces > 0 and length_scale (node areas are in units of ℓ).
    std::string prior_field = "flat";
    /// The transport prior's radiosity nodes: "anchors" (the m FPS anchors; v0.6) or "points" (all
    /// M scene points: ~4× the solve, but the nodes no longer move with FPS near-ties, so the prior
    /// is as unit-invariant as the points themselves; on 32 validation houses' views MSE 0.0151 vs
    /// 0.0178 with anchors). Only with prior_field "transport".
    std::string prior_nodes = "anchors";
    /// Occlusion in the transport prior from the scene points alone (transport/point_visibility.h):
    /// the voxel edge in units of the points' own spacing (point_spacing: ≈ √(A/M); 1 measured best
    /// on the validation views, v0.8; bench/prior_ablation.cpp); 0 = none.
    float prior_visibility = 0.f;
    /// About this many occlusion clusters (VisibilityOptions::clusters): visibility is decided
    /// between them, C²/2 segments. Only with prior_visibility > 0.
    int prior_clusters = 1024;
    /// > 0: the prior's segments are tested against the scene points as oriented discs of this
    /// radius in point spacings (transport/disc_occluder.h; no false occlusion along edges) instead of
    /// the voxels (whose edge then no longer matters). 0 = voxels. Only with prior_visibility > 0.
    float prior_discs = 0.f;
    /// How the occluded prior restores the enclosure's power balance (PriorBalance): "channel"
    /// (v0.6–v0.8: the area mean of each channel set to π L̄ Σ ρ̄^k), "grey" (one gain for all
    /// channels) or "none" (v0.9: with disc occlusion the house-wide closed-box balance only adds
    /// error — 32 validation views MSE 0.0052 without it vs 0.0092 with it). Only with prior_visibility > 0.
    std::string prior_balance = "channel";
    /// K ≥ 1: each receiver (a node of the solve, a query of the gather) blends the visibility of
    /// its K nearest visible clusters (VisibilityOptions::blend) instead of taking its one
    /// cluster's, so the prior has no seams where pixels change cluster. 1 = one cluster (v0.9).
    /// Only with prior_visibility > 0.
    int prior_blend = 1;
    /// The transport prior's near field by square patches (transport/patch_form_factor.h): nodes
    /// within 2.5 spacings of a receiver weigh by the exact form factor of a square of the node's
    /// area, so a receiver at a concave edge sees the adjacent wall over half its hemisphere (the
    /// point formula at the nodes' centres gave it ~0: bright seams). Only with prior_field "transport".
    bool prior_patches = false;
    /// R > 0: the transport prior's rows sum to each receiver's closure — the share of its
    /// hemisphere that meets a surface, from R × R rays per occlusion cluster against the points as
    /// discs (VisibilityOptions::open_rays) — instead of 1, so light that leaves through an open
    /// side or a window to nothing leaves the solve. 0 = every receiver closed (v0.11). Needs prior_discs > 0.
    int prior_open_rays = 0;
    /// θ > 0: the transport prior's solve and gather go through its cluster tree with this opening
    /// bound (transport/prior_hierarchy.h: far nodes as aggregates, O(M log M)); 0 = the dense rows.
    /// A run-time setting, not a trained one: `ltm render --prior-theta` overrides it.
    float prior_theta = 0.f;
    /// The transport prior's visibility and closure by rays against the scene's meshes instead of
    /// from the points (transport/segment_occlusion.h; every term of the tree's rows tested by one
    /// ray, each receiver's closure by prior_open_rays² rays). Needs prior_theta > 0 and the meshes:
    /// render, eval and bake-gi have them (`--prior-rays`); records for training do not. A run-time
    /// setting, like prior_theta.
    bool prior_rays = false;
    /// The prior the output multiplies is the regather R — the transport's nodes re-emitting ρ ⊙ the
    /// light traced at them (ModelConfig::traced_inputs paths a point), gathered once more — not the
    /// solved prior: no bounces are solved (the frame costs the fold's, docs/performance.md), the
    /// network corrects R, and a silenced network is R. The scene points' prior input is then
    /// their traced E⁺ (what R re-emits; free once traced), the queries' is R. Needs prior_field
    /// "transport" and the model's prior_inputs and traced_inputs; not with traced_queries (whose
    /// ln(R / Ê) it replaces) or decoder.level_points. Inference and training trace the scene.
    bool prior_regathered = false;

    static PhysicsConfig legacy() { return {false, false, 0, false, "flat", "anchors", 0.f, 1024, 0.f, "channel", 1, false, 0, 0.f}; }
    /// The JSON keys (core/config_fields.h); read over PhysicsConfig{} when "physics" is present.
    static const ConfigFields<PhysicsConfig> &fields();
    bool any() const { return emission_scale || length_scale || prior_bounces > 0 || translation_invariant; }
};

struct ModelConfig {
    std::string name = "cpu";       ///< preset name, informational
    int scene_points = 8192;        ///< M scene points the model is trained with
    EmbeddingConfig embedding;
    PTv3Config encoder;             ///< in_channels is forced to embedding.dim
    DecoderConfig decoder;
    PhysicsConfig physics;          ///< absent from a JSON config: PhysicsConfig::legacy() (v0.3)
    /// The directional radiance head; absent (no "directional" object) in irradiance-only models.
    std::optional<DirectionalConfig> directional;
    /// The network sees what it corrects (issue #30): every scene point and every query carries
    /// the transport prior's Ê⁺ there as log1p(Ê⁺ / S·Σρ̄^k) per channel (prior_features), a ratio
    /// of two quantities linear in emission and free of the unit, so emission ×k and unit ×s leave
    /// the inputs unchanged. false: the paper's inputs (p, n, albedo[, emission]) only. Needs
    /// physics.prior_field "transport".
    bool prior_inputs = false;
    /// N > 0: a few traced paths per scene point, information the prior cannot compute (issue #30,
    /// docs/results.md session 36). Every scene point also carries, beside the prior's Ê⁺ there, its
    /// traced E⁺ (N strata) and the prior regathered from the traced light (the prior's nodes
    /// re-emitting ρ ⊙ their traced E_dir + E⁺, gathered at the point), each as log1p(· / S·Σρ̄^k):
    /// irradiances like the prior's, so emission ×k and unit ×s leave them unchanged. Encoding a
    /// scene then needs its tracer (SceneFrame: PointTracer). 0: off. Needs prior_inputs.
    int traced_inputs = 0;
    /// With traced_inputs: every query also carries the regathered prior R there (the prior's own
    /// gather of the traced light, the same R the scene points carry) as ln(R_c / Ê_c), its ratio to
    /// the prior, and that column reaches the output through a learned per-channel weight besides
    /// (DecoderConfig::skip_inputs): the decoder can take the traced correction at the query itself
    /// instead of rebuilding it from its neighbours' noisy points (docs/results.md, sessions 36–37:
    /// R alone is 0.82× the prior's view MSE on houses, the local gains of k ≤ 256 points are worse
    /// than the prior). A ratio of two irradiances: emission ×k and unit ×s leave it unchanged.
    /// Not with decoder.level_points.
    bool traced_queries = false;
    /// At inference (render, bake-gi, eval, the guide) the point count follows each scene as
    /// `--scene-points auto` does (render/scene_points.h: 16 384, or 32 768 from 100 k triangles,
    /// the prior through its tree) unless --scene-points is given; scene_points stays the count the
    /// model trains with. The shipped prior-only model sets it (v0.13): its quality grows with M
    /// (docs/results.md, session 24) and it has no network trained at one M.
    bool auto_scene_points = false;

    /// The top-level keys (name, scene_points); the sections have their own fields().
    static const ConfigFields<ModelConfig> &fields();
    /// Strict: unknown keys and invalid values throw "where: /pointer: problem".
    static ModelConfig from_json(const Json &j, const std::string &where);
    /// docs/config.md's model tables: the top level and each section, from the descriptions.
    static std::string markdown_tables();
    static ModelConfig from_file(const std::string &path);
    OrderedJson to_json() const;
    int n_anchors() const { return std::max(1, int(float(scene_points) * embedding.sample_ratio)); }

private:
    /// The nested sections and their cross-field checks (read()'s rest hook).
    static void read_sections(JsonObject &o, ModelConfig &c);
};

}  // namespace ltm
