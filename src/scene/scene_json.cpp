// scene_json.cpp: the ltm scene JSON format (docs/formats.md). Strict: unknown keys, wrong
// types and non-finite numbers are errors naming the file and the JSON pointer.
#include "ltm/scene/scene_json.h"

#include <filesystem>

#include "ltm/core/error.h"
#include "ltm/core/file_util.h"
#include "ltm/scene/obj_io.h"

namespace fs = std::filesystem;

namespace ltm {

namespace {

TextureKind parse_texture_kind(const std::string &s, const std::string &where) {
    for (TextureKind k : {TextureKind::image, TextureKind::checker, TextureKind::stripes,
                          TextureKind::wood, TextureKind::noise})
        if (s == texture_kind_name(k)) return k;
    LTM_THROW(where, ": unknown texture type '", s, "' (image, checker, stripes, wood, noise)");
}

Texture texture_from_json(const Json &j, const std::string &where, const std::string &base_dir) {
    if (j.is_array()) return Texture::constant(json_to_vec3(j, where));
    JsonObject o(j, where);
    Texture t;
    t.kind = parse_texture_kind(o.require_string("type"), o.where("type"));
    if (t.kind == TextureKind::image) {
        const std::string file = o.require_string("file");
        const bool srgb = o.get_bool("srgb", true);
        t.image_srgb = srgb;
        const std::string full = fs::path(file).is_absolute() ? file : (fs::path(base_dir) / file).string();
        t.image_path = full;   // resolved; made relative again to wherever the scene is saved
        try {
            t.image = std::make_shared<const Image>(read_image(full, srgb));
        } catch (const Error &e) {
            LTM_THROW(o.where("file"), ": ", e.what());
        }
    } else {
        t.color_a = o.require_vec3("color_a");
        t.color_b = o.require_vec3("color_b");
        t.scale = o.get_float("scale", t.scale);
        if (!(t.scale > 0.f)) LTM_THROW(o.where("scale"), ": must be > 0");
        t.angle_deg = o.get_float("angle", 0.f);
        const int seed = o.get_int("seed", 0);
        if (seed < 0) LTM_THROW(o.where("seed"), ": must be >= 0");
        t.seed = uint32_t(seed);
    }
    o.finish();
    return t;
}

void check_albedo(const Texture &t, const std::string &where) {
    const Vec3f m = t.max_value();
    if (m.x > 1.f || m.y > 1.f || m.z > 1.f)
        LTM_THROW(where, ": albedo above 1 (", m, ") would create energy");
    if (t.is_constant() && (t.color_a.x < 0 || t.color_a.y < 0 || t.color_a.z < 0))
        LTM_THROW(where, ": albedo must be >= 0");
}

Material material_from_json(const Json &j, const std::string &where, const std::string &base_dir) {
    JsonObject o(j, where);
    Material m;
    m.name = o.require_string("name");
    const std::string type = o.require_string("type");
    if (type != "diffuse" && type != "emissive" && type != "conductor")
        LTM_THROW(o.where("type"), ": unknown material type '", type, "' (diffuse, emissive, conductor)");
    const bool emissive = type == "emissive";
    if (type == "conductor") {
        m.bsdf = BsdfKind::conductor;
        m.roughness = o.get_float("roughness", m.roughness);
        if (!(m.roughness >= 1e-3f && m.roughness <= 1.f))
            LTM_THROW(o.where("roughness"), ": GGX roughness must be in [0.001, 1], got ", m.roughness);
        m.specular = o.get_vec3("specular", m.specular);
        if (min(m.specular, Vec3f(0.f)) != Vec3f(0.f) || max_component(m.specular) > 1.f)
            LTM_THROW(o.where("specular"), ": must be in [0, 1]");
        m.albedo = Texture::constant(m.specular);   // what previews and albedo AOVs show
        o.finish();
        return m;
    }
    m.albedo = o.has("albedo") ? texture_from_json(o.require("albedo"), o.where("albedo"), base_dir)
                               : Texture::constant(Vec3f(emissive ? 0.f : 0.8f));
    check_albedo(m.albedo, o.where("albedo"));
    if (emissive) {
        m.emission = texture_from_json(o.require("radiance"), o.where("radiance"), base_dir);
        if (m.emission.is_constant() && (m.emission.color_a.x < 0 || m.emission.color_a.y < 0 ||
                                         m.emission.color_a.z < 0))
            LTM_THROW(o.where("radiance"), ": radiance must be >= 0");
    }
    o.finish();
    return m;
}

Transform transform_from_json(const Json &j, const std::string &where) {
    JsonObject o(j, where);
    Transform xf;
    if (o.has("matrix")) {
        const auto m = o.require_float_array("matrix");
        if (m.size() != 12 && m.size() != 16)
            LTM_THROW(o.where("matrix"), ": expected 12 or 16 numbers (row-major), got ", m.size());
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) xf.m[r][c] = m[size_t(r * 4 + c)];
    } else {
        // Applied in the order scale, rotate, translate.
        if (o.has("scale")) {
            const Json &s = o.require("scale");
            const Vec3f sv = s.is_number() ? Vec3f(json_to_float(s, o.where("scale")))
                                           : json_to_vec3(s, o.where("scale"));
            xf = Transform::scale(sv) * xf;
        }
        if (o.has("rotate")) {
            JsonObject r = o.require_object("rotate");
            const Vec3f axis = r.require_vec3("axis");
            if (length(axis) == 0.f) LTM_THROW(r.where("axis"), ": axis must be non-zero");
            xf = Transform::rotate(axis, r.require_float("degrees")) * xf;
            r.finish();
        }
        if (o.has("translate")) xf = Transform::translate(o.require_vec3("translate")) * xf;
    }
    o.finish();
    if (xf.determinant() == 0.f) LTM_THROW(where, ": transform is singular");
    return xf;
}

void add_mesh_from_json(Scene &scene, const Json &j, const std::string &where,
                        const std::string &base_dir) {
    JsonObject o(j, where);
    const std::string name = o.require_string("name");
    std::vector<TriangleMesh> parts;
    int material = -1;
    if (o.has("material")) {
        const std::string mat = o.require_string("material");
        material = scene.find_material(mat);
        if (material < 0) LTM_THROW(o.where("material"), ": material '", mat, "' is not defined");
    }
    if (o.has("file")) {
        if (o.has("positions")) LTM_THROW(where, ": give either 'file' or inline 'positions', not both");
        const std::string file = o.require_string("file");
        const std::string full = fs::path(file).is_absolute() ? file : (fs::path(base_dir) / file).string();
        if (file_extension(full) != "obj") LTM_THROW(o.where("file"), ": only .obj mesh files are supported");
        Scene sub = load_obj(full);
        for (auto &m : sub.meshes) {
            if (material < 0) {   // keep the OBJ's own materials, prefixed to stay unique
                Material mm = sub.materials[size_t(m.material)];
                mm.name = name + "/" + mm.name;
                int idx = scene.find_material(mm.name);
                m.material = idx >= 0 ? idx : scene.add_material(mm);
            } else {
                m.material = material;
            }
            m.name = name + "/" + m.name;
            parts.push_back(std::move(m));
        }
    } else {
        if (material < 0) LTM_THROW(where, ": missing required key 'material'");
        TriangleMesh m;
        m.name = name;
        m.material = material;
        const auto pos = o.require_float_array("positions");
        if (pos.size() % 3 != 0) LTM_THROW(o.where("positions"), ": length ", pos.size(), " is not a multiple of 3");
        for (size_t i = 0; i < pos.size(); i += 3) m.positions.push_back({pos[i], pos[i + 1], pos[i + 2]});
        const auto idx = o.require_int_array("indices");
        if (idx.size() % 3 != 0) LTM_THROW(o.where("indices"), ": length ", idx.size(), " is not a multiple of 3");
        for (size_t i = 0; i < idx.size(); ++i) {
            if (idx[i] < 0 || size_t(idx[i]) >= m.positions.size())
                LTM_THROW(o.where("indices"), "/", i, ": index ", idx[i], " out of range (", m.positions.size(), " vertices)");
            m.indices.push_back(uint32_t(idx[i]));
        }
        if (o.has("uvs")) {
            const auto uv = o.require_float_array("uvs");
            if (uv.size() != 2 * m.positions.size())
                LTM_THROW(o.where("uvs"), ": expected ", 2 * m.positions.size(), " numbers (2 per vertex), got ", uv.size());
            for (size_t i = 0; i < uv.size(); i += 2) m.uvs.push_back({uv[i], uv[i + 1]});
        }
        parts.push_back(std::move(m));
    }
    if (o.has("transform")) {
        const Transform xf = transform_from_json(o.require("transform"), o.where("transform"));
        for (auto &m : parts) {
            for (Vec3f &p : m.positions) p = xf.apply_point(p);
            if (xf.determinant() < 0.f)
                for (size_t t = 0; t < m.n_triangles(); ++t) std::swap(m.indices[3 * t + 1], m.indices[3 * t + 2]);
        }
    }
    o.finish();
    for (auto &m : parts) scene.meshes.push_back(std::move(m));
}

Camera camera_from_json(const Json &j, const std::string &where) {
    JsonObject o(j, where);
    Camera c;
    c.name = o.get_string("name", c.name);
    c.eye = o.require_vec3("eye");
    c.target = o.require_vec3("target");
    c.up = o.get_vec3("up", c.up);
    c.fov_y_deg = o.get_float("fov_y", c.fov_y_deg);
    c.width = o.get_int("width", c.width);
    c.height = o.get_int("height", c.height);
    o.finish();
    return c;
}

OrderedJson vec3_json(Vec3f v) { return OrderedJson::array({v.x, v.y, v.z}); }

OrderedJson texture_to_json(const Texture &t, const std::string &base_dir) {
    if (t.is_constant()) return vec3_json(t.color_a);
    OrderedJson j;
    j["type"] = texture_kind_name(t.kind);
    if (t.kind == TextureKind::image) {
        fs::path p = fs::absolute(t.image_path).lexically_normal();
        if (!base_dir.empty()) p = p.lexically_proximate(fs::absolute(base_dir).lexically_normal());
        j["file"] = p.string();
        if (!t.image_srgb) j["srgb"] = false;
    } else {
        j["color_a"] = vec3_json(t.color_a);
        j["color_b"] = vec3_json(t.color_b);
        j["scale"] = t.scale;
        j["angle"] = t.angle_deg;
        j["seed"] = t.seed;
    }
    return j;
}

}  // namespace

