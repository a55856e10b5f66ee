// radiance_eval.h: `ltm eval --radiance` — the rendered images a user sees, not E⁺ alone (issue
// #11, paper Fig. 11). Every method renders the same pixel-centre rays as the G-buffer:
//   reference      render_pathtraced at ref_spp without jitter: Le + albedo/π·(E_direct + E⁺) on
//                  diffuse pixels, full path tracing on conductors;
//   model:NAME     render_neural: Ê⁺ on diffuse pixels; on conductors NEE direct light + GGX samples
//                  of the directional head's L̂⁺ (when the weights carry a head);
//   model:NAME/diffuse-conductors   the same render's E_direct and Ê⁺ with conductors shaded as
//                  diffuse with their albedo (the best an irradiance-only model can do; its time is
//                  the render's less the head's): what the head adds;
//   ptN, pt-equal-time (spp scaled to the neural render's whole wall time), flat-oracle (every
//                  hit pixel the reference's mean colour: a floor, not a method).
// Metrics over all pixels (`all`) and over conductor pixels only (`conductors`, through
// compare_images_masked; views without a conductor pixel are left out of that table).
// References are rendered, not cached (the reference cache holds E⁺ images).
#pragma once

#include <string>
#include <vector>

#include "ltm/core/json_util.h"
#include "ltm/eval/experiment.h"

namespace ltm {

struct RadianceEvalOptions {
    EvalOptions base;          ///< size, views, ref_spp, baseline_spp, seed, out_dir (ref_cache_dir, gi_stride unused)
    int direct_spp = 16;       ///< the neural render's light samples per pixel
    int glossy_samples = 16;   ///< the neural render's GGX samples per conductor pixel
};

struct RadianceEvalReport {
    EvalReport all;          ///< every pixel of every view
    EvalReport conductors;   ///< conductor pixels only (views that have some)
    int64_t conductor_pixels = 0;   ///< over all views
    OrderedJson to_json() const;
    std::string table_markdown() const;   ///< both tables, each with its caption
};

/// Runs every scene × view × method; progress on stderr; grids (albedo | reference | model |
/// model with diffuse conductors | PT baseline | PT equal time | |model − reference|) into
/// opt.base.out_dir when it is set. Throws ltm::Error on bad options or a scene without a camera.
RadianceEvalReport run_radiance_evaluation(const std::vector<EvalScene> &scenes, std::vector<EvalModel> &models,
                                           const RadianceEvalOptions &opt);

}  // namespace ltm
