// mesh_builder.h: appends primitives (quads, boxes, cylinders) to a TriangleMesh with
// consistent winding and metric uvs, used by the built-in scenes and the generator.
#pragma once

#include "ltm/scene/mesh.h"

namespace ltm {

/// Appends quad a-b-c-d (in order around the quad) as two triangles; the normal follows
/// (b - a) × (d - a). uvs are metric: distance along a→b and a→d.
void add_quad(TriangleMesh &mesh, Vec3f a, Vec3f b, Vec3f c, Vec3f d);

/// Same, but flips the winding if needed so the normal points toward `toward`.
void add_quad_facing(TriangleMesh &mesh, Vec3f a, Vec3f b, Vec3f c, Vec3f d, Vec3f toward);

/// Axis-aligned box [lo, hi] with outward normals (12 triangles, 24 vertices, metric uvs).
void add_box(TriangleMesh &mesh, Vec3f lo, Vec3f hi);

/// Closed cylinder along +y: base centre, radius, height, `segments` sides; outward normals.
void add_cylinder(TriangleMesh &mesh, Vec3f base_center, float radius, float height, int segments);

/// Removes the triangles of zero (or non-finite) area: they carry no surface and would fail
/// validate_scene. Returns how many were removed. Used by the readers of foreign formats.
size_t drop_degenerate_triangles(TriangleMesh &mesh);

/// Applies an affine transform to every vertex appended from index `first_vertex` on;
/// flips the winding of the affected triangles if the transform mirrors.
void transform_mesh(TriangleMesh &mesh, const Transform &xf, size_t first_vertex = 0);

}  // namespace ltm
