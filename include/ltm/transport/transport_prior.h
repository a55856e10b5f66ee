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
//
// Optional occlusion from the points alone (transport/point_visibility.h): Ĝ_ij is multiplied by
// V(cluster(i), cluster(j)) before each row's normalisation, and the gather likewise — a node's
// light then reaches only the clusters that see its cluster (the failure it fixes: light through
// walls). Approximate occlusion breaks the closure that balances power (falsely blocked far nodes
// leave the rows, near ones gain: lit rooms came out 1.19× too bright), so the result is rescaled
// per channel to the enclosure's balance: area mean of E⁺ at the nodes = π L̄ Σ_{k=1..D} ρ̄^k.
// The furnace stays exact. With VisibilityOptions::blend = K > 1 a receiver's mask is the weighted
// blend of the rows of its K nearest visible clusters (ClusterVisibility::receiver_clusters), so
// the gathered image has no seams where receivers change cluster.
//
// Open rooms (VisibilityOptions::open_rays): the rows above sum to 1, as a closed room's form
// factors do. Where a receiver's hemisphere opens to nothing (the Cornell box's open front, a window,
// a void beyond the model) that keeps in the room the light that leaves it (the Cornell box's prior
// was 1.9× too bright). With a closure c per cluster (point_visibility.h: the share of rays that meet
// a disc), each row sums to the receiver's blended c instead: B_{k+1,j} = ρ_j c_j Σ_i Ĝ_ji B_{k,i}
// and E⁺(p) = c(p) Σ_j Ĝ_j(p) Σ_k B_{k,j}. c = 1 everywhere is the closed prior exactly.
//
// Near field (`patches`): the point formula above, evaluated at the nodes' centres, misses the
// adjacent wall at a concave edge (a receiver at distance x from the edge sees it over half its
// hemisphere, through elements within ~x of the edge). With patches, nodes within 2.5 s of a
// receiver (s = √a) weigh by the exact form factor F_j of a square of side s
// (transport/patch_form_factor.h), as t_j = F_j · π/a — the point term's scale — blended into the
// point formula over r ∈ [1.5 s, 2.5 s]. In the solve and the gather alike.
//
// Visibility by rays (`rays`, transport/segment_occlusion.h; `--prior-rays`): the points' clusters
// decide visibility for ~1 024 cluster pairs, and they are too coarse for furniture, partitions and
// the foot of a wall (the real rooms' largest error, docs/results.md session 27). With a ray tracer
// at hand (the renderer has the meshes) every term of a receiver's row through the tree is tested by
// one ray instead (prior_hierarchy.h), and its closure by R² rays; the emitters are never
// aggregated. Rays are geometry, not illumination: the same shadow rays the renderer casts for
// direct light.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "ltm/core/math.h"
#include "ltm/points/point_set.h"
#include "ltm/transport/point_visibility.h"
#include "ltm/transport/prior_hierarchy.h"

