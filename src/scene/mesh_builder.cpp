// mesh_builder.cpp: primitive construction with consistent winding and metric uvs.
#include "ltm/scene/mesh_builder.h"

#include <algorithm>
#include <cmath>

#include "ltm/core/error.h"

namespace ltm {

void add_quad(TriangleMesh &mesh, Vec3f a, Vec3f b, Vec3f c, Vec3f d) {
    const uint32_t base = uint32_t(mesh.positions.size());
    const Vec3f eu = normalize(b - a);
    // v axis: the component of (d - a) orthogonal to u, so uvs are metric for any quad.
    Vec3f ev = (d - a) - eu * dot(d - a, eu);
    ev = normalize(ev);
    for (Vec3f p : {a, b, c, d}) {
        mesh.positions.push_back(p);
        mesh.uvs.push_back({dot(p - a, eu), dot(p - a, ev)});
    }
    for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) mesh.indices.push_back(base + i);
}

void add_quad_facing(TriangleMesh &mesh, Vec3f a, Vec3f b, Vec3f c, Vec3f d, Vec3f toward) {
    const Vec3f n = cross(b - a, d - a);
    const Vec3f center = (a + b + c + d) * 0.25f;
    if (dot(n, toward - center) >= 0.f) add_quad(mesh, a, b, c, d);
    else add_quad(mesh, a, d, c, b);
}

void add_box(TriangleMesh &mesh, Vec3f lo, Vec3f hi) {
    LTM_CHECK(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z);
    const Vec3f c = (lo + hi) * 0.5f;
    // Corners p(ijk) with i,j,k selecting lo/hi per axis.
    auto p = [&](int i, int j, int k) { return Vec3f(i ? hi.x : lo.x, j ? hi.y : lo.y, k ? hi.z : lo.z); };
    const Vec3f out[6] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
    const Vec3f faces[6][4] = {
        {p(0, 0, 0), p(0, 0, 1), p(0, 1, 1), p(0, 1, 0)}, {p(1, 0, 0), p(1, 1, 0), p(1, 1, 1), p(1, 0, 1)},
        {p(0, 0, 0), p(1, 0, 0), p(1, 0, 1), p(0, 0, 1)}, {p(0, 1, 0), p(0, 1, 1), p(1, 1, 1), p(1, 1, 0)},
        {p(0, 0, 0), p(0, 1, 0), p(1, 1, 0), p(1, 0, 0)}, {p(0, 0, 1), p(1, 0, 1), p(1, 1, 1), p(0, 1, 1)}};
    for (int f = 0; f < 6; ++f) {
        const Vec3f toward = c + out[f] * (2.f * length(hi - lo));
        add_quad_facing(mesh, faces[f][0], faces[f][1], faces[f][2], faces[f][3], toward);
    }
}

void add_cylinder(TriangleMesh &mesh, Vec3f base, float radius, float height, int segments, bool caps) {
    LTM_CHECK(radius > 0.f && height > 0.f && segments >= 3);
    const float circumference = 2.f * k_pi * radius;
    auto ring = [&](int i, float y) {
        const double a = 2.0 * 3.14159265358979323846 * double(i % segments) / double(segments);
        return Vec3f(base.x + radius * float(std::cos(a)), base.y + y, base.z + radius * float(std::sin(a)));
    };
    const Vec3f top_c = base + Vec3f(0.f, height, 0.f);
    for (int i = 0; i < segments; ++i) {
        // Side quad, outward: (i,0) → (i,h) → (i+1,h) → (i+1,0) winds outward for ccw angles.
        const uint32_t b = uint32_t(mesh.positions.size());
        const float u0 = circumference * float(i) / float(segments);
        const float u1 = circumference * float(i + 1) / float(segments);
        mesh.positions.insert(mesh.positions.end(), {ring(i, 0), ring(i, height), ring(i + 1, height), ring(i + 1, 0)});
        mesh.uvs.insert(mesh.uvs.end(), {{u0, 0.f}, {u0, height}, {u1, height}, {u1, 0.f}});
        for (uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) mesh.indices.push_back(b + k);
    }
    for (int cap = 0; caps && cap < 2; ++cap) {   // fans, bottom facing -y, top facing +y
        const float y = cap ? height : 0.f;
        const uint32_t center = uint32_t(mesh.positions.size());
        const Vec3f cc = cap ? top_c : base;
        mesh.positions.push_back(cc);
        mesh.uvs.push_back({0.f, 0.f});
        for (int i = 0; i < segments; ++i) {
            const Vec3f r = ring(i, y);
            mesh.positions.push_back(r);
            mesh.uvs.push_back({r.x - cc.x, r.z - cc.z});
        }
        for (int i = 0; i < segments; ++i) {
            const uint32_t a = center + 1 + uint32_t(i), b = center + 1 + uint32_t((i + 1) % segments);
            // (a - c) × (b - c) points -y for increasing angle; top cap flips.
            if (cap) mesh.indices.insert(mesh.indices.end(), {center, b, a});
            else mesh.indices.insert(mesh.indices.end(), {center, a, b});
        }
    }
}

