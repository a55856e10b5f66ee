// gltf_reader.cpp: tinygltf model → world-space triangle meshes, materials, camera.
#include "ltm/scene/gltf_reader.h"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>

#include <tiny_gltf.h>

#include "ltm/core/color.h"
#include "ltm/core/error.h"
#include "ltm/core/file_util.h"
#include "ltm/core/image.h"
#include "ltm/core/log.h"
#include "ltm/scene/mesh_builder.h"

namespace fs = std::filesystem;

namespace ltm {

namespace {

std::string one_line(std::string s) {
    for (char &c : s)
        if (c == '\n' || c == '\r') c = ' ';
    while (!s.empty() && s.back() == ' ') s.pop_back();
    return s;
}

// Reads accessor `a` as doubles: count × n_components, bounds-checked against its buffer.
std::vector<double> read_accessor(const tinygltf::Model &m, int index, const std::string &where) {
    if (index < 0 || index >= int(m.accessors.size())) LTM_THROW(where, ": accessor ", index, " does not exist");
    const tinygltf::Accessor &a = m.accessors[size_t(index)];
    const std::string at = detail::concat(where, ": accessor ", index);
    if (a.sparse.isSparse) LTM_THROW(at, ": sparse accessors are not supported");
    if (a.bufferView < 0 || a.bufferView >= int(m.bufferViews.size())) LTM_THROW(at, ": no buffer view");
    const tinygltf::BufferView &v = m.bufferViews[size_t(a.bufferView)];
    if (v.buffer < 0 || v.buffer >= int(m.buffers.size())) LTM_THROW(at, ": missing buffer ", v.buffer);
    const std::vector<unsigned char> &buf = m.buffers[size_t(v.buffer)].data;
    const int nc = tinygltf::GetNumComponentsInType(uint32_t(a.type));
    const int cs = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
    if (nc <= 0 || cs <= 0) LTM_THROW(at, ": unknown type or component type");
    const size_t stride = v.byteStride ? v.byteStride : size_t(nc * cs);
    const size_t base = v.byteOffset + a.byteOffset;
    if (a.count > 0 && (base + stride * (a.count - 1) + size_t(nc * cs) > buf.size() ||
                        a.byteOffset + stride * (a.count - 1) + size_t(nc * cs) > v.byteLength))
        LTM_THROW(at, ": reads past the end of its buffer");
    std::vector<double> out(a.count * size_t(nc));
    for (size_t i = 0; i < a.count; ++i)
        for (int c = 0; c < nc; ++c) {
            const unsigned char *p = buf.data() + base + i * stride + size_t(c * cs);
            double x = 0;
            switch (a.componentType) {
            case TINYGLTF_COMPONENT_TYPE_BYTE: { int8_t t; std::memcpy(&t, p, 1); x = a.normalized ? std::max(t / 127.0, -1.0) : t; break; }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: x = a.normalized ? *p / 255.0 : *p; break;
            case TINYGLTF_COMPONENT_TYPE_SHORT: { int16_t t; std::memcpy(&t, p, 2); x = a.normalized ? std::max(t / 32767.0, -1.0) : t; break; }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t t; std::memcpy(&t, p, 2); x = a.normalized ? t / 65535.0 : t; break; }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t t; std::memcpy(&t, p, 4); x = t; break; }
            case TINYGLTF_COMPONENT_TYPE_FLOAT: { float t; std::memcpy(&t, p, 4); x = t; break; }
            default: LTM_THROW(at, ": component type ", a.componentType, " not supported");
            }
            if (!std::isfinite(x)) LTM_THROW(at, ": element ", i, " is not finite");
            out[i * size_t(nc) + size_t(c)] = x;
        }
    return out;
}

