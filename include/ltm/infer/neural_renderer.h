// neural_renderer.h: images from the light transport model (paper §5, ARCHITECTURE.md §7).
// Encode the scene once (M scene points → latents), then infer/field_render.h's render with the
// model as its Ê⁺ field: G-buffer, Ê⁺ decoded in chunks, E_direct by shadow rays, compose.
#pragma once

#include <cstdint>
#include <string>

#include "ltm/core/json_util.h"
#include "ltm/nn/ltm_model.h"
#include "ltm/points/point_set.h"
#include "ltm/render/gbuffer.h"
#include "ltm/render/gi_upsample.h"
#include "ltm/infer/field_render.h"
#include "ltm/infer/prior_model.h"

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

/// The point and prior options of infer/prior_model.h on a loaded model's config.
inline void set_scene_points(LtmModel &model, int64_t n) { set_scene_points(model->cfg, n); }
inline void set_prior_theta(LtmModel &model, double theta) { set_prior_theta(model->cfg, theta); }
inline void set_prior_rays(LtmModel &model) { set_prior_rays(model->cfg); }
inline void set_auto_scene_points(LtmModel &model, const Scene &scene, bool theta_given) {
    set_auto_scene_points(model->cfg, scene, theta_given);
}
inline int apply_point_options(LtmModel &model, int given, double prior_theta, bool prior_rays = false) {
    return apply_point_options(model->cfg, given, prior_theta, prior_rays);
}

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
/// The occlusion the model's prior traces against (infer/prior_model.h).
inline std::shared_ptr<const SegmentOcclusion> prior_occlusion(const LtmModel &model, const EmbreeAccel &accel) {
    return prior_occlusion(model->cfg, accel);
}

/// The model's irradiance head (LtmModelImpl::predict_irradiance, no autograd) as a decoder;
/// `timings` (optional) accumulates its kNN and decode seconds.
IrradianceDecoder model_irradiance(LtmModel &model, const SceneLatents &latents, DecodeTimings *timings = nullptr);
/// The model's prior alone, the network silenced (prior_irradiance): the `model-prior` rows.
/// `timings` (optional) accumulates its calls' seconds as `decode`.
IrradianceDecoder model_prior_irradiance(const SceneLatents &latents, DecodeTimings *timings = nullptr);

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

/// The whole neural render of one view.
NeuralRender render_neural(LtmModel &model, const PathTracer &pt, const Camera &camera, const NeuralRenderOptions &opt);

}  // namespace ltm
