// prior_hierarchy.h: the transport prior's rows (transport/transport_prior.h) through a tree of node
// clusters, so that far light is gathered from aggregates and near light exactly — O(log m + near)
// per receiver instead of O(m) (clustering radiosity, Smits, Arvo & Greenberg 1994; point-based GI,
// Christensen 2008). The dense rows stay the reference; the two agree exactly at θ = 0.
//
// The tree: the occlusion clusters (ClusterVisibility) are its middle level. Below each cluster, a
// binary tree of its nodes (split by the axis their normals face most where they face several,
// else at the median of the longest extent; leaves of ≤ 8 nodes). Above, the clusters are joined
// the same way, by their centroids and mean normals, up to one root. Each tree node S keeps its
// nodes' centroid c_S, bounding radius R_S (about c_S) and box, normal sum N_S = Σ_j n_j, normal cone
// β_S (the largest angle between a member's normal and N_S) and second moment Σ_j e_j e_jᵀ.
//
// A receiver (p, n) with cluster weights v (the blended visibility, as the dense rows) descends
// the tree. S stands in for its nodes when
//   - every cluster under S has one weight v_S > 0 for this receiver (a subtree weighing 0 is skipped),
//   - R_S < θ · |d|  (d = c_S − p: S is small as seen from p),
//   - the near field is not involved: |d| − R_S > 2.5 s (patches),
//   - S's normals lie within 0.6 rad of their mean (β_S; its normals' first-order terms are carried
//     below, the second-order ones are not) and
//   - every member is in front of p and faces it, by bounds on the two cosines (times r) of the point
//     formula: A_j = n·(p_j − p) ≥ max(box bound, n·d − |n·N̂| h_S − |n × N̂| R_S) > 0 (the members'
//     bounding box; h_S the subtree's thickness along N̂) and B_j = −n_j·(p_j − p) ≥ −N̂·d −
//     δ_S (|d| + R_S) − h_S > 0 (δ_S = 2 sin(β_S/2)) — no cosine is clamped inside S. The box keeps
//     a wall's lowest subtrees whole for a receiver on the floor (with R_S alone they were opened to
//     their leaves all around a room).
// With the kernel
//     k(q) = (n·(q − p)) (−n̄·(q − p)) g(|q − p|²),   g(u) = 1/(u (u + a/π)),   n̄ = N_S/|S|,
// expanded about c_S (e_j = p_j − c_S, Σ_j e_j = 0, A = n·d, B = −n̄·d, Σ = Σ_j e_j e_jᵀ):
//     Σ_j k(p_j)     ≈ |S| k(c) + g (−nᵀ Σ n̄) + 2 g′ (A (−n̄ᵀ Σ d) + B nᵀ Σ d) + A B (g′ tr Σ + 2 g″ dᵀ Σ d),
// f = that over |S| k(c) (the second-order factor, clamped to [0.5, 1.5]). Members' normals that
// differ (M = Σ_j e_j n_jᵀ, 0 when they are all equal) add the first-order terms
//     −A g tr M − g nᵀ M d − 2 A g′ dᵀ M d
// (the factor f_M of them over |S| k(c), likewise clamped), and with the values
//     Σ_j k(p_j) x_j ≈ f f_M A g (−d · Σ_j n_j x_j) + f_M ∇k(c) · Σ_j x_j e_j,   ∇k = B g n − A g n̄ + 2 A B g′ d.
// The first moment of x carries where the light lies inside S (a lamp in one corner of a ceiling
// subtree: 25 % errors at θ = 0.5 without it); a uniform x is carried exactly (the furnace). Measured on two
// rooms at θ = 0.5: 1.4 % RMS at the nodes after 5 bounces (2.6 % without the second-order factor).
// A subtree wholly behind the receiver's plane or in it (the upper bounds of A_j ≤ 1e-3 s, plus the
// patches' half-diagonal where they are used: a floor for a receiver on the floor) or with the receiver behind every member's plane (B_j ≤ 0)
// adds exactly 0 and is skipped. Otherwise its children are
// visited, and a leaf's nodes are summed exactly, near field included. θ = 0 never aggregates:
// every node is summed exactly, as in the dense row.
//
// Visibility by rays (set_rays: transport/segment_occlusion.h, the meshes' own occlusion): every
// term a walk emits is kept only when its segment is clear — an exactly summed node's from the
// receiver to the node; an aggregate's from the receiver to its representative (the member nearest
// its centroid), as Lightcuts (Walter et al. 2005) tests a cluster of lights by one shadow ray to its
// representative, and to the two ends of its longest extent: where they disagree the subtree is
// partly visible and is opened instead (hierarchical radiosity refines partly visible links,
// Hanrahan, Salzman & Aupperle 1991) — one ray alone let a floor subtree spanning two rooms through
// a doorway light the wrong room (house 900103, E⁺ MSE: the points' clusters 0.0048, one ray 0.0086,
// with the ends 0.0016). Both ends of each ray are lifted 10⁻³ s off their surfaces. Receivers walk
// with views of K = 0 (no clusters). A receiver takes the answer of the neighbour that last traced
// the same term — in its group or an earlier group of its block (RayShare) — when their distance is
// below 0.05 of the term's (the segments differ by < 0.05 rad): far terms cost a ray per
// neighbourhood, not per receiver — so with rays a group's rows are no longer bit for bit each
// receiver's alone (still deterministic at any thread count).
// Flagged nodes (the emitters, set_rays) are never aggregated: a lamp under its ceiling would
// otherwise share a ray with the ceiling behind it. A far leaf (radius < θ · distance, beyond the
// patches' reach) that is summed exactly for its shape (curved, straddling the receiver's plane) is
// tested as an aggregate is, by its representative and its two ends — if all three face the receiver
// and lie in front of it (an end facing away is hidden by its own object) — and when they agree its members
// (≤ 8) take that answer without a ray each; else each traces its own (an emitter leaf too, when
// all its members are flagged). The answers are shared between neighbouring receivers (RayShare).
//
// Up to k_group = 8 receivers walk the tree together (record_group, gather_group): each makes its
// own decisions, its bounds computed beside the others' in SIMD lanes, and the walk's node fetches
// and stack are shared while any of them descends. Every receiver's row is the one it gets alone,
// bit for bit; what the group saves depends on how alike its receivers are, so the solve groups
// consecutive places (a leaf's patch) and the gather its queries by facing and a Morton curve.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "ltm/core/key_grid.h"
#include "ltm/core/math.h"
#include "ltm/transport/point_visibility.h"
#include "ltm/transport/segment_occlusion.h"