Scene scene_from_json(const Json &j, const std::string &where, const std::string &base_dir) {
    JsonObject o(j, where);
    const std::string format = o.get_string("format", "ltm-scene");
    if (format != "ltm-scene") LTM_THROW(o.where("format"), ": expected \"ltm-scene\", got \"", format, "\"");
    const int version = o.get_int("version", k_scene_format_version);
    if (version != k_scene_format_version)
        LTM_THROW(o.where("version"), ": unsupported scene format version ", version, " (this build reads ", k_scene_format_version, ")");
    Scene s;
    s.name = o.get_string("name", fs::path(where).stem().string());
    const Json &mats = o.require("materials");
    if (!mats.is_array()) LTM_THROW(o.where("materials"), ": expected an array");
    for (size_t i = 0; i < mats.size(); ++i) {
        Material m = material_from_json(mats[i], o.where("materials") + "/" + std::to_string(i), base_dir);
        if (s.find_material(m.name) >= 0)
            LTM_THROW(o.where("materials"), "/", i, ": duplicate material name '", m.name, "'");
        s.materials.push_back(std::move(m));
    }
    const Json &meshes = o.require("meshes");
    if (!meshes.is_array()) LTM_THROW(o.where("meshes"), ": expected an array");
    for (size_t i = 0; i < meshes.size(); ++i)
        add_mesh_from_json(s, meshes[i], o.where("meshes") + "/" + std::to_string(i), base_dir);
    if (o.has("cameras")) {
        const Json &cams = o.require("cameras");
        if (!cams.is_array()) LTM_THROW(o.where("cameras"), ": expected an array");
        for (size_t i = 0; i < cams.size(); ++i)
            s.cameras.push_back(camera_from_json(cams[i], o.where("cameras") + "/" + std::to_string(i)));
    }
    if (o.has("metadata")) {
        const Json &meta = o.require("metadata");
        if (!meta.is_object()) LTM_THROW(o.where("metadata"), ": expected an object");
        s.metadata = OrderedJson::parse(meta.dump());
    }
    o.finish();
    return s;
}

