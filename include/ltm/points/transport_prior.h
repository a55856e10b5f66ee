// transport_prior.h: indirect irradiance at any surface point from a visibility-free radiosity
// solve on scene points — a closed-form prior from the points alone (no ray tracing, so the
// paper's "no illumination cues" still holds), one level per point instead of one per house.
//
// Each node j (a scene point: position p_j, unit normal n_j, albedo ρ_j, emitted radiance L_j)
// is a Lambertian disc of area a. Without visibility, the irradiance at a receiver (p, n) per unit
// radiance of node j is
//     G_j(p, n) = a · max(0, n·w) · max(0, −n_j·w) / (r² + a/π),   w = (p_j − p)/r,
// the exact on-axis irradiance of a disc (L·a/(r² + a/π)) with both cosines. Ignoring occlusion
// counts surfaces behind walls, so Σ_j G_j over-counts; in a closed scene the true form factors
// of a receiver sum to 1, so each receiver's row is normalised to sum 1 (a weighted mean of the
// radiosity in front of it, near surfaces weighing most). With B_0 = π L (exitance) and
//     B_{k+1,j} = ρ_j · Σ_i Ĝ_ji B_{k,i}   (Ĝ the row-normalised transport among nodes),
// indirect irradiance after 1..D bounces is   E⁺(p, n) = Σ_j Ĝ_j(p, n) · Σ_{k=1..D} B_{k,j}.
//
// Exact for the furnace (a closed convex box of uniform ρ and emission: π L Σ_{k=1..D} ρ^k);
// linear in emission, per colour channel independent, invariant to rotation, translation and to
// the unit of length when a scales with length² (measured on generated houses: MSE 0.42× the
// house-wide flat oracle's, scripts/analysis/radiosity_prior.py, docs/results.md).
#pragma once

#include <cstddef>
#include <vector>

#include "ltm/core/math.h"
#include "ltm/points/point_set.h"

namespace ltm {

/// A solved prior: nodes and their bounce-summed exitance Σ_{k=1..D} B_k.
struct TransportPrior {
    std::vector<Vec3f> position, normal;   ///< [m] nodes (unit normals)
    std::vector<Vec3f> exitance;           ///< [m] Σ_{k=1..D} B_k (W/m² per channel)
    float area = 0.f;                      ///< a: the area each node stands for (same unit² as positions)
};

/// Solves D bounces among m nodes. position/normal/albedo/radiance: m entries each; node_area > 0.
/// O(m²) time, O(m²) floats of memory for the transport (m = 4 096: 64 MiB). Deterministic at any
/// thread count. Throws ltm::Error on mismatched sizes, no nodes, node_area ≤ 0 or bounces < 0.
TransportPrior solve_transport_prior(const std::vector<Vec3f> &position, const std::vector<Vec3f> &normal,
                                     const std::vector<Vec3f> &albedo, const std::vector<Vec3f> &radiance,
                                     float node_area, int bounces);

/// Every scene point a node: scene_points [M, 12] (scene_point_columns()), node_area = A / M. With
/// `emission_scale` (S_c = Φ_c/A, exact from the meshes) the points' radiance is rescaled per
/// channel so that π · mean = S_c (emitters are few points; their count is noisy).
TransportPrior solve_transport_prior(const PointSet &scene_points, float node_area, int bounces,
                                     const Vec3f *emission_scale = nullptr);

/// E⁺ at n receivers: position and normal as float arrays [n, 3] (any stride ≥ 3 floats between
/// rows), out [n, 3] contiguous. A receiver that faces no node gets 0. O(n·m), deterministic.
void gather_transport_prior(const TransportPrior &prior, const float *position, const float *normal, size_t stride,
                            size_t n, float *out);

}  // namespace ltm
