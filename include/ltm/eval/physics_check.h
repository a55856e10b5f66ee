// physics_check.h: `ltm eval --physics` — does a model respond to light, colour and scale the way
// light transport must (issue #10)? On each scene, at the G-buffer points of its first camera:
//   - emission linearity: every emitter × k  ->  Ê⁺ × k            (error: mean|Ê_k − kÊ| / mean kÊ)
//   - unit invariance: every length × s, radiance kept -> Ê⁺ unchanged (error: mean|Ê_s − Ê| / mean Ê)
//   - colour response: the room shells (walls, floors, ceilings) recoloured; the model's mean-E⁺
//     chroma against the path tracer's, and the shift of chroma the recolouring causes, both
//     measured as centred-log-ratio errors (eval/field_metrics.h), and the blue share B/(R+G+B);
// and once per model the furnace box (closed, uniform albedo ρ and radiance Le) against its closed
// form E⁺ = π·Le·Σ_{k=1..D} ρ^k.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "ltm/core/json_util.h"
#include "ltm/eval/experiment.h"
#include "ltm/eval/field_metrics.h"

namespace ltm {

struct PhysicsCheckOptions {
    int width = 64, height = 64;                   ///< G-buffer of the scene's first camera
    int ref_spp = 256;                             ///< path-traced references of base and recoloured scenes
    uint64_t seed = 0;
    bool exclude_enclosed = true;                  ///< scene-point sampling as in the dataset
    std::string ref_cache_dir;                     ///< eval/reference_cache.h (empty: off)
    std::vector<float> emission_factors{0.25f, 4.f};
    std::vector<float> length_factors{0.1f, 10.f};
    Vec3f recolor{0.1f, 0.1f, 0.7f};               ///< the room shells' new albedo (blue)
    float furnace_albedo = 0.5f;                   ///< furnace box ρ (Le = 1)
    int furnace_bounces = 5;                       ///< D of the closed form: the bake's max_depth
};

struct SceneCheck {
    std::string scene, model;
    std::vector<std::pair<float, double>> emission_error;   ///< (k, relative error)
    std::vector<std::pair<float, double>> length_error;     ///< (s, relative error)
    int recolored_meshes = 0;
    Color3d model_base{}, model_recolored{}, ref_base{}, ref_recolored{};   ///< mean E⁺ over the view
    double recolor_chroma_error = 0;    ///< chroma_error(model_recolored, ref_recolored)
    double response_error = 0;          ///< RMS difference of the chroma shifts (recoloured − base)
    double blue_share_model = 0, blue_share_ref = 0;   ///< of the recoloured scene's mean E⁺
};

struct FurnaceCheck {
    std::string model;
    double predicted = 0, closed_form = 0;   ///< mean Ê⁺ luminance over the view; π·Σ_{k=1..D} ρ^k
};

struct PhysicsReport {
    PhysicsCheckOptions options;
    std::vector<SceneCheck> scenes;
    std::vector<FurnaceCheck> furnace;
    OrderedJson to_json() const;
    /// Per model: mean and max of each error over scenes, blue-share gaps, furnace ratio.
    std::string table_markdown() const;
};

PhysicsReport run_physics_checks(const std::vector<EvalScene> &scenes, std::vector<EvalModel> &models,
                                 const PhysicsCheckOptions &opt);

}  // namespace ltm