// Column-major 4×4 (glTF) → affine Transform.
Transform node_transform(const tinygltf::Node &n) {
    Transform t;
    if (n.matrix.size() == 16) {
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) t.m[r][c] = float(n.matrix[size_t(c * 4 + r)]);
        return t;
    }
    Transform s, r, tr;
    if (n.scale.size() == 3) s = Transform::scale(Vec3f(float(n.scale[0]), float(n.scale[1]), float(n.scale[2])));
    if (n.rotation.size() == 4) {   // unit quaternion (x, y, z, w)
        const double x = n.rotation[0], y = n.rotation[1], z = n.rotation[2], w = n.rotation[3];
        const double q[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                                {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                                {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) r.m[i][j] = float(q[i][j]);
    }
    if (n.translation.size() == 3) tr = Transform::translate(Vec3f(float(n.translation[0]), float(n.translation[1]), float(n.translation[2])));
    return tr * r * s;
}

class GltfReader {
public:
    GltfReader(const tinygltf::Model &m, std::string where) : m_model(m), m_where(std::move(where)) {}

    Scene read() {
        std::vector<int> roots;
        if (!m_model.scenes.empty()) {
            const int si = m_model.defaultScene >= 0 && m_model.defaultScene < int(m_model.scenes.size()) ? m_model.defaultScene : 0;
            roots = m_model.scenes[size_t(si)].nodes;
        } else {
            for (size_t i = 0; i < m_model.nodes.size(); ++i) roots.push_back(int(i));
        }
        for (int r : roots) visit(r, Transform(), 0);
        if (const std::string dropped = drop_degenerate_triangles(m_scene); !dropped.empty()) warn(dropped);
        for (const auto &[msg, count] : m_warnings) log_warn(m_where, ": ", msg, count > 1 ? detail::concat(" (", count, "×)") : "");
        m_scene.metadata["gltf"] = {{"file", m_where}, {"unit", "m"}, {"up_axis", "+y"}};
        return std::move(m_scene);
    }

private:
    void visit(int index, const Transform &parent, int depth) {
        if (index < 0 || index >= int(m_model.nodes.size())) LTM_THROW(m_where, ": node ", index, " does not exist");
        if (depth > 64) LTM_THROW(m_where, ": node hierarchy deeper than 64 (a cycle?)");
        const tinygltf::Node &n = m_model.nodes[size_t(index)];
        const Transform xf = parent * node_transform(n);
        if (n.mesh >= 0) mesh(n.mesh, xf);
        if (n.camera >= 0 && m_scene.cameras.empty()) camera(n.camera, xf);
        for (int c : n.children) visit(c, xf, depth + 1);
    }

    void camera(int index, const Transform &xf) {
        if (index >= int(m_model.cameras.size())) LTM_THROW(m_where, ": camera ", index, " does not exist");
        const tinygltf::Camera &c = m_model.cameras[size_t(index)];
        if (c.type != "perspective") {
            warn("orthographic camera skipped");
            return;
        }
        Camera cam;
        cam.name = c.name.empty() ? "gltf" : c.name;
        cam.eye = xf.apply_point(Vec3f(0.f));
        cam.target = cam.eye + normalize(xf.apply_vector({0, 0, -1}));   // glTF cameras look down −z
        cam.up = normalize(xf.apply_vector({0, 1, 0}));
        if (!(c.perspective.yfov > 0 && c.perspective.yfov < M_PI)) LTM_THROW(m_where, ": camera ", index, " has yfov out of (0, π)");
        cam.fov_y_deg = float(c.perspective.yfov * 180.0 / M_PI);
        const double aspect = c.perspective.aspectRatio;
        if (aspect != 0.0 && !(aspect >= 1.0 / 64 && aspect <= 64)) LTM_THROW(m_where, ": camera ", index, " aspect ratio ", aspect, " out of [1/64, 64]");
        if (aspect > 0) cam.height = std::max(1, int(std::lround(double(cam.width) / aspect)));
        m_scene.cameras.push_back(cam);
    }

    Texture image_texture(int tex_index, const std::vector<double> &factor) {
        if (tex_index < 0 || tex_index >= int(m_model.textures.size())) LTM_THROW(m_where, ": texture ", tex_index, " does not exist");
        const int src = m_model.textures[size_t(tex_index)].source;
        if (src < 0 || src >= int(m_model.images.size())) LTM_THROW(m_where, ": texture ", tex_index, " has no image");
        const tinygltf::Image &im = m_model.images[size_t(src)];
        if (im.width <= 0 || im.height <= 0 || im.component < 3 || im.bits != 8 ||
            im.image.size() < size_t(im.width) * size_t(im.height) * size_t(im.component))
            LTM_THROW(m_where, ": image ", src, " is not an 8-bit RGB(A) image that was decoded");
        auto img = std::make_shared<Image>(im.width, im.height);
        // glTF's uv origin is the top-left; ltm's images have v = 0 at the bottom row: rows flipped.
        for (int y = 0; y < im.height; ++y)
            for (int x = 0; x < im.width; ++x) {
                const unsigned char *p = im.image.data() + (size_t(y) * size_t(im.width) + size_t(x)) * size_t(im.component);
                Vec3f c(srgb_to_linear(p[0] / 255.f), srgb_to_linear(p[1] / 255.f), srgb_to_linear(p[2] / 255.f));
                for (int k = 0; k < 3; ++k) c[k] *= float(factor[size_t(k)]);
                img->at(x, im.height - 1 - y) = c;
            }
        Texture t;
        t.kind = TextureKind::image;
        t.image_path = im.uri.empty() || im.uri.rfind("data:", 0) == 0
                           ? detail::concat(m_where, "#image", src)
                           : (fs::path(m_where).parent_path() / im.uri).string();
        t.image = img;
        return t;
    }

    int material(int index) {
        const auto it = m_materials.find(index);
        if (it != m_materials.end()) return it->second;
        Material mat;
        if (index < 0) {
            mat.name = "gltf_default";
            mat.albedo = Texture::constant(Vec3f(1.f));   // glTF's default material: white, rough
        } else {
            if (index >= int(m_model.materials.size())) LTM_THROW(m_where, ": material ", index, " does not exist");
            const tinygltf::Material &g = m_model.materials[size_t(index)];
            mat.name = g.name.empty() ? detail::concat("gltf_material_", index) : g.name;
            const auto &pbr = g.pbrMetallicRoughness;
            std::vector<double> base = pbr.baseColorFactor.size() >= 3 ? pbr.baseColorFactor : std::vector<double>{1, 1, 1, 1};
            const Vec3f base_rgb{float(base[0]), float(base[1]), float(base[2])};
            Texture color = pbr.baseColorTexture.index >= 0 ? image_texture(pbr.baseColorTexture.index, base) : Texture::constant(base_rgb);
            if (pbr.metallicFactor >= 1.0) {
                mat.bsdf = BsdfKind::conductor;
                mat.specular = min(base_rgb, Vec3f(1.f));
                mat.roughness = float(std::clamp(pbr.roughnessFactor * pbr.roughnessFactor, 0.001, 1.0));
                if (pbr.baseColorTexture.index >= 0) warn("metallic base colour texture replaced by its factor (F0)");
            } else {
                mat.albedo = color;
                if (pbr.metallicFactor > 0.0) warn("partly metallic material read as diffuse");
            }
            if (pbr.metallicRoughnessTexture.index >= 0) warn("metallicRoughnessTexture ignored");
            double strength = 1.0;
            const auto ext = g.extensions.find("KHR_materials_emissive_strength");
            if (ext != g.extensions.end() && ext->second.Has("emissiveStrength"))
                strength = ext->second.Get("emissiveStrength").GetNumberAsDouble();
            if (g.emissiveFactor.size() == 3) {
                const Vec3f e{float(g.emissiveFactor[0] * strength), float(g.emissiveFactor[1] * strength), float(g.emissiveFactor[2] * strength)};
                if (!is_finite(e) || e.x < 0 || e.y < 0 || e.z < 0) LTM_THROW(m_where, ": material ", index, " has a bad emissive factor");
                if (max_component(e) > 0.f) mat.emission = Texture::constant(e);
            }
            if (g.emissiveTexture.index >= 0) warn("emissiveTexture ignored (emissive factor used)");
            if (g.doubleSided && max_component(mat.emission.color_a) > 0.f) warn("double-sided emissive material emits on its front side only");
        }
        while (m_scene.find_material(mat.name) >= 0) mat.name += "_";
        const int idx = m_scene.add_material(mat);
        m_materials[index] = idx;
        return idx;
    }

    void mesh(int index, const Transform &xf) {
        if (index >= int(m_model.meshes.size())) LTM_THROW(m_where, ": mesh ", index, " does not exist");
        const tinygltf::Mesh &gm = m_model.meshes[size_t(index)];
        for (size_t pi = 0; pi < gm.primitives.size(); ++pi) {
            const tinygltf::Primitive &p = gm.primitives[pi];
            const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
            if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
                warn("point and line primitives skipped");
                continue;
            }
            if (!p.targets.empty()) LTM_THROW(m_where, ": mesh ", index, " primitive ", pi, ": morph targets are not supported");
            const auto pos_it = p.attributes.find("POSITION");
            if (pos_it == p.attributes.end()) LTM_THROW(m_where, ": mesh ", index, " primitive ", pi, " has no POSITION");
            const auto pos = read_accessor(m_model, pos_it->second, m_where);
            if (m_model.accessors[size_t(pos_it->second)].type != TINYGLTF_TYPE_VEC3)
                LTM_THROW(m_where, ": mesh ", index, " primitive ", pi, ": POSITION is not VEC3");
            TriangleMesh tm;
            tm.name = detail::concat(gm.name.empty() ? "gltf_mesh" : gm.name, "_", index, "_", pi);
            for (size_t i = 0; i + 2 < pos.size(); i += 3) tm.positions.push_back(Vec3f(float(pos[i]), float(pos[i + 1]), float(pos[i + 2])));
            if (const auto uv_it = p.attributes.find("TEXCOORD_0"); uv_it != p.attributes.end()) {
                const auto uv = read_accessor(m_model, uv_it->second, m_where);
                if (uv.size() == 2 * tm.positions.size())
                    for (size_t i = 0; i < uv.size(); i += 2) tm.uvs.push_back(Vec2f{float(uv[i]), float(1.0 - uv[i + 1])});
            }
            std::vector<uint32_t> idx;
            if (p.indices >= 0) {
                for (double v : read_accessor(m_model, p.indices, m_where)) {
                    if (!(v >= 0 && v < double(tm.positions.size())))
                        LTM_THROW(m_where, ": mesh ", index, " primitive ", pi, ": index ", v, " out of range (", tm.positions.size(), " vertices)");
                    idx.push_back(uint32_t(v));
                }
            } else {
                for (size_t i = 0; i < tm.positions.size(); ++i) idx.push_back(uint32_t(i));
            }
            if (mode == TINYGLTF_MODE_TRIANGLES) {
                idx.resize(idx.size() / 3 * 3);
                tm.indices = idx;
            } else {
                for (size_t i = 2; i < idx.size(); ++i) {
                    if (mode == TINYGLTF_MODE_TRIANGLE_FAN) tm.indices.insert(tm.indices.end(), {idx[0], idx[i - 1], idx[i]});
                    else if (i % 2 == 0) tm.indices.insert(tm.indices.end(), {idx[i - 2], idx[i - 1], idx[i]});
                    else tm.indices.insert(tm.indices.end(), {idx[i - 1], idx[i - 2], idx[i]});
                }
            }
            if (tm.indices.empty()) continue;
            transform_mesh(tm, xf);   // flips the winding under a mirroring transform, as glTF specifies
            tm.material = material(p.material);
            m_scene.meshes.push_back(std::move(tm));
        }
    }

    void warn(const std::string &msg) { ++m_warnings[msg]; }

    const tinygltf::Model &m_model;
    std::string m_where;
    Scene m_scene;
    std::map<int, int> m_materials;
    std::map<std::string, int64_t> m_warnings;
};

}  // namespace

