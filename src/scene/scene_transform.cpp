// scene_transform.cpp: emission scale, unit change and recolouring of a whole scene.
#include "ltm/scene/scene_transform.h"

#include <cmath>
#include <memory>

#include "ltm/core/error.h"

namespace ltm {

void scale_emission(Scene &scene, float k) {
    if (!(k >= 0.f) || !std::isfinite(k)) LTM_THROW("scale_emission: factor ", k, " must be finite and >= 0");
    for (Material &m : scene.materials) {
        Texture &t = m.emission;
        t.color_a = t.color_a * k, t.color_b = t.color_b * k;
        if (t.image) {
            auto img = std::make_shared<Image>(*t.image);
            for (Vec3f &v : img->pixels) v *= k;
            t.image = img;
        }
    }
}

void scale_lengths(Scene &scene, float s) {
    if (!(s > 0.f) || !std::isfinite(s)) LTM_THROW("scale_lengths: factor ", s, " must be finite and > 0");
    for (TriangleMesh &mesh : scene.meshes)
        for (Vec3f &p : mesh.positions) p = p * s;
    for (Camera &c : scene.cameras) c.eye = c.eye * s, c.target = c.target * s;
}

int recolor_meshes(Scene &scene, const std::function<bool(const std::string &)> &select, Vec3f albedo,
                   const std::string &material_name) {
    Material m;
    m.name = material_name;
    m.albedo = Texture::constant(albedo);
    int material = -1, n = 0;
    for (TriangleMesh &mesh : scene.meshes) {
        if (!select(mesh.name) || scene.materials[size_t(mesh.material)].is_emissive()) continue;
        if (material < 0) material = scene.add_material(m);
        mesh.material = material;
        ++n;
    }
    return n;
}

bool is_room_shell_mesh(const std::string &name) {
    auto ends_with = [&](const std::string &suffix) {
        return name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
    };
    return ends_with("_walls") || ends_with("_floor") || ends_with("_ceiling");
}

}  // namespace ltm
