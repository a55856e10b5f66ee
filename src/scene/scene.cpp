// scene.cpp: scene queries and validation.
#include "ltm/scene/scene.h"

#include <cmath>

#include "ltm/core/error.h"
#include "ltm/scene/mesh_builder.h"

namespace ltm {

Bounds3f Scene::bounds() const {
    Bounds3f b;
    for (const auto &m : meshes)
        for (const Vec3f &p : m.positions) b.expand(p);
    return b;
}

float Scene::extent() const {
    const Bounds3f b = bounds();
    return b.empty() ? 0.f : max_component(b.extent());
}

size_t Scene::n_triangles() const {
    size_t n = 0;
    for (const auto &m : meshes) n += m.n_triangles();
    return n;
}

double Scene::total_area() const {
    double a = 0;
    for (const auto &m : meshes)
        for (size_t t = 0; t < m.n_triangles(); ++t) a += m.area(t);
    return a;
}

int Scene::find_material(const std::string &n) const {
    for (size_t i = 0; i < materials.size(); ++i)
        if (materials[i].name == n) return int(i);
    return -1;
}

int Scene::add_material(Material m) {
    LTM_CHECK_EQ(find_material(m.name), -1);
    materials.push_back(std::move(m));
    return int(materials.size()) - 1;
}

bool Scene::has_emitter() const {
    for (const auto &m : meshes)
        if (m.material >= 0 && size_t(m.material) < materials.size() &&
            materials[size_t(m.material)].is_emissive() && m.n_triangles() > 0)
            return true;
    return false;
}

void validate_scene(const Scene &scene, const std::string &where, const ValidateOptions &opt) {
    if (scene.n_triangles() == 0) LTM_THROW(where, ": scene has no triangles");
    for (const auto &mesh : scene.meshes) {
        const std::string what = where + ": mesh '" + mesh.name + "'";
        if (mesh.material < 0 || size_t(mesh.material) >= scene.materials.size())
            LTM_THROW(what, ": has no valid material");
        if (mesh.indices.size() % 3 != 0)
            LTM_THROW(what, ": index count ", mesh.indices.size(), " is not a multiple of 3");
        if (!mesh.uvs.empty() && mesh.uvs.size() != mesh.positions.size())
            LTM_THROW(what, ": ", mesh.uvs.size(), " uvs for ", mesh.positions.size(), " positions");
        for (size_t i = 0; i < mesh.positions.size(); ++i)
            if (!is_finite(mesh.positions[i]))
                LTM_THROW(what, ": vertex ", i, " has a non-finite coordinate ", mesh.positions[i]);
        for (size_t i = 0; i < mesh.uvs.size(); ++i)
            if (!std::isfinite(mesh.uvs[i].x) || !std::isfinite(mesh.uvs[i].y))
                LTM_THROW(what, ": uv ", i, " is not finite");
        for (size_t i = 0; i < mesh.indices.size(); ++i)
            if (mesh.indices[i] >= mesh.positions.size())
                LTM_THROW(what, ": index ", i, " = ", mesh.indices[i], " is out of range (",
                          mesh.positions.size(), " vertices)");
        for (size_t t = 0; t < mesh.n_triangles(); ++t)
            if (is_degenerate_triangle(mesh, t))
                LTM_THROW(what, ": triangle ", t, " is degenerate (area ", mesh.area(t), ", a sliver or a point)");
    }
    for (const auto &cam : scene.cameras) {
        const std::string what = where + ": camera '" + cam.name + "'";
        if (!is_finite(cam.eye) || !is_finite(cam.target) || !is_finite(cam.up))
            LTM_THROW(what, ": non-finite eye/target/up");
        if (length(cam.target - cam.eye) <= 0.f) LTM_THROW(what, ": eye equals target");
        if (length(cross(normalize(cam.target - cam.eye), cam.up)) < 1e-4f)
            LTM_THROW(what, ": up vector is parallel to the view direction");
        if (!(cam.fov_y_deg > 0.f && cam.fov_y_deg < 179.f))
            LTM_THROW(what, ": fov_y must be in (0, 179) degrees, got ", cam.fov_y_deg);
        if (cam.width <= 0 || cam.height <= 0 || cam.width > 16384 || cam.height > 16384)
            LTM_THROW(what, ": resolution must be in 1..16384, got ", cam.width, "x", cam.height);
    }
    if (opt.require_emitter && !scene.has_emitter())
        LTM_THROW(where, ": scene has no emitter (no material with non-zero radiance is used)");
}

}  // namespace ltm