Scene parse_gltf(const std::string &bytes, const std::string &where, bool binary) {
    tinygltf::TinyGLTF loader;
    // No file system: external buffers and images fail to load (an error, never a read).
    tinygltf::FsCallbacks fs_none;
    fs_none.FileExists = [](const std::string &, void *) { return false; };
    fs_none.ExpandFilePath = [](const std::string &p, void *) { return p; };
    fs_none.ReadWholeFile = [](std::vector<unsigned char> *, std::string *err, const std::string &, void *) {
        if (err) *err = "file access disabled";
        return false;
    };
    fs_none.WriteWholeFile = [](std::string *, const std::string &, const std::vector<unsigned char> &, void *) { return false; };
    fs_none.user_data = nullptr;
    loader.SetFsCallbacks(fs_none);
    tinygltf::Model model;
    std::string err, warn;
    const auto *data = reinterpret_cast<const unsigned char *>(bytes.data());
    const bool ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, data, unsigned(bytes.size()), "")
                           : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(), unsigned(bytes.size()), "");
    if (!ok) LTM_THROW(where, ": ", err.empty() ? "not a valid glTF 2.0 file" : one_line(err));
    return GltfReader(model, where).read();
}

Scene load_gltf(const std::string &path) {
    if (!fs::is_regular_file(path)) LTM_THROW(path, ": file not found");
    tinygltf::TinyGLTF loader;
    tinygltf::Model model;
    std::string err, warn;
    const bool binary = file_extension(path) == "glb";
    const bool ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, path) : loader.LoadASCIIFromFile(&model, &err, &warn, path);
    if (!ok) LTM_THROW(path, ": ", err.empty() ? "not a valid glTF 2.0 file" : one_line(err));
    if (!warn.empty()) log_warn(path, ": ", one_line(warn));
    Scene s = GltfReader(model, path).read();
    s.name = fs::path(path).stem().string();
    return s;
}

}  // namespace ltm
