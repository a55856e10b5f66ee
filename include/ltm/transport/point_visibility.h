// point_visibility.h: which parts of a scene see each other, from its scene points alone — the
// transport prior's occlusion (transport/transport_prior.h). No ray tracing of the meshes, so the
// paper's "no illumination cues" still holds: the input is the point cloud the model reads.
//
// A voxel grid of edge h records, per voxel, which ways the surfaces of its scene points face
// (6 bits: ±x, ±y, ±z, set for each axis where |n_a| ≥ 0.25). A segment travelling along d is
// blocked by a voxel holding a surface it meets from the front (n_a · d_a < 0 beyond a grazing
// margin, |d_a| > 0.05): so a segment leaving a surface is not stopped by that surface's own voxels, a segment
// reaching a surface's front is — except within h of its ends by the end point's own facing
// (the receiver or sender itself). Surfaces are sampled every √(A/M), so h ≈ 2 √(A/M) leaves few
// holes in a wall. The grid is centred on the points' bounding box, so it maps to itself under
// the 8 horizontal symmetries of training, translation and a unit change by a power of two.
//
// Nodes are grouped into about C clusters (centres from a coarse grid, see cluster_visibility()).
// Each node, and each receiver of the gather,
// joins the nearest centre that faces its way (so the two faces of a wall fall into different
// clusters) and that it sees (so a cluster does not straddle a wall between two floors). Two
// clusters see each other when the segment between their centres is not blocked. Both tests lift
// the segment's ends h/2 along their normals (a segment along a floor otherwise may pass beneath
// the lowest voxel of a wall standing on it).
//
// Measured before building it (scripts/analysis/visibility_prior.py, 8 validation houses,
// exact per-pair visibility among 768 nodes): house-wide MSE / flat oracle 0.53 → 0.39 (better
// in 7 of 8 houses), level 1.01 → 1.12.
#pragma once

#include <cstdint>
#include <vector>

#include "ltm/core/math.h"
#include "ltm/transport/disc_occluder.h"
#include "ltm/transport/segment_occlusion.h"
#include "ltm/points/point_grid.h"

