// radiance_eval.h: `ltm eval --radiance` — the rendered images a user sees, not E⁺ alone (issue
// #11, paper Fig. 11). Every method renders the same pixel-centre rays as the G-buffer:
//   reference      render_pathtraced at ref_spp without jitter: Le + albedo/π·(E_direct + E⁺) on
//                  diffuse pixels, full path tracing on conductors;
//   model:NAME     render_neural: Ê⁺ on diffuse pixels; on conductors NEE direct light + GGX samples
//                  of one traced bounce into the model's Ê⁺ (GlossyShading::trace, the default);
//   model:NAME/bounce-decode (/bounce-nodes with `bounce` decode)   the same render with Ê⁺ at
//                  the bounce's hits decoded at each (interpolated from the scene points): what
//                  interpolating costs in accuracy, and what it saves in time;
//   model-prior:NAME   the same render with the model's own prior wherever it reads Ê⁺ (pixels,
//                  bounce hits): the network silenced, as `ltm eval`'s E⁺ table has it;
//   model:NAME/head-conductors   the same with the directional head's L̂⁺ along the GGX samples
//                  (paper Fig. 11; only for weights that carry a head);
//   model:NAME/diffuse-conductors   the traced render's E_direct and Ê⁺ with conductors shaded as
//                  diffuse with their albedo (its time is the render's less the conductor pass);
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
#include "ltm/infer/neural_renderer.h"

namespace ltm {

struct RadianceEvalOptions {
    EvalOptions base;          ///< size, views, ref_spp, baseline_spp, seed, out_dir (ref_cache_dir, gi_stride unused)
    int direct_spp = 16;       ///< the neural render's light samples per pixel
    int glossy_samples = 0;    ///< the neural render's GGX samples per conductor pixel (0: 64 traced, 16 through the head)
    BounceIrradiance bounce = BounceIrradiance::automatic;   ///< the model rows' traced bounce (the other way: its own row)
};

struct RadianceEvalReport {
    EvalReport all;          ///< every pixel of every view
    EvalReport conductors;   ///< conductor pixels only (views that have some)
    int64_t conductor_pixels = 0;   ///< over all views
    OrderedJson to_json() const;
    std::string table_markdown() const;   ///< both tables, each with its caption
};

/// Runs every scene × view × method (each model: conductors by a traced bounce — the row
/// "model:NAME" — through the directional head where it has one — "/head-conductors" — and as
/// diffuse); progress on stderr; grids (albedo | reference | model | model, head conductors |
/// model, diffuse conductors | PT baseline | PT equal time | |model − reference|) into
/// opt.base.out_dir when it is set. Throws ltm::Error on bad options or a scene without a camera.
RadianceEvalReport run_radiance_evaluation(const std::vector<EvalScene> &scenes, std::vector<EvalModel> &models,
                                           const RadianceEvalOptions &opt);

}  // namespace ltm
