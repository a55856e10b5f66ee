// guide_builder.h: the directional head's predicted L_in⁺ bins at C surface points, as a guide
// cache for path guiding (render/guide_cache.h; `ltm render --method guided`). The scene is
// sampled and encoded exactly as for the neural renderer; the cache points are C farthest points
// of the scene points (even coverage), each with R² bins predicted at bin centres.
#pragma once

#include <cstdint>

#include "ltm/nn/ltm_model.h"
#include "ltm/render/embree_accel.h"
#include "ltm/render/guide_cache.h"

namespace ltm {

struct GuideBuildOptions {
    int points = 1024;              ///< C cache points (C·R² decodes: the model's cost)
    /// R of the guide's bins: the head takes any direction, so it is queried at the centres of
    /// R×R bins, not necessarily the R it was trained on (16: a quarter of the decodes of 32).
    int resolution = 16;
    float radius_spacings = 3.f;    ///< lookup radius in units of the cache points' spacing
    uint64_t seed = 0;              ///< scene point sampling
};

struct GuideBuild {
    GuideCache cache;
    double seconds = 0;   ///< sampling + encoding + decoding: what guiding costs before the first path
};

/// Throws ltm::Error when the model has no directional head.
GuideBuild build_guide_cache(LtmModel &model, const EmbreeAccel &accel, const GuideBuildOptions &opt);

}  // namespace ltm