namespace ltm {

class PriorTree {
public:
    /// A value x per node, summed over the tree (PriorTree::sums): per tree node its total and
    /// first moment about the centroid, and x itself at each place (the tree's node order).
    struct Sums {
        std::vector<Vec3f> dipole;   ///< [T, 3]: tree node t, channel c -> Σ_{j∈t} n_j x_jc
        std::vector<Vec3f> moment;   ///< [T, 3]: tree node t, channel c -> Σ_{j∈t} x_jc (p_j − c_t)
        std::vector<Vec3f> value;    ///< [m]: x at each place
    };

    PriorTree() = default;
    /// position, normal: the m nodes; vis: their occlusion clusters (empty: one cluster);
    /// node_area a > 0; patches: the near field by square patches within 2.5 √a (as the dense rows);
    /// theta ≥ 0: the opening bound (0: exact). Throws ltm::Error on mismatched sizes or θ < 0.
    PriorTree(const std::vector<Vec3f> &position, const std::vector<Vec3f> &normal, const ClusterVisibility &vis,
              float node_area, bool patches, float theta);

    /// Visibility by rays from now on (header): every term's segment tested against `rays`; null: the
    /// clusters' visibility of the receivers' views, as before. exact [m] (caller's node order, or
    /// empty): nodes never aggregated while rays are on — the emitters: a lamp hangs just below its
    /// ceiling, and a subtree of both, tested by one ray to a ceiling node behind the lamp, would drop
    /// the lamp with it (the Cornell box's level 0.90). Throws ltm::Error on a wrong size.
    void set_rays(std::shared_ptr<const SegmentOcclusion> rays, const std::vector<uint8_t> &exact = {});
    bool has_rays() const { return bool(m_rays); }
    /// The lift of the rays' ends off their surfaces: 10⁻³ of the nodes' spacing √a.
    float ray_lift() const { return 1e-3f * m_side; }

