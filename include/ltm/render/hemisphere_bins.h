// hemisphere_bins.h: the R×R directional grid of incident radiance (paper §7's 32×32 GT).
// Bin (i, j) is the square cell [i/R, (i+1)/R) × [j/R, (j+1)/R) of the unit square, mapped to the
// hemisphere by Shirley's concentric disk map followed by Malley's lift (the cosine warp). Both
// maps preserve measure, so every bin covers the same projected solid angle π/R², and
// E = ∫ L cosθ dω = (π/R²) Σ_bins L̄_bin. The map is invertible (direction_to_square), which is
// what importance sampling from predicted bins needs.
#pragma once

#include "ltm/core/math.h"

namespace ltm {

/// Local direction (z = normal) for a point of the unit square (= sample_cosine_hemisphere).
Vec3f square_to_direction(Vec2f u);
/// Inverse: the point of the unit square that maps to a local direction with z ≥ 0.
Vec2f direction_to_square(Vec3f w);
/// Flat bin index i·R + j of a local direction.
int direction_to_bin(Vec3f w, int resolution);

}  // namespace ltm
