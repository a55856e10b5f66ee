// gi_upsample.h: indirect irradiance decoded on a coarse pixel lattice and interpolated to the
// other pixels — irradiance caching (Ward et al. 1988) in screen space. E⁺ varies slowly along a
// surface, so a pixel between lattice pixels on the same surface takes their bilinear blend;
// where the surface changes (an edge, a crease, an occluder), the lattice neighbours are rejected
// by a normal and a tangent-plane test and the pixel is decoded on its own. With stride s, about
// 1/s² of the pixels plus the rejected ones are decoded.
#pragma once

#include <cstddef>
#include <vector>

#include "ltm/core/math.h"
#include "ltm/render/gbuffer.h"
#include "ltm/scene/camera.h"

namespace ltm {

struct GiUpsampleOptions {
    int stride = 2;                ///< lattice spacing in pixels (1: every pixel is decoded)
    float min_normal_cos = 0.9f;   ///< a lattice neighbour's normal within ~25°
    float plane_tolerance = 0.5f;  ///< |n_p·(P_c − P_p)| ≤ this × stride × pixel footprint at P_p
    float min_weight = 0.5f;       ///< accepted bilinear weight below this: decode the pixel itself
};

/// Hits on the lattice (x % stride == 0 and y % stride == 0), ascending: decode these first.
std::vector<size_t> lattice_hits(const GBuffer &gb, int stride);

struct GiInterpolation {
    std::vector<Vec3f> values;          ///< per hit: lattice values copied, the rest interpolated
    std::vector<size_t> needs_decode;   ///< hits with too little accepted weight (values[i] is 0 there)
};

/// Interpolates `lattice_values` (parallel to lattice_hits(gb, opt.stride)) to every hit.
/// `camera` gives the pixel footprint (the G-buffer must be the camera's).
GiInterpolation interpolate_from_lattice(const GBuffer &gb, const Camera &camera, const std::vector<Vec3f> &lattice_values,
                                         const GiUpsampleOptions &opt);

}  // namespace ltm