namespace ltm {

/// Voxels of a point set, with the ways their surfaces face.
class VoxelOccupancy {
public:
    VoxelOccupancy() = default;
    /// points, normals: the scene points; voxel: the edge h > 0 (same unit as the positions).
    /// splat > 0: each point also marks, with its facing, the voxels at p ± splat·d̂ for each world
    /// axis whose projection d onto the point's tangent plane is not short (|d| ≥ 0.5): a point
    /// stands for a patch of its surface, so a grid finer than the points' spacing keeps no holes
    /// in a wall, and the wall does not thicken along its normal. Axis-aligned, so the grid still
    /// maps to itself under the 8 horizontal symmetries.
    /// Throws ltm::Error on no points, mismatched sizes, h ≤ 0, splat < 0 or more than 2^28 voxels.
    VoxelOccupancy(const std::vector<Vec3f> &points, const std::vector<Vec3f> &normals, float voxel, float splat = 0.f);
    bool solid(Vec3f p) const { return facing(p) != 0; }   ///< outside the grid: not solid
    /// The facing bits of the voxel at p: bit 2a for +axis a, 2a + 1 for −axis a; 0 outside.
    uint8_t facing(Vec3f p) const;
    /// Is the segment from a (surface normal na) to b (normal nb) blocked? Samples every h/2.
    bool blocked(Vec3f a, Vec3f na, Vec3f b, Vec3f nb) const;
    float voxel() const { return m_h; }
    Vec3f center() const { return m_center; }   ///< the grid's centre: the points' bounding-box centre
    int64_t n_solid() const;

private:
    /// Linear index of the voxel holding p (x fastest), or −1 outside the grid.
    int64_t cell(Vec3f p) const;
    Vec3f m_center{0.f};
    float m_h = 0.f;
    int m_half[3] = {0, 0, 0};   ///< cells per half-axis: index = floor((p − centre)/h) + half
    std::vector<uint8_t> m_facing;
};

struct VisibilityOptions {
    float voxel = 0.f;       ///< h (absolute); 0 = use voxel_spacings
    /// h in units of the occupancy points' own spacing (point_spacing below); 0 with voxel 0 = no
    /// visibility. Measured from the points, h follows them exactly under any change of unit —
    /// the model's ℓ (mean FPS-group distance) moves with FPS near-ties, and a grid tied to it
    /// flipped voxels under a ×10 unit change (physics check: 12 % max).
    float voxel_spacings = 0.f;
    int clusters = 1024;     ///< C: about this many cluster centres; visibility between them (C² / 2 segments)
    /// Tangent splat radius of each occupancy point (VoxelOccupancy) in units of the points'
    /// spacing; 0 = each point marks only its own voxel.
    float splat_spacings = 0.f;
    /// > 0: segments are tested against the occupancy points as oriented discs of this radius in
    /// units of the points' spacing (transport/disc_occluder.h) instead of the voxels; the voxel grid
    /// then only supplies the cluster grid's centre (its edge comes from the points' spacing and
    /// count, transport_prior.cpp). 0 = voxels.
    float disc_spacings = 0.f;
    /// K ≥ 1: a receiver's visibility is the weighted blend of the rows of its K nearest visible
    /// clusters (ClusterVisibility::receiver_clusters), not of its one cluster's: the image of a
    /// surface then has no edges where its pixels change cluster. 1 = one cluster (v0.9).
    int blend = 1;
    /// R > 0: each cluster centre casts R² cosine-distributed rays (an R × R stratified grid of the
    /// concentric map) against the discs, and the share that meets a disc is its closure c (1 − its
    /// open share: a window to nothing, an open side); a receiver's row of the prior then sums to its
    /// blended c instead of 1 (transport/transport_prior.h). Needs discs. 0 = every receiver closed (v0.11).
    int open_rays = 0;
    /// Set: the prior's rows and gather take their visibility and closure from rays instead
    /// (transport/segment_occlusion.h, through the cluster tree: needs θ > 0); the clusters above are
    /// still built for the directional gather (gather_transport_prior_radiance), with their pairwise
    /// visibility unless cluster_pairs is false.
    PriorRays rays;
    /// With rays: false builds the clusters alone (the tree's partition), not their pairwise
    /// visibility and closure, which only the directional gather reads — every pair then counts as
    /// visible and the rows and gathers are bit for bit the same (the rays decide). A frame solved
    /// for its regather alone (nn/scene_frame.h) has no directional gather: on the demo house at
    /// 32 768 points the pairs' segments were a tenth of the frame's CPU. Ignored without rays.
    bool cluster_pairs = true;
};

/// The spacing of a surface sample: √(π · mean r₈² / 8), r₈ the distance of each point to its 8th
/// nearest other point (π r₈² holds ~8 points of an area-uniform sample). Free of ties (a tie
/// swaps which neighbour, not the distance), equivariant with the unit. By ring searches on a grid
/// (points/point_grid.h), exactly the values a scan of all pairs gives; deterministic.
/// Throws ltm::Error with fewer than 9 points or a non-finite one.
float point_spacing(const std::vector<Vec3f> &points);

/// Which node clusters see each other. Empty when visibility is off.
struct ClusterVisibility {
    std::vector<Vec3f> position, normal;   ///< [C] cluster centres (nodes)
    std::vector<uint32_t> node_cluster;    ///< [m] each node's cluster
    std::vector<uint8_t> visible;          ///< [C·C] symmetric; a cluster sees itself
    VoxelOccupancy occupancy;              ///< what the segments are tested against without discs; its centre anchors the cluster grid (and, without discs, its voxel count sizes it)
    DiscOccluder discs;                    ///< when not empty, what the segments are tested against instead
    PointGrid centres;                     ///< the centres on a grid of the cluster cell's edge (empty: receivers scan them all)
    int blend = 1;                         ///< K of receiver_clusters (VisibilityOptions::blend)
    /// [C] each centre's closure: the share of its cosine-weighted hemisphere that meets a surface
    /// (cluster_closure); empty: every cluster closed (1).
    std::vector<float> closure;
    /// false: built without the pairwise visibility and closure (cluster_visibility's `pairs`): the
    /// partition alone, for a tree whose visibility is by rays; a receiver's view of it is refused.
    bool pairs = true;
    static constexpr int k_candidates = 8;   ///< facing centres a receiver considers
    bool empty() const { return position.empty(); }
    size_t size() const { return position.size(); }
    /// The cluster of a receiver (p, n): of the 8 nearest centres whose normal is within 90° of n,
    /// the nearest it sees; else the nearest of them; the nearest of all when none faces that way.
    /// Ties to the lower index.
    uint32_t cluster_of(Vec3f p, Vec3f n) const;
    /// The clusters whose visibility a receiver (p, n) blends, nearest first, and their weights
    /// (sum 1); returns their count (1..blend). Of the k_candidates nearest centres facing n's way,
    /// the visible ones v_1, v_2, … (as cluster_of): the first K = blend of them weigh
    ///     w_k ∝ (1 − d_k²/d_ref²)²,   d_ref = the distance of v_{K+1} (else of the farthest candidate),
    /// so a cluster's weight falls to 0 where it swaps places with the next one: the blend is
    /// continuous as p moves, except where a centre's visibility itself flips. blend 1, or no
    /// visible candidate, or all weights 0: cluster_of's one cluster with weight 1.
    /// ids and weights hold at least k_candidates entries.
    int receiver_clusters(Vec3f p, Vec3f n, uint32_t *ids, float *weights) const;
    /// Is the segment between two surface points (a, normal na) and (b, nb) blocked? Against the
    /// discs when there are any, else against the voxels with both ends lifted h/2 along their normals.
    bool blocked(Vec3f a, Vec3f na, Vec3f b, Vec3f nb) const;
    /// The weight of every cluster for a receiver that blends clusters ids[0..K) with weights w:
    /// out[c] = Σ_k w_k V(ids_k, c), out [C].
    void blend_rows(const uint32_t *ids, const float *w, int K, float *out) const;
    /// The closure of a receiver that blends clusters ids[0..K) with weights w: Σ_k w_k c(ids_k),
    /// 1 without closures.
    float closure_of(const uint32_t *ids, const float *w, int K) const {
        if (closure.empty()) return 1.f;
        float c = 0.f;
        for (int k = 0; k < K; ++k) c += w[k] * closure[ids[k]];
        return c;
    }
};

/// The closure of each cluster centre (ClusterVisibility::closure): of rays² cosine-distributed
/// directions (the centres of an rays × rays grid on the concentric map, in Frame(normal)), the
/// share whose ray meets one of `discs` (DiscOccluder::ray_meets_disc: either side, before leaving
/// the scene). 1 in a closed room up to the discs' gaps, below 1 where the hemisphere opens to
/// nothing. O(C·rays²·L/r). Deterministic at any thread count. Needs discs; rays in [1, 256].
std::vector<float> cluster_closure(const ClusterVisibility &vis, const DiscOccluder &discs, int rays);

/// The radius of the closure's discs in point spacings. Larger than the occlusion's one spacing:
/// a closed box sampled at spacing s and covered by discs of radius s still lets 2.6 % of a
/// hemisphere's rays through (the furnace came out 0.974); an opening loses only 0.5 s at its rims.
constexpr float k_closure_disc_spacings = 1.5f;

/// Clusters the m nodes and tests visibility between every pair of cluster centres against
/// `occupancy` (of all scene points). Centres: the nodes are grouped by a cube grid of edge
/// g = h·√(2·n_solid/C) centred on the occupancy's centre and by the axis their normal faces most
/// (±x, ±y, ±z); each group's centre is its node nearest to the group's mean (ties within rounding:
/// the node nearer the grid centre, then the smaller position), groups in key order — about C of
/// them on generated houses (a target, not a cap: cells holding several facings give more groups;
/// the pair tests cost O(C²)); a pair whose ends no kept order tells apart is tested both ways.
/// Unlike farthest point
/// sampling (greedy: one node more or less changes every later centre), one node added or removed
/// changes at most its own group's centre, so the occlusion does not jump when a rescaled scene
/// samples a borderline point differently; the grid maps to itself under the training symmetries
/// and a unit change by a power of two. O(m log m + m·C + C²·L/h). Deterministic at any thread count.
/// `cell` > 0 sets g directly. The voxel count n_solid changes by one with each voxel that float
/// rounding flips under a change of unit, and g with it, moving the cell boundaries far from the
/// grid's centre; so with discs the prior passes g = s·√(2·κ·M/C) from the points' spacing s and
/// count M instead (transport/transport_prior.cpp; physics check of v0.9 on 8 test houses: unit error
/// 0.64 % mean / 3.0 % max → 0.55 % / 1.9 %).
/// Throws ltm::Error on mismatched sizes or bad options.
/// pairs false: the clusters only, `visible` all 1 (VisibilityOptions::cluster_pairs).
ClusterVisibility cluster_visibility(const std::vector<Vec3f> &node_position, const std::vector<Vec3f> &node_normal,
                                     VoxelOccupancy occupancy, int clusters, DiscOccluder discs = {}, float cell = 0.f,
                                     bool pairs = true);

}  // namespace ltm