namespace ltm {

/// How the occluded prior restores the enclosure's power balance (below): one gain per colour
/// channel (each channel's area mean matches its own closed-box value), one gain for all channels
/// (the luminance's; the solve's chroma is kept), or none.
enum class PriorBalance { per_channel, grey, none };

/// A solved prior: nodes and their bounce-summed exitance Σ_{k=1..D} B_k.
struct TransportPrior {
    std::vector<Vec3f> position, normal;   ///< [m] nodes (unit normals)
    std::vector<Vec3f> exitance;           ///< [m] Σ_{k=1..D} B_k (W/m² per channel)
    float area = 0.f;                      ///< a: the area each node stands for (same unit² as positions)
    ClusterVisibility visibility;          ///< empty: no occlusion
    /// Near field by square patches (solve_transport_prior's `patches`): the gather uses it too.
    bool patches = false;
    /// The hierarchy (solve_transport_prior's theta > 0): the solve and the irradiance gather go
    /// through it (transport/prior_hierarchy.h); null: the dense rows.
    std::shared_ptr<const PriorTree> tree;
    /// The exitance summed over the tree (PriorTree::sums), once per solve: every gather call (the
    /// model calls it per chunk of queries) reads it.
    std::shared_ptr<const PriorTree::Sums> tree_sums;
    /// Visibility by rays (solve_transport_prior's `rays`): the tree's terms are tested by rays and
    /// each receiver's closure is measured by rays; the clusters above serve only the directional gather.
    PriorRays rays;
};

/// The tree solve's first bounce records each node's row (~9 KB a node in a house at m = 65 536) and
/// the later bounces apply the recorded rows; rows past this many bytes are walked through the tree
/// again at every bounce instead. Either way the result is the same (tested): the budget bounds
/// memory, not the answer.
inline constexpr size_t k_prior_row_budget = size_t(768) << 20;

/// Solves D bounces among m nodes. position/normal/albedo/radiance: m entries each; node_area > 0.
/// theta = 0: the dense rows, O(m²) time and floats of memory for the transport at most (m = 4 096:
/// 64 MiB; with occlusion each node stores only the clusters it sees). theta in (0, 1]: through the
/// cluster tree (transport/prior_hierarchy.h) with that opening bound, O(m log m) per bounce, O(m)
/// memory; the gather then uses the tree too. Deterministic at any thread count. Throws ltm::Error
/// on mismatched sizes, no nodes, node_area ≤ 0, bounces < 0 or theta outside [0, 1].
/// row_budget: the tree solve's recorded rows (k_prior_row_budget). rays: visibility and closure by
/// rays against the scene (transport/segment_occlusion.h; the tree's every term tested, header of
/// prior_hierarchy.h) instead of by `visibility`'s clusters; needs theta > 0.
TransportPrior solve_transport_prior(const std::vector<Vec3f> &position, const std::vector<Vec3f> &normal,
                                     const std::vector<Vec3f> &albedo, const std::vector<Vec3f> &radiance,
                                     float node_area, int bounces, ClusterVisibility visibility = {},
                                     PriorBalance balance = PriorBalance::per_channel, bool patches = false,
                                     float theta = 0.f, size_t row_budget = k_prior_row_budget, const PriorRays &rays = {});

/// Every scene point a node: scene_points [M, 12] (scene_point_columns()), node_area = A / M. With
/// `emission_scale` (S_c = Φ_c/A, exact from the meshes) the points' radiance is rescaled per
/// channel so that π · mean = S_c (emitters are few points; their count is noisy). With
/// vis.voxel > 0, occlusion from the occupancy of `occupancy` (all scene points; null: the nodes).
TransportPrior solve_transport_prior(const PointSet &scene_points, float node_area, int bounces,
                                     const Vec3f *emission_scale = nullptr, const VisibilityOptions &vis = {},
                                     const PointSet *occupancy = nullptr, PriorBalance balance = PriorBalance::per_channel,
                                     bool patches = false, float theta = 0.f);

/// E⁺ at n receivers: position and normal as float arrays [n, 3] (any stride ≥ 3 floats between
/// rows), out [n, 3] contiguous. A receiver that faces no node gets 0. O(n·m) at most: with
/// occlusion the nodes are visited cluster by cluster and the clusters a receiver does not see are
/// skipped; with the prior's tree O(n log m). Deterministic at any thread count.
/// far [n, 3] (optional, the tree only: throws without one): the part of out that came through
/// the tree's aggregates — light from far subtrees; out − far came from nodes summed exactly (the
/// near field and the leaves opened for their shape). Never above out; it may dip a little below 0,
/// where an aggregate's first-moment term outweighs its mean. An analysis input (bench/prior_features).
void gather_transport_prior(const TransportPrior &prior, const float *position, const float *normal, size_t stride,
                            size_t n, float *out, float *far = nullptr);

/// gather_transport_prior for `prior` and for `also` — a copy of prior with another exitance (the
/// regather, nn/scene_frame.cpp) — in one pass: each receiver's row is walked, and with rays its
/// closure and its terms traced, once for both. out and also_out [n, 3]: bit for bit what
/// gather_transport_prior gives for each alone. Throws when `also` is not such a copy (another tree,
/// other nodes or node area, near field, rays or cluster count; the clusters' visibility itself is
/// not compared).
void gather_transport_prior_pair(const TransportPrior &prior, const TransportPrior &also, const float *position, const float *normal,
                                 size_t stride, size_t n, float *out, float *also_out);

/// Incident radiance L⁺ for n (receiver, direction) rows: the gather above, split by where each
/// node lies as seen from the receiver. The nodes' shares Ĝ_j(p, n)·ex_j fall into R×R cells of
/// equal projected solid angle π/R² (the concentric cosine map of core/sampling.h, in Frame(n));
/// a row reads L̂ = (R²/π)·E_cell bilinearly between the cells' centres on the square, so at the
/// cells' centres (π/R²)·Σ L̂ = E⁺ exactly. Near nodes are split over the cells they span.
/// Consecutive rows with the same receiver (a hemisphere's bins, a pixel's GGX samples) share one
/// histogram, so a hemisphere costs one gather. position, normal: float arrays with row stride `stride`; direction: world space, unit,
/// on the normal's side, row stride `direction_stride`; out [n, 3] contiguous. resolution R in [1, 64].
/// Deterministic at any thread count.
void gather_transport_prior_radiance(const TransportPrior &prior, const float *position, const float *normal, size_t stride,
                                     const float *direction, size_t direction_stride, size_t n, int resolution, float *out);

}  // namespace ltm
