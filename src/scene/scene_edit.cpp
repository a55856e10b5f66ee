// scene_edit.cpp: JSON-level scene edits.
#include "ltm/scene/scene_edit.h"

#include <cmath>

#include "ltm/core/error.h"

namespace ltm {

namespace {
Json &find_named(Json &scene, const char *array, const std::string &name, const std::string &where) {
    if (!scene.contains(array) || !scene[array].is_array()) LTM_THROW(where, ": scene has no '", array, "' array");
    for (auto &e : scene[array])
        if (e.is_object() && e.value("name", std::string()) == name) return e;
    LTM_THROW(where, ": no ", std::string(array).substr(0, std::string(array).size() - 1), " named '", name, "'");
}

Json vec3(Vec3f v) { return Json::array({json_float(v.x), json_float(v.y), json_float(v.z)}); }

void check_finite(Vec3f v, const std::string &what, const std::string &where) {
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) LTM_THROW(where, ": ", what, " is not finite");
}
}  // namespace

int translate_meshes(Json &scene, const std::string &name, Vec3f offset, const std::string &where) {
    check_finite(offset, "offset", where);
    if (!scene.contains("meshes") || !scene["meshes"].is_array()) LTM_THROW(where, ": scene has no 'meshes' array");
    int moved = 0;
    for (auto &m : scene["meshes"]) {
        const std::string n = m.value("name", std::string());
        if (n != name && n.rfind(name + "_", 0) != 0) continue;
        Json &t = m["transform"];
        if (t.is_null()) t = Json::object();
        if (t.contains("matrix")) {
            // Row-major 3x4 (or 4x4): the translation is the last entry of each of the first 3 rows.
            Json &mat = t["matrix"];
            if (mat.size() != 12 && mat.size() != 16) LTM_THROW(where, ": mesh '", n, "' has a matrix of ", mat.size(), " numbers");
            const size_t cols = 4;
            for (int r = 0; r < 3; ++r) mat[size_t(r) * cols + 3] = mat[size_t(r) * cols + 3].get<double>() + double(offset[r]);
        } else {
            Vec3f tr(0.f);
            if (t.contains("translate")) tr = {t["translate"][0].get<float>(), t["translate"][1].get<float>(), t["translate"][2].get<float>()};
            t["translate"] = vec3(tr + offset);
        }
        ++moved;
    }
    if (moved == 0) LTM_THROW(where, ": no mesh named '", name, "' or '", name, "_*'");
    return moved;
}

void set_albedo(Json &scene, const std::string &name, Vec3f albedo, const std::string &where) {
    check_finite(albedo, "albedo", where);
    for (int c = 0; c < 3; ++c)
        if (albedo[c] < 0.f || albedo[c] > 1.f) LTM_THROW(where, ": albedo ", albedo, " must lie in [0, 1]");
    Json &m = find_named(scene, "materials", name, where);
    if (m.value("type", std::string("diffuse")) == "emissive") LTM_THROW(where, ": material '", name, "' is emissive");
    m["albedo"] = vec3(albedo);
}

void scale_radiance(Json &scene, const std::string &name, float k, const std::string &where) {
    if (!(k >= 0.f) || !std::isfinite(k)) LTM_THROW(where, ": radiance scale ", k, " must be finite and >= 0");
    Json &m = find_named(scene, "materials", name, where);
    if (m.value("type", std::string()) != "emissive" || !m.contains("radiance") || !m["radiance"].is_array())
        LTM_THROW(where, ": material '", name, "' is not emissive with a constant radiance");
    for (auto &v : m["radiance"]) v = json_float(v.get<float>() * k);
}

}  // namespace ltm
