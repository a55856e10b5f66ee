// gi_bake.cpp: mesh refinement, per-vertex composition and the .glb writer of render/gi_bake.h.
#include "ltm/render/gi_bake.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <tuple>

#include <tiny_gltf.h>

#include "ltm/core/error.h"
#include "ltm/core/color.h"
#include "ltm/core/tonemap.h"
#include "ltm/core/parallel.h"
#include "ltm/render/embree_accel.h"
#include "ltm/render/reachable_air.h"
#include "ltm/scene/material.h"

namespace ltm {

namespace {

/// A point on a side of a surface, as a map key: its position on a grid of `quantum` (rounding
/// apart: two triangles compute a point of their shared edge differently) and its normal's bits.
using SideKey = std::tuple<int64_t, int64_t, int64_t, uint32_t, uint32_t, uint32_t>;
SideKey side_key(Vec3f p, Vec3f n, double quantum) {
    auto bits = [](float f) { uint32_t u; std::memcpy(&u, &f, 4); return u; };
    auto grid = [quantum](float x) { return int64_t(std::llround(double(x) / quantum)); };
    return {grid(p.x), grid(p.y), grid(p.z), bits(n.x), bits(n.y), bits(n.z)};
}

/// Vertices of one mesh shared by position (on a grid of `quantum`, a millionth of the scene's
/// extent: two triangles compute a lattice point of their shared edge with different rounding) and
/// normal (a box corner keeps one vertex per face). One vertex, one estimate: no seams of noise.
struct VertexTable {
    BakedMesh *mesh;
    double quantum;
    std::map<SideKey, uint32_t> index;
    uint32_t get(Vec3f p, Vec3f n, Vec3f albedo, Vec3f emission) {
        const SideKey key = side_key(p, n, quantum);
        const auto it = index.find(key);
        if (it != index.end()) return it->second;
        const uint32_t i = uint32_t(mesh->position.size());
        mesh->position.push_back(p), mesh->normal.push_back(n), mesh->albedo.push_back(albedo), mesh->emission.push_back(emission);
        index.emplace(key, i);
        return i;
    }
};

/// Lattice divisions of a triangle: its longest edge over max_edge, rounded up.
int lattice_count(Vec3f p0, Vec3f p1, Vec3f p2, float max_edge) {
    const float longest = std::max({length(p1 - p0), length(p2 - p1), length(p0 - p2)});
    return std::max(1, int(std::ceil(longest / max_edge)));
}

}  // namespace

std::vector<BakedMesh> refine_for_bake(const Scene &scene, const RefineOptions &opt) {
    if (scene.meshes.empty()) LTM_THROW("scene '", scene.name, "' has no meshes to bake");
    const Bounds3f b = scene.bounds();
    const Vec3f ext = b.hi - b.lo;
    const float max_edge = opt.max_edge > 0.f ? opt.max_edge : std::max({ext.x, ext.y, ext.z}) / 64.f;
    if (!(max_edge > 0.f)) LTM_THROW("scene '", scene.name, "' has no extent to bake");
    // Which sides of each triangle light reaches (render/reachable_air.h), then the budget, counted
    // before the vertices are built: n² triangles and (n+1)(n+2)/2 lattice points per side.
    const ReachableAir air(scene);
    std::vector<std::vector<std::array<bool, 2>>> sides(scene.meshes.size());
    int64_t estimate = 0;
    for (size_t mi = 0; mi < scene.meshes.size(); ++mi) {
        const TriangleMesh &m = scene.meshes[mi];
        sides[mi].resize(m.n_triangles());
        for (size_t t = 0; t < m.n_triangles(); ++t) {
            const Vec3f cn = m.cross_normal(t);
            if (!(length(cn) > 0.f)) continue;
            const Vec3f n = normalize(cn), c = m.position_at(t, 1.f / 3.f, 1.f / 3.f, 1.f / 3.f);
            std::array<bool, 2> &s = sides[mi][t];
            s = {air.reaches(c, n), air.reaches(c, -n)};
            if (!s[0] && !s[1]) s[0] = true;   // enclosed both ways (no verdict): the winding's side
            const int64_t k = lattice_count(m.vertex(t, 0), m.vertex(t, 1), m.vertex(t, 2), max_edge);
            estimate += (s[0] + s[1]) * (k + 1) * (k + 2) / 2;
        }
    }
    if (estimate > opt.max_vertices)
        LTM_THROW("scene '", scene.name, "': refining to edges of ", max_edge, " would make about ", estimate,
                  " vertices, over the budget of ", opt.max_vertices, " (raise --max-edge or --max-vertices)");
    std::vector<BakedMesh> out(scene.meshes.size());
    for (size_t mi = 0; mi < scene.meshes.size(); ++mi) {
        const TriangleMesh &m = scene.meshes[mi];
        const Material &mat = scene.materials[size_t(m.material)];
        BakedMesh &bm = out[mi];
        bm.name = m.name;
        bm.material = m.material;
        VertexTable table{&bm, 1e-6 * double(std::max({ext.x, ext.y, ext.z})), {}};
        for (size_t t = 0; t < m.n_triangles(); ++t) {
            const Vec3f cn = m.cross_normal(t);
            if (!(length(cn) > 0.f)) continue;
            const Vec3f n0 = normalize(cn);
            const Vec3f p0 = m.vertex(t, 0), p1 = m.vertex(t, 1), p2 = m.vertex(t, 2);
            const int k = lattice_count(p0, p1, p2, max_edge);
            for (const bool back : {false, true}) {
                // Each side that light reaches gets its own copy (a curtain, a shade, the open
                // Cornell box's walls); a side facing a closed solid's inside gets none.
                if (!sides[mi][t][back ? 1 : 0]) continue;
                const Vec3f n = back ? -n0 : n0;
                // Lattice point (i, j): barycentrics (1 − (i+j)/k, i/k, j/k).
                std::vector<uint32_t> lattice;
                lattice.reserve(size_t((k + 1) * (k + 2) / 2));
                auto at = [&](int i, int j) { return lattice[size_t(i * (2 * k + 3 - i) / 2 + j)]; };
                for (int i = 0; i <= k; ++i)
                    for (int j = 0; j <= k - i; ++j) {
                        const float b1 = float(i) / float(k), b2 = float(j) / float(k), b0 = 1.f - b1 - b2;
                        const Vec2f uv = m.uv_at(t, b0, b1, b2);
                        // Exact corners where the lattice meets the original vertices.
                        const Vec3f p = i == 0 && j == 0 ? p0 : i == k ? p1 : j == k ? p2 : m.position_at(t, b0, b1, b2);
                        // Emitters are one-sided: the back of one does not emit.
                        lattice.push_back(table.get(p, n, mat.albedo.eval(uv), back ? Vec3f(0.f) : mat.emission.eval(uv)));
                    }
                auto tri = [&](uint32_t a, uint32_t c, uint32_t d) {
                    if (back) std::swap(c, d);
                    bm.indices.insert(bm.indices.end(), {a, c, d});
                };
                for (int i = 0; i < k; ++i)
                    for (int j = 0; j < k - i; ++j) {
                        tri(at(i, j), at(i + 1, j), at(i, j + 1));
                        if (j + 1 < k - i) tri(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                    }
            }
        }
    }
    return out;
}

GBuffer vertex_points(const std::vector<BakedMesh> &meshes) {
    GBuffer gb;
    for (const BakedMesh &m : meshes)
        for (size_t v = 0; v < m.position.size(); ++v) {
            gb.hit_pixels.push_back(int64_t(gb.hit_pixels.size()));
            gb.position.push_back(m.position[v]);
            gb.normal.push_back(m.normal[v]);
            gb.albedo.push_back(m.albedo[v]);
            gb.emitted.push_back(m.emission[v]);
            gb.depth.push_back(0.f);
            gb.diffuse.push_back(1);
        }
    gb.width = int(gb.hit_pixels.size());
    gb.height = 1;
    return gb;
}

void compose_bake(std::vector<BakedMesh> &meshes, const std::vector<Vec3f> &direct, const std::vector<Vec3f> &indirect) {
    size_t total = 0;
    for (const BakedMesh &m : meshes) total += m.position.size();
    if (direct.size() != total || indirect.size() != total)
        LTM_THROW("compose_bake: ", total, " vertices, ", direct.size(), " direct and ", indirect.size(), " indirect values");
    size_t k = 0;
    for (BakedMesh &m : meshes) {
        const size_t n = m.position.size();
        m.radiance.resize(n), m.irradiance_direct.resize(n), m.irradiance_indirect.resize(n);
        for (size_t v = 0; v < n; ++v, ++k) {
            m.irradiance_direct[v] = direct[k];
            m.irradiance_indirect[v] = indirect[k];
            m.radiance[v] = m.emission[v] + m.albedo[v] * (k_inv_pi) * (direct[k] + indirect[k]);
        }
    }
}

Vec3f bake_display(Vec3f lo, float exposure) {
    Vec3f t;
    for (int i = 0; i < 3; ++i) {
        const float x = std::max(0.f, lo[i] * exposure);
        t[i] = x / (1.f + x);
    }
    return t;
}

BakeView view_bake(const std::vector<BakedMesh> &meshes, const Camera &camera) {
    Scene s;
    s.name = "bake";
    Material plain;
    plain.name = "bake";
    s.add_material(plain);
    for (const BakedMesh &m : meshes) {
        TriangleMesh t;
        t.name = m.name;
        t.positions = m.position;
        t.indices = m.indices;
        t.material = 0;
        s.meshes.push_back(std::move(t));
    }
    const EmbreeAccel accel(s);
    // A side seen from behind shows its twin (the other side's copy of the same triangle) or
    // nothing, as a rasteriser culling back faces does: twins found by centroid and normal.
    const Bounds3f bb = s.bounds();
    const double quantum = 1e-6 * double(max_component(bb.hi - bb.lo)) + 1e-30;
    auto key = [quantum](Vec3f c, Vec3f n) { return side_key(c, n, quantum); };
    auto centroid = [&](const BakedMesh &m, size_t t) {
        return (m.position[m.indices[3 * t]] + m.position[m.indices[3 * t + 1]] + m.position[m.indices[3 * t + 2]]) * (1.f / 3.f);
    };
    std::map<SideKey, std::pair<uint32_t, uint32_t>> by_side;
    for (size_t mi = 0; mi < meshes.size(); ++mi)
        for (size_t t = 0; t < meshes[mi].indices.size() / 3; ++t)
            by_side.emplace(key(centroid(meshes[mi], t), meshes[mi].normal[meshes[mi].indices[3 * t]]), std::make_pair(uint32_t(mi), uint32_t(t)));
    BakeView v{Image(camera.width, camera.height), Image(camera.width, camera.height), std::vector<uint8_t>(size_t(camera.width) * size_t(camera.height), 0)};
    parallel_for(0, int64_t(camera.height), 1, [&](int64_t y0, int64_t y1) {
        for (int64_t y = y0; y < y1; ++y)
            for (int x = 0; x < camera.width; ++x) {
                const Ray ray{camera.eye, camera.ray_direction(float(x) + 0.5f, float(y) + 0.5f)};
                const std::optional<Hit> h = accel.intersect(ray);
                if (!h) continue;
                uint32_t mi = h->mesh, t = h->triangle;
                const Vec3f p = ray.o + ray.d * h->t;
                if (dot(meshes[mi].normal[meshes[mi].indices[3 * size_t(t)]], ray.d) > 0.f) {
                    const auto it = by_side.find(key(centroid(meshes[mi], t), -meshes[mi].normal[meshes[mi].indices[3 * size_t(t)]]));
                    if (it == by_side.end()) continue;
                    mi = it->second.first, t = it->second.second;
                }
                const BakedMesh &m = meshes[mi];
                const uint32_t *tri = &m.indices[3 * size_t(t)];
                // Barycentrics of p in the triangle shown (the twin's vertices are in another order).
                const Vec3f a = m.position[tri[0]], e1 = m.position[tri[1]] - a, e2 = m.position[tri[2]] - a, q = p - a;
                const float d11 = dot(e1, e1), d12 = dot(e1, e2), d22 = dot(e2, e2), q1 = dot(q, e1), q2 = dot(q, e2);
                const float det = d11 * d22 - d12 * d12;
                if (!(det > 0.f)) continue;
                const float b1 = (d22 * q1 - d12 * q2) / det, b2 = (d11 * q2 - d12 * q1) / det, b0 = 1.f - b1 - b2;
                auto lerp = [&](const std::vector<Vec3f> &val) { return val[tri[0]] * b0 + val[tri[1]] * b1 + val[tri[2]] * b2; };
                v.radiance.at(x, int(y)) = lerp(m.radiance);
                v.irradiance_indirect.at(x, int(y)) = lerp(m.irradiance_indirect);
                v.hit[size_t(y) * size_t(camera.width) + size_t(x)] = 1;
            }
    });
    return v;
}

namespace {

/// Appends raw bytes to the buffer (4-byte aligned) and returns a buffer view of them.
int add_view(tinygltf::Model &g, const void *data, size_t bytes, int target) {
    std::vector<unsigned char> &buf = g.buffers[0].data;
    while (buf.size() % 4) buf.push_back(0);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = buf.size();
    view.byteLength = bytes;
    view.target = target;
    const auto *p = static_cast<const unsigned char *>(data);
    buf.insert(buf.end(), p, p + bytes);
    g.bufferViews.push_back(view);
    return int(g.bufferViews.size()) - 1;
}

int add_vec3(tinygltf::Model &g, const std::vector<Vec3f> &v, bool bounds) {
    tinygltf::Accessor a;
    a.bufferView = add_view(g, v.data(), v.size() * sizeof(Vec3f), TINYGLTF_TARGET_ARRAY_BUFFER);
    a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    a.type = TINYGLTF_TYPE_VEC3;
    a.count = v.size();
    if (bounds) {   // POSITION must carry min and max (glTF 2.0 §3.6.2)
        Vec3f lo(1e30f), hi(-1e30f);
        for (const Vec3f &p : v) lo = min(lo, p), hi = max(hi, p);
        a.minValues = {lo.x, lo.y, lo.z};
        a.maxValues = {hi.x, hi.y, hi.z};
    }
    g.accessors.push_back(a);
    return int(g.accessors.size()) - 1;
}

Vec3f tone_map(Vec3f lo, float exposure) {
    const Vec3f t = bake_display(lo, exposure);
    return {linear_to_srgb(t.x), linear_to_srgb(t.y), linear_to_srgb(t.z)};
}

}  // namespace

void write_bake_glb(const std::string &path, const Scene &scene, const std::vector<BakedMesh> &meshes, float exposure,
                    const std::string &generator) {
    tinygltf::Model g;
    g.asset.version = "2.0";
    g.asset.generator = generator;
    g.buffers.resize(1);
    g.extensionsUsed.push_back("KHR_materials_unlit");
    tinygltf::Scene gs;
    bool used_strength = false;
    for (const BakedMesh &m : meshes) {
        if (m.indices.empty()) continue;
        if (m.radiance.size() != m.position.size()) LTM_THROW("write_bake_glb: mesh '", m.name, "' is not baked");
        const Material &mat = scene.materials[size_t(m.material)];
        tinygltf::Material gm;
        gm.name = m.name;
        gm.doubleSided = false;   // each lit side is its own triangle (refine_for_bake)
        const Vec3f le = mat.emission.color_a;
        if (mat.is_emissive() && max_component(le) > 0.f) {   // emitters stay emitters for a renderer that reads glTF lights
            const float peak = max_component(le);
            gm.emissiveFactor = {le.x / peak, le.y / peak, le.z / peak};
            tinygltf::Value::Object strength;
            strength["emissiveStrength"] = tinygltf::Value(double(peak));
            gm.extensions["KHR_materials_emissive_strength"] = tinygltf::Value(strength);
            used_strength = true;
        }
        Vec3f mean(0.f);
        for (const Vec3f &a : m.albedo) mean = mean + a;
        mean = mean * (1.f / float(std::max<size_t>(1, m.albedo.size())));
        gm.pbrMetallicRoughness.baseColorFactor = {mean.x, mean.y, mean.z, 1.0};
        gm.extensions["KHR_materials_unlit"] = tinygltf::Value(tinygltf::Value::Object());
        if (mat.bsdf == BsdfKind::conductor) {
            gm.pbrMetallicRoughness.metallicFactor = 1.0;
            gm.pbrMetallicRoughness.roughnessFactor = std::sqrt(double(mat.roughness));   // glTF's roughness: α = r²
            gm.pbrMetallicRoughness.baseColorFactor = {mat.specular.x, mat.specular.y, mat.specular.z, 1.0};
            tinygltf::Value::Object extras;
            extras["ltm_conductor"] = tinygltf::Value(true);
            gm.extras = tinygltf::Value(extras);
        }
        g.materials.push_back(gm);
        std::vector<Vec3f> colour(m.radiance.size());
        for (size_t v = 0; v < colour.size(); ++v) colour[v] = tone_map(m.radiance[v], exposure);
        tinygltf::Primitive prim;
        prim.mode = TINYGLTF_MODE_TRIANGLES;
        prim.material = int(g.materials.size()) - 1;
        prim.attributes["POSITION"] = add_vec3(g, m.position, true);
        prim.attributes["NORMAL"] = add_vec3(g, m.normal, false);
        prim.attributes["COLOR_0"] = add_vec3(g, colour, false);
        prim.attributes["_RADIANCE"] = add_vec3(g, m.radiance, false);
        prim.attributes["_IRRADIANCE_INDIRECT"] = add_vec3(g, m.irradiance_indirect, false);
        tinygltf::Accessor idx;
        idx.bufferView = add_view(g, m.indices.data(), m.indices.size() * sizeof(uint32_t), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
        idx.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
        idx.type = TINYGLTF_TYPE_SCALAR;
        idx.count = m.indices.size();
        g.accessors.push_back(idx);
        prim.indices = int(g.accessors.size()) - 1;
        tinygltf::Mesh gmesh;
        gmesh.name = m.name;
        gmesh.primitives.push_back(prim);
        g.meshes.push_back(gmesh);
        tinygltf::Node node;
        node.name = m.name;
        node.mesh = int(g.meshes.size()) - 1;
        g.nodes.push_back(node);
        gs.nodes.push_back(int(g.nodes.size()) - 1);
    }
    if (g.meshes.empty()) LTM_THROW(path, ": nothing to write (no baked triangles)");
    // The scene's cameras as glTF cameras (a viewer's bookmarks): a node at the eye whose −z looks
    // at the target, +y toward the camera's up.
    for (const Camera &c : scene.cameras) {
        tinygltf::Camera gc;
        gc.name = c.name;
        gc.type = "perspective";
        gc.perspective.yfov = double(c.fov_y_deg) * 3.14159265358979323846 / 180.0;
        gc.perspective.aspectRatio = double(c.width) / double(std::max(1, c.height));
        gc.perspective.znear = 0.01 * double(max_component(scene.bounds().hi - scene.bounds().lo)) + 1e-6;
        g.cameras.push_back(gc);
        const Vec3f f = normalize(c.target - c.eye), r = normalize(cross(f, c.up)), u = cross(r, f);
        // Rotation with columns (r, u, −f) as a unit quaternion (x, y, z, w).
        const float m00 = r.x, m11 = u.y, m22 = -f.z, trace = m00 + m11 + m22;
        double q[4];
        if (trace > 0.f) {
            const double sq = std::sqrt(double(trace) + 1.0) * 2.0;
            q[3] = 0.25 * sq, q[0] = double(u.z - -f.y) / sq, q[1] = double(-f.x - r.z) / sq, q[2] = double(r.y - u.x) / sq;
        } else if (m00 > m11 && m00 > m22) {
            const double sq = std::sqrt(1.0 + double(m00 - m11 - m22)) * 2.0;
            q[3] = double(u.z - -f.y) / sq, q[0] = 0.25 * sq, q[1] = double(u.x + r.y) / sq, q[2] = double(-f.x + r.z) / sq;
        } else if (m11 > m22) {
            const double sq = std::sqrt(1.0 + double(m11 - m00 - m22)) * 2.0;
            q[3] = double(-f.x - r.z) / sq, q[0] = double(u.x + r.y) / sq, q[1] = 0.25 * sq, q[2] = double(-f.y + u.z) / sq;
        } else {
            const double sq = std::sqrt(1.0 + double(m22 - m00 - m11)) * 2.0;
            q[3] = double(r.y - u.x) / sq, q[0] = double(-f.x + r.z) / sq, q[1] = double(-f.y + u.z) / sq, q[2] = 0.25 * sq;
        }
        tinygltf::Node node;
        node.name = c.name;
        node.camera = int(g.cameras.size()) - 1;
        node.translation = {c.eye.x, c.eye.y, c.eye.z};
        node.rotation = {q[0], q[1], q[2], q[3]};
        g.nodes.push_back(node);
        gs.nodes.push_back(int(g.nodes.size()) - 1);
    }
    if (used_strength) g.extensionsUsed.push_back("KHR_materials_emissive_strength");
    g.scenes.push_back(gs);
    g.defaultScene = 0;
    const std::string tmp = path + ".tmp";
    tinygltf::TinyGLTF writer;
    if (!writer.WriteGltfSceneToFile(&g, tmp, /*embedImages=*/false, /*embedBuffers=*/true, /*prettyPrint=*/false, /*writeBinary=*/true)) {
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        LTM_THROW(path, ": cannot write the glTF file");
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        LTM_THROW(path, ": cannot write: ", ec.message());
    }
}

}  // namespace ltm
