// hemisphere_bins.h: the R×R directional grid of incident radiance (paper §7's 32×32 GT).
// Bin (i, j) is the square cell [i/R, (i+1)/R) × [j/R, (j+1)/R) of the unit square, mapped to the
// hemisphere by Shirley's concentric disk map followed by Malley's lift (the cosine warp). Both
// maps preserve measure, so every bin covers the same projected solid angle π/R², and
// E = ∫ L cosθ dω = (π/R²) Σ_bins L̄_bin. The map is invertible (direction_to_square), which is
// what importance sampling from predicted bins needs.
#pragma once

#include <cstdint>
#include <vector>

#include "ltm/core/math.h"
#include "ltm/points/point_set.h"

namespace ltm {

/// The point (u.x, u.y) ∈ [0, 1)² of bin b's cell (bin b = i·R + j covers [i/R, (i+1)/R) × [j/R, (j+1)/R));
/// u = (0.5, 0.5) is the cell's centre.
inline Vec2f bin_to_square(int b, int resolution, Vec2f u = {0.5f, 0.5f}) {
    return {(float(b / resolution) + u.x) / float(resolution), (float(b % resolution) + u.y) / float(resolution)};
}

/// Local direction (z = normal) for a point of the unit square (= sample_cosine_hemisphere).
Vec3f square_to_direction(Vec2f u);
/// Inverse: the point of the unit square that maps to a local direction with z ≥ 0.
Vec2f direction_to_square(Vec3f w);
/// Flat bin index i·R + j of a local direction.
int direction_to_bin(Vec3f w, int resolution);

/// Whole hemispheres of chosen rows, as a directional model takes them: every row repeated R²
/// times (its first 9 columns: p, n, albedo — query and scene points alike), each with the world
/// direction of one bin's centre in the bake's frame Frame(n), bins in order.
struct HemisphereRows {
    std::vector<float> query;       ///< [rows·R², 9]
    std::vector<float> direction;   ///< [rows·R², 3] unit
};
HemisphereRows hemisphere_rows(const PointSet &points, const std::vector<int64_t> &rows, int resolution);

}  // namespace ltm
