// sampling.h: warping functions from [0,1)^2 to geometric domains, with their pdfs, and the
// low-discrepancy sequences used for stratified surface sampling.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "ltm/core/math.h"

namespace ltm {

/// Cosine-weighted direction in the local frame (z = normal); pdf = cosθ/π.
/// Malley's method over Shirley's concentric disk map, which keeps strata compact.
Vec3f sample_cosine_hemisphere(Vec2f u);
inline float cosine_hemisphere_pdf(float cos_theta) { return std::max(cos_theta, 0.f) * k_inv_pi; }
/// Inverse of sample_cosine_hemisphere: the point of [0, 1)² that maps to local direction w
/// (z ≥ 0; only w.x, w.y are read). Both maps preserve measure, so equal cells of the square are
/// equal projected solid angles of the hemisphere (render/hemisphere_bins.h).
Vec2f cosine_hemisphere_to_square(Vec3f w);

/// The cosine-distributed local directions at the centres of an n × n grid of the square (row by row:
/// cell (a, b) at index a·n + b): n² directions of equal projected solid angle, one pattern for every
/// frame (the transport prior's closures). n ≥ 1.
std::vector<Vec3f> cosine_grid_directions(int n);

/// Concentric map of the unit square to the unit disk (Shirley & Chiu 1997).
Vec2f sample_concentric_disk(Vec2f u);

/// Uniform barycentrics (b0, b1) on a triangle, b2 = 1 - b0 - b1 (Heitz 2019 low-distortion map,
/// which keeps stratification better than the sqrt map).
Vec2f sample_uniform_triangle(Vec2f u);

/// Roberts' R2 sequence point i with a toroidal shift (Cranley–Patterson rotation), in [0,1)^2.
/// Successive indices fill the square with low discrepancy.
inline Vec2f r2_sequence(uint64_t i, Vec2f shift) {
    constexpr double a1 = 0.7548776662466927, a2 = 0.5698402909980532;   // 1/φ2, 1/φ2²
    const double x = std::fmod(double(shift.x) + a1 * double(i), 1.0);
    const double y = std::fmod(double(shift.y) + a2 * double(i), 1.0);
    return {std::min(float(x), 0x1.fffffep-1f), std::min(float(y), 0x1.fffffep-1f)};
}

}  // namespace ltm