    /// The grid on which the build compared coordinates and distances (benches compare units with it).
    const KeyGrid &key_grid() const { return m_grid; }
    bool empty() const { return m_place_node.empty(); }
    size_t nodes() const { return m_place_node.size(); }
    /// Bytes the tree holds (its arrays; what a receiver's traversal allocates is not counted).
    size_t bytes() const;

    /// x [m] in the caller's node order -> its sums over the tree. O(T).
    Sums sums(const std::vector<Vec3f> &x) const;

    /// What a receiver sees: the occlusion clusters its visibility blends and their weights
    /// (ClusterVisibility::receiver_clusters); K = 0 without occlusion (every node weighs 1).
    struct View {
        const uint32_t *ids = nullptr;
        const float *w = nullptr;
        int K = 0;
    };
    /// A receiver's row through the tree, recorded once and applied to any values (the solve's
    /// bounces reuse it): its aggregates' coefficients, its exactly summed nodes' terms, and den.
    struct Row {
        struct Aggregate {
            uint32_t node;   ///< tree node
            Vec3f along;     ///< −w f A g d: dotted with Σ n x, per channel
            Vec3f grad;      ///< w ∇k(c): dotted with Σ x e, per channel
        };
        struct Exact {
            uint32_t place;
            float coef;      ///< w t_j
        };
        std::vector<Aggregate> aggregates;
        std::vector<Exact> exact;
        double den = 0;
        void clear() { aggregates.clear(), exact.clear(), den = 0; }
        size_t bytes() const;
    };
    /// Receivers that walk the tree together (record_group): at most k_group, best neighbours that
    /// face alike, so that one walk serves them all.
    static constexpr int k_group = 8;
    struct Receiver {
        Vec3f p, n;
        View view;
    };
    /// One stack entry of a walk: a tree node, the receivers still descending (bit l: receiver l)
    /// and each one's weight for it (< 0: not known yet).
    struct Entry {
        uint32_t node = 0, mask = 0;
        float w[k_group];
    };
    /// Visibility by rays: the ray answers a walk leaves to the walks after it (one table per Scratch).
    /// Per term, the receiver that traced it and the answer, in a direct-mapped table of 4 096
    /// slots (a term that lands on another's slot evicts it). A later receiver within 0.05 of the
    /// term's distance from that receiver takes the answer: within a group and across the groups of
    /// a block (a solve's 16 or a gather's 32 consecutive groups: neighbours), so a far term costs a
    /// ray per neighbourhood. Deterministic where the walks that share one table come in an order that
    /// does not depend on the threads: the solve and the gather empty it at fixed block boundaries and
    /// run each block as one parallel chunk (transport_prior.cpp).
    struct RayShare {
        struct Slot {
            uint32_t key = ~0u;   ///< the term: a place, a leaf | 2³⁰, an aggregate | 2³¹
            uint8_t decision = 0;
            Vec3f from{0.f};      ///< the receiver that traced it
        };
        std::vector<Slot> slots;   ///< empty until the first ray
        uint64_t epoch = 0;        ///< the set_rays call whose answers the slots hold (another tree's or rays': cleared)
    };
    /// What a walk reuses between calls (one per block of neighbouring groups: with rays, RayShare):
    /// its stack, rows to record into and the rays' answers.
    struct Scratch {
        std::vector<Entry> stack;
        Row rows[k_group];
        RayShare shared;
    };
    /// One receiver's row, recorded: its terms, with den = Σ_j v_j t_j, and num_c = Σ_j v_j t_j x_jc
    /// for any values x by apply(), over the nodes it sees (v_j = Σ_k w_k V(ids_k, cluster(j)), as
    /// the dense rows), with the far ones through aggregates (header). `scratch` holds the walk's
    /// stack between calls (one per thread). Deterministic. O(K) per visited tree node for the
    /// visibility (tables of what each cluster sees of every subtree above the clusters), nothing
    /// per cluster.
    void record(Vec3f p, Vec3f n, const View &view, Row &row, Scratch &scratch) const;
    /// record() for count ≤ k_group receivers in one walk of the tree: rows[l] is receiver l's row,
    /// bit for bit what record() gives it alone. Each tree node's bounds are computed for all of
    /// them at once (lane by lane, vectorised) and its stack entry, push and pop are shared; a
    /// receiver leaves the walk where its own criteria skip or aggregate a subtree, so its row holds
    /// the same terms in the same order. The gain grows with how alike the receivers are: a tile of
    /// pixels on one wall descends the same path; receivers far apart cost what they cost alone.
    void record_group(const Receiver *receivers, int count, Row *rows, Scratch &scratch) const;
    /// record_group() and apply() in one: per receiver l its den[l] and num[l][c] against the values
    /// x, bit for bit what they give, without keeping the rows (the gather's path: each row is used once).
    /// far (optional, [count][3]): per receiver the aggregates' part of num (the rest came from exact terms).
    void gather_group(const Receiver *receivers, int count, const Sums &x, double *den, double (*num)[3], Scratch &scratch,
                      double (*far)[3] = nullptr) const;
    /// gather_group() against two value sets in one walk (the prior's exitance and its regather's):
    /// num and num2 bit for bit what gather_group gives for x and for x2 alone (den is theirs too), at
    /// the cost of one walk — with rays, one set of rays.
    void gather_group2(const Receiver *receivers, int count, const Sums &x, const Sums &x2, double *den, double (*num)[3],
                       double (*num2)[3], Scratch &scratch) const;
    /// An order of n receivers (position and normal rows of `stride` floats) in which groups of
    /// k_group consecutive ones walk well together: by the axis they face most, then along a Morton
    /// curve through their bounding box (10 bits an axis; ties by index). Deterministic. O(n log n).
    static std::vector<uint32_t> group_order(const float *position, const float *normal, size_t stride, size_t n);
    /// The tree's node at each place ([m]): consecutive places are neighbours (a leaf's ≤ 8 of them
    /// one tight patch of one facing), so groups of k_group consecutive places walk well together.
    const std::vector<uint32_t> &place_nodes() const { return m_place_node; }
    void apply(const Row &row, const Sums &x, double num[3]) const;

