// mesh_occlusion.h: the transport prior's visibility by rays against the scene's meshes
// (transport/segment_occlusion.h), over the renderer's Embree BVH.
#pragma once

#include "ltm/render/embree_accel.h"
#include "ltm/transport/segment_occlusion.h"

namespace ltm {

class MeshOcclusion final : public SegmentOcclusion {
public:
    /// Keeps a reference to `accel`: it must outlive this object (and every prior solved with it).
    explicit MeshOcclusion(const EmbreeAccel &accel) : m_accel(accel) {}
    explicit MeshOcclusion(EmbreeAccel &&) = delete;   ///< a temporary would dangle
    /// A triangle strictly inside the segment: t ∈ (10⁻⁴, 1 − 10⁻⁴) of its length.
    bool blocked(Vec3f a, Vec3f b) const override { return m_accel.occluded(Ray{a, b - a, 1e-4f, 1.f - 1e-4f}); }
    bool meets(Vec3f origin, Vec3f direction) const override { return m_accel.occluded(Ray{origin, direction, 0.f}); }

private:
    const EmbreeAccel &m_accel;
};

}  // namespace ltm
