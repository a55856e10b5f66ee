// tonemap.h: the linear tone map every image output and every metric uses (`ltm render`'s PNGs,
// eval/metrics.h's comparisons): exposure from the reference's 99th-percentile luminance.
#pragma once

#include "ltm/core/image.h"

namespace ltm {

/// Exposure that maps the reference's 99th-percentile luminance to 1:
///   s = 1 / Y_(k),  k = floor(0.99 · (n − 1)),  Y = 0.2126 R + 0.7152 G + 0.0722 B (Rec. 709),
/// where Y_(k) is the k-th smallest of the n pixel luminances. Returns 1 when Y_(k) ≤ 0
/// (a black reference), so the result is always finite and positive. Units: 1 / radiometric unit.
/// Throws ltm::Error on an empty image or a non-finite pixel.
float tonemap_scale(const Image &reference);

/// Linear tone map, no gamma: out = clamp(img · scale, 0, 1) per channel. scale ≥ 0.
Image tonemap(const Image &img, float scale);

}  // namespace ltm