    /// A receiver's ray decisions in the order its walk meets its terms (visibility by rays): the
    /// solve walks again, at every bounce, the rows its budget does not keep; a log taken on the
    /// first walk replays the same decisions without tracing (the walk is deterministic, so its
    /// terms come in the same order). One byte a term: 0 blocked, 1 clear, 2 opened (partly visible).
    struct RayLog {
        std::vector<uint8_t> decisions;
        bool complete = false;   ///< false: the next walk records; true: it replays
        size_t bytes() const { return decisions.capacity(); }
    };
    /// record_group() with ray logs (logs[l] for receiver l): each log records its walk's decisions,
    /// or replays them once complete. Rows bit for bit those of record_group(). Without rays: as it.
    void record_group(const Receiver *receivers, int count, Row *rows, Scratch &scratch, RayLog *logs) const;

    /// Counters of the last rows (a sampling of the work, not thread-safe: for benches and tests).
    struct Work {
        uint64_t visited = 0, aggregates = 0, exact = 0;   ///< tree nodes popped, aggregates used, nodes summed exactly
    };
    /// Like row(), counting the aggregates and the exactly summed nodes it used.
    Work count(Vec3f p, Vec3f n, const View &view, Scratch &scratch) const;

private:
    struct Node {
        Vec3f centroid{0.f};
        float radius = 0.f;
        Vec3f normal_sum{0.f};
        /// cos β, sin β (β: the largest angle between a member's normal and N; π when the normals
        /// cancel) and |N|
        float cos_cone = 1.f, sin_cone = 0.f, normal_length = 0.f;
        float delta = 0.f;             ///< 2 sin(β/2): how far a member's unit normal lies from N̂
        Vec3f box_min{0.f}, box_max{0.f};   ///< the members' bounding box
        float thickness = 0.f;         ///< h: the largest |N̂ · (p_j − c)| (0 for a flat subtree)
        float spread[6] = {0, 0, 0, 0, 0, 0};   ///< Σ_j e_j e_jᵀ, e_j = p_j − c: xx, xy, xz, yy, yz, zz
        float tilt[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};   ///< M = Σ_j e_j n_jᵀ, row-major (0 when all normals are equal)
        uint32_t lo = 0, hi = 0;       ///< its places [lo, hi)
        int32_t child[2] = {-1, -1};   ///< −1: a leaf (≤ 8 places)
        int32_t cluster = -1;          ///< the one cluster under it; −1 above the clusters
        int32_t upper = -1;            ///< its index in m_upper (a cluster's root or above); −1 below
        uint32_t representative = 0;   ///< the place of its member nearest the centroid (its rays' end)
        uint32_t probe[2] = {0, 0};    ///< the places at the ends of its longest extent (partial visibility's test)
        bool keep_exact = false;       ///< set_rays: holds a node never aggregated
        bool flagged_only = false;     ///< set_rays: every member flagged (an emitter leaf: tested whole, never aggregated)
    };
    template <class Sink> struct Terms;
    template <class Sink> struct RayFilter;
    /// One walk of a group of receivers, its terms summed by `sink` (gather_group, gather_group2).
    template <class Sink> void walk_sums(const Receiver *receivers, int count, Sink &sink, Scratch &scratch) const;
    /// The walk of count ≤ k_group receivers (one alone: count 1) that visit's callbacks record.
    template <class Visit> void traverse(const Receiver *receivers, int count, std::vector<Entry> &stack, Visit &&visit) const;
    int32_t build(uint32_t lo, uint32_t hi, std::vector<uint32_t> &items, bool clusters, const std::vector<Vec3f> &pos,
                  const std::vector<Vec3f> &nrm);
    void summarise(Node &t) const;

