// obj_io.cpp: Wavefront OBJ + MTL through tinyobjloader. One TriangleMesh per (shape, material).
#include "ltm/scene/obj_io.h"

#include <filesystem>
#include <map>

#include <tiny_obj_loader.h>

#include "ltm/core/color.h"
#include "ltm/core/error.h"
#include "ltm/core/log.h"
#include "ltm/scene/mesh_builder.h"

namespace fs = std::filesystem;

namespace ltm {

namespace {
Texture obj_texture(const float value[3], const std::string &map, const std::string &dir,
                    const std::string &where) {
    if (map.empty()) return Texture::constant({value[0], value[1], value[2]});
    Texture t;
    t.kind = TextureKind::image;
    t.image_path = (fs::path(dir) / map).string();
    try {
        t.image = std::make_shared<const Image>(read_image(t.image_path));
    } catch (const Error &e) {
        LTM_THROW(where, ": ", e.what());
    }
    return t;
}
}  // namespace

namespace {
Scene obj_to_scene(const tinyobj::ObjReader &reader, const std::string &path, bool allow_files);
}  // namespace

Scene load_obj(const std::string &path) {
    if (!fs::is_regular_file(path)) LTM_THROW(path, ": file not found");
    tinyobj::ObjReaderConfig cfg;
    cfg.triangulate = true;
    cfg.vertex_color = false;
    cfg.mtl_search_path = fs::path(path).parent_path().string();
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(path, cfg)) {
        std::string err = reader.Error();
        while (!err.empty() && (err.back() == '\n' || err.back() == '\r')) err.pop_back();
        LTM_THROW(path, ": cannot parse OBJ: ", err.empty() ? "unknown error" : err);
    }
    // tinyobjloader reports some malformed lines (bad face indices, missing MTL) only as warnings.
    const std::string warn = reader.Warning();
    if (warn.find("Material file") != std::string::npos || warn.find("not found") != std::string::npos)
        LTM_THROW(path, ": ", warn.substr(0, warn.find('\n')));
    return obj_to_scene(reader, path, true);
}

Scene parse_obj(const std::string &obj_text, const std::string &mtl_text, const std::string &where) {
    tinyobj::ObjReaderConfig cfg;
    cfg.triangulate = true;
    cfg.vertex_color = false;
    tinyobj::ObjReader reader;
    if (!reader.ParseFromString(obj_text, mtl_text, cfg)) {
        std::string err = reader.Error();
        for (char &c : err)
            if (c == '\n' || c == '\r') c = ' ';
        LTM_THROW(where, ": cannot parse OBJ: ", err.empty() ? "unknown error" : err);
    }
    return obj_to_scene(reader, where, false);
}

namespace {
Scene obj_to_scene(const tinyobj::ObjReader &reader, const std::string &path, bool allow_files) {
    const auto &attrib = reader.GetAttrib();
    const auto &shapes = reader.GetShapes();
    const auto &materials = reader.GetMaterials();
    const std::string dir = fs::path(path).parent_path().string();

    Scene s;
    s.name = fs::path(path).stem().string();
    for (size_t i = 0; i < materials.size(); ++i) {
        const auto &mt = materials[i];
        Material m;
        m.name = mt.name.empty() ? "material" + std::to_string(i) : mt.name;
        const std::string where = path + ": material '" + m.name + "'";
        if (!allow_files && (!mt.diffuse_texname.empty() || !mt.emissive_texname.empty()))
            LTM_THROW(where, ": texture maps need a file-based OBJ (load_obj)");
        m.albedo = obj_texture(mt.diffuse, mt.diffuse_texname, dir, where);
        m.emission = obj_texture(mt.emission, mt.emissive_texname, dir, where);
        const Vec3f amax = m.albedo.max_value();
        if (max_component(amax) > 1.f) LTM_THROW(where, ": Kd above 1 (", amax, ")");
        if (s.find_material(m.name) >= 0) m.name += "#" + std::to_string(i);
        s.materials.push_back(std::move(m));
    }
    const int default_material = int(s.materials.size());
    bool used_default = false;

    const size_t n_vertices = attrib.vertices.size() / 3;
    for (const auto &shape : shapes) {
        // Split by material; keep vertices per (position, uv) pair.
        std::map<int, TriangleMesh> by_material;
        std::map<int, std::map<std::pair<int, int>, uint32_t>> remap;
        const auto &idx = shape.mesh.indices;
        for (size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
            int mat = shape.mesh.material_ids[f];
            if (mat < 0 || size_t(mat) >= materials.size()) mat = default_material, used_default = true;
            TriangleMesh &m = by_material[mat];
            for (int k = 0; k < 3; ++k) {
                const auto &vi = idx[3 * f + size_t(k)];
                if (vi.vertex_index < 0 || size_t(vi.vertex_index) >= n_vertices)
                    LTM_THROW(path, ": shape '", shape.name, "' face ", f, ": vertex index out of range");
                const auto key = std::make_pair(vi.vertex_index, vi.texcoord_index);
                auto [it, fresh] = remap[mat].emplace(key, uint32_t(m.positions.size()));
                if (fresh) {
                    const float *v = &attrib.vertices[3 * size_t(vi.vertex_index)];
                    m.positions.push_back({v[0], v[1], v[2]});
                    Vec2f uv{0.f, 0.f};
                    if (vi.texcoord_index >= 0 && 2 * size_t(vi.texcoord_index) + 1 < attrib.texcoords.size())
                        uv = {attrib.texcoords[2 * size_t(vi.texcoord_index)], attrib.texcoords[2 * size_t(vi.texcoord_index) + 1]};
                    m.uvs.push_back(uv);
                }
                m.indices.push_back(it->second);
            }
        }
        for (auto &[mat, m] : by_material) {
            m.material = mat;
            m.name = shape.name.empty() ? "shape" + std::to_string(s.meshes.size()) : shape.name;
            if (by_material.size() > 1) m.name += "/" + (mat < default_material ? s.materials[size_t(mat)].name : "default");
            s.meshes.push_back(std::move(m));
        }
    }
    if (const std::string dropped = drop_degenerate_triangles(s); !dropped.empty()) log_warn(path, ": ", dropped);
    if (used_default) {
        Material m;
        m.name = "default";
        while (s.find_material(m.name) >= 0) m.name += "_";
        s.materials.push_back(m);
    }
    return s;
}
}  // namespace

}  // namespace ltm
