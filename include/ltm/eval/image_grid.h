// image_grid.h: side-by-side and stacked image layouts (reference | prediction | error) and
// nearest-neighbour resizing, for figures and reports.
#pragma once

#include <vector>

#include "ltm/core/image.h"
#include "ltm/core/math.h"

namespace ltm {

/// Tiles left to right with `gap` pixels of `gap_color` between neighbours (none at the outer
/// border). All tiles must have the same height. Width = Σ widths + gap · (n − 1).
Image hconcat(const std::vector<Image> &tiles, int gap = 2, Vec3f gap_color = Vec3f(1.f));

/// Tiles top to bottom, as hconcat. All tiles must have the same width.
Image vconcat(const std::vector<Image> &tiles, int gap = 2, Vec3f gap_color = Vec3f(1.f));

/// Nearest-neighbour resampling to w × h: out(x, y) = img(⌊(x + ½) · W / w⌋, ⌊(y + ½) · H / h⌋),
/// i.e. each output pixel centre takes the source pixel it falls into. Integer upscales
/// replicate pixels exactly.
Image resize_nearest(const Image &img, int w, int h);

}  // namespace ltm
