// power_balance.h: the closed-form level of indirect irradiance in an enclosure, from scene points
// alone (no ray tracing, so the paper's "no illumination cues" still holds).
//
// In a closed scene every emitted watt lands on some surface; a fraction ρ̄ is re-emitted, lands
// again, and so on. Averaged over the total area A, indirect irradiance after 1..D bounces is
//     Ē⁺_c ≈ (Φ_c / A) · Σ_{k=1..D} ρ̄_c^k,    Φ_c / A = π · (area-mean emitted radiance)_c,
// with ρ̄_c the area-mean albedo. Scene points are area-uniform samples, so both means are plain
// means over them. Exact for the furnace box; a level estimate elsewhere (openings, occlusion and
// the albedo seen by the light differ from the area mean). The model's physics prior
// (nn/model_config.h, PhysicsConfig::prior_bounces) is the same formula in torch.
#pragma once

#include <array>

#include "ltm/points/point_set.h"

namespace ltm {

/// scene_points [M, 12] (scene_point_columns()) -> Ē⁺ per channel (W/m²). bounces D >= 0.
std::array<double, 3> power_balance_irradiance(const PointSet &scene_points, int bounces);

}  // namespace ltm
