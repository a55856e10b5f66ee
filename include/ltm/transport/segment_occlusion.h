// segment_occlusion.h: visibility for the transport prior from a ray tracer — the meshes' own
// occlusion instead of the points' (transport/point_visibility.h). The prior asks two things of it:
// is a segment between two surface points blocked (a node's light reaching a receiver), and does a
// ray leaving a surface meet anything (the receiver's closure, 1 − its open share). Rays are
// geometry, not illumination: the renderer traces the same ones for direct light.
//
// The interface keeps transport/ free of the renderer: render/mesh_occlusion.h implements it over
// the scene's Embree BVH; tests implement it analytically. The prior works in the model's
// normalised frame (p − centre)/ℓ; FramedOcclusion maps that frame back to the scene's.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "ltm/core/math.h"

namespace ltm {

class SegmentOcclusion {
public:
    virtual ~SegmentOcclusion() = default;
    /// Does anything lie on the open segment a → b (its ends excluded; the caller lifts them off
    /// their surfaces)? Thread-safe.
    virtual bool blocked(Vec3f a, Vec3f b) const = 0;
    /// Does the ray from `origin` along `direction` (unit) meet a surface at any distance > 0?
    /// Thread-safe.
    virtual bool meets(Vec3f origin, Vec3f direction) const = 0;
};

/// An occlusion in another frame: a point x of this one is centre + length · x in `world`'s.
/// Directions are unchanged (length > 0).
class FramedOcclusion final : public SegmentOcclusion {
public:
    FramedOcclusion(std::shared_ptr<const SegmentOcclusion> world, Vec3f centre, float length);
    bool blocked(Vec3f a, Vec3f b) const override;
    bool meets(Vec3f origin, Vec3f direction) const override;

private:
    std::shared_ptr<const SegmentOcclusion> m_world;
    Vec3f m_centre;
    float m_length;
};

/// The transport prior's visibility by rays (transport_prior.h): what to trace against and how many
/// rays measure each receiver's closure.
struct PriorRays {
    std::shared_ptr<const SegmentOcclusion> occlusion;   ///< null: visibility from the points (off)
    int closure_rays = 8;                                 ///< R: closure from R² rays; 0: every receiver closed
    explicit operator bool() const { return bool(occlusion); }
};

/// The closure of a receiver (p, n): the share of rays² cosine-distributed directions (the centres
/// of a rays × rays grid of the concentric map, in Frame(n); one pattern for every receiver, as
/// cluster_closure) whose ray from p + lift·n meets a surface. 1 in a closed room; the open share of
/// a window to nothing, an open side, a void beyond the model, is what is missing. rays in [1, 64].
float ray_closure(const SegmentOcclusion &occlusion, Vec3f p, Vec3f n, float lift, int rays);

/// The same for many receivers: positions and normals as rows of `stride` floats, out [n].
/// Deterministic at any thread count.
void ray_closures(const SegmentOcclusion &occlusion, const float *position, const float *normal, size_t stride, size_t n,
                  float lift, int rays, float *out);

}  // namespace ltm
