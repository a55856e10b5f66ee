// direct_light.h: E_direct with analytic unshadowed irradiance and stochastic visibility — the
// ratio estimator of Heitz, Hill and McGuire 2018 ("Combining Analytic Direct Illumination and
// Stochastic Shadows"):
//     E_direct ≈ Σ_l E_unocc,l · (Σ_s V_s·w_s) / (Σ_s w_s),   w_s = cosθ_x·cosθ_l / (d²·p_A)
// per light l (an emissive mesh), where E_unocc,l is exact (Lambert's polygon formula over its
// triangles, clipped to the receiver's hemisphere; the terms of every front-facing triangle share
// one sign, so the edges that two such triangles share cancel and a mesh in view costs its outline)
// and the ratio uses the same samples on l with and without their shadow rays. The n samples are
// shared among the lights in proportion to E_unocc,l, or to its small-source approximation for a
// light farther than a few of its radii and wholly in view (at least one each), and E_unocc,l is summed only for a
// light that a sample sees: a light in another room — unoccluded analytically, occluded in fact —
// costs one shadow ray, adds no noise to the lights that are seen, and no arc terms. Unshadowed points are exact at any sample count and penumbrae keep only the noise of the
// visibility ratio, so a few samples give a clean image. A ratio of estimates is biased, but
// consistent (→ E_direct as samples grow); the path tracer's unbiased MIS estimator stays the
// ground truth. Needs constant emission (textured emitters: use the MIS estimator).
#pragma once

#include <cstdint>
#include <vector>

#include "ltm/core/image.h"
#include "ltm/render/embree_accel.h"
#include "ltm/render/gbuffer.h"

namespace ltm {

/// Irradiance at (p, n) from a one-sided triangle (v0, v1, v2) of unit radiance emitting along
/// (v1 − v0) × (v2 − v0): Lambert's formula after clipping to the hemisphere n·(x − p) ≥ 0.
/// Multiply by Le for W/m². 0 behind the emitter or below the horizon.
float triangle_irradiance(Vec3f p, Vec3f n, Vec3f v0, Vec3f v1, Vec3f v2);

class RatioDirectLight {
public:
    /// Throws if an emitter's radiance is textured (no closed form).
    RatioDirectLight(const EmbreeAccel &accel, uint64_t seed);
    /// E_unocc: every emissive triangle, no occlusion.
    Vec3f unoccluded(Vec3f p, Vec3f n) const;
    /// The ratio estimate with n_samples light samples; deterministic in (seed, key).
    Vec3f irradiance(Vec3f p, Vec3f n, uint64_t key, int n_samples) const;
    /// True if every emitter has constant radiance (the constructor's requirement).
    static bool supports(const Scene &scene);

private:
    struct Light {   // one emissive mesh of constant radiance
        std::vector<Vec3f> v;         // 3 vertices per triangle
        std::vector<Vec3f> plane;     // (v1 − v0) × (v2 − v0) per triangle, as triangle_irradiance's facing test
        std::vector<Vec3f> normal;    // plane normalised: unit, emitting side
        std::vector<double> cdf;      // by area, last = 1
        Vec3f radiance;
        Vec3f centroid{0.f};          // area-weighted: the small-source approximation's point (share_factor)
        float area = 0.f;
        // For unoccluded_factor's sum over a region's outline (index_edges):
        std::vector<int32_t> twin;    // per side k of triangle t (v_k → v_k+1): the triangle traversing it the other way, or −1
        // A binary tree over the triangles (leaves of ≤ 8): a subtree wholly behind its faces is
        // skipped, one wholly in view adds its boundary sides only.
        struct Node {
            Vec3f centre{0.f};
            float radius = 0.f;                    // bounding sphere of its vertices
            Vec3f axis{0.f, 0.f, 1.f};             // normal cone: its faces' unit normals within
            float cos_cone = -1.f, sin_cone = 0.f;  //   the angle α (cos, sin) of the axis
            uint32_t lo = 0, hi = 0;               // its triangles: order[lo, hi)
            int32_t child[2] = {-1, -1};
            uint32_t sides_lo = 0, sides_hi = 0;   // sides[lo, hi): its sides whose twin lies outside it (3t + k)
            bool whole_ok = false;                 // its sides are kept, so it may be taken whole
        };
        std::vector<Node> tree;       // preorder, [0] the root
        std::vector<uint32_t> order;  // the triangles in tree order
        std::vector<uint32_t> sides;
        void index_edges();
        int32_t build_node(uint32_t lo, uint32_t hi);   // the subtree over order[lo, hi); its index
    };
    /// Σ triangle_irradiance over l's triangles, summed over the outline of the part wholly in view
    /// (shared edges cancel) plus the triangles the horizon cuts; l's tree skips the subtrees turned
    /// away and takes those wholly in view by their outlines: about O(outline + tree nodes visited)
    /// arc terms and bounds a receiver.
    float unoccluded_factor(const Light &l, Vec3f p, Vec3f n) const;
    /// What shares irradiance()'s samples out among the lights, for unit radiance: 0 where l is
    /// wholly below p's horizon or turned away (exactly E_unocc,l there); unoccluded_factor itself
    /// (`exact`) within k_near_radii of l's bounding sphere and wherever p's horizon or the lamp's
    /// faces cut it; otherwise (far, wholly above the horizon and facing p) the small-source
    /// approximation A·cos_x·cos_l/d² at its centroid, floored so that it keeps a sample. The
    /// exact sum is then paid only for lights a sample sees: a lamp in another room costs its shadow
    /// ray and a few bounds, not its outline's arc terms.
    float share_factor(const Light &l, Vec3f p, Vec3f n, bool &exact) const;
    const EmbreeAccel &m_accel;
    std::vector<Light> m_lights;
    uint64_t m_seed;
};

/// E_direct at every G-buffer hit with the ratio estimator (progress on stderr).
IrradianceImages direct_images_ratio(const RatioDirectLight &light, const GBuffer &gb, int spp);

}  // namespace ltm
