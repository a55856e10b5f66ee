// ply_mesh.h: triangle meshes from PLY files (pbrt-v4's "plymesh"): the "vertex" element
// (x y z, optional nx ny nz and u v / s t / texture_u texture_v) and the "face" element
// (list vertex_indices or vertex_index); triangles, quads (split in two) and larger polygons
// (fanned). ASCII, binary little- and big-endian; ".ply.gz" is read through zlib. Other
// elements are skipped. Errors name the file (and the header line).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "ltm/core/math.h"

namespace ltm {

struct PlyMesh {
    std::vector<Vec3f> positions;
    std::vector<Vec3f> normals;      ///< empty or one per position
    std::vector<Vec2f> uvs;          ///< empty or one per position
    std::vector<uint32_t> indices;   ///< 3 per triangle
    int64_t n_polygons = 0;          ///< faces with more than 4 vertices (fanned)
};

PlyMesh read_ply_mesh(const std::string &path);
/// The same from the file's bytes (decompressed); `where` names the source in errors.
PlyMesh parse_ply_mesh(const std::string &bytes, const std::string &where);

}  // namespace ltm
