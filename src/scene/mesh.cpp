// mesh.cpp: per-triangle geometry helpers.
#include "ltm/scene/mesh.h"

namespace ltm {

Vec2f TriangleMesh::uv(size_t tri, int k) const {
    if (uvs.empty()) {   // default parameterisation: the triangle's barycentric corners
        const Vec2f corner[3] = {{0.f, 0.f}, {1.f, 0.f}, {0.f, 1.f}};
        return corner[k];
    }
    return uvs[indices[3 * tri + size_t(k)]];
}

Vec3f TriangleMesh::cross_normal(size_t tri) const {
    const Vec3f p0 = vertex(tri, 0), p1 = vertex(tri, 1), p2 = vertex(tri, 2);
    return cross(p1 - p0, p2 - p0);
}

}  // namespace ltm
