// mesh_builder.h: appends primitives (quads, boxes, cylinders) to a TriangleMesh with
// consistent winding and metric uvs, used by the built-in scenes and the generator.
#pragma once

#include <string>

#include "ltm/scene/mesh.h"
#include "ltm/scene/scene.h"

namespace ltm {

/// Appends quad a-b-c-d (in order around the quad) as two triangles; the normal follows
/// (b - a) × (d - a). uvs are metric: distance along a→b and a→d.
void add_quad(TriangleMesh &mesh, Vec3f a, Vec3f b, Vec3f c, Vec3f d);

/// Same, but flips the winding if needed so the normal points toward `toward`.
void add_quad_facing(TriangleMesh &mesh, Vec3f a, Vec3f b, Vec3f c, Vec3f d, Vec3f toward);

/// Axis-aligned box [lo, hi] with outward normals (12 triangles, 24 vertices, metric uvs).
void add_box(TriangleMesh &mesh, Vec3f lo, Vec3f hi);

/// Cylinder along +y: base centre, radius, height, `segments` sides; outward normals. Without
/// caps it is an open tube of one sheet (a lampshade).
void add_cylinder(TriangleMesh &mesh, Vec3f base_center, float radius, float height, int segments, bool caps = true);

/// The one rule for a degenerate triangle, shared by the scene loader (which drops them) and
/// validate_scene (which refuses them): twice its area is not above k · (longest edge)², k = 1e-6,
/// or a coordinate or the area is not finite. Relative, so it does not depend on the unit of length
/// (a well-shaped 10 µm triangle of a real file is kept); a sliver thinner than a millionth of
/// its length is dropped: its float cross product is rounding (relative error ~1e-7 · edge²), so
/// its normal is noise, and it carries no visible surface.
bool is_degenerate_triangle(Vec3f p0, Vec3f p1, Vec3f p2);
inline bool is_degenerate_triangle(const TriangleMesh &mesh, size_t tri) {
    return is_degenerate_triangle(mesh.vertex(tri, 0), mesh.vertex(tri, 1), mesh.vertex(tri, 2));
}

/// Removes the degenerate triangles (is_degenerate_triangle); returns how many were removed.
size_t drop_degenerate_triangles(TriangleMesh &mesh);
/// The same over a scene's meshes (in world space: after every transform and instancing), removing
/// the meshes left empty. The readers of foreign formats (pbrt, glTF, OBJ) call it once and print
/// what it returns — the one warning ("N of T triangles dropped as degenerate …"), empty when
/// nothing was dropped — so a real file that pbrt-v4 renders loads; validate_scene refuses what it would drop.
std::string drop_degenerate_triangles(Scene &scene);

/// Applies an affine transform to every vertex appended from index `first_vertex` on;
/// flips the winding of the affected triangles if the transform mirrors.
void transform_mesh(TriangleMesh &mesh, const Transform &xf, size_t first_vertex = 0);

}  // namespace ltm
