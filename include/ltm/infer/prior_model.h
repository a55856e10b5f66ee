// prior_model.h: a model whose body is silent, rendered without libtorch. A weights file whose
// network is silenced (its decoder's output layer zero, and its skip if it has one) predicts its
// closed-form prior at every query (nn/scene_frame.h); one whose output layer is zero but whose skip
// is not (folded: the shipped v0.14) predicts its regathered prior through the skip
// (folded_irradiance). Either way sampling its scene points, solving (and tracing) its frame and
// gathering is the whole model: the same numbers as the tensor model (infer/neural_renderer.h), which
// tests hold together, without loading libtorch. Also the model's point options (`--scene-points`,
// `--prior-theta`, `--prior-rays`), which only change its config.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include "ltm/infer/field_render.h"
#include "ltm/nn/model_config.h"
#include "ltm/nn/scene_frame.h"
#include "ltm/render/embree_accel.h"
#include "ltm/render/scene_points.h"

namespace ltm {

/// An `ltm export` weights file's config, read without libtorch.
struct PriorModel {
    ModelConfig cfg;
    std::string path;
    std::map<std::string, std::string> metadata;
    /// The network is silenced (nn/weights_file.h silent_body_skip: a silent body, no skip or a zero
    /// one): the model is its prior.
    bool silenced = false;
    /// A silent body's nonzero skip (silent_body_skip); zero otherwise, and always for an active network.
    Vec3f skip{0.f};
    /// A silent body with a skip: the model is its regathered prior through `skip` (folded_irradiance),
    /// also without libtorch.
    bool folded() const { return !(skip == Vec3f(0.f)); }
    /// Renderable without the network: the prior alone, or the folded skip.
    bool torch_free() const { return silenced || folded(); }
};
/// Reads and checks the file as load_model does (one-line "path: ..." errors).
PriorModel load_prior_model(const std::string &path);

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
void set_scene_points(ModelConfig &cfg, int64_t n);
/// Makes the model's transport prior go through its cluster tree with opening bound theta (0: the
/// dense rows; `--prior-theta`, transport/prior_hierarchy.h). Call before set_scene_points (its bound
/// depends on it). Throws a one-line error for theta outside [0, 1] or a model without the transport prior.
void set_prior_theta(ModelConfig &cfg, double theta);
/// `--scene-points auto`: set_scene_points(auto_scene_points(scene)) (render/scene_points.h) and,
/// unless the tree's θ was given (theta_given), the prior through its tree at θ 0.5 when that M is
/// above the model's (faster and ~1/3 of the memory there, measured). Logs what it chose. Call after
/// set_prior_theta. (The CLI holds "auto" as k_scene_points_auto.)
inline constexpr int64_t k_scene_points_auto = -1;
void set_auto_scene_points(ModelConfig &cfg, const Scene &scene, bool theta_given);
/// A command's `--prior-theta` (prior_theta ≥ 0; < 0: not given) and `--scene-points` (`given`: > 0 a
/// count, k_scene_points_auto, 0 not given) on a loaded model: θ, then an explicit count (its bounds
/// fail here, before any scene loads). Returns the count the command runs with: `given` when the user
/// gave one, else k_scene_points_auto for a model whose config asks for it
/// (ModelConfig::auto_scene_points), else 0 (the model's own M). On k_scene_points_auto the caller
/// calls set_auto_scene_points once the scene is loaded (eval: EvalModel::enable_auto_scene_points).
/// prior_rays (`--prior-rays`): set_prior_rays first, so an explicit θ still overrides its 0.5; rays
/// with θ 0 (the dense rows, which have no terms to test) are a one-line error here, before the scene loads.
int apply_point_options(ModelConfig &cfg, int given, double prior_theta, bool prior_rays = false);
/// `--prior-rays`: the transport prior's visibility and closure by rays against the scene's meshes
/// (physics.prior_rays), through its cluster tree (θ 0.5 unless the model already has a θ > 0).
/// Throws a one-line error for a model without the transport prior.
void set_prior_rays(ModelConfig &cfg);

/// A scene encoded for the prior: the model's M scene points (sampled as `ltm dataset build` and the
/// tensor model's encode_scene sample them) and its frame with the solved prior.
struct PriorScene {
    SceneFrame frame;
    PointSet points;   ///< [M, 12] scene_point_columns(), raw
    float spacing = 0;   ///< √(A/M), metres
    int64_t n_scene_points = 0;
    double sample_seconds = 0, geometry_seconds = 0, encode_seconds = 0;
};
/// The occlusion the prior traces against when physics.prior_rays is set (the scene's meshes;
/// `accel` must outlive the frame); null otherwise.
std::shared_ptr<const SegmentOcclusion> prior_occlusion(const ModelConfig &cfg, const EmbreeAccel &accel);
/// skip ≠ 0 (a folded skip, PriorModel::skip): also trace the scene points and regather the prior
/// (SceneFrame::regather), as the tensor model's folded encode does (the same tracer and seed: the
/// same numbers); skip = 1 in every channel reads R alone, so the prior's bounces are not solved
/// (solve_scene_frame's regather_only: the frame serves folded_irradiance at that skip only).
PriorScene encode_prior_scene(const ModelConfig &cfg, const EmbreeAccel &accel, uint64_t seed, bool exclude_enclosed = true,
                              Vec3f skip = Vec3f(0.f));
/// The same over points already sampled (sample_scene_points at cfg.scene_points), e.g. one sample
/// shared by two frames; sample_seconds is reported as the scene's PriorScene::sample_seconds.
PriorScene encode_prior_scene(const ModelConfig &cfg, const EmbreeAccel &accel, ScenePoints sampled, Vec3f skip, double sample_seconds = 0);
/// The tracer of a model's traced inputs (ModelConfig::traced_inputs strata per scene point) in this
/// scene: its own random streams (k_traced_inputs_seed, never a reference's or a record's), `accel`
/// must outlive it; empty when the model has none. point_keys: [M] the streams of the scene points
/// it will be given (ScenePoints::ids: the same point on the same stream in any unit); empty: point
/// i on stream i (the trainer's draws: statistically the same, and a record's points carry no
/// identity). Its rays' offsets scale with the scene (PathTracerConfig::offset_length: 1 % of its
/// extent).
inline constexpr uint64_t k_traced_inputs_seed = 0x7ace5eed0001ull;
PointTracer traced_inputs_tracer(const ModelConfig &cfg, const EmbreeAccel &accel, std::vector<uint64_t> point_keys = {});
/// The prior's Ê⁺ (nn/scene_frame.h prior_irradiance; with a skip w ≠ 0, folded_irradiance) as a
/// decoder; shares the frame. `timings` (optional) accumulates its calls' seconds as `decode`, as the
/// tensor model's folded path timed them.
IrradianceDecoder prior_decoder(std::shared_ptr<const SceneFrame> frame, DecodeTimings *timings = nullptr, Vec3f skip = Vec3f(0.f));
/// The render of one view by the prior alone (skip 0) or by a folded skip (PriorModel::skip):
/// encode_prior_scene, then render_with_gi. Throws for GlossyShading::head (the head is a network).
NeuralRender render_prior(const ModelConfig &cfg, const PathTracer &pt, const Camera &camera, const NeuralRenderOptions &opt,
                          Vec3f skip = Vec3f(0.f));

}  // namespace ltm