    std::vector<Node> m_tree;              ///< preorder: a parent before its children; [0] the root
    std::vector<uint32_t> m_place_node;    ///< [m] the caller's node at each place
    std::vector<uint32_t> m_upper;         ///< the clusters' roots and the nodes above them, ascending
    std::vector<uint8_t> m_visible;        ///< [C, C] the clusters' visibility (ClusterVisibility::visible)
    std::vector<uint8_t> m_upper_state;    ///< [C, U] what cluster c sees of upper node u: 0 none, 1 all, 2 some
    std::vector<Vec3f> m_pos, m_nrm;       ///< [m] by place
    std::vector<uint32_t> m_leaf_of;       ///< [m] the leaf holding each place (set_rays; empty without rays)
    std::vector<float> m_px, m_py, m_pz, m_nx, m_ny, m_nz;   ///< the same, structure of arrays
    float m_theta = 0.f, m_reg = 0.f, m_side = 0.f;
    KeyGrid m_grid;                        ///< how the build compares coordinates and distances: steps of √a / 64
    /// Members no further than this in front of the receiver's plane count as in it: a floor's own
    /// nodes for a receiver on that floor (float rounding puts them ±1e-7 off; each adds ≤ 1e-3 of a
    /// neighbour's term, 0 for the patches in the plane). 1e-3 s.
    float m_coplanar = 0.f;
    bool m_patches = false;
    size_t m_clusters = 0;                 ///< C (1 without occlusion)
    std::shared_ptr<const SegmentOcclusion> m_rays;   ///< set_rays: visibility by rays; null: by clusters
    uint64_t m_ray_epoch = 0;              ///< unique per set_rays call in the process (RayShare::epoch)
};

}  // namespace ltm