void transform_mesh(TriangleMesh &mesh, const Transform &xf, size_t first_vertex) {
    for (size_t i = first_vertex; i < mesh.positions.size(); ++i)
        mesh.positions[i] = xf.apply_point(mesh.positions[i]);
    if (xf.determinant() < 0.f) {
        for (size_t t = 0; t < mesh.n_triangles(); ++t)
            if (mesh.indices[3 * t] >= first_vertex) std::swap(mesh.indices[3 * t + 1], mesh.indices[3 * t + 2]);
    }
}

bool is_degenerate_triangle(Vec3f p0, Vec3f p1, Vec3f p2) {
    if (!is_finite(p0) || !is_finite(p1) || !is_finite(p2)) return true;
    // In double, so the rule adds no rounding of its own: the edges are exact differences of floats.
    const double e[3][3] = {{double(p1.x) - p0.x, double(p1.y) - p0.y, double(p1.z) - p0.z},
                            {double(p2.x) - p0.x, double(p2.y) - p0.y, double(p2.z) - p0.z},
                            {double(p2.x) - p1.x, double(p2.y) - p1.y, double(p2.z) - p1.z}};
    const double cx = e[0][1] * e[1][2] - e[0][2] * e[1][1], cy = e[0][2] * e[1][0] - e[0][0] * e[1][2],
                 cz = e[0][0] * e[1][1] - e[0][1] * e[1][0];
    double longest2 = 0;
    for (const auto &v : e) longest2 = std::max(longest2, v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    const double twice_area = std::sqrt(cx * cx + cy * cy + cz * cz);
    // The float area as the renderer computes it must be positive too (it divides by it).
    const float area = 0.5f * length(cross(p1 - p0, p2 - p0));
    return !(twice_area > 1e-6 * longest2) || !(area > 0.f) || !std::isfinite(area);
}

size_t drop_degenerate_triangles(TriangleMesh &mesh) {
    std::vector<uint32_t> kept;
    for (size_t t = 0; t < mesh.n_triangles(); ++t)
        if (!is_degenerate_triangle(mesh, t)) kept.insert(kept.end(), mesh.indices.begin() + long(3 * t), mesh.indices.begin() + long(3 * t + 3));
    const size_t dropped = mesh.n_triangles() - kept.size() / 3;
    mesh.indices = std::move(kept);
    return dropped;
}

std::string drop_degenerate_triangles(Scene &scene) {
    const size_t total = scene.n_triangles();
    size_t dropped = 0;
    for (auto &mesh : scene.meshes) dropped += drop_degenerate_triangles(mesh);
    scene.meshes.erase(std::remove_if(scene.meshes.begin(), scene.meshes.end(), [](const TriangleMesh &m) { return m.n_triangles() == 0; }),
                       scene.meshes.end());
    if (dropped == 0) return "";
    return std::to_string(dropped) + " of " + std::to_string(total) + " triangles dropped as degenerate (slivers or specks: no visible surface)";
}

}  // namespace ltm