OrderedJson scene_to_json(const Scene &scene, const std::string &base_dir) {
    OrderedJson j;
    j["format"] = "ltm-scene";
    j["version"] = k_scene_format_version;
    j["name"] = scene.name;
    j["materials"] = OrderedJson::array();
    for (const auto &m : scene.materials) {
        OrderedJson mj;
        mj["name"] = m.name;
        if (m.bsdf == BsdfKind::conductor) {
            mj["type"] = "conductor";
            mj["roughness"] = m.roughness;
            mj["specular"] = vec3_json(m.specular);
            j["materials"].push_back(mj);
            continue;
        }
        mj["type"] = m.is_emissive() ? "emissive" : "diffuse";
        mj["albedo"] = texture_to_json(m.albedo, base_dir);
        if (m.is_emissive()) mj["radiance"] = texture_to_json(m.emission, base_dir);
        j["materials"].push_back(mj);
    }
    j["meshes"] = OrderedJson::array();
    for (const auto &m : scene.meshes) {
        OrderedJson mj;
        mj["name"] = m.name;
        mj["material"] = scene.materials.at(size_t(m.material)).name;
        OrderedJson pos = OrderedJson::array(), idx = OrderedJson::array(), uv = OrderedJson::array();
        for (const Vec3f &p : m.positions) pos.insert(pos.end(), {p.x, p.y, p.z});
        for (uint32_t i : m.indices) idx.push_back(i);
        mj["positions"] = pos;
        mj["indices"] = idx;
        if (!m.uvs.empty()) {
            for (const Vec2f &t : m.uvs) uv.insert(uv.end(), {t.x, t.y});
            mj["uvs"] = uv;
        }
        j["meshes"].push_back(mj);
    }
    j["cameras"] = OrderedJson::array();
    for (const auto &c : scene.cameras) {
        j["cameras"].push_back({{"name", c.name}, {"eye", vec3_json(c.eye)}, {"target", vec3_json(c.target)},
                                {"up", vec3_json(c.up)}, {"fov_y", c.fov_y_deg}, {"width", c.width},
                                {"height", c.height}});
    }
    if (!scene.metadata.empty()) j["metadata"] = scene.metadata;
    return j;
}

void save_scene_json(const Scene &scene, const std::string &path) {
    write_file_atomic(path, dump_json_compact(scene_to_json(scene, parent_dir(path))));
}


}  // namespace ltm
