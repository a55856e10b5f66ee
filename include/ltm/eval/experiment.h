// experiment.h: `ltm eval` — the model against path tracing on held-out scenes (paper §6, Table 1).
// Every method is evaluated at the same G-buffer points (one per pixel centre), so the images
// compared are indirect irradiance E⁺ alone: the reference (high spp), the model(s), PT at the
// paper's 64 spp and PT at the model's own wall time.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "ltm/core/json_util.h"
#include "ltm/eval/eval_setup.h"
#include "ltm/eval/field_metrics.h"
#include "ltm/eval/metrics.h"
#include "ltm/nn/ltm_model.h"
#include "ltm/scene/scene.h"

namespace ltm {

struct EvalOptions {
    int width = 128, height = 128;   ///< every view is rendered at this size
    int views = 1;                   ///< view v turns the scene camera by 360°·v/views about its eye
    int ref_spp = 1024;              ///< reference E⁺ samples per pixel
    int baseline_spp = 64;           ///< the paper's PT baseline
    uint64_t seed = 0;
    bool exclude_enclosed = true;    ///< scene-point sampling as in the dataset
    std::string out_dir;             ///< grids go here (empty: no images)
    std::string ref_cache_dir;       ///< reuse/keep references here (eval/reference_cache.h; empty: off)
    int gi_stride = 1;               ///< > 1: also each model with E⁺ on a pixel lattice ("model:NAME/gi<S>")
    int gi_levels = 1;               ///< > 1: that lattice coarse to fine ("model:NAME/gi<S>-L<levels>"; GiUpsampleOptions); 0: auto_gi_levels
    float gi_contrast = 0.05f;       ///< GiUpsampleOptions::contrast
    /// Also estimate each reference's own noise (ViewResult::reference_noise_mse): costs one more
    /// reference's time per view (a twin of it), cached like the reference.
    bool reference_noise = false;
};

struct EvalModel {
    std::string name, path;
    LtmModel model{nullptr};
    /// `--scene-points auto`: each scene sets the model's M (and θ) from its own size
    /// (set_auto_scene_points) before it is encoded, starting again from `fixed` every time, so a
    /// scene's choice does not depend on the scenes before it. Call enable_auto_scene_points.
    bool auto_scene_points = false, theta_given = false;
    struct Fixed {
        int64_t scene_points = 0;
        float prior_theta = 0.f;
    } fixed;
    /// Turns `--scene-points auto` on, remembering the model's M and θ as they are now.
    void enable_auto_scene_points(bool theta_was_given);
    /// Sets the model's M (and θ) for `scene` when auto_scene_points, else leaves it; returns the M
    /// it will sample.
    int64_t fit_scene_points(const Scene &scene);
};

struct EvalScene {
    std::string name;
    Scene scene;
};

struct MethodResult {
    /// "model:<name>", "pt64", "pt-equal-time", "flat-oracle" (every pixel the reference's mean: a
    /// floor, not a method), "flat-prior" (every pixel the power-balance level of the scene points)
    std::string method;
    ImageMetrics metrics;
    double seconds = 0;   ///< the method's own time for this view
    int spp = 0;          ///< PT methods: samples per pixel
    FieldMetrics field;   ///< level, chroma, correlation against the reference at the hit pixels
    int64_t scene_points = 0;   ///< model rows: the scene points it sampled (0: not a model)
};

struct ViewResult {
    std::string scene, view;
    int64_t pixels = 0;             ///< pixels with a surface
    double reference_seconds = 0;   ///< when it was rendered (also if it came from the cache)
    bool reference_cached = false;
    /// The reference's own noise: the expected MSE (the table's metric) of the exact E⁺ against it,
    /// the floor under every method's MSE that no estimator can go below. From a twin b of the
    /// reference a (same spp, independent samples), tone-mapped at a's scale: E (a − b)² = 2σ² per
    /// pixel, so the floor is MSE(a, b)/2 — whatever the sampler's convergence rate (its strata make
    /// σ² fall faster than 1/spp, so half-spp renders would not do). Clamping at 1 trims the brightest
    /// outliers of both alike. NaN unless EvalOptions::reference_noise.
    double reference_noise_mse = NAN;
    std::vector<MethodResult> methods;
};

struct EvalReport {
    EvalOptions options;
    /// What the images hold, for the table's caption and the JSON's metric definition.
    std::string quantity = "E⁺ (indirect irradiance) at one surface point per pixel";
    std::vector<std::string> models;
    std::vector<ViewResult> views;
    OrderedJson to_json() const;
    /// Markdown table like the paper's Table 1: mean ± std over all views per method, with the
    /// physics columns (level ratio in [0.8, 1.25], chroma error, luminance correlation) and the
    /// number of views where the method's MSE is below the flat oracle's.
    std::string table_markdown() const;
};

/// Runs every scene × view × method; progress on stderr; grids into options.out_dir.
EvalReport run_evaluation(const std::vector<EvalScene> &scenes, std::vector<EvalModel> &models, const EvalOptions &opt);

}  // namespace ltm
