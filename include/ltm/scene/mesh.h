// mesh.h: indexed triangle meshes in world space (transforms are applied at load time).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "ltm/core/math.h"

namespace ltm {

/// Geometric normals follow the winding: n = normalize((p1 - p0) × (p2 - p0)).
/// Closed solids face outward; room shells face into the room.
struct TriangleMesh {
    std::string name;
    std::vector<Vec3f> positions;
    std::vector<Vec2f> uvs;          ///< empty, or one per position
    std::vector<uint32_t> indices;   ///< 3 per triangle
    int material = -1;               ///< index into Scene::materials

    size_t n_triangles() const { return indices.size() / 3; }
    Vec3f vertex(size_t tri, int k) const { return positions[indices[3 * tri + size_t(k)]]; }
    Vec2f uv(size_t tri, int k) const;
    /// Unnormalised geometric normal (p1 - p0) × (p2 - p0); its length is twice the area.
    Vec3f cross_normal(size_t tri) const;
    float area(size_t tri) const { return 0.5f * length(cross_normal(tri)); }
    /// Point and uv at barycentrics (b0, b1, b2) of vertices 0, 1, 2.
    Vec3f position_at(size_t tri, float b0, float b1, float b2) const {
        return vertex(tri, 0) * b0 + vertex(tri, 1) * b1 + vertex(tri, 2) * b2;
    }
    Vec2f uv_at(size_t tri, float b0, float b1, float b2) const {
        const Vec2f t0 = uv(tri, 0), t1 = uv(tri, 1), t2 = uv(tri, 2);
        return {t0.x * b0 + t1.x * b1 + t2.x * b2, t0.y * b0 + t1.y * b1 + t2.y * b2};
    }
};

}  // namespace ltm
