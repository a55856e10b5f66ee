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
//
// The emission factor S = Φ/A is better taken from the meshes than from the points: emitters are
// small (a ceiling light is ~0.3 % of a house's area, 20–130 of 8 192 points), so the point
// mean carries ±1–2 points of sampling noise — 5–10 % of S, a level error that changes with the
// sampling seed and with the unit of length. scene_emission_scale() is exact.
#pragma once

#include <array>

#include "ltm/points/point_set.h"
#include "ltm/scene/scene.h"

namespace ltm {

/// Σ_{k=1..D} ρ^k: the bounce series of the balance (ρ as given; callers clamp it).
double bounce_series(double rho, int bounces);

/// scene_points [M, 12] (scene_point_columns()) -> Ē⁺ per channel (W/m²). bounces D >= 0.
/// S = π · mean emission of the points, or `emission_scale` when given (scene_emission_scale()).
std::array<double, 3> power_balance_irradiance(const PointSet &scene_points, int bounces,
                                               const Vec3f *emission_scale = nullptr);

/// S_c = Φ_c / A (W/m²) of the scene's surfaces: Φ_c = π Σ_t A_t · L̄e_tc (L̄e: the triangle's mean
/// emitted radiance; a textured emitter is averaged over 64 stratified points per triangle) and
/// A = pass_fraction · Σ_t A_t, the area the scene points represent (SampleStats::pass_fraction()
/// when an enclosure filter dropped part of the surface; 1 without a filter). Scale-free: a scene
/// in another unit of length gives the same S. Throws on a scene of zero area or pass_fraction ∉ (0, 1].
Vec3f scene_emission_scale(const Scene &scene, double pass_fraction = 1.0);

}  // namespace ltm
