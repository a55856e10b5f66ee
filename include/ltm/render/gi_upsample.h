// gi_upsample.h: indirect irradiance decoded on a coarse pixel lattice and interpolated to the
// other pixels — irradiance caching (Ward et al. 1988) in screen space. E⁺ varies slowly along a
// surface, so a pixel between lattice pixels on the same surface takes their bilinear blend;
// where the surface changes (an edge, a crease, an occluder), the lattice neighbours are rejected
// by a normal and a tangent-plane test and the pixel is decoded on its own. With stride s, about
// 1/s² of the pixels plus the rejected ones are decoded.
//
// Coarse to fine (levels L > 1; Ward's error-controlled cache, here in screen space): the lattice is
// first decoded at stride s·2^(L−1); each finer lattice's new pixels take the blend of the coarser
// one's corners when every corner that weighs lies in the image and passes the surface tests, and
// they agree — Σ_c (max_c − min_c) over the accepted
// corners ≤ contrast × Σ_c of their blend (c: the three channels) — and are decoded otherwise. A
// contact shadow or a lamp's pool across a coarse cell makes its corners disagree, so it is decoded
// at stride s; a wall's slow gradient is not. The stride-s lattice (decoded or blended) then fills
// the other pixels as with one level. L = 1 is the one-level lattice exactly.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "ltm/core/math.h"
#include "ltm/render/gbuffer.h"
#include "ltm/scene/camera.h"

namespace ltm {

struct GiUpsampleOptions {
    int stride = 2;                ///< lattice spacing in pixels (1 with levels 1: every pixel is decoded)
    float min_normal_cos = 0.9f;   ///< a lattice neighbour's normal within ~25°
    float plane_tolerance = 0.5f;  ///< |n_p·(P_c − P_p)| ≤ this × stride × pixel footprint at P_p
    float min_weight = 0.5f;       ///< accepted bilinear weight below this: decode the pixel itself
    int levels = 1;                ///< lattices decoded coarse to fine: the first at stride·2^(levels−1) (header)
    float contrast = 0.05f;        ///< a finer lattice pixel is decoded where its coarse corners differ by more (header)
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

/// `--gi-levels auto`: 1 + the largest k ≤ 3 with stride·2^k ≤ min(width, height) / 64, so the first
/// lattice keeps ≥ 64 pixels across the image's smaller side (1 where the stride alone leaves fewer).
/// 512² at stride 2: 3 levels (a lattice of stride 8 first); 96²: 1. Measured on the demo house at
/// 512² against every pixel decoded (docs/performance.md): stride 2 alone 7.2e-5 relative MSE for
/// 65 654 decodes, 3 levels 7.9e-5 for 10 571; stride 1, 4 levels 8.1e-6 for 18 918.
int auto_gi_levels(int stride, int width, int height);

/// Decodes Ê⁺ at the listed hits, in that order: one value per listed hit.
using GiDecode = std::function<std::vector<Vec3f>(const std::vector<size_t> &hits)>;
struct GiUpsampled {
    std::vector<Vec3f> values;   ///< per hit
    int64_t decoded = 0;         ///< hits `decode` was asked for, over all its calls
};
/// Every hit's Ê⁺ from `decode` on the lattices of opt (levels coarse to fine, then the pixels in
/// between; header): decode is called once per level and once for the pixels without support. With
/// levels 1 it decodes lattice_hits(gb, opt.stride) and then interpolate_from_lattice's
/// needs_decode, as before. Deterministic. Throws ltm::Error on levels < 1, contrast < 0, a stride
/// interpolate_from_lattice refuses or a decode that returns the wrong count.
GiUpsampled upsample_gi(const GBuffer &gb, const Camera &camera, const GiUpsampleOptions &opt, const GiDecode &decode);

}  // namespace ltm
